"""A notebook-style session: the stability diagram of the PMMA scene and a
branch of stick-slip cycles, drawn with matplotlib; steady sliding across
the onset; a simulation reaching stick-slip; a small sweep. Each step
prints what it found (as a notebook cell would show it).

    python examples/python/notebook.py [OUT_DIR]
"""

import os
import sys
import time

import numpy as np

import stickslip

out = sys.argv[1] if len(sys.argv) > 1 else "notebook-out"
os.makedirs(out, exist_ok=True)
scene = stickslip.Scene.builtin("pmma").with_(K=2e5)

# In [1]: the onset
h = stickslip.hopf(scene)
print(h)

# In [2]: steady sliding continued in the stiffness, across the onset
b = stickslip.branch(scene, param="K", from_=4e5, to=1e5)
print(b)
hopf_row = b.events
print(f"  Hopf point on the branch at K = {hopf_row['K_N_per_m'][0]:.6e} N/m "
      f"(f = {hopf_row['frequency_hz'][0]:.6e} Hz); unstable eigenvalues below it: "
      f"{int(b.n_unstable[-1])}")

# In [3]: the stability diagram
d = stickslip.diagram(scene)
print(d)
for kind, nu, kappa in zip(d.special_points["kind"], d.special_points["nu"],
                           d.special_points["kappa"]):
    print(f"  {kind} at nu = {nu:.6e}, kappa = {kappa:.6e}")
print("  operating point:", d.operating_point["regime"], "—", d.operating_point["reason"])

# In [4]: the stick-slip cycles below the onset
c = stickslip.cycles(scene, kappa_fraction=0.9)
print(c)
print(f"  force drop {c.delta_s_N.min():.4e} .. {c.delta_s_N.max():.4e} N, "
      f"period {c.period_s.min():.4g} .. {c.period_s.max():.4g} s")

# In [5]: a simulation at the scene's stiffness, driven at 1 µm/s for 300 s
sim = stickslip.simulate(scene, protocol=[(1.0, 300.0)])
print(sim)

# In [6]: a sweep of the onset over stiffness and velocity
t0 = time.perf_counter()
table = stickslip.sweep("hopf", {"V": np.geomspace(0.1, 100, 20), "K": [1e5, 2e5]},
                        scene=scene, workers=0)
print(f"sweep: {len(table)} points in {time.perf_counter() - t0:.2f} s;",
      {str(k): int(n) for k, n in zip(*np.unique(np.asarray(table["criticality"], dtype=str), return_counts=True))})

# In [7]: the command line's figures, then our own with matplotlib
files = d.figures(out) + c.figures(out) + sim.figures(out)
print(f"wrote {len(files)} figures of the command line into {out}")
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("(matplotlib not installed: no figure of our own)")
    sys.exit(0)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
for crit, style in [("supercritical", "-"), ("subcritical", "--"), ("degenerate", ":")]:
    k = np.where(d.criticality == crit, d.K_over_W_per_m, np.nan)
    ax1.plot(d.V_um_per_s, k, style, color="C0", label=f"Hopf curve, {crit}")
if len(d.lpc_curve.get("nu", [])):
    ax1.plot(d.lpc_curve["V_um_per_s"], d.lpc_curve["K_over_W_per_m"], color="C3",
             label="folds of cycles")
op = d.operating_point
ax1.plot([op["V_um_per_s"]], [op["K_N_per_m"] / scene.units["W_N"]], "k*", ms=10,
         label="the rig")
ax1.set(xscale="log", yscale="log", xlabel="V [µm/s]", ylabel="critical K/W [1/m]",
        title=f"{scene.label}: stability diagram")
ax1.legend(fontsize=8)
order = np.argsort(c.kappa)
stable = np.array([s == True for s in c.stable], dtype=bool)[order]  # noqa: E712 (numpy or None)
ax2.plot(c.K_N_per_m[order], c.delta_s_N[order], "-", color="C0")
ax2.plot(c.K_N_per_m[order][stable], c.delta_s_N[order][stable], "o", ms=3, label="stable")
ax2.axvline(h.K_c, ls="--", color="gray", label="K_c (Hopf)")
ax2.set(xlabel="K [N/m]", ylabel="force drop [N]", title="stick-slip cycle branch")
ax2.legend(fontsize=8)
fig.tight_layout()
path = os.path.join(out, "notebook.png")
fig.savefig(path, dpi=100)
print("wrote", path)
