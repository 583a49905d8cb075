"""Error against run time for guidance: the explant's index error (binding) for every field and
resolution, the analytic field's statistical error against seeds, and the default scene's
connection-set distance to each field's finest level."""
import sys
from common import plt, read_csv, save

explant = read_csv(sys.argv[1])
seeds = read_csv(sys.argv[2])
conn = read_csv(sys.argv[3])
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8))
for method, m in (("particles", "o-"), ("grid implicit", "s-"), ("grid explicit", "^-")):
    g = sorted((r for r in explant if r["form"] == "binding" and r["method"] == method), key=lambda r: float(r["seconds per run"]))
    if g:
        a.errorbar([max(float(r["seconds per run"]), 1e-4) for r in g], [abs(float(r["gap"])) for r in g],
                   yerr=[1.96 * float(r["gap SE"]) for r in g], fmt=m, ms=4, capsize=2, label=method)
g = [r for r in seeds if r["form"] == "binding"]
if g:
    a.plot([max(float(r["seconds"]), 1e-4) for r in g], [float(r["SE"]) for r in g], "k*--", label="analytic: SE at 1, 2, 4... seeds")
ref = [r for r in explant if r["form"] == "binding"]
if ref:
    idx = float(ref[0]["index"]) - float(ref[0]["gap"])
    a.axhline(0.1 * idx, color="C3", ls=":", lw=1, label="10 % of the index")
a.set_xscale("log")
a.set_yscale("log")
a.set_xlabel("wall time per run (s)")
a.set_ylabel("|guidance index - analytic|")
a.set_title("explant, binding", fontsize=9)
a.legend(fontsize=6)
for method, m in (("particles", "o-"), ("grid implicit", "s-"), ("grid explicit", "^-")):
    g = [r for r in conn if r["method"] == method and r["connection-set distance to own finest"] not in ("(reference)", "")]
    if g:
        b.semilogx([max(float(r["seconds per run"]), 1e-4) for r in g],
                   [float(r["connection-set distance to own finest"]) for r in g], m, ms=4, label=method)
b.set_xlabel("wall time per run (s)")
b.set_ylabel("Jaccard distance to the finest level")
b.set_title("default scene: connection sets", fontsize=9)
b.legend(fontsize=7)
save(fig, sys.argv[-1])
