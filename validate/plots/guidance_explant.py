"""Explant: guidance index against the amount per particle, particle field vs analytic."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
an = [r for r in rows if r["field"] == "analytic"][0]
ax.axhspan(float(an["CI low"]), float(an["CI high"]), color="0.8", label="analytic (95 % CI)")
ax.axhline(float(an["guidance index"]), color="k", lw=1)
for field, m in (("particles", "o-"), ("particles (count)", "s--")):
    g = [r for r in rows if r["field"] == field]
    if not g:
        continue
    a = [float(r["amount"]) for r in g]
    gi = [float(r["guidance index"]) for r in g]
    err = [gi[i] - float(r["CI low"]) for i, r in enumerate(g)]
    ax.errorbar(a, gi, yerr=err, fmt=m, ms=4, capsize=2, label=field.replace("particles", "particles, split") if field == "particles" else field)
ax.set_xscale("log")
ax.invert_xaxis()
ax.axhline(0, color="k", ls=":", lw=1)
ax.set_xlabel("amount per particle a (smaller: more particles)")
ax.set_ylabel("guidance index <cos>")
g = [r for r in rows if r["field"] == "particles"]
top = ax.secondary_xaxis("top", functions=(lambda x: float(g[0]["n at explant"]) * float(g[0]["amount"]) / x,
                                            lambda n: float(g[0]["n at explant"]) * float(g[0]["amount"]) / n))
top.set_xlabel("particles per sensing volume at the explant", fontsize=8)
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
