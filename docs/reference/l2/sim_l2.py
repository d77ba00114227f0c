"""Independent check of l2 by direct integration at the Bautin point (m = m*, kappa = kappa_c(m*)).
Section Im<p, x - x0> = 0, Re<p, x - x0> > 0;  rho = |<p, x - x0>| (Kuznetsov-normalised p, q from kuz_l2.py).
Return map at l1 = 0:  rho -> rho + 2 pi l2 rho^5 + O(rho^6)   (coordinate-invariant leading term).
Fit f(rho) = (rho_{k+1} - rho_k)/(2 pi rho_k^5) = l2 + a rho + b rho^2 + c rho^3 and extrapolate to rho -> 0."""
import sys
import numpy as np
import mpmath as mp
from scipy.integrate import solve_ivp
from kuz_l2 import l2_kuznetsov

mp.mp.dps = 40
A, B = 0.012, 0.023


def run(nu, mstr, rhos, turns=4, rtol=1e-13):
    # eigenvectors from an independent recomputation (same formulas as kuz_l2) -- reuse its p
    import kuz_l2 as K
    import sympy as sp
    m = float(mp.mpf(mstr)); nu_f = float(nu)
    r = l2_kuznetsov(nu, mstr)
    kc = float(sp.N(r['kc'], 30)); w = float(r['w'])
    # p (left eigenvector) recomputed in double from the Jacobian
    J = np.array([[0, -kc, 0], [1/m, -A/(m*nu_f), -B*nu_f/m], [0, -1/nu_f, -nu_f]])
    ev, V = np.linalg.eig(J)
    i = np.argmin(abs(ev - 1j*w)); q = V[:, i]; q = q/np.linalg.norm(q)
    evl, W = np.linalg.eig(J.T)
    i = np.argmin(abs(evl + 1j*w)); p = W[:, i]; p = p/np.conj(np.vdot(p, q))
    x0 = np.array([0.6 + (A - B)*np.log(nu_f), nu_f, 1/nu_f])

    def f(t, y):
        s, v, th = y + x0
        return [kc*(nu_f - v), (s - 0.6 - A*np.log(v) - B*np.log(th))/m, 1 - v*th]
    zof = lambda y: np.vdot(p, y)
    ev_ = lambda t, y: np.imag(zof(y))
    ev_.direction = 1.0
    T = 2*np.pi/w
    res = []
    for rho in rhos:
        y = 2*np.real(rho*q)
        sol = solve_ivp(f, (0, (turns + 1.5)*T), y, method='DOP853', rtol=rtol, atol=1e-20, events=ev_,
                        max_step=T/200)
        zs = [zof(yy) for yy in sol.y_events[0]]
        zs = [z for z in zs if z.real > 0]
        rr = [abs(z) for z in zs][1:]  # drop first (transient off the centre manifold)
        for k in range(len(rr) - 1):
            res.append((rr[k], (rr[k+1] - rr[k])/(2*np.pi*rr[k]**5)))
    return r, np.array(res)


if __name__ == '__main__':
    for nu, mstr, rhos in [(1, '0.0016140505108687765218922615553', np.linspace(0.02, 0.16, 8)),
                           (3, '0.000179338945652086280210251283922', np.linspace(0.02, 0.16, 8)),
                           (3, '0.000179338945652086280210251283922', np.linspace(0.05, 0.5, 10))]:
        r, data = run(nu, mstr, rhos, rtol=2.5e-14)
        l2 = float(r['l2'])
        print("nu=%d  rho in [%.3g, %.3g]  l2(formula) = %.15g" % (nu, rhos[0], rhos[-1], l2))
        for rho, g in data[::3]:
            print("   rho=%.5f  drho/(2 pi rho^5) = %.10g" % (rho, g))
        for deg in (2, 3, 4, 5):
            cf = np.polyfit(data[:, 0], data[:, 1], deg)
            print("   poly deg %d extrapolation: l2(sim) = %.10g   rel.diff = %.2e" % (deg, cf[-1], (cf[-1] - l2)/l2))
        sys.stdout.flush()
