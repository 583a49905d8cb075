"""Heading autocorrelation against path length: measured and exp(-s / L_p)."""
import math
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
for lp in ("5", "20", "none"):
    g = [r for r in rows if r["L_p"] == lp]
    s = [float(r["s"]) for r in g]
    c = [float(r["C"]) for r in g]
    line = ax.errorbar(s, c, yerr=[2 * float(r["SE"]) for r in g], fmt="o", ms=3, capsize=1,
                       label=f"L_p = {lp}" if lp != "none" else "L_p null")[0]
    ax.plot(s, [float(r["expected"]) for r in g], "-", color=line.get_color(), lw=1)
ax.set_yscale("log")
ax.set_xlabel("path length s (LU)")
ax.set_ylabel("<h(s).h(0)>")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
