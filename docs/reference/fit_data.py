"""Synthetic laboratory data for `stickslip fit` (examples/data/): the
seed's PMMA values (A = 0.012, B = 0.023, D0 = 0.4 um, with mu0 = 0.5 and
mu2 = 2.4e-4 of examples/scenes/pmma.toml; a 1 kg block under its weight),
written with their own formulas, independent of the Rust code:

    mu_ss(V)   = mu0 + (A - B) ln(V/V0) + mu2 ln(V/V0)^2              (seed eq. RR5, theta = V0/V)
    mu_phi     = B + 2 mu2 ln(V0/V)
    (K/W)_c(V) = (mu_phi - A)(1 + M V^2 / (W D0 A)) / D0              (eq. C11, K/W in 1/m)
    f_c(V)     = V / (2 pi D0) sqrt(mu_phi / A - 1)                   (eq. C13, Hz)

with Gaussian noise of a fixed seed: 2e-4 on mu (no sigma column: the fit
estimates it), 2 % on (K/W)_c and on f_c (sigma columns given).

    python docs/reference/fit_data.py       # writes examples/data/pmma-*.csv
"""

import math
import pathlib

import numpy as np

A, B, D0_UM, MU0, MU2 = 0.012, 0.023, 0.4, 0.5, 2.4e-4
V0, M, G = 1.0, 1.0, 9.81
W = M * G


def steady(v):
    l = math.log(v / V0)
    return MU0 + (A - B) * l + MU2 * l * l


def onset(v):
    mu_phi = B + 2 * MU2 * math.log(V0 / v)
    d0 = D0_UM * 1e-6
    kw = (mu_phi - A) * (1 + M * (v * 1e-6) ** 2 / (W * d0 * A)) / d0
    f = v * 1e-6 / (2 * math.pi * d0) * math.sqrt(mu_phi / A - 1)
    return kw, f


def main():
    rng = np.random.default_rng(20261126)
    out = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"
    out.mkdir(exist_ok=True)
    with open(out / "pmma-steady.csv", "w") as f:
        f.write("# steady-state friction of PMMA on PMMA (synthetic: docs/reference/fit_data.py)\n")
        f.write("V_um_s,mu\n")
        for v in np.geomspace(0.1, 100, 13):
            f.write(f"{v:.6g},{steady(v) + rng.normal(0, 2e-4):.6f}\n")
    with open(out / "pmma-onset.csv", "w") as f:
        f.write("# stick-slip onset of PMMA on PMMA (synthetic: docs/reference/fit_data.py)\n")
        f.write("V_um_s,K_over_W_per_m,sigma,frequency_hz,sigma_frequency_hz\n")
        for v in np.geomspace(0.1, 100, 7):
            kw, fc = onset(v)
            f.write(f"{v:.6g},{kw * (1 + rng.normal(0, 0.02)):.6g},{0.02 * kw:.4g},"
                    f"{fc * (1 + rng.normal(0, 0.02)):.6g},{0.02 * fc:.4g}\n")


if __name__ == "__main__":
    main()
