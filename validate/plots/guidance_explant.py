"""Explant: guidance index against resolution for every field and noise form, with the analytic
index, and the gap to it (log-log) against the amount (particles) and the spacing (grids)."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
forms = ["count", "binding", "snapshot"]
methods = [("particles", "o"), ("grid implicit", "s"), ("grid explicit", "^")]
fig, axes = plt.subplots(1, 4, figsize=(14, 3.5))
for ax, form in zip(axes[:3], forms):
    ref = None
    for method, m in methods:
        g = sorted((r for r in rows if r["form"] == form and r["method"] == method), key=lambda r: int(r["level"]))
        if not g:
            continue
        lv = [int(r["level"]) for r in g]
        ax.errorbar(lv, [float(r["index"]) for r in g], yerr=[1.96 * float(r["index SE"]) for r in g], fmt=m + "-",
                    ms=4, capsize=2, label=method)
        ref = float(g[0]["index"]) - float(g[0]["gap"])
    if ref is not None:
        ax.axhline(ref, color="k", ls="--", lw=1, label="analytic")
        ax.axhspan(0.9 * ref, 1.1 * ref, color="k", alpha=0.06)
    ax.set_xlabel("level (0: default; finer to the right)")
    ax.set_ylabel("guidance index")
    ax.set_title(form, fontsize=9)
    ax.legend(fontsize=6)
ax = axes[3]
for method, m in methods:
    for form, ls in zip(forms, ("-", "--", ":")):
        g = [r for r in rows if r["form"] == form and r["method"] == method and abs(float(r["gap"])) > 0]
        if g:
            ax.loglog([float(r["a or h"]) for r in g], [abs(float(r["gap"])) for r in g], m + ls, ms=3,
                      label=f"{method}, {form}")
ax.set_xlabel("amount a (particles) or spacing h (grids)")
ax.set_ylabel("|index - analytic index|")
ax.legend(fontsize=5)
save(fig, sys.argv[-1])
