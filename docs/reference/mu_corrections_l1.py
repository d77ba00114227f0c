"""Issue 27: the first Lyapunov coefficient l1, kappa_c and omega_c with the
corrections of seed section II.D.2 in the friction law (docs/model.md's
variables, D0 = V0 = 1):

    mu(v, theta) = mu0 + A ln v + B ln theta + mu2 (ln theta)^2
                   + mu_vv (ln v)^2 + mu_vphi (ln theta)(ln v)

by the same independent route as t3_lyap.py and slip_law_l1.py: sympy's
exact derivatives of the field at the Hopf point, Kuznetsov's formula for l1
evaluated with mpmath at 50 digits.

- The slopes mu_v = v d mu/dv and mu_phi = theta d mu/dtheta at steady
  sliding (v = nu, theta = 1/nu) are sympy's derivatives of mu, not the
  closed forms A + (2 mu_vv - mu_vphi) ln nu, B + (mu_vphi - 2 mu2) ln nu;
  kappa_c and omega_c are Appendix C's C11/C13 with them, and t3_lyap.lyap
  checks that +-i omega_c are eigenvalues of the Jacobian there (to 1e-30).
- Quasi-statically v is slaved by s = mu(v, theta): with L = ln v,
  mu_vv L^2 + (A + mu_vphi ln theta) L = s - mu0 - B ln theta - mu2 (ln theta)^2,
  and the branch with d mu/d ln v > 0 is L = (-b + sqrt(b^2 + 4 a c)) / (2 a)
  (a = mu_vv, b = A + mu_vphi ln theta), written here in that plain form
  (L = c / b for mu_vv = 0).

Run: python3 mu_corrections_l1.py > mu_corrections_l1_out.txt
"""
import sympy as sp
import mpmath as mp

from t3_lyap import N, lyap, R, s, v, th


def friction(P):
    """mu(v, theta) with both corrections (module docs)."""
    lv, lt = sp.log(v), sp.log(th)
    return (P['mu0'] + P['A'] * lv + P['B'] * lt + P['mu2'] * lt**2
            + P['mu_vv'] * lv**2 + P['mu_vphi'] * lt * lv)


def slaved_velocity(P):
    """The quasi-static v(s, theta): the rising root in ln v (module docs)."""
    lt = sp.log(th)
    a = P['mu_vv']
    b = P['A'] + P['mu_vphi'] * lt
    c = s - P['mu0'] - P['B'] * lt - P['mu2'] * lt**2
    L = c / b if a == 0 else (-b + sp.sqrt(b**2 + 4 * a * c)) / (2 * a)
    return sp.exp(L)


def setup(P, inertial):
    """(F, X, x0, kappa_c, omega_c, mu_v, mu_phi) at kappa = kappa_c, exact."""
    P = {k: sp.nsimplify(val) for k, val in P.items()}
    nu, m = P['nu'], P.get('m', 0)
    mu = friction(P)
    at = {v: nu, th: 1 / nu}
    mu_v = sp.simplify((v * sp.diff(mu, v)).subs(at))
    mu_phi = sp.simplify((th * sp.diff(mu, th)).subs(at))
    kc = (mu_phi - mu_v) * (1 + m * nu**2 / mu_v)
    wc = nu * sp.sqrt(mu_phi / mu_v - 1)
    s0 = mu.subs(at)
    if inertial:
        F = sp.Matrix([kc * (nu - v), (s - mu) / m, 1 - v * th])
        X = [s, v, th]
        x0 = {s: s0, v: nu, th: 1 / nu}
    else:
        vq = slaved_velocity(P)
        assert abs(N(vq.subs({s: s0, th: 1 / nu}) - nu)) < mp.mpf(10)**-45, "steady sliding"
        F = sp.Matrix([kc * (nu - vq), 1 - vq * th])
        X = [s, th]
        x0 = {s: s0, th: 1 / nu}
    return F, X, x0, kc, wc, mu_v, mu_phi


base = dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'))
cases = [
    ('QS ln2 mu_vv=1e-3 mu_vphi=-5e-4 nu=3',
     dict(base, mu2=R('2.4e-4'), mu_vv=R('1e-3'), mu_vphi=R('-5e-4'), nu=3), False),
    ('QS RR mu_vv=-1e-3 nu=1',
     dict(base, mu2=0, mu_vv=R('-1e-3'), mu_vphi=0, nu=1), False),
    ('QS RR mu_vv=5e-4 mu_vphi=1e-3 nu=0.2',
     dict(base, mu2=0, mu_vv=R('5e-4'), mu_vphi=R('1e-3'), nu=R('0.2')), False),
    ('IN ln2 mu_vv=2e-4 mu_vphi=3e-4 m=0.1 nu=3',
     dict(A=R('0.01'), B=R('0.02'), mu0=R('0.6'), mu2=R('5e-4'), mu_vv=R('2e-4'),
          mu_vphi=R('3e-4'), m=R('0.1'), nu=3), True),
]

if __name__ == '__main__':
    mp.mp.dps = 50
    for name, P, inertial in cases:
        F, X, x0, kc, wc, mu_v, mu_phi = setup(P, inertial)
        l1, c1, *_ = lyap(F, X, x0, wc)
        print(name)
        print("  mu_v    =", mp.nstr(N(mu_v), 30))
        print("  mu_phi  =", mp.nstr(N(mu_phi), 30))
        print("  kappa_c =", mp.nstr(N(kc), 30))
        print("  omega_c =", mp.nstr(N(wc), 30))
        print("  l1      =", mp.nstr(l1, 30))
