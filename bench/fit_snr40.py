#!/usr/bin/python3
"""The cost of a 40-point fit of the stochastic SNR model (docs/methods.md §12.3, issue 40).

The data: the bias of scenes/assay-explant.sweep.json (4 steepnesses x 10 concentrations,
10 seeds a point, gain 40 and K_d = 1 nM), with each point's SE from its 95 % CI
(half-width / t(0.975, 9)). Data made by the model itself, so the fit must also recover
gain 40 and K_d 1 inside its intervals. Then `axonguide fit` with the given options (by
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
    sweep_dir = os.path.join(out, "sweep")
    subprocess.run([a.binary, "sweep", os.path.join(scenes, "assay-explant.sweep.json"), "--out", sweep_dir] + threads,
                   check=True, stdout=subprocess.DEVNULL)
    data = os.path.join(out, "data.csv")
    with open(os.path.join(sweep_dir, "summary.csv")) as f, open(data, "w") as g:
        g.write("# The bias of scenes/assay-explant.sweep.json (gain 40, K_d 1 nM), 10 seeds a point;\n"
                "# se = 95 % CI half-width / t(0.975, 9).\nconcentration,steepness,bias,se,count\n")
        for row in csv.DictReader(f):
            se = (float(row["bias_ci_high"]) - float(row["bias_ci_low"])) / (2 * T975_9)
            g.write(f"{row['cues.imposed.concentration']},{row['cues.imposed.steepness']},{row['bias_mean']},{se},10\n")
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
