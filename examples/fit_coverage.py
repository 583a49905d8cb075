#!/usr/bin/env python3
"""The coverage of `fit`'s 95 % profile-likelihood intervals, measured: synthetic outgrowth
data made by the signalling model itself at known parameters, with Gaussian noise of the
stated SE, fitted again and again; the fraction of intervals that contain the truth.

    PYTHONPATH=build/python python3 examples/fit_coverage.py --replicates 100

The model is a 40-neuron explant of scenes/assay-bicknell.json in uniform NGF (30 steps
of 1.6 h) at 7 concentrations from 0.001 to 100 nM; truth r0 = 0.07 and kext = 0.03 um/min
(off every grid point of the searched ranges 0.02-0.2 and 0.005-0.08); the noiseless data
are the model's mean over seeds 101-104 (not the fit's seeds), the SE 3 % of each value.
Each replicate fits with the defaults of axonguide.fit but a 5-point grid and one
refinement. Prints each replicate and the coverage with its Wilson 95 % interval. See
docs/validation.md §12.3.
"""

import argparse
import json
import math
import pathlib

import numpy as np

import axonguide

ROOT = pathlib.Path(__file__).resolve().parent.parent


def wilson(k, n, z=1.96):
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return c - h, c + h


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--replicates", type=int, default=100)
    ap.add_argument("--seed", type=int, default=7, help="the noise's seed (numpy)")
    args = ap.parse_args()
    base = json.loads((ROOT / "scenes" / "assay-bicknell.json").read_text())
    base["neurons"]["count"], base["steps"], base["dt"] = 40, 30, 1.6
    conc = [0.001, 0.01, 0.1, 0.3, 1, 10, 100]
    truth = {"r0": 0.07, "kext": 0.03}

    def columns(outgrowth, se):
        return {"concentration": conc, "steepness": [0.0] * 7, "outgrowth": list(outgrowth), "se": list(se),
                "count": [20] * 7}

    # The model at the truth: a fit pinned to it (ranges of 1e-6 relative width), no polish.
    pinned = axonguide.fit(base, columns([300.0] * 7, [10.0] * 7), seeds=[101, 102, 103, 104], grid=2, refine=0,
                           polish=0, params=[(p, v * (1 - 1e-6), v * (1 + 1e-6)) for p, v in truth.items()])
    mean = np.asarray(pinned.model)
    rng = np.random.default_rng(args.seed)
    covered = {p: 0 for p in truth}
    for rep in range(args.replicates):
        se = 0.03 * mean
        f = axonguide.fit(base, columns(mean + rng.normal(0.0, se), se), seeds=[1, 2], max_seeds=8, grid=5, refine=1,
                          params=[("r0", 0.02, 0.2), ("kext", 0.005, 0.08)])
        for p in truth:
            lo, hi = f.intervals[p][:2]
            covered[p] += lo <= truth[p] <= hi
        print(rep, {p: (round(f.best[p], 5), round(f.intervals[p][0], 5), round(f.intervals[p][1], 5)) for p in truth},
              f"chi2 {f.chi2:.2f} on {f.dof} dof", flush=True)
    for p, k in covered.items():
        lo, hi = wilson(k, args.replicates)
        print(f"{p}: {k} of {args.replicates} intervals contain the truth ({k / args.replicates:.2f}, "
              f"Wilson 95 % [{lo:.3f}, {hi:.3f}]; nominal 0.95)")


if __name__ == "__main__":
    main()
