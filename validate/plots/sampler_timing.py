"""Time to generate n directions per sampler, with the report's Table 3 points."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
for m in sorted({r["method"] for r in rows}):
    g = sorted((r for r in rows if r["method"] == m), key=lambda r: float(r["n"]))
    ax.loglog([float(r["n"]) for r in g], [float(r["seconds"]) for r in g], "o-", label=m)
report = {500: 0.12, 2500: 0.24, 5000: 0.39, 10000: 0.68}
ax.loglog(list(report), list(report.values()), "k^", label="report, Table 3 (trig)")
ax.set_xlabel("points n")
ax.set_ylabel("seconds")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
