"""SONATA output (docs/guide.md §1.2) read back by real clients: h5py, and PyNN's
import_from_sonata with its mock backend (no NEST here). Every number is compared exactly
with neurons.csv, connections.csv and bfs.csv of the same run.

Run from ctest (sonata.clients) with AXG_BINARY set to the built command.
"""
import csv
import json
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

BINARY = os.environ.get("AXG_BINARY", "axonguide")
UM_PER_LU = 40.0

# 400 neurons, direct guidance: most axons connect within 60 steps (LU, default speed).
LU_SCENE = {"seed": 3, "steps": 60,
            "neurons": {"count": 400, "region": {"radius": 3.0}},
            "guidance": {"model": "direct"}, "output": {"sonata": True}}
# The same in micrometres, with a stated conduction speed.
UM_SCENE = {"seed": 5, "steps": 60, "units": {"length": "um"},
            "neurons": {"count": 300, "soma_radius": 10.0, "region": {"radius": 110.0}},
            "axons": {"step_length": 14.0, "contact_distance": 2.0, "persistence_length": None},
            "guidance": {"model": "direct"}, "output": {"sonata": True, "conduction_speed": 2.0}}

NETWORK_FILES = ["nodes.h5", "edges.h5", "node_types.csv", "edge_types.csv", "circuit_config.json"]


def run(tmp_path, name, scene, threads=2):
    scene_file = tmp_path / f"{name}.json"
    scene_file.write_text(json.dumps(scene))
    out = tmp_path / name
    subprocess.run([BINARY, "run", str(scene_file), "-q", "--threads", str(threads), "--out", str(out)],
                   check=True, capture_output=True)
    return out


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module", params=["lu", "um"])
def case(request, tmp_path_factory):
    tmp = tmp_path_factory.mktemp(request.param)
    scene = LU_SCENE if request.param == "lu" else UM_SCENE
    out = run(tmp, "out", scene)
    scale = UM_PER_LU if request.param == "lu" else 1.0
    speed = scene["output"].get("conduction_speed", 0.5)
    return {"out": out, "scale": scale, "speed": speed, "scene": scene, "tmp": tmp,
            "neurons": rows(out / "neurons.csv"), "connections": rows(out / "connections.csv"),
            "bfs": rows(out / "bfs.csv")}


def column(table, key, dtype=float):
    return np.array([dtype(r[key]) for r in table])


def test_files_listed_in_manifest(case):
    manifest = json.loads((case["out"] / "manifest.json").read_text())
    for name in NETWORK_FILES:
        assert f"network/{name}" in manifest["files"]
    assert subprocess.run([BINARY, "verify", str(case["out"])], capture_output=True).returncode == 0


def test_nodes_with_h5py(case):
    neurons, bfs, s = case["neurons"], case["bfs"], case["scale"]
    with h5py.File(case["out"] / "network" / "nodes.h5", "r") as f:
        assert f.attrs["magic"] == 0x0A7A
        assert list(f.attrs["version"]) == [0, 1]
        pop = f["nodes/axonguide"]
        n = len(neurons)
        assert pop["node_id"].shape == (n,)
        assert np.array_equal(pop["node_id"][()], np.arange(n))
        assert np.array_equal(pop["node_group_index"][()], np.arange(n))
        assert not pop["node_type_id"][()].any() and not pop["node_group_id"][()].any()
        g = pop["0"]
        for axis in "xyz":
            assert np.array_equal(g[axis][()], column(neurons, f"soma_{axis}") * s), axis
            assert g[axis].attrs["units"] == b"um"
        assert np.array_equal(g["soma_radius"][()], column(neurons, "radius") * s)
        assert np.array_equal(g["axon_length"][()], column(neurons, "length") * s)
        assert np.array_equal(g["steps"][()], column(neurons, "steps", int))
        names = [x.decode() for x in g["@library/status"][()]]
        assert names == ["growing", "connected", "exited", "max_steps"]
        assert [names[k] for k in g["status"][()]] == [r["status"] for r in neurons]
        assert np.array_equal(g["bfs_level"][()], column(bfs, "level", int))
        assert np.array_equal(g["component"][()], column(bfs, "component", int))


def test_edges_with_h5py(case):
    conns, n, s = case["connections"], len(case["neurons"]), case["scale"]
    assert len(conns) > 50
    with h5py.File(case["out"] / "network" / "edges.h5", "r") as f:
        assert f.attrs["magic"] == 0x0A7A
        pop = f["edges/axonguide_to_axonguide"]
        src, tgt = pop["source_node_id"][()], pop["target_node_id"][()]
        assert pop["source_node_id"].attrs["node_population"] == b"axonguide"
        assert pop["target_node_id"].attrs["node_population"] == b"axonguide"
        assert np.array_equal(src, column(conns, "source", int))
        assert np.array_equal(tgt, column(conns, "target", int))
        assert np.array_equal(pop["0/step"][()], column(conns, "step", int))
        length = column(conns, "length") * s
        assert np.array_equal(pop["0/length"][()], length)
        assert np.array_equal(pop["0/delay"][()], length / (case["speed"] * 1000.0))
        assert pop["0/delay"].attrs["units"] == b"ms"
        assert pop["0/delay"].attrs["conduction_speed"] == case["speed"]
        assert np.array_equal(pop["0/dynamics_params/delay"][()], pop["0/delay"][()])
        assert np.array_equal(pop["edge_group_index"][()], np.arange(len(conns)))
        # The indices give every node's edges, both ways.
        for direction, ids in (("source_to_target", src), ("target_to_source", tgt)):
            ranges = pop[f"indices/{direction}/node_id_to_ranges"][()]
            edges = pop[f"indices/{direction}/range_to_edge_id"][()]
            assert ranges.shape == (n, 2)
            for v in range(n):
                got = [e for a, b in edges[ranges[v, 0]:ranges[v, 1]] for e in range(a, b)]
                assert got == list(np.flatnonzero(ids == v)), (direction, v)


def test_pynn_import(case, monkeypatch):
    """PyNN resolves the config's paths against the working directory: run it from a copy
    of network/ elsewhere, which also shows that the folder can move."""
    import pyNN.mock as sim
    from pyNN.serialization import import_from_sonata

    moved = case["tmp"] / "moved-network"
    shutil.copytree(case["out"] / "network", moved)
    monkeypatch.chdir(moved)
    sim.setup(timestep=0.1)
    net = import_from_sonata("circuit_config.json", sim)
    assert [a.label for a in net.assemblies] == ["axonguide"]
    assert sum(p.size for p in net.populations) == len(case["neurons"])
    (prj,) = net.projections
    conns = case["connections"]
    assert prj.size() == len(conns)
    got = sorted((int(i), int(j), d) for i, j, d in prj.get("delay", format="list"))
    want = [(int(r["source"]), int(r["target"]), float(r["length"]) * case["scale"] / (case["speed"] * 1000.0))
            for r in conns]
    assert got == want
    sim.end()


def test_bytes_equal_on_one_thread(case):
    again = run(case["tmp"], "again", case["scene"], threads=1)
    for name in NETWORK_FILES:
        assert (again / "network" / name).read_bytes() == (case["out"] / "network" / name).read_bytes(), name
