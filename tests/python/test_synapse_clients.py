"""Synapses read back by real clients (issue 42; docs/methods.md §2.13).

- h5py: edges.h5 holds one edge per realised synapse of synapses.csv, in its order, with
  SONATA's synapse attributes (afferent/efferent section id and position, centres in µm).
- NEURON: each node's morphology (network/morphologies/<id>.swc, soma-centred) loaded by
  Import3d; the synapse found at (afferent_section_id, afferent_section_pos), the id an
  index into the cell's sections as NEURON numbers them (soma[0], axon[i], dend[j]), lies on the dendrite within 0.1 µm of
  synapses.csv's x, y, z; the same for the axon's point at the efferent section.
"""
import csv
import json
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from neuron_cells import load_cell, neuron_with_import3d

BINARY = os.environ.get("AXG_BINARY", "axonguide")
SOURCE = Path(os.environ.get("AXG_SOURCE_DIR", Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    root = tmp_path_factory.mktemp("synapses")
    scene = json.loads((SOURCE / "scenes" / "culture.json").read_text())
    scene["neurons"]["count"] = 60
    scene["neurons"]["region"]["radius"] = 250
    scene["steps"] = 120
    scene["arbours"]["axon"]["lateral_rate"] = 0.001  # branch points along the paths too
    scene["arbours"]["dendrites"]["lateral_rate"] = 0.005
    scene["synapses"] = {"distance": 3.0, "probability": 0.8}
    scene["output"] = {"swc": True, "sonata": True}
    (root / "scene.json").write_text(json.dumps(scene))
    o = root / "out"
    subprocess.run([BINARY, "run", str(root / "scene.json"), "--out", str(o), "-q"], check=True)
    return o


def synapses(out):
    with open(out / "synapses.csv", newline="") as f:
        return [r for r in csv.DictReader(f) if r["realised"] == "1"]


def test_edges_are_the_realised_synapses(out):
    rows = synapses(out)
    assert len(rows) > 20
    with h5py.File(out / "network" / "edges.h5", "r") as f:
        pop = f["edges/axonguide_to_axonguide"]
        g = pop["0"]
        assert list(pop["source_node_id"][:]) == [int(r["pre"]) for r in rows]
        assert list(pop["target_node_id"][:]) == [int(r["post"]) for r in rows]
        for axis in "xyz":
            assert np.allclose(g[f"afferent_center_{axis}"][:], [float(r[axis]) for r in rows], rtol=0, atol=1e-9)
        pos = g["afferent_section_pos"][:]
        assert ((pos >= 0) & (pos <= 1)).all() and ((g["efferent_section_pos"][:] >= 0) & (g["efferent_section_pos"][:] <= 1)).all()
        assert (g["afferent_section_id"][:] >= 0).all()
        assert list(g["contacts"][:]) == [int(r["contacts"]) for r in rows]
        assert (g["delay"][:] >= 0).all()  # 0: a synapse where the axon leaves the soma
        assert np.allclose(g["delay"][:], g["axon_path_length"][:] / 500.0, rtol=1e-12, atol=0)  # 0.5 m/s
        assert g["dynamics_params/delay"][:].tolist() == g["delay"][:].tolist()
        assert (g["efferent_section_id"][:] >= 1).all()  # on the axon, never the soma


@pytest.fixture(scope="module")
def neuron_h():
    return neuron_with_import3d()


def sections(h, path):
    """The cell's sections by SONATA section id: NEURON's own numbering of what Import3d
    makes, soma[0] = 0, then axon[i] = 1 + i, then dend[j] = 1 + (axon sections) + j (by
    name, not h.allsec()'s order, which reloading cells in one session can change)."""
    by_type = {"soma": {}, "axon": {}, "dend": {}}
    for name, sec in load_cell(h, path).items():
        kind, index = name.rstrip("]").split("[")
        by_type[kind][int(index)] = sec
    ordered = []
    for kind in ("soma", "axon", "dend"):
        assert sorted(by_type[kind]) == list(range(len(by_type[kind])))
        ordered += [by_type[kind][i] for i in range(len(by_type[kind]))]
    return ordered


def point_at(sec, pos):
    """The 3-D point at a fraction pos of the section's arc length (NEURON's own arc3d)."""
    n = int(sec.n3d())
    arc = np.array([sec.arc3d(i) for i in range(n)])
    xyz = np.array([[sec.x3d(i), sec.y3d(i), sec.z3d(i)] for i in range(n)])
    target = pos * arc[-1]
    k = int(np.clip(np.searchsorted(arc, target), 1, n - 1))
    w = 0.0 if arc[k] == arc[k - 1] else (target - arc[k - 1]) / (arc[k] - arc[k - 1])
    return xyz[k - 1] + w * (xyz[k] - xyz[k - 1])


def test_neuron_finds_each_synapse_at_its_section_and_position(out, neuron_h):
    h = neuron_h
    with h5py.File(out / "network" / "nodes.h5", "r") as f:
        g = f["nodes/axonguide/0"]
        node = np.stack([g["x"][:], g["y"][:], g["z"][:]], axis=1)
    with h5py.File(out / "network" / "edges.h5", "r") as f:
        pop = f["edges/axonguide_to_axonguide"]
        e = {k: pop["0"][k][:] for k in ("afferent_section_id", "afferent_section_pos", "efferent_section_id",
                                         "efferent_section_pos", "efferent_center_x", "efferent_center_y",
                                         "efferent_center_z")}
        src, dst = pop["source_node_id"][:], pop["target_node_id"][:]
    rows = synapses(out)
    worst = 0.0
    checked = {"soma": 0, "dendrite": 0}
    for side in ("afferent", "efferent"):
        by_neuron = {}
        for k in range(len(rows)):
            by_neuron.setdefault(int(dst[k] if side == "afferent" else src[k]), []).append(k)
        for nid, ks in sorted(by_neuron.items()):
            secs = sections(h, out / "network" / "morphologies" / f"{nid}.swc")
            for k in ks:
                sec = secs[int(e[f"{side}_section_id"][k])]
                if side == "afferent":
                    want = np.array([float(rows[k][a]) for a in "xyz"])
                    if int(rows[k]["post_sample"]) == 1:  # the soma: its section, at the centre
                        assert sec.name().startswith("soma")
                        checked["soma"] += 1
                        continue
                    assert sec.name().startswith("dend"), sec.name()
                    checked["dendrite"] += 1
                else:
                    want = np.array([e[f"efferent_center_{a}"][k] for a in "xyz"])
                    assert sec.name().startswith("axon"), sec.name()
                got = point_at(sec, float(e[f"{side}_section_pos"][k])) + node[nid]
                worst = max(worst, float(np.linalg.norm(got - want)))
    assert checked["dendrite"] > 10
    assert worst < 0.1, f"the farthest synapse is {worst} um from its (section, position)"
