"""Synapses (issue 42): axonguide.run's synapse arrays against synapses.csv and
connections.csv, to_networkx's weights against them and against graph.graphml read by
networkx, and the synapse positions on the post neuron's dendrites."""

import json

import networkx as nx
import numpy as np
import pytest

import axonguide
from api_support import SCENES, cli, column, read_csv, same


def culture_with_synapses():
    s = json.loads((SCENES / "culture.json").read_text())
    s["neurons"]["count"] = 60
    s["neurons"]["region"]["radius"] = 300
    s["steps"] = 72
    s["dt"] = 1.0
    s["synapses"] = {"distance": 3.0, "probability": 0.7, "max_per_connection": 3}
    s["output"] = {"swc": True}
    return s


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("syn")
    scene = d / "scene.json"
    scene.write_text(json.dumps(culture_with_synapses()))
    cli("run", scene, "--out", d / "out", "--threads", 2, "-q")
    return axonguide.run(culture_with_synapses(), threads=2), d / "out"


def test_synapses_are_synapses_csv(run):
    r, out = run
    h, rows = read_csv(out / "synapses.csv")
    s = r.synapses
    assert s.dtype.names == tuple(h)
    assert len(s) == len(rows) > 0
    for name in h:
        assert same(s[name], column(rows, h, name)), name
    # Some realised, some not (probability 0.7, cap 3).
    assert 0 < s["realised"].sum() < len(s)
    assert (s["distance"] <= 3.0).all()


def test_connections_carry_the_realised_synapse_counts(run):
    r, out = run
    h, rows = read_csv(out / "connections.csv")
    assert h == ["source", "target", "synapses", "first_step"]
    c = r.connections
    for name in h:
        assert same(c[name], column(rows, h, name)), name
    s = r.synapses
    real = s[s["realised"] == 1]
    pairs, counts = np.unique(np.stack([real["pre"], real["post"]], axis=1), axis=0, return_counts=True)
    assert same(pairs[:, 0], c["source"]) and same(pairs[:, 1], c["target"]) and same(counts, c["synapses"])
    assert (c["synapses"] <= 3).all()
    firsts = [real["step"][(real["pre"] == a) & (real["post"] == b)].min() for a, b in pairs]
    assert same(firsts, c["first_step"])


def test_networkx_weights_are_the_synapse_counts(run):
    r, out = run
    g = r.to_networkx()
    c = r.connections
    assert g.number_of_edges() == len(c)
    for a, b, w in zip(c["source"].tolist(), c["target"].tolist(), c["synapses"].tolist()):
        assert g[a][b]["weight"] == w
    read = nx.read_graphml(out / "graph.graphml")
    weights = {(int(a[1:]), int(b[1:])): d["weight"] for a, b, d in read.edges(data=True)}  # node ids "n<i>"
    assert weights == {(a, b): d["weight"] for a, b, d in g.edges(data=True)}


def test_a_synapse_sits_on_a_dendrite_sample_of_the_post_neuron(run):
    """x, y, z lie on the segment that ends at post_sample (or on the soma's surface)."""
    r, out = run
    s = r.synapses
    radius = r.neurons["radius"][0]
    for row in s[:200]:
        post, k = int(row["post"]), int(row["post_sample"])
        p = np.array([row["x"], row["y"], row["z"]])
        if k == 1:
            assert abs(np.linalg.norm(p - r.soma[post]) - radius) < 1e-9
            continue
        a = r.arbour(post)  # row 0 the soma: sample k is row k - 1
        q1, q0 = a.point[k - 1], a.point[a.parent[k - 1]]
        assert a.type[k - 1] == 3
        t = np.dot(p - q0, q1 - q0) / max(np.dot(q1 - q0, q1 - q0), 1e-300)
        assert -1e-9 <= t <= 1 + 1e-9
        assert np.linalg.norm(q0 + t * (q1 - q0) - p) < 1e-9
