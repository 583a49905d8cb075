"""validate branching: the terminal-segment distribution against van Pelt's recursion, and
the recursion's convergence in the number of bins -> branching.png."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402

dist = list(csv.DictReader(open(sys.argv[1])))
conv = list(csv.DictReader(open(sys.argv[2])))
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8))
cases = []
for r in dist:
    k = (r["B"], r["E"])
    if k not in cases:
        cases.append(k)
for i, k in enumerate(cases):
    rows = [r for r in dist if (r["B"], r["E"]) == k]
    n = [int(r["n"]) for r in rows]
    c = "C%d" % i
    a.plot(n, [float(r["recursion"]) for r in rows], "-", color=c, label="B = %s, E = %s" % k)
    a.plot(n, [float(r["limit"]) for r in rows], "--", color=c, lw=0.8)
    a.plot(n, [float(r["simulated"]) for r in rows], "o", color=c, ms=3)
a.set_xlim(0.5, 30)
a.set_xlabel("terminal segments n")
a.set_ylabel("probability")
a.legend(fontsize=8)
a.set_title("10 bins: simulated (points), recursion (lines), limit (dashed)", fontsize=9)
nb = [float(r["bins N"]) for r in conv]
err = [abs(float(r["minus the limit"])) for r in conv]
b.loglog(nb, err, "o-", label="|recursion mean − limit|")
b.loglog(nb, [err[0] * nb[0] / x for x in nb], "k:", label="first order")
b.set_xlabel("bins N")
b.set_ylabel("error of the mean")
b.legend(fontsize=8)
fig.tight_layout()
savefig_whole(fig, sys.argv[-1])
