"""Issue 27: the plain quasi-static slip law's Hopf point, to higher order.

Quasi-static block (docs/model.md, D0 = V0 = 1), mu = mu0 + A ln v + B ln theta
(mu2 = 0), the velocity slaved, v = exp((s - mu0 - B ln theta)/A):
    s' = kappa (nu - v),   theta' = 1 - v theta          (ageing law)
                           theta' = -v theta ln(v theta)  (Ruina's slip law)
at kappa = kappa_c = B - A. slip_law_l1.py finds l1 = 0 for both laws (to
the working precision). The ageing law's Hopf point is degenerate to every
order (every orbit at kappa_c is periodic; Ranjith & Rice 1999). This script
computes the normal form z' = i w z + c1 z|z|^2 + c2 z|z|^4 + c3 z|z|^6 by
the generic solver of l2/nf.py (exact sympy Taylor coefficients to order 7,
homological equations solved order by order at 50 digits) and prints
l_k = Re c_k / w for both laws.

Run: python3 slip_law_qs_normal_form.py > slip_law_qs_normal_form_out.txt
"""
import sys
import sympy as sp
import mpmath as mp

sys.path.insert(0, 'l2')
from nf import TaylorEval, hopf_vectors, normal_form, jacobian  # noqa: E402

mp.mp.dps = 50
R = sp.Rational
s, th = sp.symbols('s theta')
kap = sp.symbols('kappa', positive=True)
A, B, mu0 = R('0.012'), R('0.023'), R('0.6')


def field(nu, state_law):
    v = sp.exp((s - mu0 - B*sp.log(th))/A)
    age = 1 - v*th if state_law == 'ageing' else -v*th*sp.log(v*th)
    return sp.Matrix([kap*(nu - v), age])


if __name__ == '__main__':
    order = 7
    for nu in [1, 3]:
        nun = mp.mpf(nu)
        x0fun = lambda pv, nun=nun: [mp.mpf(6)/10 + (mp.mpf(12) - 23)/1000*mp.log(nun), 1/nun]
        kc = mp.mpf(23 - 12)/1000
        w = nun*mp.sqrt(mp.mpf(23)/12 - 1)
        print("==== nu =", nu, " kappa_c =", mp.nstr(kc, 20), " omega_c =", mp.nstr(w, 25))
        for law in ['ageing', 'slip']:
            TE = TaylorEval(field(sp.Integer(nu), law), [s, th], [kap], x0fun, maxdeg=order)
            T = TE([kc])
            J = jacobian(T, 2)
            q, p = hopf_vectors(J, w)
            assert mp.norm(J*q - mp.mpc(0, 1)*w*q) < mp.mpf(10)**-40
            g, H, info = normal_form(T, w, q, p, order=order)
            ls = [mp.re(g[(k + 1, k)])/w for k in (1, 2, 3)]
            print("  %-6s l1 = %s" % (law, mp.nstr(ls[0], 12)))
            print("  %-6s l2 = %s" % (law, mp.nstr(ls[1], 30)))
            print("  %-6s l3 = %s" % (law, mp.nstr(ls[2], 30)))
            sys.stdout.flush()
