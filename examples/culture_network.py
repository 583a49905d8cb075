#!/usr/bin/env python3
"""The bundled culture network (scenes/culture-network.json: the calibrated culture grown
to 14 days, synapses where axons pass within 2 um of dendrites) over several seeds: its
network statistics with two-sided 95 % Student-t intervals over the seeds.

    PYTHONPATH=build/python python3 examples/culture_network.py --seeds 8

Each seed is one culture (300 neurons, 1 um sample length; about 10 s on 2 cores). The
statistics are `axonguide network`'s, computed here with networkx on the same graph
(tests/python/test_network.py checks that the two agree): connections and synapses per
neuron, synapses per connection, connection probability, reciprocity, the clustering
coefficient of the undirected graph, and the mean directed path length over reachable
pairs; beside them the arbours' size (axon length, axon terminal segments, dendrites per
neuron). Days 1-5 are the shared data's range (docs/validation.md §12.8); day 14 is a
prediction. --quick runs 60 neurons to day 3 with 2 seeds (for tests).
"""

import argparse
import json
import math
import pathlib
import statistics
import sys

import networkx as nx
import numpy as np

import axonguide

ROOT = pathlib.Path(__file__).resolve().parents[1]

# Two-sided 95 % Student-t quantiles by degrees of freedom.
T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228,
       11: 2.201, 12: 2.179, 15: 2.131, 19: 2.093, 29: 2.045}


def t95(df):
    return T95.get(df, T95[max(k for k in T95 if k <= df)])


def measure(result):
    g = result.to_networkx()
    n = g.number_of_nodes()
    c = result.connections
    lengths = [d for u, paths in nx.all_pairs_shortest_path_length(g) for v, d in paths.items() if u != v]
    axon_um, terminals, dendrites = [], [], []
    for i in range(n):
        a = result.arbour(i)
        is_axon = a.type == 2
        children = np.bincount(a.parent[1:], minlength=len(a.type))
        seg = np.linalg.norm(a.point[1:] - a.point[a.parent[1:]], axis=1)
        stem = a.parent[1:] == 0
        axon_um.append(float(seg[is_axon[1:] & ~stem].sum()))
        terminals.append(int(((children == 0) & is_axon).sum()))
        dendrites.append(int(((a.parent == 0) & (a.type == 3)).sum()))
    return {
        "connections per neuron": len(c) / n,
        "synapses per neuron": float(c["synapses"].sum()) / n,
        "synapses per connection": float(c["synapses"].mean()) if len(c) else math.nan,
        "connection probability": len(c) / (n * (n - 1)),
        "reciprocity": nx.reciprocity(g) if len(c) else math.nan,
        "clustering": nx.average_clustering(g.to_undirected()),
        "mean path length": statistics.fmean(lengths) if lengths else math.nan,
        "reachable pairs": len(lengths) / (n * (n - 1)),
        "axon length per neuron (um)": statistics.fmean(axon_um),
        "axon terminal segments per neuron": statistics.fmean(terminals),
        "dendrites per neuron": statistics.fmean(dendrites),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    scene = json.loads((ROOT / "scenes" / "culture-network.json").read_text())
    seeds = 2 if args.quick else args.seeds
    if args.quick:
        scene["neurons"]["count"] = 60
        scene["neurons"]["region"]["radius"] = 400
        scene["steps"] = 144
        scene["arbours"]["sample_length"] = 4
    rows = []
    for seed in range(1, seeds + 1):
        scene["seed"] = seed
        rows.append(measure(axonguide.run(scene, threads=args.threads)))
        print(f"seed {seed} done", file=sys.stderr, flush=True)
    print(f"| statistic (day {scene['steps'] * scene['dt'] / 24:g}, {scene['neurons']['count']} neurons, "
          f"{seeds} seeds) | mean | 95 % CI |")
    print("|---|---|---|")
    for key in rows[0]:
        v = [r[key] for r in rows]
        m = statistics.fmean(v)
        h = t95(len(v) - 1) * statistics.stdev(v) / math.sqrt(len(v)) if len(v) > 1 else math.nan
        print(f"| {key} | {m:.4g} | {m - h:.4g} – {m + h:.4g} |")


if __name__ == "__main__":
    main()
