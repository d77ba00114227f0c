"""Second Lyapunov coefficient of the inertial Rice-Ruina block at the Bautin point, coordinates (s, v, theta).
    s' = kappa (nu - v),  m v' = s - mu0 - A ln v - B ln theta,  theta' = 1 - v theta
kappa = kappa_c(m) = (B - A)(1 + m nu^2/A), w = nu sqrt(B/A - 1).  Normal form via nf.py (generic, order 5)."""
import sys
import sympy as sp
import mpmath as mp
from nf import TaylorEval, hopf_vectors, normal_form, jacobian

mp.mp.dps = 40
R = sp.Rational
s, v, th = sp.symbols('s v theta')
m, kap = sp.symbols('m kappa', positive=True)
A, B, mu0 = R('0.012'), R('0.023'), R('0.6')
Am, Bm = mp.mpf(12)/1000, mp.mpf(23)/1000


def build(nu):
    nu = sp.Integer(nu)
    F = sp.Matrix([kap*(nu - v), (s - mu0 - A*sp.log(v) - B*sp.log(th))/m, 1 - v*th])
    nun = mp.mpf(int(nu))
    x0fun = lambda pv: [mp.mpf(6)/10 + (Am - Bm)*mp.log(nun), nun, 1/nun]
    return TaylorEval(F, [s, v, th], [m, kap], x0fun, maxdeg=5), nun


def coeffs(TE, nun, mm, order, phase=0):
    kc = (Bm - Am)*(1 + mm*nun**2/Am)
    w = nun*mp.sqrt(Bm/Am - 1)
    T = TE([mm, kc])
    J = jacobian(T, 3)
    q, p = hopf_vectors(J, w, phase)
    assert mp.norm(J*q - mp.mpc(0, 1)*w*q) < mp.mpf(10)**-35
    g, H, info = normal_form(T, w, q, p, order=order)
    return g, w, kc, q, p, J, info


def l1_of(TE, nun, mm):
    g, w = coeffs(TE, nun, mm, 3)[:2]
    return mp.re(g[(2, 1)])/w


if __name__ == '__main__':
    for nu in [1, 3]:
        TE, nun = build(nu)
        print("==== nu =", nu)
        if nu == 1:
            for mm in ['0.001', '0.01', '0.1', '1']:
                print("  check vs t3_lyap: m=%s l1 =" % mm, mp.nstr(l1_of(TE, nun, mp.mpf(mm)), 30))
        guess = mp.mpf('0.0016140505108687765219')/nun**2
        mstar = mp.findroot(lambda mm: l1_of(TE, nun, mm), (guess*(1 - mp.mpf('1e-6')), guess*(1 + mp.mpf('1e-6'))),
                            solver='secant', tol=mp.mpf(10)**-70)
        g, w, kc, q, p, J, info = coeffs(TE, nun, mstar, 5)
        c1, c2 = g[(2, 1)], g[(3, 2)]
        print("  m*            =", mp.nstr(mstar, 30))
        print("  eta* = m* nu^2/A =", mp.nstr(mstar*nun**2/Am, 30))
        print("  kappa_c(m*)   =", mp.nstr(kc, 30))
        print("  omega         =", mp.nstr(w, 30))
        print("  eig(J)        =", [mp.nstr(e, 20) for e in mp.eig(J)[0]])
        print("  l1(m*)        =", mp.nstr(mp.re(c1)/w, 5), "  (Im c1 =", mp.nstr(mp.im(c1), 30), ")")
        print("  c2 = G32/12   =", mp.nstr(c2, 30))
        print("  l2 = Re c2/w  =", mp.nstr(mp.re(c2)/w, 30))
        print("  q =", [mp.nstr(x, 20) for x in q])
        print("  p =", [mp.nstr(x, 20) for x in p])
        print("  bordered multipliers:", [mp.nstr(abs(x), 3) for x in info.values()])
        g2 = coeffs(TE, nun, mstar, 5, phase=mp.mpf('0.37'))[0]
        print("  phase-independence check: l2(phase 0.37 pi) - l2 =", mp.nstr((mp.re(g2[(3, 2)]) - mp.re(c2))/w, 5))
        # dl1/dm at m* (useful for the unfolding)
        hh = mstar*mp.mpf('1e-12')
        print("  dl1/dm at m*  =", mp.nstr((l1_of(TE, nun, mstar + hh) - l1_of(TE, nun, mstar - hh))/(2*hh), 15))
        sys.stdout.flush()
