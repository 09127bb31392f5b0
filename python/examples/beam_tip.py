"""The tip of Dumont & Paoli's pipe between two stops (their figure 2:
the support oscillating at 10 rad/s, the β-scheme with β = 1/2, dt = 5e-5 s),
plotted against time with the stops.

    python python/examples/beam_tip.py [out.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import signorini

out = sys.argv[1] if len(sys.argv) > 1 else "beam_tip.png"
r = signorini.run({"beam": {"scene": "fig2"}})

fig, ax = plt.subplots(figsize=(9, 4))
ax.plot(r.t, r.tip, lw=0.8, label="tip ũ(L, t)")
for lo, hi in zip(r.contact_lo, r.contact_hi):
    ax.axhline(lo, color="k", ls="--", lw=0.8)
    ax.axhline(hi, color="k", ls="--", lw=0.8)
ax.set_xlabel("t (s)")
ax.set_ylabel("tip displacement (m)")
ax.set_title(f"Pipe between stops: {r.steps} steps, {r.contact_steps} in contact")
ax.legend(loc="upper right")
fig.tight_layout()
fig.savefig(out, dpi=120)
print(f"wrote {out}")
