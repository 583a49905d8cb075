#!/usr/bin/python3
"""The cost of one large direct-guidance network on one machine (docs/scaling.md §1.1).

Runs `axonguide run` on scenes/paper-direct-5000.json scaled to N neurons at the same
density (the region's radius grows as N^(1/3)) and reads the manifest: every phase's
time, the output's size, the peak memory (bytes per neuron) and the wall time of the whole
command. The ratio of the largest run to the smallest is the cost of 10x the work (linear
cost: 10). Each N runs --repeats times; the medians are reported.

Usage: bench/large_direct.py BUILD/bin/axonguide [--sizes 1000000,10000000] [--repeats R]
                             [--threads T] [--sonata] [--no-csv] [--drop-caches] [--out DIR]
                             [--json OUT.json]

--sonata writes SONATA beside the CSV; --no-csv writes SONATA instead of it
(output.csv: false), the format README recommends at 10^7. --drop-caches (root) empties the
page cache before each run, after the previous output is deleted and synced: without it the
output phase at 10^7 moved by about 1.5 s with what the cache held.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def scene(n, sonata, csv=True):
    with open(os.path.join(HERE, "..", "scenes", "paper-direct-5000.json")) as f:
        s = json.load(f)
    s["neurons"]["count"] = n
    s["neurons"]["region"]["radius"] = round(9.2101 * (n / 5000.0) ** (1.0 / 3.0), 3)
    if sonata or not csv:
        s.setdefault("output", {})["sonata"] = True
    if not csv:
        s["output"]["csv"] = False
    return s


def run_once(binary, n, threads, sonata, work, csv=True, drop_caches=False):
    path = os.path.join(work, f"scene-{n}.json")
    with open(path, "w") as f:
        json.dump(scene(n, sonata, csv), f)
    out = os.path.join(work, f"out-{n}")
    # The previous run's gigabytes of output are still being written back to the disk; that
    # traffic would land in this run's timings (its output phase moved by 2x without it).
    os.sync()
    if drop_caches:
        with open("/proc/sys/vm/drop_caches", "w") as f:
            f.write("3\n")
        time.sleep(1.0)
    t0 = time.monotonic()
    subprocess.run([binary, "run", path, "--out", out, "--force", "-q", "--threads", str(threads)], check=True)
    wall = time.monotonic() - t0
    with open(os.path.join(out, "manifest.json")) as f:
        m = json.load(f)
    size = sum(os.path.getsize(os.path.join(d, x)) for d, _, files in os.walk(out) for x in files)
    shutil.rmtree(out)
    return {"wall": wall, "phases": m["timings_seconds"], "peak": m["peak_memory_bytes"], "bytes_out": size}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("--sizes", default="1000000,10000000")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sonata", action="store_true", help="output.sonata (the CSV files are written too)")
    ap.add_argument("--no-csv", action="store_true", help="output.sonata and output.csv = false: SONATA alone")
    ap.add_argument("--drop-caches", action="store_true", help="empty the page cache before each run (root)")
    ap.add_argument("--out", default=None, help="working folder (default: a temporary one)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    sizes = [int(x) for x in a.sizes.split(",")]
    work = a.out or tempfile.mkdtemp(prefix="axg-large-")
    os.makedirs(work, exist_ok=True)
    rows = []
    for n in sizes:
        runs = [run_once(a.binary, n, a.threads, a.sonata, work, not a.no_csv, a.drop_caches) for _ in range(a.repeats)]
        phases = {k: statistics.median(r["phases"].get(k, 0.0) for r in runs) for k in runs[0]["phases"]}
        row = {"neurons": n, "wall": statistics.median(r["wall"] for r in runs), "phases": phases,
               "peak_bytes": max(r["peak"] for r in runs), "bytes_out": runs[0]["bytes_out"]}
        row["bytes_per_neuron"] = row["peak_bytes"] / n
        rows.append(row)
        print(f"{n:>10} neurons: {row['wall']:.2f} s wall, peak {row['peak_bytes'] / 1e6:.0f} MB "
              f"({row['bytes_per_neuron']:.0f} B/neuron), output {row['bytes_out'] / 1e9:.2f} GB")
        print("            " + ", ".join(f"{k} {v:.2f} s" for k, v in sorted(phases.items())))
    if len(rows) > 1:
        first, last = rows[0], rows[-1]
        work_ratio = last["neurons"] / first["neurons"]
        print(f"cost of {work_ratio:g}x the work: {last['wall'] / first['wall']:.2f}x wall")
        for k in sorted(last["phases"]):
            if first["phases"].get(k, 0) > 0:
                print(f"  {k}: {last['phases'][k] / first['phases'][k]:.2f}x")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"threads": a.threads, "sonata": a.sonata, "rows": rows}, f, indent=1)
    if not a.out:
        shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
