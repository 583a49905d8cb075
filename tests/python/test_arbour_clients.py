"""Arbours read back by real clients (issue 41; docs/methods.md §2.12, guide.md §1.2).

- NEURON's Import3d (Debian python3-neuron) loads every arbour SWC: one section per
  unbranched piece, axon sections typed axon and dendrite sections dend, each child section
  attached to its parent's end, and the section lengths summing, type by type, to the SWC's
  own polyline (NEURON keeps 3-D points in single precision: the bound allows each point's
  rounding).
- SONATA (h5py): every node names a soma-centred copy of its morphology, under the folder
  that circuit_config.json's components.morphologies_dir names; the copy placed at the
  node's x, y, z is the absolute SWC. NEURON loads the copies too.

Run from ctest (arbours.clients) with AXG_BINARY set to the built command and
AXG_SOURCE_DIR to the source tree (for scenes/culture.json).
"""
import json
import math
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from neuron_cells import load_cell, neuron_with_import3d
from swc_rows import read_swc

BINARY = os.environ.get("AXG_BINARY", "axonguide")
SOURCE = Path(os.environ.get("AXG_SOURCE_DIR", Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    root = tmp_path_factory.mktemp("arbours")
    scene = json.loads((SOURCE / "scenes" / "culture.json").read_text())
    scene["neurons"]["count"] = 24
    scene["steps"] = 96  # two days
    scene["arbours"]["axon"]["lateral_rate"] = 0.001  # per um per h: branch points along the path too
    scene["output"] = {"swc": True, "sonata": True}
    (root / "scene.json").write_text(json.dumps(scene))
    o = root / "out"
    subprocess.run([BINARY, "run", str(root / "scene.json"), "--out", str(o), "-q"], check=True)
    return o


def pieces(rows):
    """Unbranched pieces of an SWC tree as NEURON's Import3d makes them: a piece starts at a
    child of the soma or of a branch point. Returns {type: count} and {type: length}: a
    piece's polyline, from its branch point when it hangs on one; a piece on the soma starts
    at its own first point, unless that is its only point (a stem born in the last step),
    which Import3d joins to the soma's centre, since a section needs two points."""
    by_id = {r[0]: r for r in rows}
    children = {}
    for r in rows[1:]:
        children.setdefault(r[6], []).append(r[0])
    count, length = {2: 0, 3: 0}, {2: 0.0, 3: 0.0}
    for r in rows[1:]:
        parent = by_id[r[6]]
        if parent[1] == 1 or len(children[r[6]]) > 1:
            count[r[1]] += 1
        lone_stem = parent[1] == 1 and len(children.get(r[0], [])) != 1
        if parent[1] != 1 or lone_stem:
            length[r[1]] += math.dist(r[2:5], parent[2:5])
    return count, length


@pytest.fixture(scope="module")
def neuron_h():
    return neuron_with_import3d()



def check_in_neuron(h, path):
    rows = read_swc(path)
    secs = load_cell(h, path)
    count, length = pieces(rows)
    axon = [s for name, s in secs.items() if name.startswith("axon")]
    dend = [s for name, s in secs.items() if name.startswith("dend")]
    assert len(secs) == 1 + count[2] + count[3]
    assert (len(axon), len(dend)) == (count[2], count[3]), path
    largest = max(abs(c) for r in rows for c in r[2:5])
    for kind, sections in ((2, axon), (3, dend)):
        points = sum(s.n3d() for s in sections)
        bound = points * 2 * math.sqrt(3) * 2.0**-24 * largest
        assert abs(sum(s.L for s in sections) - length[kind]) <= bound, (path, kind)
        for s in sections:  # a stem hangs on the soma, a daughter on its parent's end
            parent = s.parentseg()
            assert parent is not None
            if parent.sec.name() != "soma[0]":
                assert parent.sec.name().startswith("axon" if kind == 2 else "dend")
                assert parent.x == 1.0
    return count


def test_neuron_loads_every_arbour(out, neuron_h):
    files = sorted((out / "morphologies").glob("*.swc"))
    assert len(files) == 24
    branched = 0
    for path in files:
        count = check_in_neuron(neuron_h, path)
        branched += count[2] > 1
    assert branched >= 12, "most axons branched by day 2"


def test_sonata_nodes_name_soma_centred_morphologies(out):
    net = out / "network"
    config = json.loads((net / "circuit_config.json").read_text())
    mdir = config["components"]["morphologies_dir"].replace("$BASE_DIR", str(net))
    with h5py.File(net / "nodes.h5", "r") as f:
        g = f["nodes/axonguide/0"]
        names = [m.decode() for m in g["morphology"][()]]
        xyz = np.stack([g["x"][()], g["y"][()], g["z"][()]], axis=1)
    assert names == [str(i) for i in range(24)]
    manifest = json.loads((out / "manifest.json").read_text())
    for i, name in enumerate(names):
        assert f"network/morphologies/{name}.swc" in manifest["files"]
        local = read_swc(Path(mdir) / f"{name}.swc")
        world = read_swc(out / "morphologies" / f"{i}.swc")
        assert local[0][2:5] == (0.0, 0.0, 0.0), "the soma at the origin"
        assert [r[:2] + r[5:] for r in local] == [r[:2] + r[5:] for r in world], "same tree, types and radii"
        placed = np.array([r[2:5] for r in local]) + xyz[i]
        assert np.allclose(placed, np.array([r[2:5] for r in world]), rtol=0, atol=1e-9)
    assert subprocess.run([BINARY, "verify", str(out)], capture_output=True).returncode == 0


def test_neuron_loads_the_sonata_copies(out, neuron_h):
    for path in sorted((out / "network" / "morphologies").glob("*.swc")):
        check_in_neuron(neuron_h, path)
