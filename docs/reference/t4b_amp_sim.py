"""Task 4 numerical check: direct simulation of the quasi-static ln2 law (case (a), nu=1) below kappa_c,
peak-to-peak of s on the attracting cycle vs 4 sqrt(mu_phi (mu_phi-A)(kappa_c-kappa)/mu2)."""
import numpy as np
from scipy.integrate import solve_ivp

A, B, mu0, mu2, nu = 0.012, 0.023, 0.6, 2.4e-4, 1.0
muphi = B - 2*mu2*np.log(nu)
kc = muphi - A
s0 = mu0 + A*np.log(nu) + B*np.log(1/nu) + mu2*np.log(1/nu)**2
C = 4*np.sqrt(muphi*(muphi - A)/mu2)


def f(t, y, kap):
    ds, th = y  # ds = s - s0
    lt = np.log(th)
    v = np.exp((s0 + ds - mu0 - B*lt - mu2*lt**2)/A)
    return [kap*(nu - v), 1 - v*th]


print("kappa_c =", kc, " C =", C)
for eps in [1e-1, 3e-2, 1e-2, 3e-3, 1e-3]:
    kap = kc*(1 - eps)
    pred = C*np.sqrt(kc - kap)
    # start on s-axis displaced by predicted half amplitude
    y = [pred/2, 1/nu]
    lam = nu*(kc - kap)/(2*A)            # growth rate; settle ~ 30/ (2 lam)
    w = nu*np.sqrt(muphi/A - 1)
    Tsettle = max(15/(2*lam), 200*2*np.pi/w)
    sol = solve_ivp(f, (0, Tsettle), y, args=(kap,), method='DOP853', rtol=1e-11, atol=1e-14)
    y = sol.y[:, -1]
    sol = solve_ivp(f, (0, 20*2*np.pi/w), y, args=(kap,), method='DOP853', rtol=1e-11, atol=1e-14, max_step=2*np.pi/w/400)
    S = sol.y[0]
    dpp = S.max() - S.min()
    print("eps=%.0e kappa=%.10g  Delta_s(sim)=%.8g  pred=%.8g  ratio=%.6f" % (eps, kap, dpp, pred, dpp/pred))
