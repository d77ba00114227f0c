"""Independent check of l1 by direct integration at kappa = kappa_c.
Poincare map on the section Im<p, x-x0> = 0, Re>0 : rho_{n+1} = rho_n + 2 pi l1 rho_n^3 + O(rho^4),
rho = |<p, x-x0>|. Fit (rho_{n+1}-rho_n)/rho_n^3 = 2 pi l1 + a rho + b rho^2 over several rho."""
import numpy as np
import sympy as sp
import mpmath as mp
from scipy.integrate import solve_ivp
from t3_lyap import setup, lyap, cases, N

mp.mp.dps = 40


def run(case, rhos):
    name, law, P, inertial = case
    F, X, x0, kc, wc, mphi = setup(law, P, inertial)
    l1, c1, q, p, J, w = lyap(F, X, x0, wc)
    n = len(X)
    x0n = np.array([float(N(x0[x])) for x in X])
    # vector field in deviation variables, with x0 exact-ish
    Y = sp.symbols('y0:%d' % n)
    Fy = F.subs({X[i]: sp.Float(str(N(x0[X[i]])), 30) + Y[i] for i in range(n)}, simultaneous=True)
    f = sp.lambdify([Y], list(Fy), 'numpy')
    qn = np.array([complex(x) for x in q]); pn = np.array([complex(x) for x in p])
    wn = float(w)
    T = 2*np.pi/wn

    def zof(y):
        return np.vdot(pn, y)  # conj(p).y

    ev = lambda t, y: np.imag(zof(y))
    ev.direction = 1.0  # Im z increasing through 0 with Re z > 0 (rotation counterclockwise? check sign below)
    out = []
    for rho in rhos:
        y = 2*np.real(rho*qn)
        # find rotation direction: Im z increasing when Re z>0 iff omega>0 in z' = i w z
        sol = solve_ivp(lambda t, y: f(y), (0, 6.5*T), y, method='DOP853', rtol=1e-13, atol=1e-18,
                        events=ev, dense_output=False)
        zs = [zof(yy) for yy in sol.y_events[0]]
        zs = [z for z in zs if z.real > 0]
        r = [abs(z) for z in zs]
        # use returns after transient (skip first)
        g = [(r[k+1]-r[k])/r[k]**3 for k in range(1, len(r)-1)]
        out.append((r[1], g[0]))
    return float(l1), out


if __name__ == '__main__':
    sel = {'(a) QS ln2 nu=1': [0.1, 0.07, 0.05, 0.035, 0.025],
           '(b) QS RR nu=1': [0.4, 0.2, 0.1],
           '(c) IN ln2 m=0.1 nu=3': [0.1, 0.07, 0.05, 0.035, 0.025],
           '(d) IN RR m=0.001 nu=1': [0.2, 0.14, 0.1, 0.07, 0.05],
           '(d) IN RR m=0.01 nu=1': [0.2, 0.14, 0.1, 0.07, 0.05],
           '(d) IN RR m=1 nu=1': [0.02, 0.014, 0.01, 0.007],
           '(d) IN RR m=0.1 nu=1': [0.05, 0.035, 0.025, 0.018],
           '(e) IN cutoff thc=0.01 m=1e-3 nu=50': [0.4, 0.3, 0.2, 0.14, 0.1],
           }
    for case in cases:
        if case[0] not in sel:
            continue
        l1, out = run(case, sel[case[0]])
        rs = np.array([o[0] for o in out]); gs = np.array([o[1] for o in out])
        print(case[0], " l1(formula) =", l1)
        for r_, g_ in zip(rs, gs):
            print("   rho=%.4g  g/(2pi)=%.10g" % (r_, g_/(2*np.pi)))
        if len(rs) >= 3:
            cf = np.polyfit(rs, gs/(2*np.pi), 2)
            print("   quadratic extrapolation rho->0: l1(sim) = %.8g   rel.diff = %.2e" % (cf[-1], (cf[-1]-l1)/l1 if l1 != 0 else cf[-1]))
