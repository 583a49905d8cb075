"""Directional bias against concentration, one curve per steepness."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
for s in sorted({r["steepness"] for r in rows}, key=float):
    g = [r for r in rows if r["steepness"] == s]
    c = [float(r["concentration"]) for r in g]
    b = [float(r["bias"]) for r in g]
    ax.errorbar(c, b, yerr=[[x - float(r["ci_low"]) for x, r in zip(b, g)], [float(r["ci_high"]) - x for x, r in zip(b, g)]],
                fmt="o-", ms=3, capsize=2, label=f"{s} % / 10 um")
ax.set_xscale("log")
ax.axhline(0, color="0.5", lw=0.8)
ax.set_xlabel("concentration at the explant")
ax.set_ylabel("directional bias")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
