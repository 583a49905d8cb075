"""axonguide.run and its Result (docs/guide.md §2)."""

import os
import pathlib
import warnings
from collections import namedtuple
from functools import cached_property

import numpy as np

from . import _core
from ._errors import InputError, check_flag, check_path
from ._scene import Scene, _check_seed, as_scene

STATUS_NAMES = tuple(_core.STATUS_NAMES)
CUE_KIND_NAMES = tuple(_core.CUE_KIND_NAMES)
BACKENDS = ("reference", "cuda", "emulated")

# One particle frame (output.paths or output.vtk with a particle field): positions (k, 3)
# float64 and cue ids (k,) uint16 of every stride-th particle by id; count particles in all.
Frame = namedtuple("Frame", "step positions cue count stride")
# One neuron's arbour in SWC order (row 0: the soma): point (k, 3) float64 in the scene's
# length unit, parent (k,) int64 (row of the parent, -1 for the soma), type (k,) uint8 (1 soma,
# 2 axon, 3 dendrite), step (k,) uint32 (the step that made the point).
Arbour = namedtuple("Arbour", "point parent type step")
# bfs.csv's columns: level (int32, -1 unreached) and parent (int64, -1 none) from
# analysis.bfs_sources, component (uint32, the lowest id in it); None when not analysed.
Bfs = namedtuple("Bfs", "level parent component sources max_level reached component_count largest_component")


def check_threads(threads):
    if threads is None:
        return 0
    if isinstance(threads, bool) or not hasattr(threads, "__index__"):
        raise InputError(f"threads = {threads!r}: must be None or an integer, 0 (all cores) to 4096")
    threads = threads.__index__()
    if not 0 <= threads <= 4096:
        raise InputError(f"threads = {threads}: must be None or 0 (all cores) to 4096")
    return threads


def check_backend(backend):
    if backend not in BACKENDS:
        raise InputError(f"backend = {backend!r}: must be one of {', '.join(BACKENDS)}")
    return backend


def run(scene=None, threads=None, backend="reference", seed=None):
    """Runs a scene as `axonguide run` does and returns its Result.

    scene: a Scene or anything Scene() takes (dict, JSON text, path; None: the default).
    threads: worker threads (None or 0: all cores); the results do not depend on it.
    backend: "reference", "cuda" (the GPU, when built and present) or "emulated" (the GPU
    pipeline compiled for the CPU). seed: overrides the scene's (as --seed does).
    The GIL is released while the run works. Raises SceneError for a bad scene, InputError
    for a bad argument, RunError when the run cannot proceed; a KeyboardInterrupt (Ctrl-C)
    ends the run at the end of the current step and is raised.
    """
    s = as_scene(scene)
    h = _core.run(s._h, check_threads(threads), check_backend(backend), None if seed is None else _check_seed(seed))
    return Result(h)


class Result:
    """A finished run: the values of its output files as NumPy arrays (docs/guide.md §2)."""

    def __init__(self, handle):
        self._h = handle

    @cached_property
    def neurons(self):
        """neurons.csv: structured (id u4, soma_x/y/z f8, radius f8, status u1 (STATUS_NAMES),
        tip_x/y/z f8, length f8, steps u4, target i8 (-1: none))."""
        return self._h.neurons()

    @cached_property
    def connections(self):
        """connections.csv: structured (source u4, target u4, step u4, length f8), by source; in
        a scene with synapses (source u4, target u4, synapses u4, first_step u4), by source then
        target."""
        return self._h.connections()

    @cached_property
    def synapses(self):
        """synapses.csv (scenes with synapses; None otherwise): structured (pre u4, post u4,
        pre_sample u4, post_sample u4, x/y/z f8 (on the dendrite), distance f8, contacts u4,
        step u4, realised u1), one row per apposition, sorted by pre, post, pre_sample,
        post_sample."""
        return self._h.synapses()

    @cached_property
    def stats(self):
        """stats.csv: structured (step u4, growing, connected, exited, particles u8), every
        output.stats_every steps and the last."""
        return self._h.stats(False)

    @cached_property
    def step_stats(self):
        """As stats, for every step (0 to the last run)."""
        return self._h.stats(True)

    @cached_property
    def sources(self):
        """sources.csv: structured (cue u4, kind u1 (CUE_KIND_NAMES), x/y/z, emission,
        diffusion, decay, kd, min_concentration, max_concentration f8); empty without cues."""
        return self._h.sources()

    @cached_property
    def paths(self):
        """(steps run + 1, neurons, 3) float64: the tips after each step (paths.csv holds
        neuron i's rows up to its steps); None without output.paths."""
        return self._h.paths()

    def arbour(self, i):
        """Neuron i's arbour as NumPy arrays (an Arbour: point, parent, type, step), the rows
        of morphologies/<i>.swc in order (coordinates in the scene's length unit, not
        micrometres); None for a scene without arbours."""
        a = self._h.arbour(int(i))
        return None if a is None else Arbour(*a)

    @cached_property
    def arbours(self):
        """Every neuron's arbour (a list of Arbour, by neuron id); None without arbours."""
        if self._h.arbour(0) is None:
            return None
        return [Arbour(*self._h.arbour(i)) for i in range(len(self.soma))]

    @cached_property
    def soma(self):
        """(neurons, 3) float64, read-only: the soma positions."""
        return self._h.soma()

    @cached_property
    def frames(self):
        """particles.csv: a list of Frame(step, positions, cue, count, stride); read-only views."""
        return [Frame(*f) for f in self._h.frames()]

    @cached_property
    def bfs(self):
        d = self._h.bfs()
        return Bfs(d["level"], d["parent"], d["component"], list(d["sources"]), d["max_level"], d["reached"],
                   d["component_count"], d["largest_component"])

    @cached_property
    def summary(self):
        """manifest.json's summary, and the graph's edge count, largest component, BFS reach."""
        return self._h.summary()

    @property
    def timings(self):
        """Seconds per phase (timings.csv summed): the only values that vary between runs."""
        return self._h.timings()

    @cached_property
    def scene(self):
        """The scene as run (with the seed given to run())."""
        return Scene(self._h.scene())

    @property
    def warnings(self):
        return list(self._h.warnings)

    @property
    def backend(self):
        return self._h.backend

    @property
    def threads(self):
        return self._h.threads

    @property
    def statuses(self):
        """The status names of the neurons, as neurons.csv writes them."""
        return np.asarray(STATUS_NAMES)[self.neurons["status"]]

    def connections_csv(self):
        """The bytes of connections.csv (sweeps hash them)."""
        return self._h.connections_csv()

    def to_networkx(self):
        """A networkx.DiGraph: node i (neuron id) with position (soma), status, tip, length,
        steps and, when analysed, level (BFS, -1 unreached) and component; an edge per
        connection with step and length (with synapses: weight, the realised synapse count, and
        step, the connection's first step)."""
        import networkx as nx

        g = nx.DiGraph()
        n = self.neurons
        b = self.bfs
        status = self.statuses
        level = b.level.tolist() if b.level is not None else None
        comp = b.component.tolist() if b.component is not None else None
        soma = np.stack([n["soma_x"], n["soma_y"], n["soma_z"]], axis=1).tolist()
        tip = np.stack([n["tip_x"], n["tip_y"], n["tip_z"]], axis=1).tolist()
        length = n["length"].tolist()
        steps = n["steps"].tolist()
        nodes = []
        for i in range(len(n)):
            a = {"position": tuple(soma[i]), "status": str(status[i]), "tip": tuple(tip[i]), "length": length[i],
                 "steps": steps[i]}
            if level is not None:
                a["level"] = level[i]
            if comp is not None:
                a["component"] = comp[i]
            nodes.append((i, a))
        g.add_nodes_from(nodes)
        c = self.connections
        if "synapses" in c.dtype.names:  # a synapse scene: weight is the realised synapse count
            g.add_edges_from((s, t, {"weight": w, "step": st}) for s, t, w, st in
                             zip(c["source"].tolist(), c["target"].tolist(), c["synapses"].tolist(),
                                 c["first_step"].tolist()))
        else:
            g.add_edges_from((s, t, {"step": st, "length": ln}) for s, t, st, ln in
                             zip(c["source"].tolist(), c["target"].tolist(), c["step"].tolist(), c["length"].tolist()))
        g.graph["seed"] = self.scene.seed
        return g

    def write(self, dir, force=False):
        """Writes the run folder `axonguide run --out DIR` writes, with the same bytes in every
        file but timings.csv and the manifest's run facts (threads, backend, times, peak memory,
        creation time). A folder holding a run is refused (InputError) unless force, which
        replaces exactly the files its manifest lists; a complete run replaced is put back if
        the write fails. Returns the folder as a pathlib.Path."""
        b = check_path(dir, "write(dir)")
        path = pathlib.Path(os.fsdecode(b))
        out = self._h.write(b, check_flag(force, "force"))
        for name in out["foreign"]:
            if name.endswith((".csv", ".graphml", ".pvd", ".vtp", ".swc", ".h5", ".json")) or name == "view.html" \
                    or name.startswith(("assay", "plot")):
                warnings.warn(f"{path}/{name} is not this run's (its manifest will not list it)", stacklevel=2)
        return path

    def assay_metrics(self):
        """assay_metrics(self)."""
        return assay_metrics(self)

    def __repr__(self):
        s = self.summary
        return (f"<axonguide.Result {s['neurons']} neurons, {s['steps_run']} steps: connected {s['connected']}, "
                f"exited {s['exited']}, max_steps {s['max_steps']}; {s['edges']} edges>")


def assay_metrics(result):
    """The assay metrics of a run (docs/validation.md §12.1), as `axonguide assay` and the sweep
    records compute them: the scalar metrics by name (bias, guidance_ratio, ... with their
    standard errors), profile (R(θ), 36 sectors at profile_theta_deg), profile_axons, turning
    (counts per 10° bin between turning_edges_deg). The GIL is released while it measures."""
    if not isinstance(result, Result):
        raise TypeError(f"assay_metrics(): a Result, not {type(result).__name__}")
    return _core.assay_metrics(result._h)


def verify(dir):
    """`axonguide verify DIR`: whole (bool), status, problems, notes."""
    return _core.verify(check_path(dir, "verify(dir)"))
