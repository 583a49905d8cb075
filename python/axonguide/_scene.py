"""axonguide.Scene: a validated scene (docs/methods.md §3, docs/guide.md §2)."""

import errno
import json
import math
import os
import warnings
from collections.abc import Mapping

from . import _core
from ._errors import InputError, SceneError, check_int, check_path


class SceneWarning(UserWarning):
    """What reading a scene noticed (the command line's `axonguide: warning: ...`)."""


def _json_default(value):
    # NumPy scalars and arrays, and paths, as JSON values.
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def _non_finite(value, path=""):
    # The key path of the first NaN or infinity in a dict or list, or None.
    if isinstance(value, float) and not math.isfinite(value):
        return path or "the value"
    items = value.items() if isinstance(value, Mapping) else enumerate(value) if isinstance(value, (list, tuple)) else ()
    for k, v in items:
        found = _non_finite(v, f"{path}[{k}]" if isinstance(k, int) else (f"{path}.{k}" if path else str(k)))
        if found:
            return found
    return None


def dumps(value, error=InputError):
    """JSON text of a dict (floats in their shortest round-trip form, as Python prints them).
    JSON has no NaN or infinity: one is `error` naming its key path."""
    try:
        return json.dumps(value, default=_json_default, allow_nan=False)
    except ValueError:
        path = _non_finite(value)
        if path is None:
            raise
        raise error(f"{path}: not a finite number (JSON has no NaN or infinity)", key=path) from None


def _check_file(path):
    # Bytes in the file system's encoding: any name it holds reaches the core as it is.
    b = check_path(path, "scene file")
    if not os.path.exists(b):
        raise FileNotFoundError(errno.ENOENT, "no such scene file", os.fsdecode(b))
    return b


def _looks_like_json(text):
    return text.lstrip().startswith("{")


class Scene:
    """A scene, validated exactly as `axonguide run` and `axonguide scene check` validate it.

    ``Scene(source)`` takes a dict, a JSON string, a file path (str or os.PathLike), another
    Scene, or nothing (the built-in default scene, ``Scene.default()``). A wrong scene raises
    SceneError (a ValueError) naming the key path, the value and what is allowed; a missing
    file raises FileNotFoundError. What parsing noticed is in ``warnings`` (and is issued as
    SceneWarning).
    """

    __slots__ = ("_h",)

    def __init__(self, source=None):
        if source is None:
            h = _core.scene_default()
        elif isinstance(source, Scene):
            h = source._h
        elif isinstance(source, _core.SceneHandle):
            h = source
        elif isinstance(source, Mapping):
            h = _core.scene_from_text(dumps(dict(source), SceneError), "<dict>")
        elif isinstance(source, str) and _looks_like_json(source):
            h = _core.scene_from_text(source, "<string>")
        elif isinstance(source, (str, bytes, os.PathLike)):
            h = _core.scene_from_file(_check_file(source))
        else:
            raise TypeError(f"Scene(): a dict, a JSON string, a path or None, not {type(source).__name__}")
        self._h = h
        if not isinstance(source, (Scene, _core.SceneHandle)):
            for w in h.warnings:
                warnings.warn(w, SceneWarning, stacklevel=2)

    @classmethod
    def default(cls):
        """The built-in scene `axonguide run` runs without a scene file."""
        return cls(None)

    @classmethod
    def from_file(cls, path):
        return cls(_core.scene_from_file(_check_file(path)))._warn()

    @classmethod
    def from_json(cls, text, origin="<string>"):
        return cls(_core.scene_from_text(text, origin))._warn()

    @classmethod
    def from_dict(cls, d):
        return cls(_core.scene_from_text(dumps(dict(d), SceneError), "<dict>"))._warn()

    def _warn(self):
        for w in self._h.warnings:
            warnings.warn(w, SceneWarning, stacklevel=3)
        return self

    def to_json(self, indent=2):
        """The canonical form (every key, defaults filled in, keys sorted, sources in canonical
        order): with indent=2 the text `axonguide scene check` prints; None: one line."""
        return self._h.canonical_json(-1 if indent is None else check_int(indent, "to_json(indent)", 0, 32))

    def to_dict(self):
        return json.loads(self._h.canonical_json(-1))

    @property
    def warnings(self):
        return list(self._h.warnings)

    @property
    def seed(self):
        return self._h.seed

    def with_seed(self, seed):
        """The same scene with another seed."""
        return Scene(self._h.with_seed(_check_seed(seed)))

    @property
    def origin(self):
        return self._h.origin

    @property
    def neuron_count(self):
        return self._h.neuron_count

    @property
    def steps(self):
        return self._h.steps

    def estimate_bytes(self):
        """The memory a run needs, estimated as `axonguide run` estimates it before starting."""
        return self._h.estimate_bytes()

    def planned_outputs(self):
        """The files a run folder of this scene holds ("vtk/*.vtp" for the VTK frames)."""
        return list(self._h.planned_outputs())

    def __eq__(self, other):
        if not isinstance(other, Scene):
            return NotImplemented
        return self.to_json(None) == other.to_json(None)

    def __hash__(self):
        return hash(self.to_json(None))

    def __repr__(self):
        return f"<axonguide.Scene {self.origin}: {self.neuron_count} neurons, {self.steps} steps, seed {self.seed}>"

    def __reduce__(self):
        return (Scene.from_json, (self.to_json(None), self.origin))


def _check_seed(seed):
    from ._errors import InputError

    if isinstance(seed, bool) or not isinstance(seed, int) and not hasattr(seed, "__index__"):
        raise InputError(f"seed = {seed!r}: must be an unsigned 64-bit integer (0 to 18446744073709551615)")
    seed = int(seed.__index__())
    if not 0 <= seed < 2**64:
        raise InputError(f"seed = {seed}: must be an unsigned 64-bit integer (0 to 18446744073709551615)")
    return seed


def as_scene(scene):
    """A Scene from whatever Scene() takes."""
    return scene if isinstance(scene, Scene) else Scene(scene)
