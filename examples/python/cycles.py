"""The stick-slip onset of the PMMA scene with a spring of 2e5 N/m, and the
stick-slip cycles below it, from Python; with matplotlib installed, the
branch (force drop against stiffness) and a few orbits are drawn.

    python examples/python/cycles.py [FIGURE.png]
"""

import os
import sys

import numpy as np

import stickslip

scene = stickslip.Scene.builtin("pmma").with_(K=2e5)
print(scene, "—", scene.description)

h = stickslip.hopf(scene)
print(h)
print(f"K_c = {h.K_c:.6e} N/m (Appendix C: kappa_c = {h.appendix_c['kappa_c']:.14e},"
      f" rel. diff {h.appendix_c['kappa_c_rel_diff']:.1e})")
print("operating point:", h.operating_point["regime"], "—", h.operating_point["reason"])

c = stickslip.cycles(scene, kappa_fraction=0.9, at={"K": [1.9e5]})
print(c)
stable = np.array([s is True for s in c.stable])
print(f"{len(c)} cycles, {stable.sum()} stable; force drop from {c.delta_s_N.min():.4e} N"
      f" to {c.delta_s_N.max():.4e} N, period {c.period_s.min():.4g} .. {c.period_s.max():.4g} s")
at = c.user_point.nonzero()[0][0]
print(f"at K = {c.K_N_per_m[at]:.6e} N/m: period {c.period_s[at]:.6e} s,"
      f" force drop {c.delta_s_N[at]:.6e} N, slip velocity up to {c.v_max_um_per_s[at]:.4e} µm/s")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("(matplotlib not installed: no figure)")
    sys.exit(0)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
order = np.argsort(c.kappa)
ax1.plot(c.K_N_per_m[order], c.delta_s_N[order], "-o", ms=3)
ax1.axvline(h.K_c, ls="--", color="gray", label="K_c (Hopf)")
ax1.set_xlabel("K [N/m]")
ax1.set_ylabel("force drop [N]")
ax1.set_title(f"{scene.name}: stick-slip cycles")
ax1.legend()
for i in np.linspace(0, len(c) - 1, 4).astype(int):
    o = c.orbit(i)
    ax2.plot(o["s"], np.log(o["v"]), label=f"K = {c.K_N_per_m[i]:.4g} N/m")
ax2.set_xlabel("spring force s = Kx/W")
ax2.set_ylabel("ln(v/V0)")
ax2.set_title("orbits")
ax2.legend(fontsize=8)
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "out/python-cycles.png"
os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
fig.savefig(out, dpi=100)
print("wrote", out)
