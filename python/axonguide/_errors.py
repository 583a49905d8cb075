"""The exceptions of axonguide (docs/guide.md §2), and the checks of arguments that raise
them."""

import math
import numbers
import os


class InputError(ValueError):
    """The input is wrong (exit 2 on the command line): a scene, a sweep, fit data, an argument.

    ``key`` is the key path ("cues.sources[2].kd"), ``value`` the value as written and
    ``allowed`` what is allowed, when the error names them; otherwise None.
    """

    def __init__(self, message, key=None, value=None, allowed=None):
        super().__init__(message)
        self.key = key
        self.value = value
        self.allowed = allowed


class SceneError(InputError):
    """A scene is wrong: the command line's `axonguide: error: scene: ...` (exit 2)."""


class RunError(RuntimeError):
    """The input is valid but the run cannot proceed (exit 3 on the command line): placement
    too dense, a memory estimate above what this process may allocate, no usable GPU."""

    def __init__(self, message, key=None, value=None, allowed=None):
        super().__init__(message)


for _cls in (InputError, SceneError, RunError):
    _cls.__module__ = "axonguide"


def check_path(path, what):
    """A path argument as the C++ core takes it: os.fspath, then bytes in the file system's
    encoding (surrogateescape: any name the file system holds). An empty path, or one with a
    NUL byte (which would cut it short), is an InputError naming `what`."""
    p = os.fspath(path)
    b = os.fsencode(p)
    if not b:
        raise InputError(f"{what}: an empty path")
    if b"\0" in b:
        raise InputError(f"{what} = {p!r}: a NUL byte in a path")
    return b


def check_flag(value, what):
    """A yes/no argument: a bool (or NumPy's), not anything truthy ("no" is not False)."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    raise InputError(f"{what} = {value!r}: must be True or False")


def check_int(value, what, lo, hi):
    """An integer argument in [lo, hi] (not a bool, not a float that would be cut)."""
    if isinstance(value, bool) or not hasattr(value, "__index__"):
        raise InputError(f"{what} = {value!r}: must be an integer in [{lo}, {hi}]")
    v = value.__index__()
    if not lo <= v <= hi:
        raise InputError(f"{what} = {v}: must be an integer in [{lo}, {hi}]")
    return v


def check_number(value, what):
    """A finite real argument."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise InputError(f"{what} = {value!r}: must be a finite number")
    return float(value)
