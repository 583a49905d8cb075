"""validate branching §E and §F: cue-steered arbours' guidance against dt (with the direct
control), and lateral branching's mean cone count against the exact discrete recursion and
its limit -> branching_arbours.png."""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402


def mean_se(cell):
    m, se = cell.split("±")
    return float(m), float(se)


guided = list(csv.DictReader(open(sys.argv[1])))
lateral = list(csv.DictReader(open(sys.argv[2])))
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.8))
dt = [float(r["dt (h)"]) for r in guided]
for key, label in (("guidance cosine", "steered (SNR, T = 1 h)"), ("control (direct)", "control: direct guidance")):
    ms = [mean_se(r[key]) for r in guided]
    a.errorbar(dt, [m for m, _ in ms], yerr=[2 * s for _, s in ms], fmt="o-", capsize=3, label=label)
a.set_xscale("log")
a.minorticks_off()
a.set_xticks(dt, ["%g" % x for x in dt])
a.axhline(0, color="k", lw=0.5)
a.set_xlabel("dt (h)")
a.set_ylabel("axon terminals' cosine to the gradient")
a.set_title("culture in a 1 %/10 µm gradient (±2 SE)", fontsize=9)
a.legend(fontsize=8)
steps = [float(r["dt"]) for r in lateral]
sim = [mean_se(r["simulated mean cones"]) for r in lateral]
rec = [float(r["exact discrete mean"]) for r in lateral]
limit = rec[0] - float(lateral[0]["discrete minus limit"])
b.errorbar(steps, [m for m, _ in sim], yerr=[2 * s for _, s in sim], fmt="o", capsize=3, label="simulated (±2 SE)")
b.plot(steps, rec, "s-", ms=4, label="exact discrete recursion")
b.axhline(limit, color="k", ls="--", lw=0.8, label="limit cosh(√(λ v0) T) = %.3f" % limit)
b.set_xscale("log")
b.minorticks_off()
b.set_xticks(steps, ["%g" % x for x in steps])
b.set_xlabel("dt")
b.set_ylabel("mean cones per neuron")
b.set_title("lateral branching alone: λ = 0.25, v0 = 1, T = 4", fontsize=9)
b.legend(fontsize=8)
fig.tight_layout()
savefig_whole(fig, sys.argv[-1])
