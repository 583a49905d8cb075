"""Convergence of the cue fields: particles against particle count, grids against h."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.4))
p = [r for r in rows if r["method"] == "particles"]
if p:
    n = [float(r["size"]) for r in p]
    e = [float(r["error_C"]) for r in p]
    a.loglog(n, e, "o-", label="particles, C")
    a.loglog(n, [float(r["error_grad"]) for r in p], "s--", label="particles, grad C")
    a.loglog(n, [e[0] * (x / n[0]) ** -0.5 for x in n], "k:", label="N^(-1/2)")
    a.set_xlabel("mean particle count N")
    a.set_ylabel("relative RMS error")
    a.legend()
methods = sorted({r["method"] for r in rows if r["method"] != "particles"})
for m in methods:
    g = [r for r in rows if r["method"] == m]
    b.loglog([float(r["size"]) for r in g], [float(r["error_C"]) for r in g], "o-", label=m)
hs = sorted({float(r["size"]) for r in rows if r["method"] != "particles"})
if hs:
    ref = [r for r in rows if r["method"].startswith("unsplit")]
    e0 = float(ref[0]["error_C"]) if ref else 0.05
    b.loglog(hs, [e0 * (h / hs[-1]) ** 2 for h in hs], "k:", label="h^2")
b.set_xlabel("grid spacing h (LU)")
b.set_ylabel("relative RMS error of C")
b.legend(fontsize=7)
save(fig, sys.argv[-1])
