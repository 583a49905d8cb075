"""Shared by tests/python/test_api_*.py: the command line beside the module, its CSV files.

ctest sets PYTHONPATH (BUILD/python), AXG_BINARY (BUILD/bin/axonguide) and AXG_SOURCE_DIR;
by hand: PYTHONPATH=build-py/python AXG_BINARY=build-py/bin/axonguide python3 -m pytest tests/python/test_api_*.py
"""

import csv
import hashlib
import math
import os
import pathlib
import subprocess

import numpy as np

SOURCE_DIR = pathlib.Path(os.environ.get("AXG_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = pathlib.Path(os.environ.get("AXG_BINARY", SOURCE_DIR / "build" / "bin" / "axonguide"))
SCENES = SOURCE_DIR / "scenes"

# A small cue scene that exercises every table: the built-in default (two attractants and
# two repellents, a particle field) with 200 neurons and 40 steps, paths, particle and VTK
# frames, BFS from two sources, components; about 0.1 s.
def small_cue_scene():
    import json

    s = json.loads((SCENES / "default.json").read_text())
    s["seed"] = 3
    s["steps"] = 40
    s["neurons"]["count"] = 200
    s["output"].update({"paths": True, "vtk": True, "frames_every": 10, "stats_every": 3})
    s["analysis"] = {"bfs_sources": [0, 5], "components": True}
    return s


SMALL_CUE_SCENE = small_cue_scene()


def cli(*args, check=True, cwd=None):
    """Runs the command line; returns the CompletedProcess (text)."""
    p = subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    if check and p.returncode != 0:
        raise AssertionError(f"axonguide {' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def read_csv(path):
    """(header, rows) of a CSV file, every cell a string."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def num(cell):
    return math.nan if cell == "" else float(cell)


def column(rows, header, name, convert=num):
    k = header.index(name)
    return np.array([convert(r[k]) for r in rows])


def same(a, b):
    """Equal arrays, NaN equal to NaN."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return False
    if a.dtype.kind == "f" or b.dtype.kind == "f":
        return bool(np.array_equal(a.astype(float), b.astype(float), equal_nan=True))
    return bool(np.array_equal(a, b))


def same_structured(a, b):
    return a.dtype.names == b.dtype.names and len(a) == len(b) and all(same(a[n], b[n]) for n in a.dtype.names)


def file_hashes(folder):
    """{relative path: sha256} of every file under folder."""
    folder = pathlib.Path(folder)
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


# The manifest's run facts: what may differ between two runs of one scene (README, SPEC §4).
RUN_FACTS = ("threads", "backend", "created", "timings_seconds", "peak_memory_bytes")


def manifest_without_run_facts(folder):
    import json

    m = json.loads((pathlib.Path(folder) / "manifest.json").read_text())
    for k in RUN_FACTS:
        m.pop(k, None)
    m["files"].pop("timings.csv", None)
    return m
