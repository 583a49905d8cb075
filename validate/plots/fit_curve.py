"""axonguide fit: the fitted curves against the data, one panel per measure (bias,
outgrowth), one colour per steepness -> DIR/fit.png. Points are drawn at the model's
(corrected) concentration."""
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402

d = Path(sys.argv[1])
pts = list(csv.DictReader(open(d / "fit_points.csv")))
curve = list(csv.DictReader(open(d / "fit_curve.csv")))
fit = json.load(open(d / "fit.json"))
measures = fit["measured"]
fig, axes = plt.subplots(1, len(measures), figsize=(6 * len(measures), 4), squeeze=False)
steeps = sorted({float(r["steepness"]) for r in pts})
labels = {"bias": "directional bias (%s)" % fit["bias_metric"], "outgrowth": "radial outgrowth"}
for ax, m in zip(axes[0], measures):
    for k, s in enumerate(steeps):
        col = "C%d" % k
        c = [r for r in curve if float(r["steepness"]) == s and r["measure"] == m and r["model"]]
        ax.plot([float(r["concentration"]) for r in c], [float(r["model"]) for r in c], "-", color=col,
                label="model, %g %%" % s)
        p = [r for r in pts if float(r["steepness"]) == s and r["measure"] == m]
        ax.errorbar([float(r["model_concentration"]) for r in p], [float(r["value"]) for r in p],
                    yerr=[2 * float(r["se"]) for r in p], fmt="o", color=col, capsize=3, label="data, %g %%" % s)
        bad = [r for r in p if r["reachable"] == "no"]
        ax.plot([float(r["model_concentration"]) for r in bad], [float(r["value"]) for r in bad], "x", color="k",
                ms=10)
    ax.set_xscale("log")
    if m == "bias":
        ax.axhline(0, color="0.5", lw=0.8)
    ax.set_xlabel("concentration (%s)" % fit["units"].split("concentration ")[-1])
    ax.set_ylabel(labels[m])
    ax.legend(fontsize=7)
best = ", ".join("%s %.3g" % (k, v["best"]) for k, v in fit["parameters"].items())
fig.suptitle("%s; chi2/dof %.2f (x: unreachable)" % (best, fit["chi2_per_dof"]), fontsize=9)
fig.tight_layout()
savefig_whole(fig, d / "fit.png", dpi=110)
