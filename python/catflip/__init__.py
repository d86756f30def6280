"""catflip from Python: plan and check how a falling cat turns itself over.

The same Rust library as the ``catflip`` command line, called directly: every report is the
dict of the CLI's ``--json`` output for the same problem (the same numbers, to the last bit),
time series are numpy arrays, every refusal is a :class:`CatflipError` with the CLI's message.

>>> import catflip
>>> p = catflip.load("problems/paper.toml", overrides={"manoeuvre.profile": "cycloidal"})
>>> m = catflip.simulate(p)                       # the exact engine
>>> round(m.twist_deg, 3), m.series.tau.shape     # doctest: +SKIP

The nouns (README, "Python"):

- :func:`load`, :func:`loads`, :func:`from_dict` → :class:`Problem`;
- :func:`simulate` (exact or rapier) and :func:`verify` → :class:`Measurement`;
- :func:`compare` → the peak-torque table; :func:`optimize` → :class:`Optimization`;
  :func:`optimize_whole` → :class:`WholeOptimum`; :func:`compare_models` → each cat model's
  whole optimum, side by side;
- :func:`import_schedule` (numpy arrays), :func:`read_schedule` (a CSV) → :class:`Schedule`,
  which :func:`simulate` takes in place of the problem's own schedule;
- :func:`export` (URDF, MJCF, schedule CSV), :func:`model_files`;
- :func:`sweep` → a list of records; :func:`frame` → a pandas/polars frame.

Long calls release the GIL and run on a worker thread; Ctrl-C raises ``KeyboardInterrupt`` at
once while the worker finishes in the background (its result is dropped).
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _catflip
from ._catflip import CatflipError, Problem, Schedule, __version__
from ._problem import CatflipWarning, _warn, from_dict, load, loads
from ._results import Measurement, Optimization, Series, WholeOptimum
from ._table import frame, records_from_csv

__all__ = [
    "CatflipError",
    "CatflipWarning",
    "Measurement",
    "Optimization",
    "Problem",
    "Schedule",
    "Series",
    "WholeOptimum",
    "__version__",
    "compare",
    "compare_models",
    "export",
    "frame",
    "from_dict",
    "import_schedule",
    "load",
    "loads",
    "model_files",
    "optimize",
    "optimize_whole",
    "read_schedule",
    "schedule_series",
    "simulate",
    "sweep",
    "verify",
]

#: Intervals per phase of a time series (the CLI's default for schedule files).
STEPS_PER_PIECE = 400


def _report(pair: Any) -> Dict[str, Any]:
    text, warnings = pair
    _warn(warnings)
    return json.loads(text)


def _spin(problem: Problem) -> List[float]:
    """The problem's release spin, ``drop.angular_momentum`` (N·m·s; zeros without spin)."""
    return list(problem.to_dict().get("drop", {}).get("angular_momentum", [0.0, 0.0, 0.0]))


def _series_wanted(problem: Problem, series: Optional[bool]) -> bool:
    """Whether a call samples the time series: ``series`` as given, or (``None``) when the
    release has no spin. The series is the zero-momentum flip's, so asking for it with spin is
    refused here, naming the argument (the library's refusal names the CLI's files)."""
    spin = _spin(problem)
    spins = any(x != 0.0 for x in spin)
    if series is None:
        return not spins
    if series and spins:
        raise CatflipError(
            f"series=True: the time series is the zero-momentum flip's, and drop.angular_momentum = {spin} "
            "releases the cat with spin: pass series=False (the report itself is the spinning release's)"
        )
    return bool(series)


def _sampling(steps_per_piece: Optional[int], rate_hz: Optional[float]) -> "tuple[int, Optional[float]]":
    """The series' sampling, checked and named as the arguments are: ``steps_per_piece``
    intervals per phase (default :data:`STEPS_PER_PIECE`) or the uniform grid ``rate_hz``, one of
    the two."""
    if steps_per_piece is not None and rate_hz is not None:
        raise CatflipError(
            f"steps_per_piece = {steps_per_piece!r} and rate_hz = {rate_hz!r}: give one of them "
            "(intervals per phase, or a uniform grid in Hz)"
        )
    if steps_per_piece is not None and (
        isinstance(steps_per_piece, bool) or not isinstance(steps_per_piece, int) or steps_per_piece < 1
    ):
        raise CatflipError(f"steps_per_piece = {steps_per_piece!r}: must be a whole number of intervals, at least 1")
    if rate_hz is not None:
        ok = isinstance(rate_hz, (int, float)) and not isinstance(rate_hz, bool)
        if not ok or not (float(rate_hz) > 0.0 and float(rate_hz) < float("inf")):
            raise CatflipError(f"rate_hz = {rate_hz!r}: must be a finite, positive number of Hz (or None)")
        return STEPS_PER_PIECE, float(rate_hz)
    return (STEPS_PER_PIECE if steps_per_piece is None else steps_per_piece), None


def _engine(engine: Any) -> str:
    """``engine`` when it is a name (the library says which names are engines)."""
    if not isinstance(engine, str):
        raise CatflipError(f'engine = {engine!r}: must be "exact" or "rapier"')
    return engine


def simulate(
    problem: Problem,
    engine: str = "exact",
    *,
    schedule: Optional[Schedule] = None,
    series: Optional[bool] = None,
    steps_per_piece: Optional[int] = None,
    rate_hz: Optional[float] = None,
) -> Measurement:
    """Runs the problem's schedule (or ``schedule``, imported, on the problem's cat) through an
    engine: ``"exact"`` (the momentum-map engine, ground truth) or ``"rapier"`` (the rapier3d
    verification, ending in a verdict). ``report`` is ``catflip simulate --json`` (with
    ``--schedule`` when ``schedule`` is given).

    The problem's schedule is sampled too (:class:`Series`: ``steps_per_piece`` intervals per
    phase, 400 by default, or the uniform grid ``rate_hz``, one of the two), the exact engine's
    torques and orientation on every row, unless ``series`` is false. The series is the
    zero-momentum flip's: by default (``series=None``) it is left out for a release with spin,
    and ``series=True`` with spin is refused. An imported ``schedule`` is measured as given:
    ``series``, ``steps_per_piece`` and ``rate_hz`` sample the problem's own, and are refused
    beside it.
    """
    engine = _engine(engine)
    if schedule is not None:
        sampling = (("series", series), ("steps_per_piece", steps_per_piece), ("rate_hz", rate_hz))
        given = [f"{k} = {v!r}" for k, v in sampling if v is not None]
        if given:
            raise CatflipError(
                f"{', '.join(given)}: an imported schedule is measured as given; these sample the problem's own schedule"
            )
        return Measurement(_report(_catflip.simulate_schedule(problem, schedule, engine)))
    steps, rate = _sampling(steps_per_piece, rate_hz)
    wanted = _series_wanted(problem, series)
    report = _report(_catflip.simulate(problem, engine))
    return Measurement(report, schedule_series(problem, steps, rate) if wanted else None)


def verify(problem: Problem, *, schedule: Optional[Schedule] = None, series: Optional[bool] = False) -> Measurement:
    """The rapier verification of the problem's schedule (or of ``schedule``):
    ``simulate(problem, "rapier")``; ``report["verdict"]`` is ``verified``, ``not verified`` or
    ``inconclusive`` against the ``[rapier]`` tolerances."""
    return simulate(problem, "rapier", schedule=schedule, series=series)


def schedule_series(problem: Problem, steps_per_piece: Optional[int] = None, rate_hz: Optional[float] = None) -> Series:
    """The problem's schedule sampled as ``catflip run`` writes ``schedules/problem.csv``
    (``steps_per_piece`` intervals per phase, 400 by default, or the uniform grid ``rate_hz``)."""
    steps, rate = _sampling(steps_per_piece, rate_hz)
    return Series.from_csv(*_catflip.schedule_file(problem, steps, rate))


def compare(problem: Problem, *, verify: bool = False) -> Dict[str, Any]:
    """``catflip compare --json``: every library profile on the problem's path and circulation,
    side by side (``["rows"]``, one record per profile: peak torques, twist, swing, jumps). With
    ``verify`` (``catflip compare --verify --json``), each profile verified in rapier too:
    ``["table"]`` is that table and ``["rapier"]`` one record per profile, with its
    ``["verdict"]``."""
    return _report(_catflip.compare(problem, verify))


def compare_models(problem: Problem, *, verify: bool = False) -> Dict[str, Any]:
    """``catflip compare-models --json``: the whole-manoeuvre optimum of each cat model (the
    problem's halves, and their mean half when they differ, on the universal, the no-twist and
    the spherical joint; with ``[cat.tail]`` the problem's cat with its tail) on the problem's
    fall: ``["rows"]``, one record per model (``optimum`` is ``None`` when a model has none, its
    ``status`` then ``"no-optimum"`` or ``"not-run"`` and ``reason`` says why), ``["cheapest"]`` the key of the cheapest
    model (``None`` without any optimum); with ``verify`` each optimum's rapier verification."""
    return _report(_catflip.compare_models(problem, verify))


def optimize(
    problem: Problem, *, series: bool = True, steps_per_piece: Optional[int] = None, rate_hz: Optional[float] = None
) -> Optimization:
    """``catflip optimize --json``: the profile QP (Clarabel), its exact-dynamics refinement and
    every phase retimed against its exact peak, with the problem's ``[optimize]`` settings; with
    ``series``, each optimum's time series by name (sampled as :func:`schedule_series`). Refused
    for a problem released with spin."""
    steps, rate = _sampling(steps_per_piece, rate_hz)
    text, warnings, files = _catflip.optimize(problem, series, steps, rate)
    _warn(warnings)
    return Optimization(json.loads(text), {name: Series.from_csv(csv, sidecar) for name, csv, sidecar in files})


def optimize_whole(
    problem: Problem,
    *,
    series: Optional[bool] = None,
    steps_per_piece: Optional[int] = None,
    rate_hz: Optional[float] = None,
) -> WholeOptimum:
    """``catflip optimize --whole --json``: both joint paths optimised over the whole fall (twist
    π and swing 0 as constraints), with ``[optimize.whole]``; a release with spin is planned
    under its spin. No optimum is not an error here: ``solved`` is false and
    ``report["status"]`` says why (the CLI exits non-zero). The optimum's time series
    (``whole-optimum.csv``: ``steps_per_piece`` intervals per knot span of its spline, 400 by
    default, or the uniform grid ``rate_hz``) comes with it unless ``series`` is false; it is the
    zero-momentum flip's, so by default (``series=None``) it is left out with spin, and
    ``series=True`` with spin is refused."""
    steps, rate = _sampling(steps_per_piece, rate_hz)
    wanted = _series_wanted(problem, series)
    text, warnings, file = _catflip.optimize_whole(problem, wanted, steps, rate)
    _warn(warnings)
    return WholeOptimum(json.loads(text), Series.from_csv(*file) if file is not None else None)


def read_schedule(path: Union[str, "os.PathLike[str]"]) -> Schedule:
    """Reads a schedule CSV (``t, q1, q2`` and optionally ``qd1, qd2``, ``qdd1, qdd2``, ``phase``),
    as ``catflip simulate --schedule FILE.csv`` does."""
    return _catflip.read_schedule(os.fspath(path))


def import_schedule(
    t: Any,
    q: Any,
    qd: Any = None,
    qdd: Any = None,
    *,
    name: str = "<arrays>",
) -> Schedule:
    """A schedule from arrays: times ``t`` (s, ``(n,)``), joint angles ``q`` (rad, ``(n, 2)``),
    optionally rates ``qd`` and accelerations ``qdd`` (``(n, 2)``). Read by the same parser as a
    schedule file, with the same checks and messages (row ``k`` is "line ``k + 2``", ``name``
    stands for the file); a time written twice in a row splits the schedule into pieces there."""
    def numbers(label: str, value: Any) -> Any:
        try:
            return np.asarray(value, dtype=float)
        except (TypeError, ValueError) as e:
            raise CatflipError(f"{name}: `{label}` must hold numbers: {e}") from None

    times = numbers("t", t)
    if times.ndim != 1:
        raise CatflipError(f"{name}: `t` must have shape (n,), not {times.shape}")
    columns = [("t", times)]
    for names, value in ((("q1", "q2"), q), (("qd1", "qd2"), qd), (("qdd1", "qdd2"), qdd)):
        if value is None:
            continue
        label = names[0][:-1]
        a = numbers(label, value)
        if a.ndim != 2 or a.shape[1] != 2:
            raise CatflipError(f"{name}: `{label}` must have shape (n, 2), not {a.shape}")
        if a.shape[0] != times.shape[0]:
            raise CatflipError(f"{name}: `{label}` has {a.shape[0]} rows and `t` {times.shape[0]}: one row per time")
        columns += [(names[0], a[:, 0]), (names[1], a[:, 1])]
    return _catflip.schedule_from_columns([c[0] for c in columns], [c[1].tolist() for c in columns], name)


def model_files(problem: Problem) -> Dict[str, str]:
    """The cat as ``model.urdf`` and ``model.xml`` (MJCF): file name → text, as ``catflip run``
    writes them beside the schedules (true inertias, zero gravity: the falling frame); on the
    no-twist joint a ball joint in ``model.xml`` and pyBullet's non-standard spherical joint in
    ``model.urdf``."""
    return dict(_catflip.model_files(problem))


def export(
    problem: Problem,
    out: Union[str, "os.PathLike[str]"],
    *,
    optimum: Optional[WholeOptimum] = None,
    steps_per_piece: Optional[int] = None,
    rate_hz: Optional[float] = None,
) -> List[str]:
    """Writes into the folder ``out`` what ``catflip run`` writes into ``schedules/``: the
    problem's schedule (``problem.csv`` + ``problem.json`` sidecar), the model (``model.urdf``,
    ``model.xml``) and, when given and solved, the whole optimum (``whole-optimum.csv`` +
    ``whole-optimum.json``).
    Returns the paths written. Everything is computed before the folder is made: a refused call
    leaves nothing behind. An optimum without its time series (solved with ``series=False``) is
    refused; one not solved is left out with a :class:`CatflipWarning`."""
    steps, rate = _sampling(steps_per_piece, rate_hz)
    csv, sidecar = _catflip.schedule_file(problem, steps, rate)
    files = {"problem.csv": csv, "problem.json": sidecar, **model_files(problem)}
    if optimum is not None and not optimum.solved:
        _warn([f"optimum: not solved ({optimum.report.get('status')}): whole-optimum.csv is not written"])
    elif optimum is not None and optimum.series is None:
        raise CatflipError(
            "optimum: solved without its time series (optimize_whole(..., series=False)): "
            "solve it with series=True to export it"
        )
    elif optimum is not None:
        files["whole-optimum.csv"] = optimum.series.csv
        if optimum.series.sidecar is not None:
            files["whole-optimum.json"] = optimum.series.sidecar
    os.makedirs(out, exist_ok=True)
    written = []
    for name, text in files.items():
        path = os.path.join(out, name)
        with open(path, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        written.append(path)
    return written


def sweep(path: Union[str, "os.PathLike[str]"], *, out: Union[str, "os.PathLike[str]", None] = None) -> List[Dict[str, Any]]:
    """Runs a sweep file (``catflip sweep SWEEP.toml``) and returns its tidy table, one record per
    case × schedule × engine (the rows of ``sweep.csv``); with ``out``, also writes the CLI's
    output folder ``<out>/<name>/`` (table, summary, plots). :func:`frame` makes it a frame."""
    text, _written, warnings = _catflip.sweep(os.fspath(path), os.fspath(out) if out is not None else None)
    _warn(warnings)
    return records_from_csv(text)
