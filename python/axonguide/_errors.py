"""The exceptions of axonguide (docs/methods.md §13)."""


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
