"""Task 3(b)/4: symbolic l1 for the quasi-static ln2 law in coordinates (s, theta), Kuznetsov normalization,
and onset amplitude of s."""
import sympy as sp

s, th = sp.symbols('s theta', real=True)
A, nu, mu2, w, mu0 = sp.symbols('A nu mu2 omega mu0', positive=True)
I = sp.I
# parametrize so that omega_c = w:  mu_phi = A (1 + w^2/nu^2),  B = mu_phi + 2 mu2 ln nu
muphi = A*(1 + w**2/nu**2)
B = muphi + 2*mu2*sp.log(nu)
kc = muphi - A
g = B*sp.log(th) + mu2*sp.log(th)**2
vq = sp.exp((s - mu0 - g)/A)
F = sp.Matrix([kc*(nu - vq), 1 - vq*th])
X = [s, th]
x0 = {s: mu0 + A*sp.log(nu) + g.subs(th, 1/nu), th: 1/nu}
n = 2


def at0(e):
    return sp.simplify(sp.expand_log(e.subs(x0), force=True))


J = sp.Matrix(2, 2, lambda i, j: at0(sp.diff(F[i], X[j])))
Bt = [[[at0(sp.diff(F[i], X[j], X[k])) for k in range(n)] for j in range(n)] for i in range(n)]
Ct = [[[[at0(sp.diff(F[i], X[j], X[k], X[l])) for l in range(n)] for k in range(n)] for j in range(n)] for i in range(n)]
print("J =", J)
print("trace J =", sp.simplify(J.trace()), " det J =", sp.simplify(J.det()), " (omega^2 =", w**2, ")")

M = J - I*w*sp.eye(2)
q = sp.Matrix([-M[0, 1], M[0, 0]])                # unnormalized
Mt = J.T + I*w*sp.eye(2)
p = sp.Matrix([-Mt[0, 1], Mt[0, 0]])
cj = lambda x: x.subs(I, -I)                      # all symbols real
ip = lambda a, b: sp.simplify(sum(cj(a[i])*b[i] for i in range(n)))
assert sp.simplify(J*q - I*w*q) == sp.zeros(2, 1)
assert sp.simplify(J.T*p + I*w*p) == sp.zeros(2, 1)
p = p/cj(ip(p, q))
assert sp.simplify(ip(p, q) - 1) == 0
qb = cj(q)
Bf = lambda x, y: sp.Matrix([sum(Bt[i][j][k]*x[j]*y[k] for j in range(n) for k in range(n)) for i in range(n)])
Cf = lambda x, y, z: sp.Matrix([sum(Ct[i][j][k][l]*x[j]*y[k]*z[l] for j in range(n) for k in range(n) for l in range(n)) for i in range(n)])
h11 = J.LUsolve(Bf(q, qb))
h20 = (2*I*w*sp.eye(2) - J).LUsolve(Bf(q, q))
val = ip(p, Cf(q, q, qb)) - 2*ip(p, Bf(q, h11)) + ip(p, Bf(qb, h20))
val = sp.simplify(val)
reval = sp.simplify(sp.re(sp.expand_complex(val)))
qq = ip(q, q)
l1 = sp.simplify(reval/(2*w)/qq)        # Kuznetsov l1 with conj(q).q = 1
print("\nl1 (Kuznetsov, (s,theta) coords, conj(q).q=1) =", sp.factor(l1))
print("  at mu2=0:", sp.simplify(l1.subs(mu2, 0)))
Rec1 = sp.simplify(reval/2/qq)
print("Re c1 = w*l1 =", sp.factor(Rec1))
# Amplitude: x = x0 + 2 Re(z q) + O(|z|^2), |z|^2 = Re(lambda')*(kappa_c-kappa)/Re(c1)
dRe = -nu/(2*A)
qs2 = sp.simplify(q[0]*cj(q[0])/qq)
coef2 = sp.simplify(16*qs2*dRe/Rec1)      # (Delta s)^2/(kappa_c - kappa)
mphi_s = sp.Symbol('mu_phi', positive=True)
coef2_m = sp.simplify(coef2.subs(w, nu*sp.sqrt(mphi_s/A - 1)))
print("\n(Delta s_pp)^2/(kappa_c-kappa) =", sp.factor(coef2_m))
claimed = 16*mphi_s*(mphi_s - A)/mu2
print("ratio to claimed 16 mu_phi (mu_phi - A)/mu2 :", sp.simplify(coef2_m/claimed))
l1_m = sp.simplify(l1.subs(w, nu*sp.sqrt(mphi_s/A - 1)))
print("\nl1 in terms of mu_phi:", sp.factor(l1_m))
print("Re c1 in terms of mu_phi:", sp.factor(sp.simplify(Rec1.subs(w, nu*sp.sqrt(mphi_s/A - 1)))))
print("|q_s|^2 (conj(q).q=1):", sp.factor(sp.simplify(qs2.subs(w, nu*sp.sqrt(mphi_s/A - 1)))))

# numeric check against t3 case (a)
import mpmath as mp
mp.mp.dps = 30
for nuv in [1, 10]:
    sub = {A: sp.Rational('0.012'), mu2: sp.Rational('2.4e-4'), nu: nuv,
           mphi_s: sp.Rational('0.023') - 2*sp.Rational('2.4e-4')*sp.log(nuv)}
    print("nu=%d: l1 =" % nuv, sp.N(l1_m.subs(sub), 25), "  Delta_s coef sqrt(coef2) =", sp.N(sp.sqrt(coef2_m.subs(sub)), 25),
          "  claimed 4 sqrt(mu_phi(mu_phi-A)/mu2) =", sp.N(sp.sqrt(claimed.subs(sub)), 25))
