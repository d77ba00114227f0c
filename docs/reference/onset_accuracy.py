"""Reference stick-slip cycles from the Hopf point to half the critical
stiffness, independent of stickslip's code: shooting in deviation variables
with a Taylor-series integrator in mpmath.

For each case and each distance from onset eps = (kappa_c - kappa)/kappa_c in
{1e-5, 1e-4, 1e-3, 1e-2, 0.1, 0.5} it reports the period T, the peak-to-peak
spring force Delta_s = max s - min s (docs/model.md's s = K (V t - x) / W), s_min,
s_max, the slowest and fastest slip velocity v_min, v_max, and the nontrivial
Floquet multipliers, in docs/model.md's variables and units.

Why deviation variables. Near onset the cycle is a small oscillation around
steady sliding (x* = (s*, nu, 1/nu)); at eps = 1e-5 its Delta_s is 1e-3 of
s* ~ mu0, and at fixed stiffness its amplitude is ill-determined (the
nontrivial multiplier is 1 - O(eps)): an error delta per period in the
integration becomes an error delta / (1 - mu) in the amplitude. The
equations are therefore written for

    y = s - s*,   w = ln(v / nu),   phi = ln(theta nu),

all zero at steady sliding, with every difference evaluated in closed form
(no cancellation against mu0):

    dy/dt   = -kappa nu (e^w - 1)
    dw/dt   = (y - A w - G(phi)) / (m nu e^w)              (inertial)
    dphi/dt = nu (e^-phi - e^w)
    w       = (y - G(phi)) / A                             (quasi-static)

with the ageing term's deviation G(phi) = ageing(e^phi / nu) - ageing(1/nu):

    ln2 (plain RR: mu2 = 0):  G = (B - 2 mu2 ln nu) phi + mu2 phi^2
    cutoff:                    G = B ln(1 + (e^phi - 1) / (1 + nu theta_c))

and computed at 40 significant digits, so that even the ill-conditioned
amplitude at eps = 1e-5 keeps 25 digits.

Method. The spring force s is extreme exactly where ds/dt = 0, i.e. w = 0:
its maximum where w crosses 0 upward, its minimum where it crosses downward.
The Poincare section is w = 0 crossed upward: the state there is (y, phi)
for the inertial block (2 unknowns) and phi for the quasi-static one (y =
G(phi), 1 unknown). The return map P is integrated by a Taylor method of
order 40 (coefficients by the recurrences of exp, log and products, local
error below 1e-36 of the orbit's size), the crossing located on the step's
Taylor polynomial by Newton's method; the fixed point P(z) = z is found by
Newton's method with a forward-difference Jacobian (step 1e-20 of the
orbit's size). T is the return time, s_max = s* + y on the section, s_min
the value at the downward crossing, v_min and v_max at the zeros of dw/dt
(located on the Taylor polynomials). The eigenvalues of dP/dz are the
nontrivial Floquet multipliers. Starting guesses: a double-precision run of
the same shooting (continued in eps from a scan of the amplitude along the
linear Hopf mode at eps = 1e-3), then Newton at 40 digits.

Every parameter is taken as the IEEE double stickslip reads (mpf(float)),
kappa_c from the closed form of docs/model.md at those values, and kappa as the
double nearest kappa_c (1 - eps): the CSV gives that double to 17 digits, so
stickslip is run at exactly the stiffness of the reference.

Self-checks (written to onset_accuracy_check.txt by `--check`):
  1. the same shooting at 50 digits, Taylor order 50, local error 1e-46:
     T, Delta_s, v_min, v_max agree with the 40-digit values;
  2. an independent integrator on an independent right-hand side:
     mpmath.odefun (Taylor coefficients from Euler steps in extended
     precision, not from recurrences) integrating the plain equations from
     the reference's section point over the reference period: the orbit
     closes and passes through s_min at the reference time of s_min;
  3. scipy's DOP853 (double precision, rtol 1e-13) with Newton on the same
     section: agreement within the expected double-precision error amplified
     by 1 / (1 - mu).

Run: python3 onset_accuracy.py            (writes onset_accuracy.csv)
     python3 onset_accuracy.py --check    (writes onset_accuracy_check.txt)
"""

import math
import sys
import time

import mpmath as mp

EPS = [1e-5, 1e-4, 1e-3, 1e-2, 0.1, 0.5]

# Parameters as stickslip reads them (`--set` on the built-in pmma scene,
# mu0 = 0.5): plain Rice-Ruina (mu2 = 0), ln2 (mu2 > 0), cutoff (theta_c).
# The plain law has no quasi-static case: its quasi-static Hopf point is
# degenerate (l1 = 0, no branch of cycles born there).
CASES = [
    dict(name="rr-inertial", A=0.01, B=0.015, mu0=0.5, mu2=0.0, theta_c=None, m=2.0, nu=1.0),
    dict(name="rr-inertial-light", A=0.012, B=0.023, mu0=0.5, mu2=0.0, theta_c=None, m=0.01, nu=1.0),
    dict(name="ln2-qs", A=0.012, B=0.023, mu0=0.5, mu2=2.4e-4, theta_c=None, m=0.0, nu=1.0),
    dict(name="ln2-qs-nu3", A=0.012, B=0.023, mu0=0.5, mu2=2.4e-4, theta_c=None, m=0.0, nu=3.0),
    dict(name="ln2-inertial", A=0.012, B=0.023, mu0=0.5, mu2=2.4e-4, theta_c=None, m=0.01, nu=1.0),
    dict(name="ln2-inertial-nu3", A=0.01, B=0.02, mu0=0.5, mu2=5e-4, theta_c=None, m=0.1, nu=3.0),
    dict(name="cutoff-qs", A=0.012, B=0.023, mu0=0.5, mu2=0.0, theta_c=0.5, m=0.0, nu=1.0),
    dict(name="cutoff-inertial", A=0.012, B=0.023, mu0=0.5, mu2=0.0, theta_c=0.5, m=0.5, nu=1.0),
]


class Arith:
    """Scalar arithmetic: Python floats or mpmath at `dps` digits."""

    def __init__(self, dps=None):
        self.mp = dps is not None
        if self.mp:
            mp.mp.dps = dps
            self.exp, self.log, self.num = mp.exp, mp.log, mp.mpf
        else:
            self.exp, self.log, self.num = math.exp, math.log, float


class Block:
    """The driven block of a case at stiffness kappa, in deviation variables."""

    def __init__(self, case, kappa, ar):
        n = ar.num
        self.ar = ar
        self.A, self.B, self.mu2 = n(case["A"]), n(case["B"]), n(case["mu2"])
        self.mu0, self.m, self.nu = n(case["mu0"]), n(case["m"]), n(case["nu"])
        self.cutoff = case["theta_c"] is not None
        self.theta_c = n(case["theta_c"]) if self.cutoff else None
        self.kappa = n(kappa)
        self.inertial = case["m"] > 0
        self.L = ar.log(self.nu)
        if self.cutoff:
            self.c = 1 + self.nu * self.theta_c  # G = B ln((c - 1 + e^phi) / c)
            self.ln_c = ar.log(self.c)
        else:
            self.a1 = self.B - 2 * self.mu2 * self.L  # G = a1 phi + mu2 phi^2
        self.dim = 3 if self.inertial else 2
        # relative perturbations of the right-hand sides (y, phi, w), for the
        # conditioning of Delta_s
        self.pert = [ar.num(1)] * 3

    def s_star(self):
        """Steady-sliding spring force mu(nu, 1/nu)."""
        ar = self.ar
        th = 1 / self.nu
        if self.cutoff:
            age = self.B * ar.log(1 + th / self.theta_c)
        else:
            lt = ar.log(th)
            age = self.B * lt + self.mu2 * lt * lt
        return self.mu0 + self.A * self.L + age

    def G(self, phi):
        if self.cutoff:
            return self.B * (self.ar.log(self.c - 1 + self.ar.exp(phi)) - self.ln_c)
        return self.a1 * phi + self.mu2 * phi * phi

    def G1(self):
        """G'(0) = mu_phi."""
        return self.B / self.c if self.cutoff else self.a1

    # -- plain right-hand side (for the independent integrators) ----------
    def rhs(self, x):
        ar = self.ar
        if self.inertial:
            y, w, phi = x
            ew = ar.exp(w)
            return [
                -self.kappa * self.nu * (ew - 1) * self.pert[0],
                (y - self.A * w - self.G(phi)) / (self.m * self.nu * ew) * self.pert[2],
                self.nu * (ar.exp(-phi) - ew) * self.pert[1],
            ]
        y, phi = x
        ew = ar.exp((y - self.G(phi)) / self.A)
        return [-self.kappa * self.nu * (ew - 1) * self.pert[0], self.nu * (ar.exp(-phi) - ew) * self.pert[1]]

    def w_of(self, x):
        return x[1] if self.inertial else (x[0] - self.G(x[1])) / self.A

    # -- Taylor coefficients -----------------------------------------------
    def series(self, x0, p):
        """Taylor coefficients (order p) of the solution through x0 and of w."""
        ar = self.ar
        zero = ar.num(0)

        def exp_rec(U, E, k, sign=1):
            if k == 0:
                return ar.exp(sign * U[0])
            acc = zero
            for j in range(1, k + 1):
                acc += j * U[j] * E[k - j]
            return sign * acc / k

        def log_rec(H, Lg, k):
            if k == 0:
                return ar.log(H[0])
            acc = zero
            for j in range(1, k):
                acc += j * Lg[j] * H[k - j]
            return (H[k] - acc / k) / H[0]

        def mul(a, b, k):
            acc = zero
            for j in range(k + 1):
                acc += a[j] * b[k - j]
            return acc

        kn = self.kappa * self.nu
        P = [x0[-1]]
        Y = [x0[0]]
        W = [x0[1]] if self.inertial else []
        E, Ei, Q, G, F, H, LH = [], [], [], [], [], [], []
        for k in range(p):
            # ageing deviation G(phi), order k
            if self.cutoff:
                F.append(exp_rec(P, F, k))
                H.append(self.c - 1 + F[0] if k == 0 else F[k])
                LH.append(log_rec(H, LH, k))
                G.append(self.B * (LH[k] - (self.ln_c if k == 0 else 0)))
            else:
                G.append(self.a1 * P[k] + self.mu2 * mul(P, P, k))
            if not self.inertial:
                W.append((Y[k] - G[k]) / self.A)
            E.append(exp_rec(W, E, k))
            Q.append(exp_rec(P, Q, k, -1))
            dy = -kn * (E[k] - (1 if k == 0 else 0)) * self.pert[0]
            dphi = self.nu * (Q[k] - E[k]) * self.pert[1]
            Y.append(dy / (k + 1))
            P.append(dphi / (k + 1))
            if self.inertial:
                Ei.append(exp_rec(W, Ei, k, -1))
                N = [Y[j] - self.A * W[j] - G[j] for j in range(k + 1)]
                W.append(mul(N, Ei, k) / (self.m * self.nu) / (k + 1) * self.pert[2])
        if not self.inertial:
            # w to order p from y and phi to order p
            if self.cutoff:
                F.append(exp_rec(P, F, p))
                H.append(F[p])
                LH.append(log_rec(H, LH, p))
                G.append(self.B * LH[p])
            else:
                G.append(self.a1 * P[p] + self.mu2 * mul(P, P, p))
            W.append((Y[p] - G[p]) / self.A)
        state = [Y, W, P] if self.inertial else [Y, P]
        return state, W


def poly(c, t):
    acc = 0 * t
    for a in reversed(c):
        acc = acc * t + a
    return acc


def dpoly(c):
    return [k * c[k] for k in range(1, len(c))]


def root(c, a, b, ar, tol):
    """A root of polynomial c in [a, b] where it changes sign: bisection
    safeguarding Newton."""
    fa = poly(c, a)
    d = dpoly(c)
    t = (a + b) / 2
    for _ in range(200):
        ft = poly(c, t)
        if ft == 0:
            return t
        if (ft > 0) == (fa > 0):
            a, fa = t, ft
        else:
            b = t
        dt = poly(d, t)
        tn = t - ft / dt if dt != 0 else (a + b) / 2
        if not (a < tn < b):
            tn = (a + b) / 2
        if abs(tn - t) <= tol * (1 + abs(t)):
            return tn
        t = tn
    return t


class Settings:
    def __init__(self, dps, order, tol):
        self.ar = Arith(dps)
        self.order, self.tol = order, tol
        self.root_tol = 10.0 ** (-dps + 2) if dps else 1e-16
        self.newton_tol = 10.0 ** (-(dps - 12)) if dps else 1e-12


def return_map(block, z, st, scale):
    """Integrates from the section point z (w = 0 crossing upward) to the next
    upward crossing. Returns (z', T, extremes) with extremes = (y_min, w_min,
    w_max, t_ymin)."""
    ar = block.ar
    if block.inertial:
        x = [z[0], ar.num(0), z[1]]
    else:
        x = [block.G(z[0]), z[0]]
    t = ar.num(0)
    p = st.order
    armed = False  # a downward crossing (s_min) has been passed
    y_min = t_ymin = None
    w_lo, w_hi = ar.num(0), ar.num(0)
    steps = 0
    while True:
        state, W = block.series(x, p)
        h = None
        for c, sc in zip(state, scale):
            for k in (p - 1, p):
                a = abs(c[k])
                if a > 0:
                    hk = (st.tol * sc / a) ** (ar.num(1) / k)
                    h = hk if h is None else min(h, hk)
        h = 0.5 * h
        steps += 1
        if steps > 200000:
            raise RuntimeError("too many steps")
        # events inside [0, h]: sample the polynomial of w and of dw/dt
        nsub = 8
        taus = [h * j / nsub for j in range(nsub + 1)]
        wv = [poly(W, s) for s in taus]
        dW = dpoly(W)
        dv = [poly(dW, s) for s in taus]
        for j in range(nsub):
            a, b = taus[j], taus[j + 1]
            if (dv[j] > 0) != (dv[j + 1] > 0) and dv[j] != 0:
                r = root(dW, a, b, ar, st.root_tol)
                wr = poly(W, r)
                w_lo, w_hi = min(w_lo, wr), max(w_hi, wr)
            if wv[j] > 0 and wv[j + 1] <= 0:
                r = root(W, a, b, ar, st.root_tol)
                y_min, t_ymin = poly(state[0], r), t + r
                armed = True
            if armed and wv[j] <= 0 and wv[j + 1] > 0:
                r = root(W, a, b, ar, st.root_tol)
                xr = [poly(c, r) for c in state]
                zr = [xr[0], xr[2]] if block.inertial else [xr[1]]
                return zr, t + r, (y_min, w_lo, w_hi, t_ymin)
        x = [poly(c, h) for c in state]
        t = t + h


def solve_lin(J, r, ar):
    n = len(r)
    if ar.mp:
        return list(mp.lu_solve(mp.matrix(J), mp.matrix(r)))
    # Gaussian elimination with partial pivoting (n <= 2)
    A = [row[:] + [r[i]] for i, row in enumerate(J)]
    for i in range(n):
        piv = max(range(i, n), key=lambda k: abs(A[k][i]))
        A[i], A[piv] = A[piv], A[i]
        for k in range(i + 1, n):
            f = A[k][i] / A[i][i]
            for j in range(i, n + 1):
                A[k][j] -= f * A[i][j]
    xs = [0.0] * n
    for i in reversed(range(n)):
        xs[i] = (A[i][n] - sum(A[i][j] * xs[j] for j in range(i + 1, n))) / A[i][i]
    return xs


def shoot(block, z, st, scale, fd_step, max_iter=30, iterations=None):
    """Newton on P(z) - z (until converged, or exactly `iterations` steps).
    Returns (z, T, extremes, dP/dz)."""
    ar = block.ar
    n = len(z)
    zsc = [scale[0], scale[-1]] if block.inertial else [scale[-1]]
    last = None
    for it in range(max_iter):
        pz, T, ext = return_map(block, z, st, scale)
        F = [pz[i] - z[i] for i in range(n)]
        J = []
        cols = []
        for i in range(n):
            dz = list(z)
            d = fd_step * zsc[i]
            dz[i] += d
            pd, _, _ = return_map(block, dz, st, scale)
            cols.append([(pd[k] - pz[k]) / d for k in range(n)])
        J = [[cols[j][i] - (1 if i == j else 0) for j in range(n)] for i in range(n)]
        dzs = solve_lin(J, [-f for f in F], ar)
        size = max(abs(dzs[i]) / zsc[i] for i in range(n))
        z = [z[i] + dzs[i] for i in range(n)]
        # at 40 digits the amplitude near onset keeps about 30 (conditioning 1/(1 - mu))
        converged = size < st.newton_tol or (iterations is not None and it + 1 == iterations)
        # double precision: stop when the step no longer shrinks
        if converged or (not ar.mp and last is not None and size > 0.5 * last and size < 1e-6):
            pz, T, ext = return_map(block, z, st, scale)
            M = [[cols[j][i] for j in range(n)] for i in range(n)]
            return z, T, ext, M
        last = size
    raise RuntimeError("Newton did not converge")


def kappa_c(case, ar):
    """kappa_c = (mu_phi - mu_v)(1 + m nu^2 / mu_v) (docs/model.md)."""
    n = ar.num
    A, B, mu2, m, nu = n(case["A"]), n(case["B"]), n(case["mu2"]), n(case["m"]), n(case["nu"])
    if case["theta_c"] is not None:
        mu_phi = B / (1 + nu * n(case["theta_c"]))
    else:
        mu_phi = B - 2 * mu2 * ar.log(nu)
    return (mu_phi - A) * (1 + m * nu * nu / A)


def linear_mode(block):
    """Section direction of the linear Hopf mode: the deviation (y, phi) [or
    phi] where the mode's w crosses 0 upward, unit-less."""
    b = block
    A, nu, kn, G1 = b.A, b.nu, b.kappa * b.nu, b.G1()
    if b.inertial:
        m = b.m
        J = mp.matrix([[0, -kn, 0], [1 / (m * nu), -A / (m * nu), -G1 / (m * nu)], [0, -nu, -nu]])
    else:
        J = mp.matrix([[-kn / A, kn * G1 / A], [-nu / A, -nu + nu * G1 / A]])
    ev, er = mp.eig(J)
    i = max(range(len(ev)), key=lambda k: mp.im(ev[k]))
    q = [er[r, i] for r in range(len(ev))]
    # w component of the mode
    qw = q[1] if b.inertial else (q[0] - G1 * q[1]) / A
    # x(t) = Re(q e^{i omega t}); w = |qw| cos(omega t + arg qw) crosses 0
    # upward at omega t + arg qw = -pi/2.
    ph = mp.expj(-mp.pi / 2 - mp.arg(qw))
    x = [mp.re(c * ph) for c in q]
    d = [x[0], x[2]] if b.inertial else [x[1]]
    nrm = max(abs(v) for v in d)
    return [float(v / nrm) for v in d]


def scan_start(case, kappa, st):
    """A first section point at eps = 1e-3: the amplitude along the linear
    mode where the return map stops growing it (double precision)."""
    block = Block(case, kappa, st.ar)
    d = linear_mode(block)
    scale = [1.0] * block.dim

    def growth(a):
        # the first return lands on the slow manifold (the third multiplier
        # of the inertial block is small), the second tells growth or decay
        z1, _, _ = return_map(block, [a * v for v in d], st, scale)
        z2, _, _ = return_map(block, z1, st, scale)
        return abs(z2[0]) - abs(z1[0])

    a = 1e-5
    g0 = growth(a)
    while True:
        a2 = 2 * a
        g1 = growth(a2)
        if (g1 > 0) != (g0 > 0):
            break
        a, g0 = a2, g1
        if a > 10:
            raise RuntimeError("no sign change in the amplitude scan")
    lo, hi = a, a2
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if (growth(mid) > 0) == (g0 > 0):
            lo = mid
        else:
            hi = mid
    z, _, _ = return_map(block, [0.5 * (lo + hi) * v for v in d], st, scale)
    return z


def orbit_scale(block, z):
    """Component sizes of the orbit through section point z (for tolerances)."""
    if block.inertial:
        s = max(abs(z[0]), abs(z[1]), 1e-300)
        return [abs(z[0]) or s, s, abs(z[1]) or s]
    y = block.G(z[0])
    s = max(abs(y), abs(z[0]), 1e-300)
    return [abs(y) or s, abs(z[0]) or s]


def solve_case(case, eps_list, dps=40, order=40, tol_exp=36, verbose=False, with_cond=True):
    """Reference values of one case at each eps in eps_list (ascending)."""
    dbl = Settings(None, 20, 1e-15)
    hi = Settings(dps, order, mp.mpf(10) ** (-tol_exp))
    kc_mp = kappa_c(case, Arith(60))

    def kappa_of(e):
        mp.mp.dps = 60
        return float(kc_mp * (1 - mp.mpf(e)))

    # Double precision from the amplitude scan at eps = 1e-3 up to the
    # largest eps, through intermediate values (guesses extrapolated
    # linearly in eps); below 1e-3 the amplitude is too ill-conditioned for
    # double precision (1 - mu ~ 1e-7 at eps = 1e-5), and the guesses are
    # the 40-digit orbit at the next larger eps scaled by sqrt(eps ratio).
    start = 1e-3
    guesses = {}
    z = scan_start(case, kappa_of(start), dbl)
    targets = sorted(e for e in eps_list if e >= start)
    path = [start]
    while targets and path[-1] < targets[-1]:
        e = min(path[-1] * 1.5, targets[-1])
        nxt = [t for t in targets if path[-1] < t <= e]
        path.append(nxt[0] if nxt else e)
    history = []
    for e in path:
        block = Block(case, kappa_of(e), dbl.ar)
        if len(history) >= 2:
            (e0, z0), (e1, z1) = history[-2], history[-1]
            z = [b + (b - a) * (e - e1) / (e1 - e0) for a, b in zip(z0, z1)]
        z, _, _, _ = shoot(block, z, dbl, orbit_scale(block, z), 1e-7)
        history.append((e, z))
        guesses[e] = z
    rows = {}
    previous = None
    for e in sorted(eps_list, reverse=True):
        kappa = kappa_of(e)
        t0 = time.time()
        mp.mp.dps = dps
        block = Block(case, kappa, hi.ar)
        if e in guesses:
            z = [mp.mpf(v) for v in guesses[e]]
        else:
            e1, z1 = previous or (mp.mpf(start), [mp.mpf(v) for v in guesses[start]])
            z = [v * mp.sqrt(mp.mpf(e) / e1) for v in z1]
        sc = orbit_scale(block, z)
        z, T, (y_min, w_lo, w_hi, t_ymin), M = shoot(block, z, hi, sc, mp.mpf(10) ** (-(dps // 2)))
        if max(abs(a) / s for a, s in zip(z, [sc[0], sc[-1]])) < 0.1:
            raise RuntimeError(f"eps = {e}: Newton collapsed onto steady sliding")
        previous = (mp.mpf(e), z)
        s_star = block.s_star()
        y_max = z[0] if block.inertial else block.G(z[0])
        # Conditioning: a relative error delta in the right-hand side of one
        # equation changes Delta_s by cond * delta (relative), the largest over
        # the equations (one Newton iteration from the orbit is exact to
        # O(delta^2)).
        cond = mp.mpf(0)
        if with_cond:
            delta = mp.mpf(10) ** -15
            for j in range(3 if block.inertial else 2):
                block.pert = [mp.mpf(1)] * 3
                block.pert[j] += delta
                zj, _, (yj_min, _, _, _), _ = shoot(
                    block, list(z), hi, sc, mp.mpf(10) ** (-(dps // 2)), iterations=1
                )
                yj_max = zj[0] if block.inertial else block.G(zj[0])
                cond = max(cond, abs(((yj_max - yj_min) / (y_max - y_min) - 1) / delta))
            block.pert = [mp.mpf(1)] * 3
        mults = mp.eig(mp.matrix(M))[0] if len(M) > 1 else [M[0][0]]
        mults = sorted(mults, key=lambda v: -abs(v))
        rows[e] = dict(
            case=case["name"],
            eps=e,
            kappa=kappa,
            kappa_c=kc_mp,
            period=T,
            delta_s=y_max - y_min,
            s_min=s_star + y_min,
            s_max=s_star + y_max,
            v_min=block.nu * mp.exp(w_lo),
            v_max=block.nu * mp.exp(w_hi),
            multipliers=mults,
            section=z,
            t_smin=t_ymin,
            cond=cond,
            seconds=time.time() - t0,
        )
        if verbose:
            print(
                f"  {case['name']} eps={e:g}: T={mp.nstr(T, 20)} Delta_s={mp.nstr(y_max - y_min, 20)}"
                f" ({time.time() - t0:.1f} s)",
                flush=True,
            )
    return [rows[e] for e in eps_list]


def fmt(v, digits=20):
    return mp.nstr(mp.mpf(v), digits, min_fixed=0, max_fixed=0)


COLUMNS = [
    "case", "A", "B", "mu0", "mu2", "theta_c", "m", "nu", "kappa_c", "eps", "kappa",
    "period", "delta_s", "s_min", "s_max", "v_min", "v_max", "multiplier_1", "multiplier_2",
    "delta_s_condition",
]


def csv_row(case, r):
    mults = list(r["multipliers"]) + [None] * (2 - len(r["multipliers"]))
    cells = [
        case["name"], repr(case["A"]), repr(case["B"]), repr(case["mu0"]), repr(case["mu2"]),
        "" if case["theta_c"] is None else repr(case["theta_c"]), repr(case["m"]), repr(case["nu"]),
        fmt(r["kappa_c"]), repr(r["eps"]), repr(r["kappa"]),
        fmt(r["period"]), fmt(r["delta_s"]), fmt(r["s_min"]), fmt(r["s_max"]),
        fmt(r["v_min"]), fmt(r["v_max"]),
    ]
    for mu in mults:
        if mu is None:
            cells.append("")
        elif abs(mp.im(mu)) > 1e-30 * abs(mu):
            cells.append(f"{fmt(mp.re(mu), 12)}{'+' if mp.im(mu) >= 0 else '-'}{fmt(abs(mp.im(mu)), 12)}i")
        else:
            cells.append(fmt(mp.re(mu), 12))
    cells.append(mp.nstr(r["cond"], 3))
    return ",".join(cells)


def read_csv(path):
    """The reference table as dicts of strings, keyed by (case, eps)."""
    import csv

    with open(path) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        return {(r["case"], float(r["eps"])): r for r in rows}


def dop853_shoot(case, kappa, z0, t_guess):
    """Double-precision shooting with scipy's DOP853 (rtol 1e-13) in the
    same deviation variables, on the plain right-hand side (atol 1e-18): (T, Delta_s)."""
    import numpy as np
    from scipy.integrate import solve_ivp

    block = Block(case, kappa, Arith(None))

    def start(z):
        return [z[0], 0.0, z[1]] if block.inertial else [block.G(z[0]), z[0]]

    def section(x):
        return [x[0], x[2]] if block.inertial else [x[1]]

    def w(t, x):
        return block.w_of(x)

    def run(z):
        up = lambda t, x: w(t, x)  # noqa: E731
        up.direction = 1
        down = lambda t, x: w(t, x)  # noqa: E731
        down.direction = -1
        sol = solve_ivp(
            lambda t, x: block.rhs(list(x)), (0, 2.5 * t_guess), start(z), method="DOP853",
            rtol=1e-13, atol=1e-18, events=(up, down),
        )
        t_down = sol.t_events[1][0]
        ups = [i for i, t in enumerate(sol.t_events[0]) if t > t_down]
        i = ups[0]
        return section(sol.y_events[0][i]), sol.t_events[0][i], sol.y_events[1][0][0]

    z = [float(v) for v in z0]
    for _ in range(8):
        pz, T, _ = run(z)
        F = np.array(pz) - np.array(z)
        n = len(z)
        J = np.zeros((n, n))
        for j in range(n):
            h = 1e-6 * abs(z[j])
            zp, zm = list(z), list(z)
            zp[j] += h
            zm[j] -= h
            J[:, j] = (np.array(run(zp)[0]) - np.array(run(zm)[0])) / (2 * h)
        dz = np.linalg.solve(J - np.eye(n), -F)
        z = list(np.array(z) + dz)
        if max(abs(dz / np.array(z))) < 1e-13:
            break
    pz, T, y_min = run(z)
    y_max = z[0] if block.inertial else block.G(z[0])
    return T, y_max - y_min


def check(out="onset_accuracy_check.txt"):
    """The self-checks of the module docstring against onset_accuracy.csv."""
    table = read_csv("onset_accuracy.csv")
    lines = [
        "Self-checks of onset_accuracy.csv (python3 onset_accuracy.py --check).",
        "1: the same shooting at 50 digits, Taylor order 50, local error 1e-46: largest relative",
        "   difference of T, Delta_s, v_min, v_max (s_min, s_max relative to Delta_s) over eps.",
        "2: mpmath.odefun (Taylor coefficients from Euler steps, 30 digits, tol 1e-25) on the plain",
        "   right-hand side from the 50-digit section point over the 50-digit period: the orbit's",
        "   closure |x(T) - x(0)| relative to its size, and |y(t_smin) - y_min| / Delta_s.",
        "3: scipy DOP853 (double precision, rtol 1e-13) shooting on the same section: relative",
        "   difference of T and Delta_s (double-precision rounding amplified by 1/(1 - mu)).",
        "",
    ]
    for case in CASES:
        t0 = time.time()
        rows = solve_case(case, EPS, dps=50, order=50, tol_exp=46, with_cond=False)
        worst = mp.mpf(0)
        for r in rows:
            ref = table[(case["name"], r["eps"])]
            assert float(ref["kappa"]) == r["kappa"]
            ds = mp.mpf(ref["delta_s"])
            for key in ("period", "delta_s", "v_min", "v_max"):
                worst = max(worst, abs(r[key] / mp.mpf(ref[key]) - 1))
            for key in ("s_min", "s_max"):
                worst = max(worst, abs(r[key] - mp.mpf(ref[key])) / ds)
        lines.append(f"{case['name']}: 1: 50 digits vs the table: {mp.nstr(worst, 2)}")
        for r in rows:
            mp.mp.dps = 30
            block = Block(case, r["kappa"], Arith(30))
            z = r["section"]
            x0 = [mp.mpf(z[0]), mp.mpf(0), mp.mpf(z[1])] if block.inertial else [block.G(mp.mpf(z[0])), mp.mpf(z[0])]
            t1 = time.time()
            msg = f"  eps {r['eps']:g}: "
            try:
                f = mp.odefun(lambda t, x: block.rhs(x), 0, x0, tol=mp.mpf(10) ** -25)
                xT = f(r["period"])
                size = max(abs(v) for v in x0)
                closure = max(abs(a - b) for a, b in zip(xT, x0)) / size
                y_min = f(r["t_smin"])[0]
                gap = abs(y_min - (r["s_min"] - block.s_star())) / r["delta_s"]
                msg += f"2: closure {mp.nstr(closure, 2)}, s_min {mp.nstr(gap, 2)} ({time.time() - t1:.0f} s); "
            except Exception as e:  # noqa: BLE001
                msg += f"2: odefun failed ({e}); "
            try:
                T, ds = dop853_shoot(case, r["kappa"], [float(v) for v in z], float(r["period"]))
                msg += (
                    f"3: DOP853 T {abs(T / float(r['period']) - 1):.1e}, "
                    f"Delta_s {abs(ds / float(r['delta_s']) - 1):.1e}"
                )
            except Exception as e:  # noqa: BLE001
                msg += f"3: DOP853 failed ({e})"
            lines.append(msg)
            print(lines[-1], flush=True)
        print(f"{case['name']}: {time.time() - t0:.0f} s", flush=True)
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", out)


def main():
    if "--check" in sys.argv:
        check()
        return
    out = "onset_accuracy.csv"
    names = [a for a in sys.argv[1:] if not a.startswith("--")]
    cases = [c for c in CASES if not names or c["name"] in names]
    lines = [
        "# Reference stick-slip cycles (docs/reference/onset_accuracy.py): shooting in deviation "
        "variables, Taylor order 40, 40 digits; docs/model.md variables; eps = (kappa_c - kappa)/kappa_c, "
        "kappa the double nearest kappa_c (1 - eps)",
        ",".join(COLUMNS),
    ]
    for case in cases:
        t0 = time.time()
        rows = solve_case(case, EPS, verbose=True)
        lines += [csv_row(case, r) for r in rows]
        print(f"{case['name']}: {time.time() - t0:.0f} s", flush=True)
    if not names:
        with open(out, "w") as f:
            f.write("\n".join(lines) + "\n")
        print("wrote", out)
    else:
        print("\n".join(lines))


if __name__ == "__main__":
    main()
