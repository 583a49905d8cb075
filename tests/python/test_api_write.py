"""Result.write gives the bytes of `axonguide run`, and owns its folder as the command does."""

import json
import os

import pytest

import axonguide
from api_support import SMALL_CUE_SCENE, cli, file_hashes, manifest_without_run_facts


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    d = tmp_path_factory.mktemp("write")
    scene = d / "scene.json"
    # Every kind of output: CSV, GraphML, VTK frames, SWC morphologies, SONATA network/.
    full = json.loads(json.dumps(SMALL_CUE_SCENE))
    full["output"].update({"swc": True, "sonata": True})
    scene.write_text(json.dumps(full))
    cli("run", scene, "--out", d / "cli", "--threads", 2, "-q")
    r = axonguide.run(scene, threads=1)
    assert r.write(d / "py") == d / "py"
    return r, d / "py", d / "cli"


def test_every_file_but_timings_has_the_commands_bytes(folders):
    _, py, ref = folders
    a, b = file_hashes(py), file_hashes(ref)
    assert set(a) == set(b)
    assert {"neurons.csv", "paths.csv", "particles.csv", "growth.pvd", "graph.graphml"} <= set(a)
    assert any(name.startswith("vtk/") for name in a)
    assert any(name.startswith("morphologies/") for name in a) and "network/nodes.h5" in a
    ma, mb = (json.loads((f / "manifest.json").read_text())["axonguide"]["commit"] for f in (py, ref))
    assert ma == mb, "the module and the command come from different builds: build both"
    differ = sorted(k for k in a if a[k] != b[k])
    assert differ == ["manifest.json", "timings.csv"]
    # The manifests differ only in the run facts (threads 1 here, 2 there; times).
    assert manifest_without_run_facts(py) == manifest_without_run_facts(ref)
    m = json.loads((py / "manifest.json").read_text())
    assert m["threads"] == 1 and m["backend"] == "reference" and m["status"] == "complete"


def test_verify_and_assay_accept_the_folder(folders):
    r, py, _ = folders
    p = cli("verify", py)
    assert "a whole run" in p.stdout
    assert axonguide.verify(py)["whole"] is True
    assert not (py / ".axonguide.lock").exists()


def test_a_folder_holding_a_run_is_refused_without_force(folders, tmp_path):
    r, _, _ = folders
    out = tmp_path / "out"
    r.write(out)
    with pytest.raises(axonguide.InputError, match="--force|force"):
        r.write(out)
    (out / "notes.txt").write_text("mine")
    r.write(out, force=True)
    assert (out / "notes.txt").read_text() == "mine"
    assert axonguide.verify(out)["whole"]
    # A smaller run replaces exactly the files the old manifest listed.
    small = axonguide.run({"neurons": {"count": 20}, "steps": 3})
    small.write(out, force=True)
    assert not (out / "paths.csv").exists() and not (out / "vtk").exists()
    assert axonguide.verify(out)["whole"] and (out / "notes.txt").exists()


def test_a_failed_write_takes_its_folder_back(folders, tmp_path):
    r, _, _ = folders
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(axonguide.InputError):
        r.write(blocker)  # not a directory
    assert blocker.read_text() == "x"


def test_paths_and_flags_are_checked_and_any_name_is_kept(folders, tmp_path):
    r, _, _ = folders
    for bad, message in (("", "an empty path"), (str(tmp_path / "o\0x"), "NUL byte")):
        with pytest.raises(axonguide.InputError, match=message):
            r.write(bad)
    assert not (tmp_path / "o").exists()
    with pytest.raises(axonguide.InputError, match="force = 'no'"):
        r.write(tmp_path / "f", force="no")
    assert not (tmp_path / "f").exists()
    # A name that is not UTF-8, beside the run: kept, and named (as Python names it).
    out = tmp_path / "u"
    out.mkdir()
    with open(os.path.join(os.fsencode(out), b"notes\xff.csv"), "w") as f:
        f.write("mine")
    with pytest.warns(UserWarning, match="notes"):
        r.write(out)
    assert axonguide.verify(out)["whole"]
    assert axonguide.verify(os.fsencode(tmp_path) + b"/\xff")["problems"]
    # A name too long for the file system: RunError, as the command's exit 3.
    with pytest.raises(axonguide.RunError):
        r.write(tmp_path / ("x" * 300))
