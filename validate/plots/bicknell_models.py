"""The signalling model (Bicknell et al. 2018) beside the SNR model: directional bias and
radial outgrowth against concentration. Arguments: the paper-parameter fit_curve.csv, the
outgrowth-fitted fit_curve.csv, the SNR explant sweep's summary.csv, the gradient and the
uniform outgrowth data (CSV with '#' comments), the PNG."""
import sys
from common import plt, read_csv, save


def data_rows(path):
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#")]
    head = lines[0].strip().split(",")
    return [dict(zip(head, l.strip().split(","))) for l in lines[1:] if l.strip()]


paper, fitted, snr = read_csv(sys.argv[1]), read_csv(sys.argv[2]), read_csv(sys.argv[3])
grad, unif = data_rows(sys.argv[4]), data_rows(sys.argv[5])
fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 3.8))
colours = {"0.12": "C0", "0.18": "C1", "0.24": "C2", "0.3": "C3"}
for s, col in colours.items():
    for rows, style, who in ((paper, "-", "signalling, Table 1"), (fitted, "--", "signalling, fitted to outgrowth")):
        g = [r for r in rows if r["measure"] == "bias" and r["steepness"] == s]
        ax.plot([float(r["concentration"]) for r in g], [float(r["model"]) for r in g], style, color=col,
                label=f"{who}, {s} %" if s in ("0.12", "0.3") else None)
for s, col in (("0.1", "C0"), ("0.3", "C3")):
    g = [r for r in snr if r["steepness"] == s]
    ax.plot([float(r["concentration"]) for r in g], [float(r["bias"]) for r in g], ":", marker="o", ms=3, color=col,
            label=f"SNR explant, {s} %")
ax.set_xscale("log")
ax.axhline(0, color="0.5", lw=0.8)
ax.set_xlabel("NGF at the explant (nM, corrected)")
ax.set_ylabel("directional bias")
ax.legend(fontsize=6)
for rows, style, who in ((paper, "-", "signalling, Table 1"), (fitted, "--", "signalling, fitted")):
    g = [r for r in rows if r["measure"] == "outgrowth" and r["steepness"] == "0"]
    bx.plot([float(r["concentration"]) for r in g], [float(r["model"]) for r in g], style, color="k", label=who)
for s, col in list(colours.items()) + [("0", "0.4")]:
    g = [r for r in grad if r["steepness"] == s]
    bx.errorbar([float(r["concentration"]) for r in g], [float(r["outgrowth"]) for r in g],
                yerr=[2 * float(r["se"]) for r in g], fmt="o", ms=3, capsize=2, color=col,
                label=f"gradient data, {s} %" if s != "0" else "uniform control (gradient series)")
bx.errorbar([float(r["concentration"]) for r in unif], [float(r["outgrowth"]) for r in unif],
            yerr=[2 * float(r["se"]) for r in unif], fmt="s", ms=3, capsize=2, color="0.6", mfc="none",
            label="uniform data (Fig 1C series)")
bx.axhline(351.3, color="C4", lw=1, ls=":", label="SNR: outgrowth independent of C (best constant)")
bx.set_xscale("log")
bx.set_xlabel("NGF at the explant (nM, nominal)")
bx.set_ylabel("radial outgrowth (um)")
bx.legend(fontsize=6)
save(fig, sys.argv[-1])
