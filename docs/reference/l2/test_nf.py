"""Validation of nf.py on systems with known l2.
 T1: Bautin normal form Z' = i w Z + c1 Z|Z|^2 + c2 Z|Z|^4 in (x, y); q = (1,-i)/sqrt2 => c2_nf = 4 c2, l2 = 4 Re c2 / w.
 T2: the same plus a third, slaved variable, a nonlinear near-identity change of variables mixing all three
     and a linear change x = M u: expected c2 = 4 c2 / |M q_u|^4 (Re part; Re c1 = 0).
 Also checks independence from the phase of q."""
import sympy as sp
import mpmath as mp
from nf import TaylorEval, hopf_vectors, normal_form, jacobian

mp.mp.dps = 40
R = sp.Rational
x, y, u3 = sp.symbols('x y u3', real=True)
w = R(7, 5)


def bautin_field(c1, c2):
    Z = x + sp.I*y
    f = sp.I*w*Z + c1*Z*(x**2 + y**2) + c2*Z*(x**2 + y**2)**2
    f = sp.expand(f)
    return sp.Matrix([sp.re(f), sp.im(f)])


def run(F, X, phase=0):
    TE = TaylorEval(F, X, [], lambda pv: [0]*len(X), maxdeg=5)
    T = TE([])
    J = jacobian(T, len(X))
    q, p = hopf_vectors(J, mp.mpf(w.p)/w.q, phase)
    g, H, info = normal_form(T, mp.mpf(w.p)/w.q, q, p, order=5)
    return g, q, info


print("T1: Bautin normal form in real coordinates")
for c1, c2 in [(sp.I*R(3, 10), R(-13, 17) + sp.I*R(2, 3)), (R(1, 4) - sp.I*R(1, 2), R(5, 7) - sp.I*R(1, 9))]:
    F = bautin_field(c1, c2)
    for ph in [0, mp.mpf('0.3141')]:
        g, q, info = run(F, [x, y], ph)
        exp_c1 = 2*complex(c1); exp_c2 = 4*complex(c2)
        print("  c1=%s c2=%s phase=%s" % (c1, c2, mp.nstr(ph, 5)))
        print("    g21 =", mp.nstr(g[(2, 1)], 25), " expected", exp_c1)
        print("    g32 =", mp.nstr(g[(3, 2)], 25), " expected", exp_c2)
        print("    l2 = Re g32/w =", mp.nstr(mp.re(g[(3, 2)])/(mp.mpf(7)/5), 25),
              " expected 4 Re c2/w =", mp.nstr(4*mp.mpf(sp.re(c2).p)/sp.re(c2).q/(mp.mpf(7)/5), 25))

print("\nT2: 3D system: Bautin NF (Re c1 = 0) + slaved stable variable + nonlinear + linear change of variables")
c1, c2 = sp.I*R(3, 10), R(-13, 17) + sp.I*R(2, 3)
u1, u2 = sp.symbols('u1 u2', real=True)
Z = u1 + sp.I*u2
f = sp.expand(sp.I*w*Z + c1*Z*(u1**2 + u2**2) + c2*Z*(u1**2 + u2**2)**2)
G = sp.Matrix([sp.re(f), sp.im(f), -R(5, 2)*u3 + u1**2 - R(1, 3)*u1*u2 + R(2, 1)*u2**3 + u3*u1])
U = [u1, u2, u3]
X = list(sp.symbols('x1:4'))


def trunc_poly(P, N=5):
    return sp.Poly.from_dict({m: c for m, c in P.as_dict().items() if sum(m) <= N}, *P.gens, domain=P.domain)


def tsubs(e, old, new_polys, N=5):
    """Substitute old symbols -> truncated polys (sp.Poly in X), multiplying with truncation at degree N."""
    P = sp.Poly(sp.expand(e), *old)
    out = sp.Poly(0, *X, domain='QQ')
    cache = {}
    for mon, c in P.terms():
        term = sp.Poly(c, *X, domain='QQ')
        for v, k in enumerate(mon):
            for _ in range(k):
                term = trunc_poly(term*new_polys[v], N)
        out = out + term
    return out


def trunc(e, vars_, N=5):
    return trunc_poly(sp.Poly(sp.expand(e), *vars_, domain='QQ'), N).as_expr()


# v = Psi(u) = Phi3(Phi2(Phi1(u))), triangular maps with explicit inverses; then x = Mlin v.
def Phi1(a): return [a[0] + R(1, 2)*a[1]**2 + R(1, 3)*a[1]*a[2] - a[2]**3/5, a[1], a[2]]
def Phi1i(a): return [a[0] - (R(1, 2)*a[1]**2 + R(1, 3)*a[1]*a[2] - a[2]**3/5), a[1], a[2]]
def Phi2(a): return [a[0], a[1], a[2] + R(3, 4)*a[0]**2 - R(2, 7)*a[0]*a[1] + a[0]**2*a[1]/3]
def Phi2i(a): return [a[0], a[1], a[2] - (R(3, 4)*a[0]**2 - R(2, 7)*a[0]*a[1] + a[0]**2*a[1]/3)]
def Phi3(a): return [a[0], a[1] + R(2, 5)*a[0]*a[2] - R(1, 6)*a[2]**2 + a[0]*a[1]*a[2], a[2]]
def Phi3i(a): return [a[0], a[1] - (R(2, 5)*a[0]*a[2] - R(1, 6)*a[2]**2 + a[0]*a[1]*a[2]), a[2]]


Mlin = sp.Matrix([[2, R(1, 3), -1], [R(1, 2), 1, R(2, 5)], [R(-1, 3), R(1, 4), R(3, 2)]])
Psi = sp.Matrix(Phi3(Phi2(Phi1(U))))
DPsi = Psi.jacobian(U)
vx = list(Mlin.inv()*sp.Matrix(X))
V3 = list(sp.symbols('w1:4'))
a1 = [sp.Poly(e, *X, domain='QQ') for e in vx]
a2 = [tsubs(e, V3, a1) for e in Phi3i(V3)]
a3 = [tsubs(e, V3, a2) for e in Phi2i(V3)]
uofx = [tsubs(e, V3, a3) for e in Phi1i(V3)]
Fx = Mlin*(DPsi*G)
Fx = sp.Matrix([tsubs(e, U, uofx).as_expr() for e in Fx])
# sanity: linear part of Fx equals Mlin * DPsi(0) * J_G * (Mlin DPsi(0))^-1 (DPsi(0) = I)
qu = sp.Matrix([1, -sp.I, 0])/sp.sqrt(2)
Mq = Mlin*qu
nrm2 = sp.nsimplify(sp.expand((Mq.H*Mq)[0]))
expected_c2 = 4*c2/nrm2**2
for ph in [0, mp.mpf('0.77')]:
    g, q, info = run(Fx, X, ph)
    print("  phase=%s g21 =" % mp.nstr(ph, 3), mp.nstr(g[(2, 1)], 25), " expected", mp.nstr(mp.mpc(0, mp.mpf(str(sp.N(sp.im(2*c1/nrm2), 50)))), 25))
    print("    g32 =", mp.nstr(g[(3, 2)], 30))
    ev = mp.mpf(str(sp.N(sp.re(expected_c2), 50)))
    print("    expected Re g32 = 4 Re c2/|M q_u|^4 =", mp.nstr(ev, 30))
    print("    rel.err Re g32 =", mp.nstr((mp.re(g[(3, 2)]) - ev)/ev, 5))
    print("    bordered-system multipliers (must be ~0):", [mp.nstr(abs(v), 3) for k, v in info.items()])
