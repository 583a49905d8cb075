"""P(turn toward) against gamma for several mu: empirical points, Phi(SNR) lines."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, ax = plt.subplots(figsize=(5.5, 3.6))
for mu in sorted({float(r["mu"]) for r in rows}):
    g = sorted((r for r in rows if float(r["mu"]) == mu), key=lambda r: float(r["gamma"]))
    x = [float(r["gamma"]) for r in g]
    line, = ax.semilogx(x, [float(r["Phi(SNR)"]) for r in g], "-", label=f"mu = {mu:g}")
    ax.semilogx(x, [float(r["P(toward)"]) for r in g], "o", color=line.get_color(), ms=4)
ax.axvline(0.5, color="k", ls=":", lw=1)
ax.set_xlabel("gamma = C / K_d")
ax.set_ylabel("P(turn toward the gradient)")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
