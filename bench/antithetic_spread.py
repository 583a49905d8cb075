#!/usr/bin/python3
"""The variance that antithetic mirror images remove (docs/validation.md §12.3).

scenes/assay-explant.json at steepness 0.2 % and three concentrations (0.01, 1 and 100 x
K_d), N seeds: each seed run with the gradient, with its mirror image on the same draws,
and with its mirror image antithetic (guidance.antithetic). Prints, per concentration, the
mean and the SD over seeds of the pair's mean bias for both kinds of pair, the SD of a
single run's bias, and the variance ratio with a 95 % bootstrap interval (seeds resampled,
the two kinds of pair kept together: they share their first run).

Usage: bench/antithetic_spread.py BUILD/bin/axonguide [--seeds N] [--out DIR]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile

import random

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("--seeds", type=int, default=32)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    out = a.out or tempfile.mkdtemp(prefix="antithetic.")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(HERE, "..", "scenes", "assay-explant.json")) as f:
        base = json.load(f)
    biases = {}
    for name, sign, anti in (("plain", 1, False), ("mirror", -1, False), ("antithetic", -1, True)):
        scene = json.loads(json.dumps(base))
        scene["cues"]["imposed"]["direction"] = [sign, 0, 0]
        if anti:
            scene["guidance"]["antithetic"] = True
        spec = {"scene": scene, "seeds": a.seeds,
                "parameters": [{"key": "cues.imposed.concentration", "values": [0.01, 1, 100]},
                               {"key": "cues.imposed.steepness", "values": [0.2]}]}
        path = os.path.join(out, name + ".sweep.json")
        with open(path, "w") as f:
            json.dump(spec, f)
        subprocess.run([a.binary, "sweep", path, "--out", os.path.join(out, name)], check=True,
                       stdout=subprocess.DEVNULL)
        with open(os.path.join(out, name, "sweep.csv")) as f:
            biases[name] = {(float(r["cues.imposed.concentration"]), int(r["seed"])): float(r["bias"])
                            for r in csv.DictReader(f)}
    rows = []
    for c in (0.01, 1.0, 100.0):
        seeds = range(1, a.seeds + 1)
        single = [biases["plain"][(c, s)] for s in seeds]
        row = {"concentration": c, "single_sd": statistics.stdev(single)}
        for kind in ("mirror", "antithetic"):
            pair = [0.5 * (biases["plain"][(c, s)] + biases[kind][(c, s)]) for s in seeds]
            row[kind + "_mean"] = statistics.mean(pair)
            row[kind + "_sd"] = statistics.stdev(pair)
        ratio = (row["mirror_sd"] / row["antithetic_sd"]) ** 2
        rng = random.Random(1)
        boot = []
        for _ in range(2000):
            pick = [rng.choice(list(seeds)) for _ in seeds]
            m = [0.5 * (biases["plain"][(c, s)] + biases["mirror"][(c, s)]) for s in pick]
            t = [0.5 * (biases["plain"][(c, s)] + biases["antithetic"][(c, s)]) for s in pick]
            if statistics.variance(t) > 0:
                boot.append(statistics.variance(m) / statistics.variance(t))
        boot.sort()
        row["variance_ratio"] = ratio
        row["variance_ratio_95"] = [boot[int(0.025 * len(boot))], boot[int(0.975 * len(boot)) - 1]]
        rows.append(row)
    print(json.dumps({"seeds": a.seeds, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
