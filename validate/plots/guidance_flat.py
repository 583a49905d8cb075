"""Flat field: P(turn toward own estimate) and Rayleigh p-values against particles per mesh cell."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.4))
estimators = []
for r in rows:
    if r["estimator"] not in estimators:
        estimators.append(r["estimator"])
for est, m in zip(estimators, ("o", "s", "^", "v")):
    g = [r for r in rows if r["estimator"] == est]
    n = [float(r["nu"]) for r in g]
    p = [float(r["P(toward own)"]) for r in g]
    lo = [p[i] - float(r["CI low"]) for i, r in enumerate(g)]
    hi = [float(r["CI high"]) - p[i] for i, r in enumerate(g)]
    a.errorbar(n, p, yerr=[lo, hi], fmt=m + "-", ms=4, capsize=2, label=est)
    b.semilogx(n, [float(r["Rayleigh p"]) for r in g], m + "-", ms=4, label=est)
a.axhline(0.5, color="k", ls=":", lw=1)
a.set_xscale("log")
a.set_xlabel("particles per mesh cell (one frame)")
a.set_ylabel("P(turn toward own estimate)")
a.legend(fontsize=7)
b.set_yscale("log")
b.axhline(0.01 / (4 * len({r["nu"] for r in rows})), color="k", ls=":", lw=1)
b.set_xlabel("particles per mesh cell (one frame)")
b.set_ylabel("Rayleigh p-value of the turn side")
save(fig, sys.argv[-1])
