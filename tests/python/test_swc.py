"""output.swc read back by a real client: NEURON's Import3d (Debian python3-neuron).

Every morphology follows SONATA's SWC rules (ids from 1, parents before children, one
single-point soma first), and NEURON's reconstruction of each axon has the length that
neurons.csv reports (x 40 um per LU). NEURON keeps 3-D points in single precision, so
the length it computes can differ from ours by the rounding of every point it read: at most
2 sqrt(3) 2^-24 max|coordinate| per segment, the bound the test allows."""
import csv
import json
import math
import os
import subprocess

import pytest
from swc_rows import read_swc

AXONGUIDE = os.environ.get("AXG_BINARY", "axonguide")
UM_PER_LU = 40.0


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    root = tmp_path_factory.mktemp("swc")
    scene = {"neurons": {"count": 150}, "steps": 40, "guidance": {"model": "direct"},
             "output": {"swc": True}}
    (root / "scene.json").write_text(json.dumps(scene))
    out = root / "out"
    subprocess.run([AXONGUIDE, "run", str(root / "scene.json"), "--out", str(out), "-q"], check=True)
    with open(out / "neurons.csv") as f:
        neurons = list(csv.DictReader(f))
    return out, neurons


def test_sonata_swc_rules(run):
    out, neurons = run
    files = sorted((out / "morphologies").iterdir())
    assert len(files) == len(neurons)
    for n in neurons:
        rows = read_swc(out / "morphologies" / f"{n['id']}.swc")
        assert [r[0] for r in rows] == list(range(1, len(rows) + 1)), "ids from 1, consecutive"
        assert rows[0][1] == 1 and rows[0][6] == -1, "the soma first, a root"
        assert sum(1 for r in rows if r[1] == 1) == 1, "a single-point soma"
        assert all(r[1] == 2 for r in rows[1:]), "the rest is axon"
        assert all(0 < r[6] < r[0] for r in rows[1:]), "parents before children"
        soma = [float(n[k]) * UM_PER_LU for k in ("soma_x", "soma_y", "soma_z")]
        assert rows[0][2:5] == pytest.approx(tuple(soma), rel=1e-12, abs=1e-9)
        assert rows[0][5] == pytest.approx(float(n["radius"]) * UM_PER_LU, rel=1e-12)
        # The axon is the tip after each step it grew: steps + 1 points.
        grew = float(n["length"]) > 0
        assert len(rows) - 1 == (int(n["steps"]) + 1 if grew else 0)
        if grew:
            tip = [float(n[k]) * UM_PER_LU for k in ("tip_x", "tip_y", "tip_z")]
            assert rows[-1][2:5] == pytest.approx(tuple(tip), rel=1e-12, abs=1e-9)
            polyline = sum(math.dist(a[2:5], b[2:5]) for a, b in zip(rows[1:], rows[2:]))
            assert polyline == pytest.approx(float(n["length"]) * UM_PER_LU, rel=1e-9)


def test_neuron_import3d_lengths(run):
    neuron = pytest.importorskip("neuron", reason="python3-neuron is not installed")
    h = neuron.h
    h.load_file("stdlib.hoc")
    h.load_file("import3d.hoc")
    out, neurons = run
    checked = 0
    for n in neurons:
        for sec in list(h.allsec()):
            h.delete_section(sec=sec)
        reader = h.Import3d_SWC_read()
        reader.quiet = 1
        reader.input(str(out / "morphologies" / f"{n['id']}.swc"))
        h.Import3d_GUI(reader, 0).instantiate(None)
        secs = {sec.name(): sec for sec in h.allsec()}
        assert "soma[0]" in secs
        length = float(n["length"]) * UM_PER_LU
        if length == 0:
            assert [s for s in secs if s.startswith("axon")] == []
            continue
        axon = secs["axon[0]"]
        assert len(secs) == 2, f"one soma and one unbranched axon, got {sorted(secs)}"
        assert axon.parentseg().sec == secs["soma[0]"]
        assert axon.n3d() == int(n["steps"]) + 1
        points = [(axon.x3d(k), axon.y3d(k), axon.z3d(k)) for k in range(axon.n3d())]
        largest = max(abs(c) for p in points for c in p)
        bound = (axon.n3d() - 1) * 2 * math.sqrt(3) * 2.0**-24 * largest
        assert abs(axon.L - length) <= bound, (axon.L, length, bound)
        checked += 1
    assert checked > 100, "most axons grew"
