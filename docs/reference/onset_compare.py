"""stickslip's cycles against the reference table onset_accuracy.csv.

For every case of the table, runs `stickslip cycles --json` with the case's
parameters and `--at-kappa` at the table's stiffnesses (the branch from the
Hopf point lands exactly on them), and prints the relative errors of the
period and of Delta_s, and the largest error of s_min, s_max (relative to
Delta_s) and of v_min, v_max (relative), as a Markdown table.

Run: python3 onset_compare.py [path/to/stickslip] [case,case,...]
"""

import csv
import json
import subprocess
import sys
import tempfile
import time

BINARY = sys.argv[1] if len(sys.argv) > 1 else "target/release/stickslip"
ONLY = sys.argv[2].split(",") if len(sys.argv) > 2 else None


def table(path="onset_accuracy.csv"):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    cases = {}
    for r in rows:
        cases.setdefault(r["case"], []).append(r)
    return cases


def run(rows):
    r0 = rows[0]
    args = [BINARY, "cycles", "--json"]
    for key in ("A", "B", "mu0", "m", "nu"):
        args += ["--set", f"{key}={r0[key]}"]
    if r0["theta_c"]:
        args += ["--set", f"theta_c={r0['theta_c']}"]
    else:
        args += ["--set", f"mu2={r0['mu2']}"]
    args += ["--at-kappa", ",".join(r["kappa"] for r in rows)]
    with tempfile.TemporaryDirectory() as out:
        t0 = time.time()
        p = subprocess.run(args + ["--out", out], capture_output=True, text=True, check=False)
        seconds = time.time() - t0
    cycles = json.loads(p.stdout)["cycles"]
    return {c["kappa"]: c for c in cycles if c["user_point"]}, seconds


def main():
    here = sys.path[0] or "."
    cases = table(f"{here}/onset_accuracy.csv")
    print("| case | eps | T | Delta_s | s extremes / Delta_s | v extremes | estimate | NTST |")
    print("|---|---|---|---|---|---|---|---|")
    for name, rows in cases.items():
        if ONLY and name not in ONLY:
            continue
        got, seconds = run(rows)
        for r in rows:
            c = got.get(float(r["kappa"]))
            if c is None:
                print(f"| {name} | {r['eps']} | not delivered | | | | | |")
                continue
            ds = float(r["delta_s"])
            e_t = c["period"] / float(r["period"]) - 1
            e_ds = c["delta_s"] / ds - 1
            e_s = max(abs(c[k] - float(r[k])) / ds for k in ("s_min", "s_max"))
            e_v = max(abs(c[k] / float(r[k]) - 1) for k in ("v_min", "v_max"))
            est = c["error_estimate"]
            print(
                f"| {name} | {r['eps']} | {e_t:.1e} | {e_ds:.1e} | {e_s:.1e} | {e_v:.1e} | "
                f"{'n/a' if est is None else f'{est:.0e}'} | {c['ntst']} |"
            )
        print(f"<!-- {name}: {seconds:.1f} s -->", file=sys.stderr)


if __name__ == "__main__":
    main()
