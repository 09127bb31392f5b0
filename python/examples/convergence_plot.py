"""The convergence plot of the mass-redistribution papers: on the
Signorini–Dirichlet bar (dx/dt = 10, T = 3), the L∞(0,T;L²) error of u and
the L²(0,T) error of the energy against dx, for the seven schemes with the
standard mass and with the redistributed mass (mod), rates in the legend.

    python python/examples/convergence_plot.py [out.png] [--quick]

(--quick: m = 10, 20, 40 instead of 10 … 640.)
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import signorini

args = [a for a in sys.argv[1:] if not a.startswith("--")]
out = args[0] if args else "convergence.png"
levels = [10, 20, 40] if "--quick" in sys.argv else None

res = signorini.convergence(benchmark="bar-dirichlet", masses=["std", "mod"], levels=levels)

fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharex=True)
styles = {"std": dict(ls="--", marker="o", mfc="none"), "mod": dict(ls="-", marker="s")}
for ax, norm in zip(axes, ["linf_l2_u", "l2_energy"]):
    for i, scheme in enumerate(res.schemes):
        for j, mass in enumerate(res.masses):
            rate = res.rate(norm, scheme, mass)
            ax.loglog(res["dx"][i, j], res[norm][i, j], color=f"C{i}", label=f"{scheme} {mass} ({rate:.2f})", **styles[mass])
    ax.set_xlabel("dx")
    ax.set_ylabel(norm)
    ax.grid(True, which="both", lw=0.3)
axes[0].set_title(f"bar-dirichlet: L∞(0,T;L²) error of u (dx/dt = {res.ratio:g}, T = {res.t_end:g})")
axes[1].set_title("L²(0,T) error of the energy")
axes[1].legend(fontsize=7, ncol=2, loc="lower right")
fig.tight_layout()
fig.savefig(out, dpi=120)
print(f"wrote {out} ({sum(len(res.levels) for _ in res.configs)} runs in {res.wall_s:.1f} s)")
