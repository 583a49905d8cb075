"""axonguide morphometry DIR: the Sholl profile (mean crossings ± 2 SE) and the per-neuron
distributions of axon length and dendrite count -> DIR/morphometry.png."""
import csv
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402

d = Path(sys.argv[1])
sh = list(csv.DictReader(open(d / "sholl.csv")))
neurons = list(csv.DictReader(open(d / "morphometry_neurons.csv")))


def col(rows, k):
    return [float(r[k]) for r in rows]


fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
ax = axes[0]
if sh:
    r = col(sh, "radius")
    for g, c in (("axon", "C0"), ("dendrite", "C1")):
        m = col(sh, g + "_mean")
        se = [0.0 if math.isnan(x) else x for x in col(sh, g + "_se")]
        ax.plot(r, m, color=c, label=g + "s")
        ax.fill_between(r, [a - 2 * b for a, b in zip(m, se)], [a + 2 * b for a, b in zip(m, se)], color=c, alpha=0.2)
    ax.legend(fontsize=8)
ax.set_xlabel("distance from the soma (µm)")
ax.set_ylabel("crossings per neuron")
ax.set_title("Sholl profile (mean ± 2 SE)", fontsize=9)
lengths = [float(n["total_axon_length"]) for n in neurons if n["has_axon"] == "1"]
axes[1].hist(lengths, bins=30)
axes[1].set_xlabel("total axon length (µm)")
axes[1].set_ylabel("neurons")
dend = [int(n["number_of_dendrites_per_neuron"]) for n in neurons]
axes[2].hist(dend, bins=range(0, max(dend + [1]) + 2), align="left")
axes[2].set_xlabel("dendrites per neuron")
axes[2].set_ylabel("neurons")
fig.tight_layout()
savefig_whole(fig, d / "morphometry.png")
