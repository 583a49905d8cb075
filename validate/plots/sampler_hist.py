"""Histogram of the z coordinate of 3D directions per sampler (uniform: flat at 1/2)."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.4))
for m in [k for k in rows[0].keys() if k != "z"]:
    ax.plot([float(r["z"]) for r in rows], [float(r[m]) for r in rows], drawstyle="steps-mid", label=m)
ax.axhline(0.5, color="k", ls=":", lw=1)
ax.set_xlabel("z (third coordinate)")
ax.set_ylabel("density")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
