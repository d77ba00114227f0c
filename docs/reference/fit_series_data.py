"""Synthetic time series for `stickslip fit` (examples/data/): a velocity
step and the relaxation after the drive stops, on the stiff machine of
examples/scenes/pmma-machine.toml (K = 1e6 N/m, a 1 kg block under its
weight, W = 9.81 N), with the seed's PMMA values (A = 0.012, B = 0.023,
D0 = 0.4 um, mu0 = 0.5, mu2 = 2.4e-4). Written with their own formulas and
integrator (the standard library only), independent of the Rust code: the
quasi-static spring-block equations in physical time (docs/model.md),

    mu(V, theta)   = mu0 + A ln(V/V0) + B ln theta + mu2 ln(theta)^2     (theta = phi V0/D0)
    ds/dt          = (K/W) (V_drive - V)                                  (s = spring force / W)
    V              = V0 exp((s - mu0 - B ln theta - mu2 ln(theta)^2) / A) (quasi-static: s = mu)
    d ln theta/dt  = (V0/D0) (1/theta - V/V0)                             (ageing law)

from steady sliding (theta = V0/V, s = mu_ss(V)), by the classical
fourth-order Runge-Kutta method with steps of at most 1e-3 s (1e-3 (1 + t)
in a relaxation, whose rates fall as 1/t): `h |lambda| <= 0.03` with the fastest rate `lambda = (K/W)
V / A`, an error far below the noise.

- pmma-velocity-step.csv: V = 1 um/s, 3 um/s from t = 2 s, 1 um/s from
  t = 10 s; 2000 rows, 100 per second; noise 1e-4 on mu (no sigma column:
  the fit estimates it).
- pmma-relaxation-{0.3,1,3}.csv: the slip x(t) - x(0) after the drive stops
  at t = 0 from steady sliding at V; t = 0 and 200 times log-spaced from
  1e-3 to 1000 s; noise 1 nm (sigma column 0.001 um).

    python3 docs/reference/fit_series_data.py   # writes examples/data/pmma-*.csv
"""

import math
import pathlib
import random

A, B, D0_UM, MU0, MU2 = 0.012, 0.023, 0.4, 0.5, 2.4e-4
V0 = 1.0  # um/s
K_OVER_W = 1e6 / 9.81  # 1/m


def ageing(ln_theta):
    return B * ln_theta + MU2 * ln_theta * ln_theta


def steady(v):
    return MU0 + A * math.log(v / V0) + ageing(math.log(V0 / v))


def rates(y, v_drive):
    s, ln_theta = y
    v = V0 * math.exp((s - MU0 - ageing(ln_theta)) / A)
    return (K_OVER_W * (v_drive - v) * 1e-6, (V0 / D0_UM) * (math.exp(-ln_theta) - v / V0))


def rk4(y, v_drive, t0, t1, h_max):
    """y at t1 from y at t0 under the drive v_drive."""
    n = max(1, math.ceil((t1 - t0) / h_max))
    h = (t1 - t0) / n
    for _ in range(n):
        k1 = rates(y, v_drive)
        k2 = rates([a + 0.5 * h * b for a, b in zip(y, k1)], v_drive)
        k3 = rates([a + 0.5 * h * b for a, b in zip(y, k2)], v_drive)
        k4 = rates([a + h * b for a, b in zip(y, k3)], v_drive)
        y = [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(y, k1, k2, k3, k4)]
    return y


def velocity_step(rng, path):
    protocol = [(0.0, 1.0), (2.0, 3.0), (10.0, 1.0)]

    def drive(t):
        return [v for t0, v in protocol if t0 <= t][-1]

    times = [i / 100 for i in range(2000)]
    y = [steady(1.0), math.log(V0 / 1.0)]
    with open(path, "w") as f:
        f.write("# velocity steps 1 -> 3 -> 1 um/s, PMMA on a stiff machine (K/W = 1.02e5 1/m)\n")
        f.write("# synthetic: docs/reference/fit_series_data.py; scene examples/scenes/pmma-machine.toml\n")
        f.write("t_s,V_um_s,mu\n")
        for i, t in enumerate(times):
            if i > 0:
                y = rk4(y, drive(times[i - 1]), times[i - 1], t, 1e-3)
            f.write(f"{t:.2f},{drive(t):g},{y[0] + rng.gauss(0, 1e-4):.7f}\n")


def relaxation(rng, v, path):
    times = [0.0] + [1e-3 * 1e6 ** (i / 199) for i in range(200)]
    s0 = steady(v)
    y = [s0, math.log(V0 / v)]
    with open(path, "w") as f:
        f.write(f"# slip after the drive stops at t = 0 from steady sliding at {v:g} um/s\n")
        f.write("# synthetic: docs/reference/fit_series_data.py; scene examples/scenes/pmma-machine.toml\n")
        f.write("t_s,slip_um,V_um_s,sigma\n")
        for i, t in enumerate(times):
            if i > 0:
                y = rk4(y, 0.0, times[i - 1], t, 1e-3 * (1 + times[i - 1]))
            slip = (s0 - y[0]) / K_OVER_W * 1e6
            f.write(f"{t:.6g},{slip + rng.gauss(0, 1e-3):.6f},{v:g},0.001\n")


def main():
    rng = random.Random(20261126)
    out = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"
    out.mkdir(exist_ok=True)
    velocity_step(rng, out / "pmma-velocity-step.csv")
    for v in (0.3, 1.0, 3.0):
        relaxation(rng, v, out / f"pmma-relaxation-{v:g}.csv")


if __name__ == "__main__":
    main()
