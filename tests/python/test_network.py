"""`axonguide network DIR` (issue 42) against networkx on the same graph: degree
distributions, synapses per connection, reciprocity, clustering, path length and the
connection probability's pair counts; malformed input is exit 2 naming the line."""

import csv
import hashlib
import itertools
import json
import math
import os
import pathlib
import shutil
import subprocess

import networkx as nx
import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("AXG_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = pathlib.Path(os.environ.get("AXG_BINARY", SOURCE_DIR / "build" / "bin" / "axonguide"))


def cli(*args, check=True):
    p = subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"axonguide {args}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module", params=["synapses", "autapses", "soma-contact"])
def analysed(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(request.param)
    if request.param != "soma-contact":
        s = json.loads((SOURCE_DIR / "scenes" / "culture.json").read_text())
        s["neurons"]["count"] = 120
        s["neurons"]["region"]["radius"] = 350
        s["steps"] = 96
        s["dt"] = 1.0
        s["output"] = {}
        s["synapses"] = {"distance": 3.0, "autapses": request.param == "autapses"}
    else:  # one unbranched axon per neuron, stopped at the first soma (the default scene's)
        s = json.loads((SOURCE_DIR / "scenes" / "default.json").read_text())
        s["neurons"]["count"] = 400
    (d / "scene.json").write_text(json.dumps(s))
    cli("run", d / "scene.json", "--out", d / "run", "-q")
    cli("network", d / "run", "--bin", 40)
    return d / "run"


def graph(run):
    n = len(rows(run / "neurons.csv"))
    g = nx.DiGraph()
    g.add_nodes_from(range(n))
    for r in rows(run / "connections.csv"):
        g.add_edge(int(r["source"]), int(r["target"]), weight=int(r.get("synapses", 1)))
    return g


def summary(run):
    return {r["statistic"]: float(r["value"]) for r in rows(run / "network.csv")}


def test_the_graph_has_edges(analysed):
    assert graph(analysed).number_of_edges() > 20


def test_degrees_and_synapses_per_connection_are_networkx(analysed):
    g = graph(analysed)
    deg = rows(analysed / "degrees.csv")
    out = np.bincount([d for _, d in g.out_degree()], minlength=len(deg))
    inn = np.bincount([d for _, d in g.in_degree()], minlength=len(deg))
    assert [int(r["out_neurons"]) for r in deg] == out.tolist()
    assert [int(r["in_neurons"]) for r in deg] == inn.tolist()
    per = {int(r["synapses"]): int(r["connections"]) for r in rows(analysed / "synapses_per_connection.csv")}
    w = np.bincount([d["weight"] for _, _, d in g.edges(data=True)])
    assert per == {k: int(c) for k, c in enumerate(w) if k > 0}
    s = summary(analysed)
    assert s["connections"] == g.number_of_edges()
    assert s["synapses"] == sum(d["weight"] for _, _, d in g.edges(data=True))


def test_reciprocity_clustering_and_path_length_are_networkx(analysed):
    g = graph(analysed)
    s = summary(analysed)
    assert s["reciprocity"] == pytest.approx(nx.reciprocity(g), rel=1e-12, abs=1e-15)
    assert s["clustering"] == pytest.approx(nx.average_clustering(g.to_undirected()), rel=1e-12, abs=1e-15)
    lengths = [d for u, paths in nx.all_pairs_shortest_path_length(g) for v, d in paths.items() if u != v]
    n = g.number_of_nodes()
    assert s["mean_path_length"] == pytest.approx(np.mean(lengths), rel=1e-12)
    assert s["reachable_pairs"] == pytest.approx(len(lengths) / (n * (n - 1)), rel=1e-12)
    assert s["path_sources"] == n


def test_connection_probability_counts_every_ordered_pair(analysed):
    soma = np.array([[float(r["soma_x"]), float(r["soma_y"]), float(r["soma_z"])] for r in rows(analysed / "neurons.csv")])
    g = graph(analysed)
    bins = rows(analysed / "connection_probability.csv")
    units = json.loads((analysed / "manifest.json").read_text())["scene"].get("units", {})
    width = 40.0 / (1.0 if units.get("length") == "um" else 40.0)  # --bin 40 um in the scene's length unit
    pairs = np.zeros(len(bins), int)
    hits = np.zeros(len(bins), int)
    for i, j in itertools.permutations(range(len(soma)), 2):
        pairs[int(np.linalg.norm(soma[i] - soma[j]) / width)] += 1
    for i, j in g.edges():
        if i != j:
            hits[int(np.linalg.norm(soma[i] - soma[j]) / width)] += 1
    assert [int(r["pairs"]) for r in bins] == pairs.tolist()
    assert [int(r["connected"]) for r in bins] == hits.tolist()
    for r in bins:
        if int(r["pairs"]):
            p = float(r["probability"])
            assert float(r["ci_lo"]) <= p <= float(r["ci_hi"])


def test_malformed_connections_name_the_line(analysed, tmp_path):
    bad = tmp_path / "bad"
    shutil.copytree(analysed, bad)
    lines = (bad / "connections.csv").read_text().splitlines()
    lines[2] = "1,x,1,0"
    (bad / "connections.csv").write_text("\n".join(lines) + "\n")
    m = json.loads((bad / "manifest.json").read_text())
    m["files"]["connections.csv"]["sha256"] = hashlib.sha256((bad / "connections.csv").read_bytes()).hexdigest()
    (bad / "manifest.json").write_text(json.dumps(m))  # a whole run whose file is malformed
    p = cli("network", bad, check=False)
    assert p.returncode == 2 and "connections.csv: line 3" in p.stderr, p.stderr
    p = cli("network", analysed, "--bin", 0, check=False)
    assert p.returncode == 2 and "--bin" in p.stderr
