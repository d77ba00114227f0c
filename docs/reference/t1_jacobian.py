"""Task 1 + 2: symbolic Jacobian, characteristic polynomial, Hopf, transversality, large-kappa asymptotics."""
import sympy as sp

s, v, th, l = sp.symbols('s v theta lambda')
kap, nu, m, A, B, mu0, mu2, thc = sp.symbols('kappa nu m A B mu0 mu2 theta_c', positive=True)
muv, muphi = sp.symbols('mu_v mu_phi', real=True)

laws = {
    'ln2': mu0 + A*sp.log(v) + B*sp.log(th) + mu2*sp.log(th)**2,
    'cutoff': mu0 + A*sp.log(v) + B*sp.log(1 + th/thc),
}
mphi_expr = {'ln2': B - 2*mu2*sp.log(nu), 'cutoff': B/(1 + nu*thc)}

print("=== inertial ===")
for name, mu in laws.items():
    F = sp.Matrix([kap*(nu - v), (s - mu)/m, 1 - v*th])
    X = sp.Matrix([s, v, th])
    ss = {v: nu, th: 1/nu, s: mu.subs({v: nu, th: 1/nu})}
    assert sp.simplify(F.subs(ss)) == sp.zeros(3, 1)
    J = F.jacobian(X).subs(ss)
    J = sp.simplify(J)
    # check mu_phi
    mphi = sp.simplify((th*sp.diff(mu, th)).subs(ss))
    print(name, "mu_phi =", mphi, " matches:", sp.simplify(mphi - mphi_expr[name]) == 0)
    P = sp.expand(m*(l*sp.eye(3) - J).det())
    target = m*l**3 + (A/nu + m*nu)*l**2 + (kap + A - mphi_expr[name])*l + kap*nu
    print(name, "J =", J.tolist())
    print(name, "m*det(lI-J) - claimed =", sp.simplify(P - target))

print("=== quasi-static ===")
for name, mu in laws.items():
    g = mu - mu0 - A*sp.log(v)
    vq = sp.exp((s - mu0 - g)/A)
    F = sp.Matrix([kap*(nu - vq), 1 - vq*th])
    X = sp.Matrix([s, th])
    s0 = mu.subs({v: nu, th: 1/nu})
    ss = {th: 1/nu, s: s0}
    assert sp.simplify(F.subs(ss)) == sp.zeros(2, 1)
    J = sp.simplify(F.jacobian(X).subs(ss))
    P = sp.expand((l*sp.eye(2) - J).det())
    target = (A/nu)*l**2 + (kap + A - mphi_expr[name])*l + kap*nu
    print(name, "J =", J.tolist())
    print(name, "(A/nu)*det(lI-J) - claimed =", sp.simplify(sp.expand((A/nu)*P - target)))

print("=== Hopf (generic mu_v, mu_phi) ===")
a3, a2, a1, a0 = m, muv/nu + m*nu, kap + muv - muphi, kap*nu
P = a3*l**3 + a2*l**2 + a1*l + a0
kc = sp.solve(sp.Eq(a2*a1, a3*a0), kap)[0]
print("kappa_c =", sp.factor(kc), " claimed diff:", sp.simplify(kc - (muphi - muv)*(1 + m*nu**2/muv)))
w2 = sp.simplify((a0/a2).subs(kap, kc))
print("omega_c^2 =", sp.factor(w2), " claimed diff:", sp.simplify(w2 - nu**2*(muphi/muv - 1)))
w = sp.Symbol('omega', positive=True)
# check P(i w)=0 at kappa_c
print("P(i w_c) at kappa_c:", sp.simplify(sp.expand(P.subs({kap: kc, l: sp.I*nu*sp.sqrt(muphi/muv - 1)}))))
# transversality: parametrize mu_phi = mu_v (1 + w^2/nu^2) so that omega_c = w exactly
sub = {muphi: muv*(1 + w**2/nu**2)}
dl = (-sp.diff(P, kap)/sp.diff(P, l)).subs(sub)
dl_h = sp.simplify(dl.subs({kap: kc.subs(sub)}).subs(l, sp.I*w))
re_, im_ = [sp.simplify(t) for t in dl_h.as_real_imag()]
print("dRe(lambda)/dkappa at Hopf =", sp.factor(re_))
claimed_re = -(muv/nu)/(2*(m**2*w**2 + (muv/nu + m*nu)**2))
print("  vs -(mu_v/nu)/(2(m^2 w^2 + (mu_v/nu+m nu)^2)) diff:", sp.simplify(re_ - claimed_re))
print("dIm(lambda)/dkappa at Hopf =", sp.factor(im_))
claimed_im = (nu*(muv/nu + m*nu) + m*w**2)/(2*w*(m**2*w**2 + (muv/nu + m*nu)**2))
print("  vs (nu a2 + m w^2)/(2 w (m^2 w^2 + a2^2)) diff:", sp.simplify(im_ - claimed_im))
# quasi-static
Pq = (muv/nu)*l**2 + (kap + muv - muphi)*l + kap*nu
kq = muphi - muv
print("QS: Re lambda =", sp.simplify(-(kap + muv - muphi)/(2*muv/nu)), " d/dkappa =", -nu/(2*muv))

print("=== Task 2: large kappa asymptotics ===")
eps = sp.Symbol('epsilon', positive=True)  # eps = 1/kappa
# real root: lambda = -nu + sum c_k eps^k
c1, c2, c3 = sp.symbols('c1 c2 c3')
lr = -nu + c1*eps + c2*eps**2 + c3*eps**3
expr = sp.expand(eps*P.subs({l: lr, kap: 1/eps}))
sol = {}
for k, c in zip([1, 2, 3], [c1, c2, c3]):
    co = sp.expand(expr.coeff(eps, k).subs(sol))
    sol[c] = sp.solve(co, c)[0]
print("real root: -nu + eps*", sp.factor(sol[c1]), " + eps^2*", sp.factor(sol[c2]))
# complex pair: lambda = i*sqrt(kappa/m) * (1 + ...) expansion in h = 1/sqrt(kappa)
h = sp.Symbol('h', positive=True)
d = sp.symbols('d0:7')
lc = sp.I/sp.sqrt(m)/h + sum(d[k]*h**(k-0) for k in range(0, 7))
expr = sp.expand(h**3*P.subs({l: lc, kap: 1/h**2}))
sol2 = {}
for k in range(0, 5):
    # find lowest order coefficient not yet zero
    pass
ser = sp.series(expr, h, 0, 8).removeO()
sol2 = {}
for order in range(0, 8):
    co = sp.simplify(sp.expand(ser.coeff(h, order).subs(sol2)))
    if co == 0:
        continue
    unknowns = [x for x in d if x in co.free_symbols and x not in sol2]
    if not unknowns:
        print("inconsistent at order", order, co); break
    x = sorted(unknowns, key=lambda t: int(str(t)[1:]))[0]
    sol2[x] = sp.simplify(sp.solve(co, x)[0])
for x in d:
    if x in sol2:
        print(" ", x, "=", sp.factor(sp.simplify(sol2[x])))
print("complex root (upper): i sqrt(kappa/m) + d0 + d1/sqrt(kappa) + d2/kappa + ...")
