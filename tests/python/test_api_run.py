"""axonguide.run: its arrays against the CSV files `axonguide run` writes, thread
invariance, the GIL, networkx, RunError and Ctrl-C."""

import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import axonguide
from api_support import SMALL_CUE_SCENE, SOURCE_DIR, cli, column, num, read_csv, same, same_structured

# Wandering axons in a wide domain: every axon grows every step (about 1.2 ms a step on one
# core), for the GIL and interrupt tests.
LONG = {"neurons": {"count": 3000, "region": {"radius": 50}}, "axons": {"bounds_radius": 1000}}


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """The small cue scene run by Python and by the command line."""
    d = tmp_path_factory.mktemp("cli")
    scene = d / "scene.json"
    scene.write_text(json.dumps(SMALL_CUE_SCENE))
    cli("run", scene, "--out", d / "out", "--threads", 2, "-q")
    return axonguide.run(SMALL_CUE_SCENE, threads=2), d / "out"


def test_neurons_are_neurons_csv(small):
    r, out = small
    h, rows = read_csv(out / "neurons.csv")
    n = r.neurons
    assert n.dtype.names == tuple(h)
    assert n.dtype["id"] == np.uint32 and n.dtype["status"] == np.uint8 and n.dtype["target"] == np.int64
    assert len(n) == len(rows) == 200
    for name in h:
        if name == "status":
            assert list(np.asarray(axonguide.STATUS_NAMES)[n["status"]]) == [row[h.index(name)] for row in rows]
            assert list(r.statuses) == [row[h.index(name)] for row in rows]
        else:
            assert same(n[name], column(rows, h, name)), name
    assert same(r.soma, np.stack([n["soma_x"], n["soma_y"], n["soma_z"]], axis=1))
    assert not r.soma.flags.writeable


def test_connections_stats_bfs_sources_are_their_csv(small):
    r, out = small
    h, rows = read_csv(out / "connections.csv")
    assert r.connections.dtype.names == tuple(h) and len(r.connections) == len(rows) > 0
    for name in h:
        assert same(r.connections[name], column(rows, h, name)), name
    h, rows = read_csv(out / "stats.csv")
    assert r.stats.dtype.names == tuple(h) and len(r.stats) == len(rows)
    for name in h:
        assert same(r.stats[name], column(rows, h, name)), name
    assert len(r.step_stats) == r.summary["steps_run"] + 1 > len(r.stats)  # stats_every 3
    h, rows = read_csv(out / "bfs.csv")
    assert h == ["id", "level", "parent", "component"]
    assert r.bfs.level.dtype == np.int32 and r.bfs.parent.dtype == np.int64 and r.bfs.component.dtype == np.uint32
    assert same(r.bfs.level, column(rows, h, "level"))
    assert same(r.bfs.parent, column(rows, h, "parent"))
    assert same(r.bfs.component, column(rows, h, "component"))
    assert r.bfs.sources == [0, 5]
    h, rows = read_csv(out / "sources.csv")
    assert r.sources.dtype.names == tuple(h) and len(r.sources) == len(rows) == 4
    for name in h:
        if name == "kind":
            assert [axonguide.CUE_KIND_NAMES[k] for k in r.sources["kind"]] == [row[1] for row in rows]
        else:
            assert same(r.sources[name], column(rows, h, name)), name


def test_paths_and_frames_are_their_csv(small):
    r, out = small
    h, rows = read_csv(out / "paths.csv")
    p = r.paths
    steps = r.neurons["steps"]
    assert p.shape == (r.summary["steps_run"] + 1, 200, 3) and p.dtype == np.float64
    ids = column(rows, h, "id").astype(int)
    st = column(rows, h, "step").astype(int)
    assert len(rows) == int(np.sum(np.minimum(steps, p.shape[0] - 1) + 1))
    xyz = np.stack([column(rows, h, c) for c in ("x", "y", "z")], axis=1)
    assert same(p[st, ids], xyz)
    assert np.all(st <= steps[ids])
    h, rows = read_csv(out / "particles.csv")
    assert [f.step for f in r.frames] == sorted({int(row[0]) for row in rows})
    pos = np.concatenate([f.positions for f in r.frames])
    cue = np.concatenate([f.cue for f in r.frames])
    assert same(pos, np.stack([column(rows, h, c) for c in ("x", "y", "z")], axis=1))
    assert same(cue, column(rows, h, "cue"))
    assert all(f.positions.shape == (len(f.cue), 3) and not f.positions.flags.writeable for f in r.frames)


def test_summary_is_the_manifests(small):
    r, out = small
    m = json.loads((out / "manifest.json").read_text())
    for k, v in m["summary"].items():
        assert r.summary[k] == v, k
    assert r.summary["edges"] == len(r.connections)
    assert r.scene == axonguide.Scene(SMALL_CUE_SCENE)
    assert r.threads == 2 and r.backend == "reference"
    assert set(r.timings) >= {"placement", "graph"}


def test_threads_do_not_change_any_array(small):
    r2, _ = small
    r1 = axonguide.run(SMALL_CUE_SCENE, threads=1)
    for name in ("neurons", "connections", "stats", "step_stats", "sources"):
        assert same_structured(getattr(r1, name), getattr(r2, name)), name
    assert same(r1.paths, r2.paths)
    for a, b in zip(r1.bfs[:3], r2.bfs[:3]):
        assert same(a, b)
    assert len(r1.frames) == len(r2.frames)
    for a, b in zip(r1.frames, r2.frames):
        assert a.step == b.step and same(a.positions, b.positions) and same(a.cue, b.cue)
    assert r1.connections_csv() == r2.connections_csv()


def test_seed_overrides_like_the_flag(tmp_path):
    scene = {"neurons": {"count": 300}, "steps": 30}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(scene))
    cli("run", path, "--seed", 7, "--out", tmp_path / "out", "-q")
    r = axonguide.run(scene, seed=7)
    assert r.scene.seed == 7
    assert r.connections_csv() == (tmp_path / "out" / "connections.csv").read_bytes()
    assert r.connections_csv() != axonguide.run(scene).connections_csv()


def test_to_networkx(small):
    r, _ = small
    g = r.to_networkx()
    assert g.number_of_nodes() == 200
    assert g.number_of_edges() == len(r.connections) == r.summary["edges"]
    for s, t, step, length in r.connections.tolist():
        assert g.edges[s, t] == {"step": step, "length": length}
    for i in (0, 5, 199):
        node = g.nodes[i]
        assert node["position"] == tuple(r.soma[i])
        assert node["status"] == r.statuses[i]
        assert node["level"] == r.bfs.level[i] and node["component"] == r.bfs.component[i]


def test_no_paths_no_frames_without_output_paths():
    r = axonguide.run({"neurons": {"count": 50}, "steps": 5})
    assert r.paths is None and r.frames == []
    assert r.bfs.level is not None or r.bfs.level is None  # present per the scene's analysis


def test_run_error_for_a_placement_too_dense(tmp_path):
    scene = {"neurons": {"count": 2000, "soma_radius": 0.25, "region": {"shape": "ball", "radius": 2.5}}, "steps": 5}
    with pytest.raises(axonguide.RunError, match="placement impossible") as e:
        axonguide.run(scene)
    assert isinstance(e.value, RuntimeError) and not isinstance(e.value, ValueError)
    path = tmp_path / "dense.json"
    path.write_text(json.dumps(scene))
    p = cli("run", path, "--out", tmp_path / "out", check=False)
    assert p.returncode == 3 and p.stderr.strip() == f"axonguide: cannot run: {e.value}"


def test_run_error_for_a_memory_estimate():
    with pytest.raises(axonguide.RunError, match="memory|estimate"):
        axonguide.run({"neurons": {"count": 10}, "steps": 1000000000})


def test_the_gil_is_released_while_a_run_works():
    scene = axonguide.Scene({**LONG, "steps": 300})
    # The main thread's rate alone.
    count, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < 0.05:
        count += 1
    solo_rate = count / (time.perf_counter() - t0)
    box = {}

    def work():
        box["t0"] = time.perf_counter()
        box["result"] = axonguide.run(scene, threads=1)
        box["t1"] = time.perf_counter()

    t = threading.Thread(target=work)
    count = 0
    t.start()
    while t.is_alive():
        count += 1
    t.join()
    seconds = box["t1"] - box["t0"]
    assert box["result"].summary["steps_run"] == 300
    assert seconds > 0.1
    # Holding the GIL, the C++ run would never yield it (the switch interval applies only
    # between bytecodes), so the main thread could not count at all while it works;
    # released, it counts at some share of its solo rate. The share depends on the load of
    # the machine (a test run keeps every core busy), so the bound is 1 % of the solo rate,
    # far above the zero that a held GIL gives.
    assert count > max(1000, 0.01 * solo_rate * seconds), (count, solo_rate, seconds)


def test_ctrl_c_ends_the_run_at_the_end_of_a_step():
    scene = axonguide.Scene({**LONG, "steps": 4000})  # about 5 s
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    t0 = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            axonguide.run(scene, threads=1)
    finally:
        timer.cancel()
        timer.join()
    assert time.perf_counter() - t0 < 2.5


def test_the_emulated_accelerator_gives_the_same_arrays(small):
    r, _ = small
    e = axonguide.run(SMALL_CUE_SCENE, backend="emulated")
    assert e.backend == "emulated"
    for name in ("neurons", "connections", "step_stats", "sources"):
        assert same_structured(getattr(e, name), getattr(r, name)), name
    assert same(e.paths, r.paths)


def test_cuda_is_refused_where_it_cannot_run():
    reason = axonguide.cuda_unavailable_reason()
    if not reason:
        pytest.skip("the CUDA engine can run here")
    with pytest.raises((axonguide.InputError, axonguide.RunError)):
        axonguide.run({"neurons": {"count": 10}, "steps": 2}, backend="cuda")


def test_arbours_are_the_swc_files(tmp_path):
    """Run.arbour(i): NumPy arrays of the rows of morphologies/<i>.swc, in order (the culture
    is in micrometres, so the coordinates are the file's)."""
    scene = json.loads((SOURCE_DIR / "scenes" / "culture.json").read_text())
    scene["neurons"]["count"] = 12
    scene["neurons"]["region"]["radius"] = 300
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    cli("run", path, "--out", tmp_path / "out", "--threads", 2, "-q")
    r = axonguide.run(scene, threads=2)
    assert len(r.arbours) == 12
    for i in range(12):
        a = r.arbour(i)
        rows = [line.split() for line in (tmp_path / "out" / "morphologies" / f"{i}.swc").read_text().splitlines()
                if not line.startswith("#")]
        assert len(rows) == len(a.point) == len(a.parent) == len(a.type) == len(a.step)
        assert a.point.dtype == np.float64 and a.parent.dtype == np.int64 and a.type.dtype == np.uint8
        assert [int(x[1]) for x in rows] == list(a.type)
        assert [int(x[6]) - 1 if int(x[6]) > 0 else -1 for x in rows] == list(a.parent)
        assert np.array_equal(np.array([[float(v) for v in x[2:5]] for x in rows]), a.point)
        assert all(a.parent[k] < k for k in range(1, len(a.parent)))
        assert a.type[0] == 1 and set(a.type[1:]) <= {2, 3}
    assert axonguide.run({"neurons": {"count": 3}, "guidance": {"model": "direct"}}, threads=1).arbours is None
