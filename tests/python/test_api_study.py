"""Sweeps, assay metrics and the fit from Python against `axonguide sweep` and `axonguide fit`."""

import hashlib
import json
import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import axonguide
from api_support import SCENES, cli, file_hashes, read_csv


def small_explant():
    base = json.loads((SCENES / "assay-explant.json").read_text())
    base["neurons"]["populations"][0]["count"] = 200
    base["steps"] = 40
    return base


SPEC = {
    "scene": small_explant(),
    "parameters": [{"key": "cues.imposed.concentration", "values": [0.01, 1, 100]}],
    "seeds": 2,
}


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep")
    spec = d / "spec.json"
    spec.write_text(json.dumps(SPEC))
    cli("sweep", spec, "--out", d / "cli", "--threads", 2, "-q")
    py = axonguide.sweep(spec, out=d / "py", threads=2)
    mem = axonguide.sweep(SPEC, threads=1)
    return py, mem, d


def cell_equal(cell, value):
    # sweep.csv: shortest round-trip numbers; an empty cell for a non-finite value.
    if cell == "":
        return not math.isfinite(value)
    return float(cell) == value


def test_sweep_folder_has_the_commands_bytes(sweeps):
    py, _, d = sweeps
    a, b = file_hashes(d / "py"), file_hashes(d / "cli")
    assert set(a) == set(b) >= {"sweep.csv", "summary.csv", "sweep.json", "members/m0000000.json"}
    assert a == b
    assert py.out == d / "py" and py.failed == 0 and py.reused == 0
    # A second sweep into the folder reuses every verified record, and writes the same bytes.
    again = axonguide.sweep(d / "spec.json", out=d / "py")
    assert again.reused == 6 and bool(np.all(again.records["reused"]))
    assert file_hashes(d / "py") == b


def test_records_and_summary_are_the_csv_files(sweeps):
    py, mem, d = sweeps
    h, rows = read_csv(d / "cli" / "sweep.csv")
    assert list(mem.records)[:-1] == h  # and "reused"
    assert len(mem) == len(rows) == 6
    for k, name in enumerate(h):
        col = mem.records[name]
        for m, row in enumerate(rows):
            v = col[m]
            if isinstance(v, str):
                assert v == row[k], (name, m)
            else:
                assert cell_equal(row[k], float(v)), (name, m, row[k], v)
    assert mem.records["cues.imposed.concentration"].dtype == np.float64
    for name in h:
        if isinstance(mem.records[name][0], str):
            assert list(mem.records[name]) == list(py.records[name])
        else:
            assert np.array_equal(mem.records[name], py.records[name], equal_nan=True), name
    h, rows = read_csv(d / "cli" / "summary.csv")
    assert list(mem.summary) == h
    for k, name in enumerate(h):
        for p, row in enumerate(rows):
            assert cell_equal(row[k], float(mem.summary[name][p])), (name, p)
    assert mem.record(3)["seed"] == 2 and mem.record(3)["point"] == 1


def test_assay_metrics_equal_the_sweep_records(sweeps):
    _, mem, _ = sweeps
    spec = axonguide.SweepSpec(SPEC)
    assert (spec.member_count, spec.point_count, spec.seeds) == (6, 3, [1, 2])
    assert spec.parameters == ["cues.imposed.concentration"] and spec.point_values(2) == [100]
    for m in (0, 3, 5):
        scene = spec.member_scene(m)
        assert scene.seed == spec.seeds[m % 2]
        r = axonguide.run(scene)
        metrics = axonguide.assay_metrics(r)
        assert r.assay_metrics()["bias"] == metrics["bias"] or math.isnan(metrics["bias"])
        for name in axonguide.metric_names:
            a, b = metrics[name], mem.records[name][m]
            assert a == b or (math.isnan(a) and math.isnan(b)), (m, name, a, b)
        assert hashlib.sha256(r.connections_csv()).hexdigest() == mem.records["connections_sha256"][m]
        assert metrics["profile"].shape == (36,) and metrics["turning"].shape == (36,)
        assert int(metrics["turning"].sum()) <= metrics["axons"]


def test_bad_sweep_specs():
    with pytest.raises(axonguide.InputError, match="seeds"):
        axonguide.SweepSpec({**SPEC, "seeds": 0})
    with pytest.raises(axonguide.InputError, match="unknown key"):
        axonguide.SweepSpec({**SPEC, "sedes": 2})
    with pytest.raises(FileNotFoundError):
        axonguide.sweep("/nonexistent/sweep.json")


DATA = [(0.01, 0.2, 0.05, 0.05, 10), (0.1, 0.2, 0.1, 0.05, 10), (1.0, 0.2, 0.02, 0.05, 10)]


def test_fit_equals_the_command(tmp_path):
    base = tmp_path / "base.json"
    base.write_text(json.dumps(small_explant()))
    data = tmp_path / "data.csv"
    data.write_text("concentration,steepness,bias,se,count\n" + "".join(",".join(map(str, r)) + "\n" for r in DATA))
    f = axonguide.fit(base, DATA, seeds=1, grid=2, refine=0, threads=2, polish=0)
    # 4 parameter sets x 3 points x 1 seed, each run with the gradient and its mirror image.
    assert f.runs == 4 * 3 * 2 and f.dof == 1 and len(f.evaluations["chi2"]) == 4
    assert f.model.shape == (3,) and f.reachable.dtype == bool
    assert f.chi2 == min(f.evaluations["chi2"]) and f.chi2_per_dof == f.chi2 / f.dof
    cli("fit", data, "--scene", base, "--out", tmp_path / "fit", "--seeds", 1, "--grid", 2, "--refine", 0, "--polish", 0,
        "--max-chi2", 1e9, "--threads", 2)
    j = json.loads((tmp_path / "fit" / "fit.json").read_text())
    assert (f.gain, f.kd, f.scale, f.chi2, f.runs) == (j["gain"], j["kd"], j["concentration_scale"], j["chi2"],
                                                       j["runs"])
    h, rows = read_csv(tmp_path / "fit" / "fit_grid.csv")
    assert [float(r[h.index("chi2")]) for r in rows] == list(f.evaluations["chi2"])
    # The data as a path or as columns gives the same fit.
    g = axonguide.fit(axonguide.Scene(base), {c: [r[k] for r in DATA] for k, c in
                                             enumerate(("concentration", "steepness", "bias", "se", "count"))},
                      seeds=[1], grid=2, refine=0, polish=0)
    assert (g.gain, g.kd, g.chi2) == (f.gain, f.kd, f.chi2)


def test_fit_refuses_bad_data_and_options(tmp_path):
    base = small_explant()
    with pytest.raises(axonguide.InputError, match="line 3: concentration"):
        axonguide.fit(base, [DATA[0], (0.0, 0.2, 0.1, 0.05, 10), DATA[2]], seeds=1, grid=2, refine=0)
    with pytest.raises(axonguide.InputError, match="at least 3"):
        axonguide.fit(base, DATA[:2], seeds=1, grid=2, refine=0)
    with pytest.raises(axonguide.InputError, match="grid"):
        axonguide.fit(base, DATA, grid=1)
    with pytest.raises(axonguide.InputError, match="gain"):
        axonguide.fit(base, DATA, gain_min=10, gain_max=1)
    with pytest.raises(axonguide.InputError, match="imposed gradient"):
        axonguide.fit({"neurons": {"count": 10}}, DATA, seeds=1, grid=2, refine=0)
    with pytest.raises(axonguide.SceneError):
        axonguide.fit({"neurons": {"count": -1}}, DATA)
    # Arguments of the wrong type or value: InputError naming them, never cut or coerced.
    for kw, message in ((dict(grid=2.9), "grid = 2.9"), (dict(seeds=True), "seeds = True"),
                        (dict(seeds=[1, 1]), "seed 1 is given twice"), (dict(max_seeds=-1), "max_seeds = -1"),
                        (dict(gain_min=math.nan), "gain_min = nan"), (dict(mirror="no"), "mirror = 'no'"),
                        (dict(antithetic=1), "antithetic = 1"),
                        (dict(corrections=[1, 2]), "corrections"), (dict(params=[("gain",)]), "params"),
                        (dict(bias_metric="x"), "bias_metric"), (dict(target_se=math.inf), "target_se")):
        with pytest.raises(axonguide.InputError, match=message.replace("(", r"\(")):
            axonguide.fit(base, DATA, **kw)


def test_ctrl_c_stops_a_sweep_and_keeps_its_records(tmp_path):
    scene = json.loads((SCENES / "assay-explant.json").read_text())
    scene["neurons"]["populations"][0]["count"] = 20000
    scene["steps"] = 600
    spec = {"scene": scene, "parameters": [{"key": "cues.imposed.steepness", "values": [0.1, 0.2, 0.3, 0.4]}],
            "seeds": 8}  # 32 members of about 0.15 s each on 2 threads
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    t0 = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            axonguide.sweep(spec, out=tmp_path / "s", threads=2)
    finally:
        timer.cancel()
        timer.join()
    assert time.perf_counter() - t0 < 3.0
    kept = len(list((tmp_path / "s" / "members").glob("m*.json")))
    assert kept < 32 and not (tmp_path / "s" / "sweep.csv").exists()
    done = axonguide.sweep(spec, out=tmp_path / "s", threads=2)
    assert done.reused == kept and done.failed == 0


def test_fit_of_signalling_outgrowth_from_columns_equals_the_command(tmp_path):
    base = json.loads((SCENES / "assay-bicknell.json").read_text())
    base["neurons"]["count"] = 40
    base["steps"] = 30
    base["dt"] = 1.6
    (tmp_path / "base.json").write_text(json.dumps(base))
    cols = {"concentration": [0.001, 0.1, 10.0, 100.0], "steepness": [0.0, 0.0, 0.2, 0.2],
            "outgrowth": [330.0, 600.0, 280.0, 220.0], "se": [10.0, 20.0, 10.0, 10.0], "count": [20, 20, 20, 20]}
    (tmp_path / "data.csv").write_text(",".join(cols) + "\n" + "".join(
        ",".join(str(cols[c][i]) for c in cols) + "\n" for i in range(4)))
    f = axonguide.fit(tmp_path / "base.json", cols, seeds=2, grid=3, refine=0, polish=1, threads=2,
                      params=[("r0", 0.02, 0.2), "kext"], corrections={0.2: 1.5})
    assert f.parameters == ["r0", "kext"] and set(f.intervals) == {"r0", "kext"}
    assert f.dof == 2 and f.model.shape == (4,)
    cli("fit", tmp_path / "data.csv", "--scene", tmp_path / "base.json", "--out", tmp_path / "fit", "--seeds", 2,
        "--grid", 3, "--refine", 0, "--polish", 1, "--threads", 2, "--param", "r0=0.02:0.2", "--param", "kext",
        "--correct", "0.2=1.5", "--max-chi2", 1e9)
    j = json.loads((tmp_path / "fit" / "fit.json").read_text())
    assert j["measured"] == ["outgrowth"] and j["chi2"] == f.chi2 and j["runs"] == f.runs
    assert [j["parameters"][p]["best"] for p in ("r0", "kext")] == [f.best["r0"], f.best["kext"]]
    with pytest.raises(axonguide.InputError, match="unknown column"):
        axonguide.fit(tmp_path / "base.json", {**cols, "speed": [1, 2, 3, 4]}, seeds=1, grid=2, refine=0)
