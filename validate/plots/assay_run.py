"""axonguide assay DIR: R(theta) (polar) and the turning-angle histogram -> DIR/assay.png."""
import csv
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from whole_file import savefig_whole  # noqa: E402

d = Path(sys.argv[1])
prof = list(csv.DictReader(open(d / "assay_profile.csv")))
turn = list(csv.DictReader(open(d / "assay_turning.csv")))
metrics = {r["metric"]: r for r in csv.DictReader(open(d / "assay.csv"))}

fig = plt.figure(figsize=(9, 4))
ax = fig.add_subplot(1, 2, 1, projection="polar")
th = [math.radians(float(r["theta_deg"])) for r in prof]
R = [float(r["outgrowth"]) for r in prof]
ax.plot(th + th[:1], R + R[:1], "-o", ms=3)
ax.set_title("outgrowth R(θ); gradient up (θ = 90°)\nbias %s" % metrics["bias"]["value"][:7], fontsize=9)
ax2 = fig.add_subplot(1, 2, 2)
lo = [float(r["from_deg"]) for r in turn]
n = [int(r["axons"]) for r in turn]
ax2.bar(lo, n, width=10, align="edge")
ax2.set_xlabel("turning angle (°, + toward the gradient)")
ax2.set_ylabel("axons")
ax2.set_title("mean %s°" % metrics["mean_turning_deg"]["value"][:6], fontsize=9)
fig.tight_layout()
savefig_whole(fig, d / "assay.png", dpi=110)
