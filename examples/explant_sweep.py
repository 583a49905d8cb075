#!/usr/bin/env python3
"""The explant assay swept over concentration: directional bias against the nominal
concentration at the explant, one curve per gradient steepness, with 95 % intervals.

    PYTHONPATH=build/python python3 examples/explant_sweep.py --out fig.png

It runs scenes/assay-explant.sweep.json (4 steepnesses x 10 concentrations x 10 seeds =
400 members of 1000 neurons) with a no-gradient control added (steepness 0 at every
concentration: 100 more members; about 5 s on 2 cores) through axonguide.sweep, in
memory, and plots summary's bias_mean with its two-sided 95 % Student-t interval over the
seeds (bias_ci_low, bias_ci_high); the control's intervals should cover 0. --quick runs a
small version (200 neurons, 40 steps, the control and one steepness, 4 concentrations,
3 seeds; well under a second) for tests. See docs/methods.md
§12 (the assay and its metrics) and docs/guide.md §2 (the Python API).
"""

import argparse
import json
import pathlib
import sys
import time

import axonguide

ROOT = pathlib.Path(__file__).resolve().parents[1]


def with_control(spec):
    """The sweep with steepness 0 (no gradient) added: the control beside the treatment."""
    for p in spec["parameters"]:
        if p.get("key") == "cues.imposed.steepness" and 0 not in p["values"]:
            p["values"] = [0] + p["values"]
    return spec


def quick_spec(spec_path):
    """The sweep file with its scene inlined and made small."""
    spec = json.loads(spec_path.read_text())
    scene = json.loads((spec_path.parent / spec["scene"]).read_text())
    scene["neurons"]["populations"][0]["count"] = 200
    scene["steps"] = 40
    spec["scene"] = scene
    spec["parameters"] = [
        {"key": "cues.imposed.steepness", "values": [0.2]},
        {"key": "cues.imposed.concentration", "log": {"from": 0.001, "to": 100, "count": 4}},
    ]
    spec["seeds"] = 3
    return spec


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default="explant_sweep.png", help="the figure (PNG)")
    p.add_argument("--spec", default=str(ROOT / "scenes" / "assay-explant.sweep.json"), help="the sweep file")
    p.add_argument("--threads", type=int, default=None, help="worker threads (default: all cores)")
    p.add_argument("--quick", action="store_true", help="a small sweep (for tests)")
    args = p.parse_args(argv)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    spec_path = pathlib.Path(args.spec)
    spec_dict = quick_spec(spec_path) if args.quick else json.loads(spec_path.read_text())
    spec = axonguide.SweepSpec(with_control(spec_dict), folder=spec_path.parent)
    base = spec.member_scene(0).to_dict()
    unit = base["units"]["concentration"] or "concentration units"
    t0 = time.perf_counter()
    result = axonguide.sweep(spec, threads=args.threads)
    seconds = time.perf_counter() - t0
    if result.failed:
        print(f"explant_sweep: {result.failed} of {len(result)} members failed:", file=sys.stderr)
        for m in np.flatnonzero(result.records["status"] == "failed")[:5]:
            print(f"  member {m}: {result.records['message'][m]}", file=sys.stderr)

    s = result.summary
    conc = np.asarray(s["cues.imposed.concentration"], dtype=float)
    steep = np.asarray(s["cues.imposed.steepness"], dtype=float) if "cues.imposed.steepness" in s \
        else np.full(len(conc), base["cues"]["imposed"]["steepness"])
    mean, lo, hi = s["bias_mean"], s["bias_ci_low"], s["bias_ci_high"]

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ref = base["cues"]["imposed"]["reference_length"]
    length = {"um": "µm", "": "LU"}.get(base["units"]["length"], base["units"]["length"])
    for k, g in enumerate(sorted(set(steep.tolist()))):
        sel = steep == g
        order = np.argsort(conc[sel])
        x, y = conc[sel][order], mean[sel][order]
        err = np.vstack([y - lo[sel][order], hi[sel][order] - y])
        err = np.where(np.isfinite(err), err, 0.0)
        # Points side by side within a decade, so that the bars do not overlap.
        shift = 10 ** (0.03 * (k - (len(set(steep.tolist())) - 1) / 2))
        ax.errorbar(x * shift, y, yerr=err, marker="o", ms=4, capsize=3, lw=1.2,
                    color="0.45" if g == 0 else None, ls="--" if g == 0 else "-",
                    label="0 (control, no gradient)" if g == 0 else f"{g:g} % per {ref:g} {length}")
        print(f"steepness {g:g}: " + ", ".join(f"{c:.3g} {unit}: {b:+.4f}" for c, b in zip(x, y)))
    kd = [src.get("kd") for src in base["cues"]["sources"]]
    if kd and kd[0]:
        ax.axvline(kd[0], color="0.6", lw=0.8, ls=":")
        ax.text(kd[0], 0.98, " $K_d$", transform=ax.get_xaxis_transform(), va="top", color="0.4")
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel(f"concentration at the explant ({unit})")
    ax.set_ylabel("directional bias (mean, 95 % CI)")
    n = len(spec.seeds)
    ax.set_title(f"Explant assay: {len(result)} runs ({n} seeds per point){' — quick' if args.quick else ''}")
    ax.legend(title="gradient steepness", fontsize=8, title_fontsize=8)
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out)
    print(f"explant_sweep: {len(result)} members in {seconds:.1f} s on {result.threads} threads; wrote {args.out}")
    return 1 if result.failed else 0


if __name__ == "__main__":
    sys.exit(main())
