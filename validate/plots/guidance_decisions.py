"""Linear gradient: P(toward) against particles per mesh cell, and |P - Phi| (log-log)."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
fig, (a, b, c) = plt.subplots(1, 3, figsize=(11, 3.4))
for form, ax in (("binding", a), ("count", b)):
    for snr in sorted({float(r["SNR"]) for r in rows if r["form"] == form}):
        g = [r for r in rows if r["form"] == form and float(r["SNR"]) == snr]
        n = [float(r["nu"]) for r in g]
        line = ax.errorbar(n, [float(r["P(toward)"]) for r in g], yerr=[1.96 * float(r["SE"]) for r in g],
                           fmt="o-", ms=4, capsize=2, label=f"SNR {snr:g}")[0]
        ax.axhline(float(g[0]["Phi(SNR)"]), color=line.get_color(), ls="--", lw=1)
    ax.set_xscale("log")
    ax.set_xlabel("particles per mesh cell")
    ax.set_ylabel("P(turn toward +x)")
    ax.set_title(form, fontsize=9)
    ax.legend(fontsize=7)
for form, m in (("binding", "o-"), ("count", "^--")):
    for snr in sorted({float(r["SNR"]) for r in rows if r["form"] == form}):
        g = [r for r in rows if r["form"] == form and float(r["SNR"]) == snr]
        pts = [(float(r["nu"]), abs(float(r["P - Phi"]))) for r in g if abs(float(r["P - Phi"])) > 0]
        if pts:
            c.loglog([p[0] for p in pts], [p[1] for p in pts], m, ms=4, label=f"{form}, SNR {snr:g}")
ns = sorted({float(r["nu"]) for r in rows})
c.loglog(ns, [0.1 * ns[0] / x for x in ns], "k:", label="1/nu")
c.set_xlabel("particles per mesh cell")
c.set_ylabel("|P - Phi|")
c.legend(fontsize=6)
save(fig, sys.argv[-1])
