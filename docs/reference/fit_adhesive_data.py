"""Synthetic laboratory data for `stickslip fit` on an adhesive scene
(examples/data/gel-*.csv, tests/data/gel-*.csv): the built-in gel scene's
values (examples/scenes/gel.toml: F_a = 0.05 N, V_s = 0.025 um/s,
tau_out = 1 s, tau_on = 0.1 s, F_v = 5e-4 N, alpha = 0.6, M = 1 g),
written with their own formulas, independent of the Rust code: mpmath's
E1 at 40 digits and its numerical differentiation (mp.diff).

Dimensionless (docs/model.md, "Soft adhesive contacts"), u = v / V_s,
z = 1/u, g(z) = e^z E1(z), T(u) = z g(z) (eq. D7), r = tau_on / tau_out:

    n_ss(u)  = T / (T + r)                                        (eq. D2)
    F(n, u)  = n g(1/u) + f_v u^(1 - alpha),   f_v = F_v / F_a
    F_ss(V)  = F_a F(n_ss(u), u)                                  [N]
    lambda_n = 1/r + 1/T(u),  F_u = dF/du at fixed n,  chi = m lambda_n / F_u,
    m        = M V_s / (F_a tau_out)
    kappa_c  = -lambda_n dF_ss/du (1 + chi)           (docs/model.md, "Linear stability")
    K_c(V)   = kappa_c F_a / (V_s tau_out)                         [N/m]

Files (a fixed seed: Python's random.Random(20261127)):

- examples/data/gel-steady.csv: 25 velocities 0.1 .. 1000 um/s, Gaussian
  noise 3e-4 N on F (no sigma column: the fit estimates it);
- examples/data/gel-onset.csv: 8 velocities 1 .. 80 um/s (between the
  friction maximum and minimum), 3 % noise on K_c, sigma column given;
- tests/data/gel-steady-exact.csv, tests/data/gel-onset-exact.csv: the same
  velocities without noise, 17 digits;
- tests/data/gel-steady-slow.csv: 15 velocities 0.05 .. 2 um/s only (no
  viscous regime), noise 3e-4 N.

Run: python3 docs/reference/fit_adhesive_data.py > docs/reference/fit_adhesive_data_out.txt
"""
import pathlib
import random

import mpmath as mp

mp.mp.dps = 40

F_A, V_S_UM, TAU_OUT, TAU_ON, F_V, ALPHA, M = (
    mp.mpf("0.05"), mp.mpf("0.025"), mp.mpf(1), mp.mpf("0.1"),
    mp.mpf("5e-4"), mp.mpf("0.6"), mp.mpf("1e-3"))
R = TAU_ON / TAU_OUT
FV = F_V / F_A
V_S = V_S_UM * mp.mpf("1e-6")  # m/s
MASS = M * V_S / (F_A * TAU_OUT)


def g(z):
    return mp.exp(z) * mp.e1(z)


def lifetime(u):
    return (1 / u) * g(1 / u)


def force(n, u):
    return n * g(1 / u) + FV * u ** (1 - ALPHA)


def n_ss(u):
    t = lifetime(u)
    return t / (t + R)


def f_ss(u):
    return force(n_ss(u), u)


def steady_n(v_um):
    """Steady friction [N] at v um/s."""
    return F_A * f_ss(mp.mpf(v_um) / V_S_UM)


def critical_n_m(v_um):
    """The critical stiffness K_c [N/m] at v um/s, with the block's inertia."""
    u = mp.mpf(v_um) / V_S_UM
    lam = 1 / R + 1 / lifetime(u)
    n = n_ss(u)
    f_u = mp.diff(lambda w: force(n, w), u)
    chi = MASS * lam / f_u
    kappa_c = -lam * mp.diff(f_ss, u) * (1 + chi)
    return kappa_c * F_A / (V_S * TAU_OUT)


def geomspace(lo, hi, n):
    return [lo * (hi / lo) ** (i / (n - 1)) for i in range(n)]


def main():
    rng = random.Random(20261127)
    root = pathlib.Path(__file__).resolve().parents[2]
    (root / "tests" / "data").mkdir(exist_ok=True)
    steady_v = [float(f"{v:.6g}") for v in geomspace(0.1, 1000.0, 25)]
    onset_v = [float(f"{v:.6g}") for v in geomspace(1.0, 80.0, 8)]
    slow_v = [float(f"{v:.6g}") for v in geomspace(0.05, 2.0, 15)]
    source = "synthetic: docs/reference/fit_adhesive_data.py"
    examples, tests = root / "examples" / "data", root / "tests" / "data"

    def write(path, what, header, rows):
        with open(path, "w") as f:
            f.write(f"# {what} ({source})\n{header}\n")
            for row in rows:
                f.write(",".join(row) + "\n")

    # The noisy files draw in this order: steady, onset, slow.
    write(examples / "gel-steady.csv", "steady friction of a gelatin gel on glass",
          "V_um_s,F_N",
          [(f"{v:.6g}", f"{float(steady_n(v)) + rng.gauss(0, 3e-4):.6e}") for v in steady_v])
    onset = [(v, float(critical_n_m(v))) for v in onset_v]
    write(examples / "gel-onset.csv", "stick-slip onset of a gelatin gel on glass",
          "V_um_s,K_N_per_m,sigma",
          [(f"{v:.6g}", f"{k * (1 + rng.gauss(0, 0.03)):.6e}", f"{0.03 * k:.4e}")
           for v, k in onset])
    write(tests / "gel-steady-exact.csv", "steady friction of the gel scene without noise",
          "V_um_s,F_N", [(f"{v:.6g}", mp.nstr(steady_n(v), 17)) for v in steady_v])
    write(tests / "gel-onset-exact.csv", "critical stiffness of the gel scene without noise",
          "V_um_s,K_N_per_m", [(f"{v:.6g}", mp.nstr(critical_n_m(v), 17)) for v in onset_v])
    write(tests / "gel-steady-slow.csv",
          "steady friction of the gel below 2 um/s, no viscous regime", "V_um_s,F_N",
          [(f"{v:.6g}", f"{float(steady_n(v)) + rng.gauss(0, 3e-4):.6e}") for v in slow_v])
    print("generating parameters (examples/scenes/gel.toml)")
    for name, value in [("F_a", F_A), ("V_s", V_S_UM), ("tau_on", TAU_ON),
                        ("tau_out", TAU_OUT), ("F_v", F_V), ("alpha", ALPHA)]:
        print(f"{name} {mp.nstr(value, 17)}")
    print("checks against docs/model.md (adhesive_gel.py)")
    print(f"F_ss(20 um/s) N {mp.nstr(steady_n(20), 17)}")
    u20 = mp.mpf(20) / V_S_UM
    lam = 1 / R + 1 / lifetime(u20)
    kc_qs = -lam * mp.diff(f_ss, u20) * F_A / (V_S * TAU_OUT)
    print(f"K_c(20 um/s) quasi-static N/m {mp.nstr(kc_qs, 17)}")
    print(f"K_c(20 um/s) with inertia N/m {mp.nstr(critical_n_m(20), 17)}")


if __name__ == "__main__":
    main()
