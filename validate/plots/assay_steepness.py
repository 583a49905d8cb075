"""Directional bias against steepness, with the shallow-gradient line."""
import sys
from common import plt, read_csv, save

rows = read_csv(sys.argv[1])
s = [float(r["steepness (%/10 um)"]) for r in rows]
b = [float(r["bias"]) for r in rows]
lo = [float(r["CI low"]) for r in rows]
hi = [float(r["CI high"]) for r in rows]
fig, ax = plt.subplots(figsize=(5.5, 3.6))
ax.errorbar(s, b, yerr=[[x - l for x, l in zip(b, lo)], [h - x for x, h in zip(b, hi)]], fmt="o", capsize=2,
            label="model, 95% CI")
ax.plot(s, [float(r["shallow line"]) for r in rows], "--", lw=1, label="line through shallow points")
ax.set_xscale("log")
ax.set_ylim(min(lo) - 0.05, max(hi) + 0.1)
ax.set_xlabel("steepness (% per 10 um)")
ax.set_ylabel("directional bias")
ax.legend(fontsize=7)
save(fig, sys.argv[-1])
