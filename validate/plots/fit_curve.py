"""axonguide fit: the fitted bias curve against the data, per steepness -> DIR/fit.png."""
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

d = Path(sys.argv[1])
pts = list(csv.DictReader(open(d / "fit_points.csv")))
curve = list(csv.DictReader(open(d / "fit_curve.csv")))
fit = json.load(open(d / "fit.json"))
fig, ax = plt.subplots(figsize=(6, 4))
steeps = sorted({float(r["steepness"]) for r in pts})
for k, s in enumerate(steeps):
    col = "C%d" % k
    c = [r for r in curve if float(r["steepness"]) == s]
    ax.plot([float(r["concentration"]) for r in c], [float(r["model"]) for r in c], "-", color=col,
            label="model, %g %%" % s)
    p = [r for r in pts if float(r["steepness"]) == s]
    ax.errorbar([float(r["concentration"]) for r in p], [float(r["bias"]) for r in p],
                yerr=[2 * float(r["se"]) for r in p], fmt="o" , color=col, capsize=3, label="data, %g %%" % s)
    bad = [r for r in p if r["reachable"] == "no"]
    ax.plot([float(r["concentration"]) for r in bad], [float(r["bias"]) for r in bad], "x", color="k", ms=10)
ax.set_xscale("log")
ax.axhline(0, color="0.5", lw=0.8)
ax.set_xlabel("concentration (%s)" % fit["units"].split("concentration ")[-1])
ax.set_ylabel("directional bias")
ax.set_title("gain %.3g, K_d %.3g, chi2/dof %.2f (x: unreachable)" % (fit["gain"], fit["kd"], fit["chi2_per_dof"]),
             fontsize=9)
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(d / "fit.png", dpi=110)
