#!/usr/bin/python3
"""Strong and weak scaling of one network decomposed over MPI ranks (docs/scaling.md §3).

Runs `mpirun -np K axonguide run` and reads rank 0's manifest: the phase times and the
decomposition's facts (placement rounds, axons and particles migrated, the halo's
particles and ghost values, messages and bytes per step, peak memory). Every run is
checked against the one-process run of the same scene (neurons.csv, connections.csv,
bfs.csv and stats.csv compared byte for byte); a mismatch stops the benchmark.

--field direct (the default): direct-guidance scenes at the report's density (100
  neurons in a ball of radius 2.5 LU), the default wandering, 100 steps.
--field particles: the particle field, SNR steering on the estimate, at the report's
  density; sources of 20000 particles a step (--emission) at the centres of the K blocks (weak) or the
  first source alone at the centre (strong), 60 steps.
--field gather: the same particles, source_vector_sum steering: every growth cone gathers
  the particles within r from the hashed grid, so every rank keeps a halo r wide.
--field grid: the implicit grid field, SNR steering, the same neurons; grid spacing h =
  radius / 70
  (strong), or h / K^(1/3) so that the nodes grow with K (weak), 60 steps.

  strong: N fixed, K = 1, 2, 4 (one thread a rank; the one-process reference engine on
          1 and 2 threads beside it);
  weak:   N = N1 x K, K = 1, 2, 4 (each beside the one-process engine on 1 thread).

Throughput per rank: particle-steps (the particles alive after each step, summed over
the steps) or voxel updates (nodes x cues x sub-steps x steps) per second of field time,
divided by the rank count.

On a machine with fewer cores than ranks the ranks share cores (--oversubscribe): the
times then show the cost of the decomposition, not its speed-up; the bytes and messages
per step are what a real cluster would carry.

Usage: bench/mpi_scaling.py BUILD/bin/axonguide [--field F] [--strong N] [--weak N1 (0: none)]
                            [--ranks 1,2,4] [--repeats R] [--mca pml=ob1] [--json OUT.json]
                            [--markdown OUT.md]

--mca KEY=VALUE passes `--mca KEY VALUE` to mpirun. On one machine Open MPI 4.1 from Debian
starts its UCX layer by default, which costs about 0.2 s of every run's start on the 2-core
VM (MPI_Init of an empty program: 0.33 s, 0.11 s with pml=ob1, its shared-memory path).
"""
import argparse
import filecmp
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

COMPARED = ["neurons.csv", "connections.csv", "bfs.csv", "stats.csv"]


FIELD = "direct"
EMISSION = 20000  # particles a step from each source
WEAK_K = 1  # the weak-scaling rank count the scene is sized for (sources, grid nodes)
MCA = []  # mpirun's --mca options (--mca pml ob1: Open MPI's shared-memory path, without UCX's start-up)


def block_centres(k, half):
    bx, by, bz = {1: (1, 1, 1), 2: (2, 1, 1), 4: (2, 2, 1), 8: (2, 2, 2)}[k]
    c = lambda i, p: -half + (i + 0.5) * 2 * half / p
    return [[c(i, bx), c(j, by), c(l, bz)] for l in range(bz) for j in range(by) for i in range(bx)]


def scene(n):
    radius = round(2.5 * (n / 100.0) ** (1.0 / 3.0) * 1e4) / 1e4
    s = {"neurons": {"count": n, "region": {"radius": radius}}, "guidance": {"model": "direct"}, "steps": 100,
         "analysis": {"bfs_sources": [0], "components": True}}
    if FIELD == "direct":
        return s
    s["guidance"] = {"model": "snr"}
    s["steps"] = 60
    s["output"] = {"stats_every": 1}
    if FIELD == "gather":
        s["guidance"] = {"model": "source_vector_sum"}
    if FIELD in ("particles", "gather"):
        centres = block_centres(WEAK_K, radius) if WEAK_K > 1 else [[0.0, 0.0, 0.0]]
        s["cues"] = {"field": "particles", "sources": [{"kind": "attractant", "position": p, "emission": EMISSION}
                                                       for p in centres]}
    else:
        h = round(radius / 70.0 / WEAK_K ** (1.0 / 3.0) * 1e4) / 1e4
        s["cues"] = {"field": "grid", "sources": [{"kind": "attractant", "position": [0.3, 0.2, -0.1]}],
                     "grid": {"spacing": h}}
    return s


def field_work(out, m):
    """Particle-steps (stats.csv) or voxel updates (the grid's note) of a run."""
    if FIELD in ("particles", "gather"):
        rows = open(os.path.join(out, "stats.csv")).read().split("\n")[1:]
        return float(sum(int(r.split(",")[4]) for r in rows if r and not r.startswith("0,")))
    if FIELD == "grid":
        import re
        n = int(re.search(r"(\d+)\^3 nodes", m["summary"]["cue_field"]).group(1))
        return float(n ** 3) * len(scene(1)["cues"]["sources"]) * m["summary"]["steps_run"]
    return 0.0


def run(cmd, out):
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    p = subprocess.run(cmd + ["--out", out, "-q"], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stderr}")
    m = json.load(open(os.path.join(out, "manifest.json")))
    m["field_work"] = field_work(out, m)
    return wall, m


def measure(exe, mpiexec, n, ranks, repeats, tmp, one_threads):
    path = os.path.join(tmp, f"scene-{n}-{WEAK_K}.json")
    json.dump(scene(n), open(path, "w"))
    rows = []
    ref_dir = os.path.join(tmp, f"one-{n}-{WEAK_K}")
    for threads in one_threads:
        walls, mans = [], []
        for _ in range(repeats):
            w, m = run([exe, "run", path, "--threads", str(threads)], ref_dir)
            walls.append(w), mans.append(m)
        rows.append(summarize(n, 0, threads, walls, mans))
    for k in ranks:
        walls, mans = [], []
        out = os.path.join(tmp, f"np{k}-{n}")
        for _ in range(repeats):
            w, m = run([mpiexec, "--allow-run-as-root", "--oversubscribe"] + MCA + ["-np", str(k), exe, "run", path,
                        "--threads", "1"], out)
            walls.append(w), mans.append(m)
            for f in COMPARED:
                if not filecmp.cmp(os.path.join(ref_dir, f), os.path.join(out, f), shallow=False):
                    sys.exit(f"-np {k}, {n} neurons: {f} differs from the one-process run")
        rows.append(summarize(n, k, 1, walls, mans))
    return rows


def summarize(n, ranks, threads, walls, mans):
    med = lambda xs: statistics.median(xs)
    t = lambda key: med([m["timings_seconds"].get(key, 0.0) for m in mans])
    steps = t("grow") + t("compact") + t("migrate") + t("steer")
    field = sum(med([m["timings_seconds"].get(k, 0.0) for m in mans])
                for k in mans[0]["timings_seconds"] if k.startswith("particles.") or k.startswith("grid."))
    steps += field
    summary = mans[0]["summary"]
    work = mans[0]["field_work"]
    row = {"neurons": n, "field_s": field, "field_work": work,
           "per_rank_throughput": work / field / max(ranks, 1) if field > 0 else 0.0, "ranks": ranks, "threads": threads, "wall_s": med(walls), "wall_min_s": min(walls),
           "wall_max_s": max(walls), "placement_s": t("placement"), "setup_s": t("setup"), "steps_s": steps,
           "readback_s": t("readback"), "graph_s": t("graph"), "output_s": t("output"),
           "steps_run": mans[0]["summary"]["steps_run"], "peak_rank0_bytes": mans[0]["peak_memory_bytes"]}
    d = mans[0].get("decomposition")
    if d:
        row.update({"blocks": d["blocks"], "placement_rounds": d["placement"]["rounds"],
                    "placement_collective_bytes": d["placement"]["collective_bytes"],
                    "migrated_per_step": d["per_step"]["migrated_axons"], "messages_per_step": d["per_step"]["messages"],
                    "message_bytes_per_step": d["per_step"]["message_bytes"],
                    "collectives_per_step_rank": d["per_step"]["collectives_per_rank"],
                    "collective_bytes_per_step": d["per_step"]["collective_bytes"],
                    "halo_somas": d["halo_somas"], "somas_per_rank_max": d["somas_per_rank"]["max"],
                    "gathered_bytes": d["gathered"]["bytes"],
                    "peak_other_bytes": d["peak_memory_bytes"]["largest_other"],
                    "migrated_particles_per_step": d["per_step"].get("migrated_particles", 0.0),
                    "halo_particles_per_step": d["per_step"].get("halo_particles", 0.0),
                    "owned_particles_per_step": d["per_step"].get("owned_particles", 0.0),
                    "halo_message_bytes_per_step": d["per_step"].get("halo_message_bytes", 0.0),
                    "ghost_values_per_step": d["per_step"].get("ghost_values", 0.0),
                    "pipeline_stages_per_step": d["per_step"].get("pipeline_stages", 0.0)})
    return row


def markdown_field(rows, title):
    unit = "voxel updates/s" if FIELD == "grid" else "particle-steps/s"
    out = [f"**{title}**", "",
           f"| neurons | run | wall s (min–max) | field s | steps s (field included) | {unit} per rank | "
           "migrated particles / step | halo particles / step | ghost values / step | pipeline stages / step | "
           "halo bytes / step | all bytes / step | peak MiB rank 0 / other |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        who = f"1 process, {r['threads']} thread{'s' if r['threads'] > 1 else ''}" if r["ranks"] == 0 else \
            f"-np {r['ranks']} ({'×'.join(map(str, r['blocks']))})"
        dec = r["ranks"] > 0
        out.append(
            f"| {r['neurons']:,} | {who} | {r['wall_s']:.2f} ({r['wall_min_s']:.2f}–{r['wall_max_s']:.2f}) | "
            f"{r['field_s']:.2f} | {r['steps_s']:.2f} | {r['per_rank_throughput']:.3g} | "
            + (f"{r['migrated_particles_per_step']:.0f} | {r['halo_particles_per_step']:.0f} | "
               f"{r['ghost_values_per_step']:.0f} | {r['pipeline_stages_per_step']:.0f} | "
               f"{r['halo_message_bytes_per_step']:.0f} | "
               f"{r['message_bytes_per_step'] + r['collective_bytes_per_step']:.0f} | "
               f"{r['peak_rank0_bytes'] / 2**20:.0f} / {r['peak_other_bytes'] / 2**20:.0f} |"
               if dec else f"– | – | – | – | – | – | {r['peak_rank0_bytes'] / 2**20:.0f} |"))
    return "\n".join(out)


def markdown(rows, title):
    if FIELD != "direct":
        return markdown_field(rows, title)
    out = [f"**{title}**", "",
           "| neurons | run | wall s (min–max) | placement s | steps s | readback + graph + output s | "
           "rounds | migrated / step | messages / step | bytes / step | collectives / step / rank | peak MiB rank 0 / other |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        who = f"1 process, {r['threads']} thread{'s' if r['threads'] > 1 else ''}" if r["ranks"] == 0 else \
            f"-np {r['ranks']} ({'×'.join(map(str, r['blocks']))})"
        dec = r["ranks"] > 0
        out.append(
            f"| {r['neurons']:,} | {who} | {r['wall_s']:.2f} ({r['wall_min_s']:.2f}–{r['wall_max_s']:.2f}) | "
            f"{r['placement_s']:.2f} | {r['steps_s']:.2f} | {r['readback_s'] + r['graph_s'] + r['output_s']:.2f} | "
            + (f"{r['placement_rounds']} | {r['migrated_per_step']:.0f} | {r['messages_per_step']:.1f} | "
               f"{r['message_bytes_per_step']:.0f} + {r['collective_bytes_per_step']:.0f} | "
               f"{r['collectives_per_step_rank']:.0f} | {r['peak_rank0_bytes'] / 2**20:.0f} / "
               f"{r['peak_other_bytes'] / 2**20:.0f} |"
               if dec else f"– | – | – | – | – | {r['peak_rank0_bytes'] / 2**20:.0f} |"))
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("exe")
    ap.add_argument("--mpiexec", default=shutil.which("mpiexec") or "mpiexec")
    ap.add_argument("--strong", type=int, default=1000000)
    ap.add_argument("--weak", type=int, default=250000, help="neurons a rank; 0: strong scaling alone")
    ap.add_argument("--ranks", default="1,2,4")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--field", choices=["direct", "particles", "gather", "grid"], default="direct")
    ap.add_argument("--emission", type=int, default=20000)
    ap.add_argument("--mca", action="append", default=[], metavar="KEY=VALUE",
                    help="an Open MPI parameter for mpirun (repeatable), e.g. pml=ob1")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    a = ap.parse_args()
    global FIELD, WEAK_K, EMISSION, MCA
    FIELD, EMISSION = a.field, a.emission
    for kv in a.mca:
        key, _, value = kv.partition("=")
        MCA += ["--mca", key, value]
    ranks = [int(k) for k in a.ranks.split(",")]
    tmp = tempfile.mkdtemp(prefix="axg-scaling-")
    try:
        strong = measure(a.exe, a.mpiexec, a.strong, ranks, a.repeats, tmp, [1, 2])
        weak = []
        for k in (ranks if a.weak > 0 else []):
            WEAK_K = k
            weak += measure(a.exe, a.mpiexec, a.weak * k, [k], a.repeats, tmp, [1])
        WEAK_K = 1
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    mca = f" (mpirun {' '.join(MCA)})" if MCA else ""
    text = "\n\n".join([markdown(strong, f"Strong scaling, {a.strong:,} neurons{mca}")]
                       + ([markdown(weak, f"Weak scaling, {a.weak:,} neurons a rank{mca}")] if weak else []))
    print(text)
    if a.markdown:
        open(a.markdown, "w").write(text + "\n")
    if a.json:
        json.dump({"strong": strong, "weak": weak, "cores": os.cpu_count()}, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
