"""axonguide.Scene against `axonguide scene check` / `scene default`, and the exceptions."""

import json
import pathlib

import pytest

import axonguide
from api_support import SCENES, cli

EXPLANT = SCENES / "assay-explant.json"


def test_dict_json_and_file_give_the_canonical_form_of_scene_check():
    text = EXPLANT.read_text()
    printed = cli("scene", "check", EXPLANT).stdout
    forms = [
        axonguide.Scene(json.loads(text)),
        axonguide.Scene(text),
        axonguide.Scene(str(EXPLANT)),
        axonguide.Scene(EXPLANT),
        axonguide.Scene.from_file(EXPLANT),
        axonguide.Scene.from_json(text),
        axonguide.Scene.from_dict(json.loads(text)),
    ]
    for s in forms:
        assert s.to_json() + "\n" == printed
        assert s == forms[0]
        assert hash(s) == hash(forms[0])
    s = forms[0]
    assert axonguide.Scene(s.to_dict()) == s
    assert s.to_dict() == json.loads(printed)
    assert s.seed == 1 and s.neuron_count == 1000 and s.steps == 100
    assert s.with_seed(7).seed == 7 and s.with_seed(7) != s and s.seed == 1


def test_default_is_scene_default():
    assert axonguide.Scene.default().to_json() + "\n" == cli("scene", "default").stdout
    assert axonguide.Scene() == axonguide.Scene.default()


def test_permuted_sources_give_the_same_scene():
    a = {"guidance": {"model": "snr"}, "cues": {"sources": [
        {"kind": "attractant", "position": [1, 0, 0]}, {"kind": "repellent", "position": [-1, 0, 0]}]}}
    b = {"guidance": {"model": "snr"}, "cues": {"sources": list(reversed(a["cues"]["sources"]))}}
    assert axonguide.Scene(a) == axonguide.Scene(b)


def scene_error_of_file(tmp_path, scene):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene))
    p = cli("scene", "check", path, check=False)
    assert p.returncode == 2
    with pytest.raises(axonguide.SceneError) as e:
        axonguide.Scene(path)
    assert p.stderr.strip() == f"axonguide: error: {e.value}"
    return e.value


def test_bad_value_names_key_value_and_what_is_allowed(tmp_path):
    with pytest.raises(axonguide.SceneError) as e:
        axonguide.Scene({"neurons": {"count": -1}})
    err = e.value
    assert isinstance(err, ValueError) and isinstance(err, axonguide.InputError)
    assert err.key == "neurons.count"
    assert err.value == "-1"
    assert err.allowed and err.allowed in str(err)
    assert str(err).startswith("scene: neurons.count = -1: ")
    # The same message as the command line's, for the same scene in a file.
    f = scene_error_of_file(tmp_path, {"neurons": {"count": -1}})
    assert (f.key, f.value, f.allowed) == (err.key, err.value, err.allowed)


def test_unknown_key(tmp_path):
    with pytest.raises(axonguide.SceneError) as e:
        axonguide.Scene({"neurons": {"cuont": 5}})
    assert e.value.key == "neurons.cuont"
    assert e.value.value == "5"
    assert "count" in e.value.allowed
    assert "unknown key neurons.cuont" in str(e.value)
    scene_error_of_file(tmp_path, {"neurons": {"cuont": 5}})


def test_nested_key_path_and_malformed_json():
    with pytest.raises(axonguide.SceneError) as e:
        axonguide.Scene({"guidance": {"model": "snr"},
                         "cues": {"sources": [{"kind": "attractant"}, {"kind": "sideways"}]}})
    assert e.value.key.startswith("cues.sources[") and e.value.key.endswith("].kind")
    assert e.value.value == '"sideways"'
    with pytest.raises(axonguide.SceneError) as e:
        axonguide.Scene('{"steps": 10,')
    assert e.value.key is None and e.value.value is None and e.value.allowed is None


def test_missing_file_and_wrong_types(tmp_path):
    with pytest.raises(FileNotFoundError):
        axonguide.Scene(tmp_path / "nope.json")
    with pytest.raises(FileNotFoundError):
        axonguide.Scene.from_file(str(tmp_path / "nope.json"))
    with pytest.raises(TypeError):
        axonguide.Scene(42)
    with pytest.raises(axonguide.InputError):
        axonguide.Scene().with_seed(-1)


def test_warnings_are_kept_and_issued():
    with pytest.warns(axonguide.SceneWarning, match="output.paths is enabled"):
        s = axonguide.Scene({"output": {"vtk": True}})
    assert any("output.paths is enabled" in w for w in s.warnings)
    assert s.to_dict()["output"]["paths"] is True


def test_numpy_values_in_a_dict():
    np = pytest.importorskip("numpy")
    s = axonguide.Scene({"steps": np.int64(12), "neurons": {"region": {"radius": np.float64(2.0)}}})
    assert s.steps == 12 and s.to_dict()["neurons"]["region"]["radius"] == 2.0


def test_pickle_round_trip():
    import pickle

    s = axonguide.Scene(EXPLANT)
    assert pickle.loads(pickle.dumps(s)) == s


def test_argument_errors():
    with pytest.raises(axonguide.InputError, match="backend"):
        axonguide.run({"neurons": {"count": 10}, "steps": 1}, backend="quantum")
    with pytest.raises(axonguide.InputError, match="threads"):
        axonguide.run({"neurons": {"count": 10}, "steps": 1}, threads=-1)
    with pytest.raises(axonguide.InputError, match="seed"):
        axonguide.run({"neurons": {"count": 10}, "steps": 1}, seed=-3)
    assert issubclass(axonguide.RunError, RuntimeError)
    assert not issubclass(axonguide.RunError, ValueError)


def test_a_nan_in_a_dict_is_named_and_wide_indents_are_refused():
    with pytest.raises(axonguide.SceneError, match=r"cues.sources\[0\].position\[1\]: not a finite number") as e:
        axonguide.Scene({"cues": {"sources": [{"kind": "attractant", "position": [0, float("inf"), 0]}]}})
    assert e.value.key == "cues.sources[0].position[1]"
    s = axonguide.Scene.default()
    for indent in (33, 10**7, True, "2"):  # nlohmann's serializer read past its buffer for a wide indent
        with pytest.raises(axonguide.InputError, match="indent"):
            s.to_json(indent)
    assert s.to_json(0) and s.to_json(32)
