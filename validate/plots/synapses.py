"""validate synapses §A, §B and §D: contacts against Steiner's expectation, contacts and
appositions of straight neurites against the step (with the crossing term), and appositions
and connections per neuron of grown arbours as the numerics are refined -> synapses.png."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402


def mean_se(cell):
    m, se = cell.split("±")
    return float(m), float(se)


contacts = list(csv.DictReader(open(sys.argv[1])))
straight = list(csv.DictReader(open(sys.argv[2])))
grown = list(csv.DictReader(open(sys.argv[3])))
fig, (a, b, c) = plt.subplots(1, 3, figsize=(14, 3.9))

exp = [float(r["Steiner expectation"]) for r in contacts]
sim = [mean_se(r["contacts per replicate"]) for r in contacts]
a.errorbar(exp, [m for m, _ in sim], yerr=[2 * s for _, s in sim], fmt="o", capsize=3, label="simulated (±2 SE)")
lo, hi = min(exp) * 0.8, max(exp) * 1.2
a.plot([lo, hi], [lo, hi], "k--", lw=0.8, label="Steiner's formula")
for r, e, (m, _) in zip(contacts, exp, sim):
    a.annotate("l=%s d=%s" % (r["segment length"], r["d"]), (e, m), fontsize=6, xytext=(3, -8), textcoords="offset points")
a.set_xscale("log")
a.set_yscale("log")
a.set_xlabel("expected contacts")
a.set_ylabel("contacts per replicate")
a.set_title("§A contacts of uniform isotropic segments", fontsize=9)
a.legend(fontsize=8)

step = [float(r["step"]) for r in straight]
con = [mean_se(r["contacts"]) for r in straight]
app = [mean_se(r["appositions"]) for r in straight]
b.errorbar(step, [m for m, _ in con], yerr=[2 * s for _, s in con], fmt="s-", capsize=3, label="contacts (segment pairs)")
b.errorbar(step, [m for m, _ in app], yerr=[2 * s for _, s in app], fmt="o-", capsize=3, label="appositions (runs)")
b.set_xscale("log")
b.set_yscale("log")
b.minorticks_off()
b.set_xticks(step, ["%g" % x for x in step])
b.set_xlabel("step along the neurites")
b.set_ylabel("count per replicate")
b.set_title("§B straight neurites: runs have a limit", fontsize=9)
b.legend(fontsize=8)

labels = [r["level"] for r in grown]
x = range(len(labels))
ap = [mean_se(r["appositions per neuron"]) for r in grown]
cn = [mean_se(r["connections per neuron"]) for r in grown]
c.errorbar(x, [m for m, _ in ap], yerr=[2 * s for _, s in ap], fmt="o", capsize=3, label="appositions per neuron")
c.errorbar(x, [m for m, _ in cn], yerr=[2 * s for _, s in cn], fmt="s", capsize=3, label="connections per neuron")
c.set_xticks(list(x), labels, rotation=35, ha="right", fontsize=7)
c.set_ylabel("per neuron (±2 SE)")
c.set_title("§D grown cultures (5 days, d = 2 µm; ±2 SE over seeds)", fontsize=9)
c.legend(fontsize=8)
fig.tight_layout()
savefig_whole(fig, sys.argv[-1])
