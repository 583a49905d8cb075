"""Work-precision: error of C against wall time for every field method."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
for m in sorted({r["method"] for r in rows}):
    g = sorted((r for r in rows if r["method"] == m), key=lambda r: float(r["seconds"]))
    ax.loglog([max(float(r["seconds"]), 1e-4) for r in g], [float(r["error_C"]) for r in g], "o-", label=m)
ax.set_xlabel("wall time to steady state (s)")
ax.set_ylabel("relative RMS error of C")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
