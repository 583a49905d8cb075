"""Sweeps and the fit from Python (docs/validation.md §12, docs/guide.md §2)."""

import io
import numbers
import os
import pathlib
from collections.abc import Mapping

import numpy as np

from . import _core
from ._errors import InputError, check_flag, check_int, check_number, check_path
from ._result import check_backend, check_threads
from ._scene import Scene, as_scene, dumps


def _column(values):
    # A parameter's values: float64 when every one is a number, else an object array
    # (case labels, arrays such as a position).
    if all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in values):
        return np.asarray(values, dtype=np.float64)
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def _table(d):
    return {k: (v if isinstance(v, np.ndarray) else _column(v)) for k, v in d.items()}


class SweepSpec:
    """A sweep file (docs/validation.md §12.2) from a path, a dict or JSON text, validated as
    `axonguide sweep` validates it (InputError). A relative "scene" path is read from the
    sweep file's folder (for a dict or text: `folder`, by default the working directory)."""

    __slots__ = ("_h",)

    def __init__(self, source, folder=None):
        if isinstance(source, SweepSpec):
            self._h = source._h
            return
        folder = check_path(folder, "SweepSpec(folder)") if folder is not None else os.fsencode(os.getcwd())
        if isinstance(source, Mapping):
            self._h = _core.sweep_spec_from_text(dumps(dict(source)), "<dict>", folder)
        elif isinstance(source, str) and source.lstrip().startswith("{"):
            self._h = _core.sweep_spec_from_text(source, "<string>", folder)
        elif isinstance(source, (str, bytes, os.PathLike)):
            path = check_path(source, "sweep file")
            if not os.path.exists(path):
                raise FileNotFoundError(2, "no such sweep file", os.fsdecode(path))
            self._h = _core.sweep_spec_from_file(path)
        else:
            raise TypeError(f"SweepSpec(): a path, a dict or JSON text, not {type(source).__name__}")

    @property
    def member_count(self):
        return self._h.member_count

    @property
    def point_count(self):
        return self._h.point_count

    @property
    def seeds(self):
        return list(self._h.seeds)

    @property
    def parameters(self):
        """The parameter (column) names."""
        return list(self._h.parameter_names)

    def point_values(self, point):
        return self._h.point_values(point)

    def member_scene(self, member):
        """Member m's scene: the base with its point's values and its seed (member m is point
        m // len(seeds), seed seeds[m % len(seeds)])."""
        return Scene.from_json(self._h.member_scene_json(member), f"member {member}")

    def __repr__(self):
        return (f"<axonguide.SweepSpec {self._h.origin}: {self.point_count} points x {len(self.seeds)} seeds"
                f" = {self.member_count} members>")


class SweepResult:
    """records: sweep.csv's columns (member, point, one per parameter, seed, status,
    exit_code, every assay metric, connections_sha256, message; and reused: a verified
    record of an earlier sweep into `out` was kept), each a NumPy array (object arrays for
    text). summary: summary.csv's columns (point, parameters, members, ok, failed, and
    METRIC_mean, METRIC_ci_low, METRIC_ci_high: the two-sided 95 % Student-t interval over
    the point's seeds). failed: members that failed (their metrics are NaN)."""

    def __init__(self, spec, d, out):
        self.spec = spec
        self.records = _table(d["records"])
        self.summary = _table(d["summary"])
        self.failed = d["failed"]
        self.reused = d["reused"]
        self.threads = d["threads"]
        self.out = out
        self.metric_names = list(_core.metric_names())

    def record(self, member):
        """Member m's record as a dict of Python values."""
        return {k: (v[member].item() if hasattr(v[member], "item") else v[member]) for k, v in self.records.items()}

    def __len__(self):
        return len(self.records["member"])

    def __repr__(self):
        return f"<axonguide.SweepResult {len(self)} members, {self.failed} failed>"


def sweep(spec, out=None, threads=None, backend="reference"):
    """Runs a sweep (docs/validation.md §12.2): spec is a SweepSpec or anything SweepSpec()
    takes. With out, it is `axonguide sweep SPEC --out OUT` (sweep.csv, summary.csv,
    sweep.json, members/: the same bytes; members already recorded and verified there are
    reused); without, the members run in memory and nothing is written. The GIL is released
    while the members run; the records do not depend on the thread count. Ctrl-C stops every
    member at the end of its current step and raises KeyboardInterrupt; the records already
    written to out are kept, and the same call later reuses them."""
    s = spec if isinstance(spec, SweepSpec) else SweepSpec(spec)
    out_bytes = None if out is None else check_path(out, "sweep(out)")
    out_path = None if out is None else pathlib.Path(os.fsdecode(out_bytes))
    d = _core.sweep(s._h, out_bytes, check_threads(threads), check_backend(backend))
    return SweepResult(s, d, out_path)


class FitResult:
    """The fit of `axonguide fit` (docs/validation.md §12.3): parameters (names), best and
    intervals (name -> value; name -> (lo, hi, open_low, open_high), 95 % profile
    likelihood), gain, kd, scale (the scene's where not fitted), chi2, dof, chi2_per_dof,
    runs, seeds, model_se_ratio_max; per residual (a data point's measure: point, measure)
    model, model_se, model_min, model_max, reachable (within 2 se of the range the model
    produced); evaluations (each parameter's values and chi2 per set, and model, model_se
    per set and residual, in the order evaluated); data (the points read)."""

    def __init__(self, d):
        self.__dict__.update(d)

    def __repr__(self):
        return (f"<axonguide.FitResult gain {self.gain:.4g}, K_d {self.kd:.4g}, scale {self.scale:.4g}: "
                f"chi2/dof {self.chi2_per_dof:.3f} ({self.dof} dof)>")


_DATA_COLUMNS = ("concentration", "steepness", "bias", "se", "count")


def _data_text(data):
    # A path (read as `axonguide fit DATA` reads it), a dict of columns, or rows (dicts, or
    # (concentration, steepness, bias, se, count) tuples): the CSV the command line reads.
    # A dict's keys (or the first dict row's) are the header: any columns `fit` reads
    # (concentration, steepness, count, bias and/or outgrowth, se or bias_se/outgrowth_se).
    if isinstance(data, (str, bytes, os.PathLike)):
        path = check_path(data, "fit(data)")
        if not os.path.exists(path):
            raise FileNotFoundError(2, "no such data file", os.fsdecode(path))
        with open(path, "rb") as f:  # the bytes, as the command line reads them
            return f.read(), path
    if isinstance(data, Mapping):
        header = [str(c) for c in data]
        cols = [list(np.asarray(data[c]).tolist()) for c in data]
        if len({len(c) for c in cols}) > 1:
            raise InputError("fit: data columns must have the same length")
        rows = list(zip(*cols))
    else:
        rows, header = [], None
        for r in data:
            if isinstance(r, Mapping):
                if header is None:
                    header = [str(c) for c in r]
                missing = [c for c in header if c not in r]
                if missing or len(r) != len(header):
                    raise InputError(f"fit: data rows as dicts need the same keys ({', '.join(header)})")
                r = tuple(r[c] for c in header)
            rows.append(tuple(np.asarray(r).tolist()))
        if header is None:
            header = list(_DATA_COLUMNS)
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    for r in rows:
        if len(r) != len(header):
            raise InputError(f"fit: a data row has {len(r)} values, {len(header)} are needed ({', '.join(header)})")
        buf.write(",".join(repr(float(v)) if not isinstance(v, int) else str(v) for v in r) + "\n")
    return buf.getvalue(), "<rows>"


def _base_text(base):
    # The base scene as written (a file's text, a dict's JSON), as `axonguide fit --scene` reads it.
    if isinstance(base, Scene):
        return base.to_json(None), base.origin
    if isinstance(base, Mapping):
        return dumps(dict(base)), "<dict>"
    if isinstance(base, str) and base.lstrip().startswith("{"):
        return base, "<string>"
    if isinstance(base, (str, bytes, os.PathLike)):
        path = check_path(base, "fit(base_scene)")
        as_scene(path)  # FileNotFoundError, SceneError
        with open(path, "rb") as f:
            return f.read(), path
    raise TypeError(f"fit(): the base scene is a Scene, dict, JSON text or path, not {type(base).__name__}")


def fit(base_scene, data, *, seeds=4, scale=False, gain_min=1.0, gain_max=1000.0, kd_min=None, kd_max=None,
        grid=7, refine=2, threads=None, backend="reference", mirror=True, target_se=1.0 / 3.0, max_seeds=64,
        params=None, corrections=None, bias_metric="", polish=4, antithetic=True):
    """`axonguide fit DATA --scene BASE` (docs/validation.md §12.3): fits the model's parameters
    (SNR: gain and K_d, with scale=True a scale on the nominal concentrations; signalling:
    r0, kext, a1b; or `params`) to measured directional bias and/or radial outgrowth.
    data: a CSV path (the columns of `axonguide fit`), a dict of columns, or rows. seeds: a count (seeds 1..N, as --seeds) or a list. grid and refine are
    --grid and --refine; kd_min/kd_max bound the coarse K_d grid (None: from the data).
    mirror, antithetic, target_se, max_seeds, bias_metric: --no-mirror, --no-antithetic,
    --target-se, --max-seeds, --bias-metric; polish: --polish (Gauss-Newton steps from the grid's best); params: names or (name, lo, hi) tuples (--param); corrections: a dict
    {steepness: factor} (--correct).
    Returns a FitResult. The GIL is released while the model runs; Ctrl-C stops it at the end
    of the runs' current steps and raises KeyboardInterrupt."""
    base, origin = _base_text(base_scene)
    text, data_origin = _data_text(data)
    if isinstance(seeds, numbers.Integral) and not isinstance(seeds, bool):
        seed_list = list(range(1, check_int(seeds, "fit: seeds", 1, 1000) + 1))
    elif isinstance(seeds, (str, bytes, Mapping)) or not hasattr(seeds, "__iter__"):
        raise InputError(f"fit: seeds = {seeds!r}: must be a count in [1, 1000] or a list of seeds")
    else:
        seed_list = [check_int(s, "fit: a seed", 0, 2**64 - 1) for s in seeds]
    param_list = []
    for p in params or []:
        if isinstance(p, str):
            param_list.append((p, 0.0, 0.0))
        elif isinstance(p, (tuple, list)) and len(p) == 3 and isinstance(p[0], str):
            param_list.append((p[0], check_number(p[1], f"fit: {p[0]} lo"), check_number(p[2], f"fit: {p[0]} hi")))
        else:
            raise InputError(f"fit: params: {p!r} is not a name or a (name, lo, hi) tuple")
    if corrections is not None and not isinstance(corrections, Mapping):
        raise InputError(f"fit: corrections = {corrections!r}: must be a dict {{steepness: factor}}")
    correction_list = [(check_number(s, "fit: a correction's steepness"), check_number(f, "fit: a correction's factor"))
                       for s, f in (corrections or {}).items()]
    if bias_metric not in ("", "bias", "outgrowth_bias", "guidance_ratio"):
        raise InputError(f"fit: bias_metric = {bias_metric!r}: must be bias, outgrowth_bias or guidance_ratio")
    d = _core.fit(base, origin, text, data_origin, check_threads(threads), seed_list, check_flag(scale, "fit: scale"),
                  check_number(gain_min, "fit: gain_min"), check_number(gain_max, "fit: gain_max"),
                  0.0 if kd_min is None else check_number(kd_min, "fit: kd_min"),
                  0.0 if kd_max is None else check_number(kd_max, "fit: kd_max"),
                  check_int(grid, "fit: grid", 2, 50), check_int(refine, "fit: refine", 0, 10), check_backend(backend),
                  check_flag(mirror, "fit: mirror"), check_number(target_se, "fit: target_se"),
                  check_int(max_seeds, "fit: max_seeds", 1, 1000), param_list, correction_list, bias_metric,
                  check_int(polish, "fit: polish", 0, 20), check_flag(antithetic, "fit: antithetic"))
    d["evaluations"] = dict(d["evaluations"])
    d["data"] = dict(d["data"])
    return FitResult(d)
