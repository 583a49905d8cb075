"""`axonguide plot DIR`: PNG plots of one run's outputs (matplotlib).

Writes into DIR: growth.png (connections and growing axons against step), in_degree.png,
bfs_levels.png, axon_lengths.png and projection.png (the network projected on the x-y
plane). Plots whose input file is missing are skipped with a message.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

plt.rcParams.update({"figure.dpi": 100, "font.size": 9, "axes.grid": True, "grid.alpha": 0.3})
STATUS_COLORS = {"growing": "#1f77b4", "connected": "#2ca02c", "exited": "#ff7f0e", "max_steps": "#9467bd"}


def rows(d, name):
    path = os.path.join(d, name)
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, d, name, made):
    fig.tight_layout()
    fig.savefig(os.path.join(d, name))
    plt.close(fig)
    made.append(name)


def main(d):
    made, skipped = [], []
    stats = rows(d, "stats.csv")
    if stats:
        step = [int(r["step"]) for r in stats]
        fig, ax = plt.subplots(figsize=(5.5, 3.5))
        ax.plot(step, [int(r["connected"]) for r in stats], label="connected")
        ax.plot(step, [int(r["growing"]) for r in stats], label="growing")
        ax.plot(step, [int(r["exited"]) for r in stats], label="exited")
        if any(int(r["particles"]) for r in stats):
            ax2 = ax.twinx()
            ax2.plot(step, [int(r["particles"]) for r in stats], "k:", label="particles")
            ax2.set_ylabel("particles")
            ax2.grid(False)
        ax.set_xlabel("step")
        ax.set_ylabel("axons")
        ax.legend(loc="center right")
        save(fig, d, "growth.png", made)
    else:
        skipped.append("growth.png (no stats.csv)")
    neurons = rows(d, "neurons.csv")
    conns = rows(d, "connections.csv")
    if neurons and conns is not None:
        indeg = [0] * len(neurons)
        for c in conns:
            indeg[int(c["target"])] += 1
        fig, ax = plt.subplots(figsize=(5, 3.5))
        top = max(indeg) if indeg else 0
        counts = [indeg.count(k) for k in range(top + 1)]
        ax.bar(range(top + 1), counts)
        ax.set_yscale("log")
        ax.set_xlabel("in-degree (axons ending on the neuron)")
        ax.set_ylabel("neurons")
        save(fig, d, "in_degree.png", made)
    else:
        skipped.append("in_degree.png (needs neurons.csv and connections.csv)")
    bfs = rows(d, "bfs.csv")
    if bfs and "level" in bfs[0]:
        levels = [int(r["level"]) for r in bfs]
        reached = [v for v in levels if v >= 0]
        fig, ax = plt.subplots(figsize=(5, 3.5))
        top = max(reached) if reached else 0
        ax.bar(range(top + 1), [reached.count(k) for k in range(top + 1)])
        ax.set_xlabel("BFS level (from analysis.bfs_sources)")
        ax.set_ylabel("neurons")
        ax.set_title(f"{len(reached)} of {len(levels)} reached")
        save(fig, d, "bfs_levels.png", made)
    else:
        skipped.append("bfs_levels.png (no BFS levels in bfs.csv)")
    if neurons:
        fig, ax = plt.subplots(figsize=(5, 3.5))
        for status, color in STATUS_COLORS.items():
            lengths = [float(r["length"]) for r in neurons if r["status"] == status]
            if lengths:
                ax.hist(lengths, bins=40, alpha=0.6, color=color, label=f"{status} ({len(lengths)})")
        ax.set_xlabel("axon length (LU)")
        ax.set_ylabel("axons")
        ax.legend()
        save(fig, d, "axon_lengths.png", made)
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
        xs = [float(r["soma_x"]) for r in neurons]
        ys = [float(r["soma_y"]) for r in neurons]
        if conns:
            segs = [((xs[int(c["source"])], ys[int(c["source"])]), (xs[int(c["target"])], ys[int(c["target"])])) for c in conns]
            ax.add_collection(LineCollection(segs, linewidths=0.4, colors="#555555", alpha=0.5))
        ax.scatter(xs, ys, s=max(0.5, 30 / math.sqrt(len(xs) + 1)), c=[STATUS_COLORS.get(r["status"], "k") for r in neurons])
        sources = rows(d, "sources.csv")
        for s in sources or []:
            ax.plot(float(s["x"]), float(s["y"]), "*", ms=14, color="green" if s["kind"] == "attractant" else "red",
                    markeredgecolor="k")
        ax.set_aspect("equal")
        ax.set_xlabel("x (LU)")
        ax.set_ylabel("y (LU)")
        ax.set_title("somas by status, connections, cue sources (x-y projection)")
        save(fig, d, "projection.png", made)
    else:
        skipped.append("axon_lengths.png, projection.png (no neurons.csv)")
    for m in made:
        print(f"wrote {os.path.join(d, m)}")
    for s in skipped:
        print(f"skipped {s}")
    return 0 if made else 2


def run(argv):
    """Every failure is one line on stderr and exit 2 (data that is not a run's) or 3 (the
    machine: files, memory, matplotlib); never a traceback."""
    if len(argv) != 2:
        print("axonguide: plot: usage: plot_run.py DIR", file=sys.stderr)
        return 2
    try:
        return main(argv[1])
    except (ValueError, KeyError, IndexError, TypeError, ZeroDivisionError, UnicodeError, csv.Error) as e:
        print(f"axonguide: plot: {argv[1]} holds data that is not a run's ({type(e).__name__}: {e})", file=sys.stderr)
        return 2
    except MemoryError:
        print("axonguide: plot: out of memory", file=sys.stderr)
        return 3
    except OSError as e:
        print(f"axonguide: plot: {e.strerror or e} ({e.filename or argv[1]})", file=sys.stderr)
        return 3
    except Exception as e:  # matplotlib's own failures, and anything else
        print(f"axonguide: plot: failed: {type(e).__name__}: {e}", file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(run(sys.argv))
