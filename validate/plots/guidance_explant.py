"""Explant: guidance index against the amount per particle, particle field vs the analytic
field under the same noise form (count and binding)."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.8, 3.8))
for noise, colour, m in (("count", "C0", "o"), ("binding", "C3", "s")):
    g = [r for r in rows if r["noise"] == noise]
    if not g:
        continue
    a = [float(r["amount"]) for r in g]
    an = [float(r["analytic"]) for r in g]
    ae = [float(r["analytic_ci95"]) for r in g]
    ax.fill_between(a, [x - e for x, e in zip(an, ae)], [x + e for x, e in zip(an, ae)], color=colour, alpha=0.15)
    ax.plot(a, an, "-", color=colour, lw=1, label=f"analytic, {noise}")
    gi = [float(r["particles"]) for r in g]
    pe = [float(r["particles_ci95"]) for r in g]
    ax.errorbar(a, gi, yerr=pe, fmt=m, color=colour, ms=4, capsize=2,
                label=f"particles, {noise}" + (" (count decision)" if noise == "count" else " (split estimate)"))
ax.set_xscale("log")
ax.invert_xaxis()
ax.axhline(0, color="k", ls=":", lw=1)
ax.set_xlabel("amount per particle a (smaller: more particles)")
ax.set_ylabel("guidance index <cos>")
g = [r for r in rows if r["noise"] == "count"]
k = float(g[0]["n"]) * float(g[0]["amount"])
top = ax.secondary_xaxis("top", functions=(lambda x: k / x, lambda n: k / n))
top.set_xlabel("particles per sensing volume at the explant", fontsize=8)
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
