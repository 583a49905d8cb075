"""axonguide: deterministic simulation of axon growth and guidance (docs/guide.md §2).

    import axonguide
    scene = axonguide.Scene("scenes/assay-explant.json")     # or a dict, JSON text, a Path
    result = axonguide.run(scene, threads=2)                 # the GIL is released meanwhile
    result.neurons["status"], result.connections, result.stats, result.paths
    result.to_networkx(); result.write("out", force=True)    # the bytes of `axonguide run`
    axonguide.sweep("scenes/assay-explant.sweep.json")       # records and summary
    axonguide.assay_metrics(result); axonguide.fit(scene, "data.csv", grid=3, refine=0)
"""

from . import _core
from ._errors import InputError, RunError, SceneError
from ._result import (BACKENDS, CUE_KIND_NAMES, STATUS_NAMES, Arbour, Bfs, Frame, Result, assay_metrics, run,
                      verify)
from ._scene import Scene, SceneWarning
from ._study import FitResult, SweepResult, SweepSpec, fit, sweep

__version__ = _core.__version__
commit = _core.commit
metric_names = tuple(_core.metric_names())


def cuda_unavailable_reason():
    """Empty when backend="cuda" can run here; otherwise why not."""
    return _core.cuda_unavailable_reason()


__all__ = [
    "BACKENDS", "CUE_KIND_NAMES", "STATUS_NAMES", "Arbour", "Bfs", "FitResult", "Frame", "InputError", "Result", "RunError",
    "Scene", "SceneError", "SceneWarning", "SweepResult", "SweepSpec", "assay_metrics", "commit",
    "cuda_unavailable_reason", "fit", "metric_names", "run", "sweep", "verify",
]
