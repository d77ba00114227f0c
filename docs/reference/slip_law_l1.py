"""Issue 27: the first Lyapunov coefficient l1 under Ruina's slip law,
theta' = -v theta ln(v theta) (docs/model.md's variables, D0 = V0 = 1), next to
the ageing law theta' = 1 - v theta, by the same independent route as
t3_lyap.py: sympy's exact derivatives of the field at the Hopf point,
Kuznetsov's formula for l1 evaluated with mpmath at 40 digits.

Both laws have the steady state v theta = 1 and the same linearization there
(d/dv and d/dtheta of -v theta ln(v theta) are -theta and -v at v theta = 1,
as for 1 - v theta), hence the same kappa_c and omega_c (eq. C11); their
second and third derivatives differ, hence l1.

Run: python3 slip_law_l1.py > slip_law_l1_out.txt
"""
import sympy as sp
import mpmath as mp

from t3_lyap import N, lyap, setup, R, v, th


def with_state_law(F, X, state_law):
    """The field F of t3_lyap.setup with its age equation replaced by the slip law."""
    if state_law == 'ageing':
        return F
    G = sp.Matrix(F)
    vq = v
    if X == [sp.Symbol('s'), th]:
        # quasi-static: v is slaved, read it from the ageing row 1 - v theta
        vq = (1 - F[1]) / th
    G[len(X) - 1] = -vq * th * sp.log(vq * th)
    return G


cases = [
    ('QS ln2 nu=1', 'ln2', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=R('2.4e-4'), nu=1), False),
    ('QS RR nu=1', 'ln2', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=0, nu=1), False),
    ('QS RR nu=3', 'ln2', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=0, nu=3), False),
    ('IN RR m=0.1 nu=1', 'ln2', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=0, m=R('0.1'), nu=1), True),
    ('IN ln2 m=0.1 nu=3', 'ln2', dict(A=R('0.01'), B=R('0.02'), mu0=R('0.6'), mu2=R('5e-4'), m=R('0.1'), nu=3), True),
    ('IN cutoff thc=0.01 m=1e-3 nu=50', 'cutoff', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), thc=R('0.01'), m=R('1e-3'), nu=50), True),
]

if __name__ == '__main__':
    mp.mp.dps = 40
    for name, law, P, inertial in cases:
        F, X, x0, kc, wc, _ = setup(law, P, inertial)
        print(name)
        print("  kappa_c =", mp.nstr(N(kc), 25))
        print("  omega_c =", mp.nstr(N(wc), 25))
        for state_law in ['ageing', 'slip']:
            G = with_state_law(F, X, state_law)
            l1, c1, *_ = lyap(G, X, x0, wc)
            print("  %-6s l1 = %s" % (state_law, mp.nstr(l1, 30)))
