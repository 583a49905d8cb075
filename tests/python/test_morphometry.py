"""`axonguide morphometry` against an independent reader: random SWC trees (stems of types
2, 3 and 4, branch points of degree 2 and 3) measured by a recursive Python parser written
from the data's conventions (../shared/data/ramakers-culture/development.csv: the axon is
all type-2 neurites of a neuron, each type-3/4 stem one dendrite, a segment ends at a branch
point or a tip, an unbranched neurite's mean intermediate length is 0, the soma-to-stem piece
is not neurite), in 3-D and in xy projection; and malformed SWC refused with exit 2 naming
the file and the line, with nothing written."""
import csv
import math
import os
import random
import subprocess

import pytest

AXONGUIDE = os.environ.get("AXG_BINARY", "axonguide")


def random_swc(rng):
    lines = ["# random tree", "1 1 0 0 0 6 -1"]
    nid = 2
    open_ = []
    for _ in range(rng.randint(1, 6)):
        t = rng.choice([2, 3, 3, 4])
        p = (rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-3, 3))
        lines.append("%d %d %r %r %r 1 1" % (nid, t, *p))
        open_.append((nid, t, p, 0))
        nid += 1
    while open_:
        i, t, p, depth = open_.pop(rng.randrange(len(open_)))  # children after parents, order shuffled
        kids = 0 if depth > 8 else rng.choice([0, 1, 1, 1, 2, 2, 3])
        for _ in range(kids):
            q = (p[0] + rng.uniform(-15, 15), p[1] + rng.uniform(-15, 15), p[2] + rng.uniform(-4, 4))
            lines.append("%d %d %r %r %r 1 %d" % (nid, t, *q, i))
            open_.append((nid, t, q, depth + 1))
            nid += 1
    return "\n".join(lines) + "\n"


def parse(path):
    s = {}
    for line in open(path):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        i, t, x, y, z, r, p = line.split()
        s[int(i)] = (int(t), float(x), float(y), float(z), int(p))
    return s


def dist(a, b, xy):
    dz = 0.0 if xy else a[3] - b[3]
    return math.sqrt((a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2 + dz ** 2)


def neurite(s, kids, stem, xy):
    """(total length, branch points, terminal segments, terminal lengths, intermediate lengths)"""
    acc = {"total": 0.0, "bp": 0, "term": [], "inter": []}

    def walk(node, seg):
        ch = kids.get(node, [])
        if not ch:
            acc["term"].append(seg)
            return
        if len(ch) >= 2:
            acc["bp"] += 1
            acc["inter"].append(seg)
            seg = 0.0
        for c in ch:
            d = dist(s[c], s[node], xy)
            acc["total"] += d
            walk(c, seg + d)

    walk(stem, 0.0)
    return acc


def stats(s, xy):
    kids = {}
    for i, v in s.items():
        kids.setdefault(v[4], []).append(i)
    stems = [i for i, v in s.items() if v[0] != 1 and (v[4] == -1 or s[v[4]][0] == 1)]
    axon = {"total": 0.0, "bp": 0, "term": [], "inter": []}
    has_axon = False
    dendrites = []
    for st in stems:
        a = neurite(s, kids, st, xy)
        if s[st][0] == 2:
            has_axon = True
            for k in ("total", "bp"):
                axon[k] += a[k]
            axon["term"] += a["term"]
            axon["inter"] += a["inter"]
        elif s[st][0] in (3, 4):
            dendrites.append(a)
    return has_axon, axon, dendrites


def summary(x):
    n = len(x)
    m = sum(x) / n if n else float("nan")
    sd = math.sqrt(sum((v - m) ** 2 for v in x) / (n - 1)) if n > 1 else float("nan")
    return n, m, sd, sd / math.sqrt(n) if n > 1 else float("nan")


def mean0(v):
    return sum(v) / len(v) if v else 0.0


def expected(files, xy):
    v = {k: [] for k in ["total_axon_length", "branch_points_per_axon", "terminal_segments_per_axon",
                         "axons_mean_terminal_segment_length", "axons_mean_intermediate_segment_length",
                         "number_of_dendrites_per_neuron", "total_dendrite_length", "branch_points_per_dendrite",
                         "terminal_segments_per_dendrite", "dendrites_mean_terminal_segment_length",
                         "dendrites_mean_intermediate_segment_length"]}
    for f in files:
        has_axon, a, ds = stats(parse(f), xy)
        if has_axon:
            v["total_axon_length"].append(a["total"])
            v["branch_points_per_axon"].append(a["bp"])
            v["terminal_segments_per_axon"].append(len(a["term"]))
            v["axons_mean_terminal_segment_length"].append(mean0(a["term"]))
            v["axons_mean_intermediate_segment_length"].append(mean0(a["inter"]))
        v["number_of_dendrites_per_neuron"].append(len(ds))
        for d in ds:
            v["total_dendrite_length"].append(d["total"])
            v["branch_points_per_dendrite"].append(d["bp"])
            v["terminal_segments_per_dendrite"].append(len(d["term"]))
            v["dendrites_mean_terminal_segment_length"].append(mean0(d["term"]))
            v["dendrites_mean_intermediate_segment_length"].append(mean0(d["inter"]))
    return {k: summary(x) for k, x in v.items()}


def close(a, b):
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("swc")
    rng = random.Random(20261207)
    files = []
    for k in range(40):
        f = d / ("cell%02d.swc" % k)
        f.write_text(random_swc(rng))
        files.append(f)
    return d, files


@pytest.mark.parametrize("projection", ["none", "xy"])
def test_population_statistics_match_an_independent_reader(folder, tmp_path, projection):
    d, files = folder
    out = tmp_path / "m"
    subprocess.run([AXONGUIDE, "morphometry", str(d), "--out", str(out), "--projection", projection], check=True,
                   stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(out / "morphometry.csv")))
    want = expected(files, projection == "xy")
    assert [r["statistic"] for r in rows] == list(want)
    for r in rows:
        n, m, sd, se = want[r["statistic"]]
        assert int(r["n"]) == n, r
        for got, exp in ((r["mean"], m), (r["sd"], sd), (r["se"], se)):
            assert close(float(got), exp), (r, m, sd, se)


def test_sholl_matches_an_independent_count(folder, tmp_path):
    d, files = folder
    out = tmp_path / "m"
    subprocess.run([AXONGUIDE, "morphometry", str(d), "--out", str(out), "--sholl-step", "7"], check=True,
                   stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(out / "sholl.csv")))
    counts = []
    for f in files:
        s = parse(f)
        soma = s[1]
        group = {}
        for i in sorted(s):
            t, p = s[i][0], s[i][4]
            if t == 1:
                continue
            group[i] = t if s[p][0] == 1 else group[p]
        c = {}
        for i, g in group.items():
            p = s[i][4]
            if g != 2 or s[p][0] == 1:
                continue
            a, b = dist(s[i], soma, False), dist(s[p], soma, False)
            for k, r in enumerate(rows):
                rad = float(r["radius"])
                if (a <= rad) != (b <= rad):
                    c[k] = c.get(k, 0) + 1
        counts.append(c)
    for k, r in enumerate(rows):
        m = sum(c.get(k, 0) for c in counts) / len(files)
        assert close(float(r["axon_mean"]), m), (k, r, m)


@pytest.mark.parametrize("text,needle", [
    ("1 1 0 0 0 1 -1\n2 2 1 0 0 1 9\n", "bad.swc:2: sample 2: its parent 9 is not in the file"),
    ("1 1 0 0 0 1 -1\n2 2 1 0 0 1 3\n3 2 2 0 0 1 2\n", "bad.swc:2: sample 2: its parents lead back to it (a cycle)"),
    ("1 1 0 0 0 1 -1\n2 2 1 0 0 1 3\n3 2 2 0 0 1 1\n", "bad.swc:2: sample 2: its parent 3 comes after it (line 3)"),
    ("1 1 0 0 0 1 -1\n2 2 1 zero 0 1 1\n", "bad.swc:2: field 4 (y) = \"zero\" is not a finite number"),
])
def test_malformed_swc_exits_2_naming_file_and_line(tmp_path, text, needle):
    d = tmp_path / "in"
    d.mkdir()
    (d / "good.swc").write_text("1 1 0 0 0 1 -1\n2 2 1 0 0 1 1\n")
    (d / "bad.swc").write_text(text)
    out = tmp_path / "out"
    p = subprocess.run([AXONGUIDE, "morphometry", str(d), "--out", str(out)], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert needle in p.stderr, p.stderr
    assert not out.exists()
