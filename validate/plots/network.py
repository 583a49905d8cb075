"""axonguide network DIR: the out- and in-degree distributions, synapses per connection, and
the connection probability against intersomatic distance (95 % Wilson intervals)
-> DIR/network.png."""
import csv
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402

d = Path(sys.argv[1])
deg = list(csv.DictReader(open(d / "degrees.csv")))
per = list(csv.DictReader(open(d / "synapses_per_connection.csv")))
prob = list(csv.DictReader(open(d / "connection_probability.csv")))
summary = {r["statistic"]: float(r["value"]) for r in csv.DictReader(open(d / "network.csv"))}

fig, axes = plt.subplots(1, 3, figsize=(13, 3.7))
ax = axes[0]
k = [int(r["degree"]) for r in deg]
ax.step(k, [int(r["out_neurons"]) for r in deg], where="mid", label="out-degree")
ax.step(k, [int(r["in_neurons"]) for r in deg], where="mid", label="in-degree")
ax.set_xlabel("degree (connections)")
ax.set_ylabel("neurons")
ax.set_title("reciprocity %.3f, clustering %.3f, path %.2f" % (summary["reciprocity"], summary["clustering"],
                                                               summary["mean_path_length"]), fontsize=9)
ax.legend(fontsize=8)
ax = axes[1]
if per:
    ax.bar([int(r["synapses"]) for r in per], [int(r["connections"]) for r in per], width=0.8)
ax.set_xlabel("synapses per connection")
ax.set_ylabel("connections")
ax.set_title("mean %.2f synapses per connection" % summary["mean_synapses_per_connection"]
             if not math.isnan(summary["mean_synapses_per_connection"]) else "no connections", fontsize=9)
ax = axes[2]
rows = [r for r in prob if int(r["pairs"]) > 0]
if rows:
    mid = [(float(r["distance_lo_um"]) + float(r["distance_hi_um"])) / 2 for r in rows]
    p = [float(r["probability"]) for r in rows]
    lo = [pp - float(r["ci_lo"]) for pp, r in zip(p, rows)]
    hi = [float(r["ci_hi"]) - pp for pp, r in zip(p, rows)]
    ax.errorbar(mid, p, yerr=[lo, hi], fmt="o", ms=3, capsize=2)
ax.set_xlabel("intersomatic distance (µm)")
ax.set_ylabel("P(i → j connected)")
ax.set_title("connection probability (95 % Wilson CI)", fontsize=9)
fig.tight_layout()
savefig_whole(fig, d / "network.png")
