"""Issue 27: the first Lyapunov coefficient l1, kappa_c and omega_c with
radiation damping, the force eta_d v beside friction in the force balance
(docs/model.md's variables, D0 = V0 = 1):

    m v' = s - mu(v, theta) - eta_d v
    mu(v, theta) = mu0 + A ln v + B ln theta + mu2 (ln theta)^2
                   + mu_vv (ln v)^2 + mu_vphi (ln theta)(ln v)

by the same independent route as mu_corrections_l1.py: sympy's exact
derivatives of the field at the Hopf point, Kuznetsov's formula for l1
evaluated with mpmath at 50 digits (t3_lyap.lyap).

- kappa_c and omega_c are Appendix C's C11/C13 with mu_v replaced by the
  slope of the resisting force, mu_v + eta_d nu (sympy's derivatives at
  steady sliding, v = nu, theta = 1/nu); t3_lyap.lyap checks that +-i omega_c
  are eigenvalues of the Jacobian of the damped field there (to 1e-30),
  which checks that replacement independently.
- Quasi-statically v is slaved by s = mu(v, theta) + eta_d v. With mu_vv = 0
  and L = ln v this is b L + eta_d e^L = c (b = A + mu_vphi ln theta,
  c = s - mu0 - B ln theta - mu2 (ln theta)^2), solved by Lambert's W:
  L = c / b - W((eta_d / b) e^(c / b)), not by the Newton iteration of the
  Rust code.

Run: python3 radiation_damping_l1.py > radiation_damping_l1_out.txt
"""
import sympy as sp
import mpmath as mp

from t3_lyap import N, lyap, R, s, v, th
from mu_corrections_l1 import friction


def slaved_velocity(P):
    """The quasi-static v(s, theta) through Lambert's W (module docs)."""
    assert P['mu_vv'] == 0
    lt = sp.log(th)
    b = P['A'] + P['mu_vphi'] * lt
    c = s - P['mu0'] - P['B'] * lt - P['mu2'] * lt**2
    return sp.exp(c / b - sp.LambertW(P['eta_d'] / b * sp.exp(c / b)))


def setup(P, inertial):
    """(F, X, x0, kappa_c, omega_c, mu_v + eta_d nu, mu_phi) at kappa = kappa_c."""
    P = {k: sp.nsimplify(val) for k, val in P.items()}
    nu, m, eta = P['nu'], P.get('m', 0), P['eta_d']
    mu = friction(P)
    at = {v: nu, th: 1 / nu}
    mu_v = sp.simplify((v * sp.diff(mu + eta * v, v)).subs(at))
    mu_phi = sp.simplify((th * sp.diff(mu, th)).subs(at))
    kc = (mu_phi - mu_v) * (1 + m * nu**2 / mu_v)
    wc = nu * sp.sqrt(mu_phi / mu_v - 1)
    s0 = (mu + eta * v).subs(at)
    if inertial:
        F = sp.Matrix([kc * (nu - v), (s - mu - eta * v) / m, 1 - v * th])
        X = [s, v, th]
        x0 = {s: s0, v: nu, th: 1 / nu}
    else:
        vq = slaved_velocity(P)
        assert abs(N(vq.subs({s: s0, th: 1 / nu}) - nu)) < mp.mpf(10)**-45, "steady sliding"
        F = sp.Matrix([kc * (nu - vq), 1 - vq * th])
        X = [s, th]
        x0 = {s: s0, th: 1 / nu}
    return F, X, x0, kc, wc, mu_v, mu_phi


base = dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu_vv=0)
cases = [
    ('QS ln2 eta_d=5e-3 nu=1',
     dict(base, mu2=R('2.4e-4'), mu_vphi=0, eta_d=R('5e-3'), nu=1), False),
    ('QS RR mu_vphi=1e-3 eta_d=2e-2 nu=0.3',
     dict(base, mu2=0, mu_vphi=R('1e-3'), eta_d=R('2e-2'), nu=R('0.3')), False),
    ('QS ln2 eta_d=1e-4 nu=10',
     dict(base, mu2=R('2.4e-4'), mu_vphi=0, eta_d=R('1e-4'), nu=10), False),
    ('IN ln2 mu_vv=2e-4 mu_vphi=3e-4 eta_d=1e-3 m=0.1 nu=3',
     dict(A=R('0.01'), B=R('0.02'), mu0=R('0.6'), mu2=R('5e-4'), mu_vv=R('2e-4'),
          mu_vphi=R('3e-4'), eta_d=R('1e-3'), m=R('0.1'), nu=3), True),
]

if __name__ == '__main__':
    mp.mp.dps = 50
    for name, P, inertial in cases:
        F, X, x0, kc, wc, mu_v, mu_phi = setup(P, inertial)
        l1, c1, *_ = lyap(F, X, x0, wc)
        print(name)
        print("  mu_v+eta_d nu =", mp.nstr(N(mu_v), 30))
        print("  mu_phi  =", mp.nstr(N(mu_phi), 30))
        print("  kappa_c =", mp.nstr(N(kc), 30))
        print("  omega_c =", mp.nstr(N(wc), 30))
        print("  l1      =", mp.nstr(l1, 30))
