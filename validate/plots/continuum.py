"""Work against precision of every refinement ladder: |answer - finest| against seconds per run."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(7.0, 4.6))
ladders = []
for r in rows:
    key = (r["scene"], r["parameter"])
    if key not in ladders:
        ladders.append(key)
for scene, parameter in ladders:
    g = [r for r in rows if r["scene"] == scene and r["parameter"] == parameter][:-1]
    x = [float(r["seconds per run"]) for r in g]
    y = [max(abs(float(r["minus finest"])), 1e-5) for r in g]
    style = "--" if "control" in scene else "-"
    ax.loglog(x, y, style, marker="o", ms=3, label=f"{scene}: {parameter}")
ax.set_xlabel("seconds per run")
ax.set_ylabel("|answer - finest level|")
ax.legend(fontsize=5, ncol=2)
save(fig, sys.argv[-1])
