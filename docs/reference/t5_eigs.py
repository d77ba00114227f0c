"""Task 5: eigenvalues of the inertial Jacobian (plain RR, A=0.012, B=0.023, nu=1, m=0.01) at kappa=0.02 and 1e4,
two independent ways (mpmath eig of the matrix, polyroots of the cubic), plus asymptotic check (task 2)
and Bautin point (l1 = 0) in m for case (d)."""
import mpmath as mp
mp.mp.dps = 50
A, B, nu, m = mp.mpf('0.012'), mp.mpf('0.023'), mp.mpf(1), mp.mpf('0.01')
muv, muphi = A, B
for kap in [mp.mpf('0.02'), mp.mpf('1e4')]:
    J = mp.matrix([[0, -kap, 0], [1/m, -muv/(m*nu), -muphi*nu/m], [0, -1/nu, -nu]])
    e1 = sorted(mp.eig(J)[0], key=lambda z: (mp.im(z), mp.re(z)))
    e2 = sorted(mp.polyroots([m, muv/nu + m*nu, kap + muv - muphi, kap*nu], maxsteps=200, extraprec=200),
                key=lambda z: (mp.im(z), mp.re(z)))
    print("kappa =", kap)
    for a, b in zip(e1, e2):
        print("   eig:", mp.nstr(a, 20), "   polyroot:", mp.nstr(b, 20), "   |diff| =", mp.nstr(abs(a - b), 3))
    if kap > 1:
        real = -nu - muphi*nu/kap + muphi*nu*(m*nu**2 - muphi - muv)/kap**2
        d0 = -muv/(2*m*nu)
        d1 = -(4*m*muphi*nu**2 + muv**2)/(8*m**mp.mpf(1.5)*nu**2)  # times i
        d2 = muphi*nu/2
        pair = mp.mpc(d0 + d2/kap, mp.sqrt(kap/m) + d1/mp.sqrt(kap))
        print("   asymptotic real root  (-nu - mu_phi nu/k + mu_phi nu (m nu^2-mu_phi-mu_v)/k^2):", mp.nstr(real, 20))
        print("   asymptotic upper root (through 1/kappa):", mp.nstr(pair, 20))
        print("   leading-order only: real -nu, pair", mp.nstr(mp.mpc(d0, mp.sqrt(kap/m)), 20))

# Bautin point for case (d): l1(m) = 0
import sympy as sp
from t3_lyap import setup, lyap
mp.mp.dps = 40


def l1_of_m(mm):
    mm_r = sp.Rational(mp.nstr(mm, 35))
    F, X, x0, kc, wc, mphi = setup('ln2', dict(A=sp.Rational('0.012'), B=sp.Rational('0.023'), mu0=sp.Rational('0.6'),
                                               mu2=0, m=mm_r, nu=1), True)
    return lyap(F, X, x0, wc)[0]


mstar = mp.findroot(l1_of_m, (mp.mpf('1e-3'), mp.mpf('2e-3')), solver='secant', tol=1e-28)
print("\nBautin point case (d) params (A=0.012,B=0.023,nu=1,mu2=0): l1 = 0 at m* =", mp.nstr(mstar, 20))
