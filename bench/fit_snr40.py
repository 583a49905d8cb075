#!/usr/bin/python3
"""The cost of a 40-point fit of the stochastic SNR model (docs/validation.md §12.3, issue 40).

The data: the bias at the points of scenes/assay-explant.sweep.json (4 steepnesses x 10
concentrations, gain 40 and K_d = 1 nM), 10 seeds a point, each point on its own seeds
(1000 + 10 i to 1000 + 10 i + 9 for point i: explants shared between points would share
their random asymmetry, and the points' errors would not be independent), with each
point's SE from its 95 % CI (half-width / t(0.975, 9)). Data made by the model itself, so
the fit must also recover gain 40 and K_d 1 inside its intervals. Then `axonguide fit` with the given options (by
default the command's own: a 7 x 7 grid, two 5 x 5 refinements, the Gauss-Newton polish
and the profile intervals; the model's SE at most a third of the data's at every point),
timed end to end. Prints one JSON object: the wall time, parameter sets, runs, seeds, chi2,
and each parameter with its interval.

Usage: bench/fit_snr40.py BUILD/bin/axonguide [--out DIR] [--threads T] [-- FIT OPTIONS...]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
T975_9 = 2.2621571627409915  # Student t, 0.975 quantile, 9 dof


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("--out", default=None)
    ap.add_argument("--threads", type=int, default=0)
    argv = sys.argv[1:]
    fit_args = argv[argv.index("--") + 1:] if "--" in argv else []
    a = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    out = a.out or tempfile.mkdtemp(prefix="fit_snr40.")
    os.makedirs(out, exist_ok=True)
    scenes = os.path.join(HERE, "..", "scenes")
    threads = ["--threads", str(a.threads)] if a.threads else []
    with open(os.path.join(scenes, "assay-explant.sweep.json")) as f:
        grid = {p["key"]: p for p in json.load(f)["parameters"]}
    steepnesses = grid["cues.imposed.steepness"]["values"]
    lg = grid["cues.imposed.concentration"]["log"]
    concentrations = [lg["from"] * (lg["to"] / lg["from"]) ** (k / (lg["count"] - 1)) for k in range(lg["count"])]
    data = os.path.join(out, "data.csv")
    with open(data, "w") as g:
        g.write("# The bias at the points of scenes/assay-explant.sweep.json (gain 40, K_d 1 nM), 10 seeds a point,\n"
                "# point i on seeds 1000 + 10 i ... + 9; se = 95 % CI half-width / t(0.975, 9).\n"
                "concentration,steepness,bias,se,count\n")
        for i, (st, c) in enumerate((st, c) for st in steepnesses for c in concentrations):
            spec = {"scene": os.path.abspath(os.path.join(scenes, "assay-explant.json")),
                    "parameters": [{"key": "cues.imposed.steepness", "values": [st]},
                                   {"key": "cues.imposed.concentration", "values": [c]}],
                    "seeds": list(range(1000 + 10 * i, 1010 + 10 * i))}
            point_dir = os.path.join(out, "data", f"point{i:02d}")
            os.makedirs(point_dir, exist_ok=True)
            spec_path = os.path.join(point_dir, "sweep.json")
            with open(spec_path, "w") as f:
                json.dump(spec, f)
            subprocess.run([a.binary, "sweep", spec_path, "--out", os.path.join(point_dir, "sweep")] + threads,
                           check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(point_dir, "sweep", "summary.csv")) as f:
                row = next(csv.DictReader(f))
            se = (float(row["bias_ci_high"]) - float(row["bias_ci_low"])) / (2 * T975_9)
            g.write(f"{c!r},{st!r},{row['bias_mean']},{se},10\n")
    fit_dir = os.path.join(out, "fit")
    extra = fit_args
    t0 = time.monotonic()
    p = subprocess.run([a.binary, "fit", data, "--scene", os.path.join(scenes, "assay-explant.json"), "--out", fit_dir,
                        "--max-chi2", "1e9"] + threads + extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.stderr.write(p.stdout + p.stderr)
        sys.exit(p.returncode)
    with open(os.path.join(fit_dir, "fit.json")) as f:
        r = json.load(f)
    print(json.dumps({"wall_s": round(wall, 1), "fit_options": extra, "fit": r}, indent=1))


if __name__ == "__main__":
    main()
