"""critspeed: the critical hunting speed of a railway wheelset, from Python.

A thin layer over the Rust library the ``critspeed`` command line is built on: every function
calls the same library function as the matching command, and returns what that command prints
with ``--json`` (a dict) or the columns of the CSV file it writes (a dict of numpy arrays).

A *study* is any of

* a path to a study file (``str`` or ``os.PathLike``); relative paths inside it (geometry
  tables, profiles) are taken from the file's folder;
* the TOML text of a study (a ``str`` containing a newline or ``=``); relative paths inside it
  are taken from the current directory;
* a ``dict`` with the same structure as the file (sections are nested dicts); values are numbers
  in SI units or strings with a unit (``"850 N/mm"``), exactly as in a file.

Nothing is written to disk unless ``out=`` is given: then the files the command line writes go
to ``out/<study name>/`` as with ``critspeed --out OUT``.

Errors: a bad study or argument raises :class:`StudyError` (a ``ValueError``) whose message is
the command line's (it names the key, the value and the rule); a numerical failure raises
:class:`ComputationError` (a ``RuntimeError``). What the command line prints as ``warning: …``
(a value outside its plausible range, a figure written as a note because it has nothing to
draw) is issued as a :class:`CritspeedWarning` (a ``UserWarning``) through :mod:`warnings`.

Threads and the GIL: every call releases the GIL while it computes. The long ones
(:func:`bifurcation`, :func:`sweep`, :func:`uncertainty`, :func:`simulate`) run on a worker
thread and check for Ctrl-C every 50 ms; on Ctrl-C the computation stops at its next step
(continuation step, sweep point, uncertainty evaluation or simulated speed) and
``KeyboardInterrupt`` is raised. A sweep or uncertainty study interrupted with ``out=`` keeps
its finished points and resumes from them when called again.
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import ComputationError, StudyError

__version__: str = _native.version()

__all__ = [
    "__version__",
    "StudyError",
    "ComputationError",
    "CritspeedWarning",
    "check",
    "linear",
    "bifurcation",
    "curve",
    "attractors",
    "simulate",
    "sweep",
    "uncertainty",
    "conicity",
    "geometry",
]

Study = Union[str, "os.PathLike[str]", Mapping[str, Any]]
"""A study: a file path, TOML text, or a dict with the file's structure."""

Quantity = Union[float, int, str]
"""A number in SI units, or a string with a unit (``"5 mm"``, ``"200 km/h"``)."""

PathLike = Union[str, "os.PathLike[str]"]


class CritspeedWarning(UserWarning):
    """A study value outside its plausible range (the study is computed as given), or a figure
    written as a note saying why it has nothing to draw (the numbers are returned and written)."""


def _warned(result: Tuple[Any, ...]) -> Any:
    """The native result without its last element, the warnings, which are issued."""
    *value, messages = result
    for m in messages:
        warnings.warn(m, CritspeedWarning, stacklevel=3)
    return value[0] if len(value) == 1 else tuple(value)


def _study(study: Study) -> Tuple[str, Any]:
    """The study's kind ("path", "text" or "dict") and value, for the native module."""
    if isinstance(study, Mapping):
        return "dict", dict(study)
    if isinstance(study, os.PathLike):
        return "path", os.fspath(study)
    if isinstance(study, str):
        if "\n" in study or "=" in study:
            return "text", study
        return "path", study
    raise TypeError(
        f"study must be a path, TOML text or a dict, not {type(study).__name__}"
    )


def _quantity(name: str, value: Quantity, dim: str) -> float:
    """A number (SI) or a string with a unit of ``dim``, in SI."""
    if isinstance(value, str):
        return _native.quantity(name, value, dim)
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        raise StudyError(
            f"{name} = {value!r}: expected a number in SI or a string with a unit"
        )
    return float(value)


def _out(out: Optional[PathLike]) -> Optional[str]:
    return None if out is None else os.fspath(out)


def _columns(cols: Sequence[Tuple[str, str, Any]]) -> Dict[str, np.ndarray]:
    """The native module's CSV columns as numpy arrays, in the CSV's column order."""
    result: Dict[str, np.ndarray] = {}
    for name, kind, data in cols:
        if kind == "f64":
            result[name] = np.frombuffer(data, dtype=np.float64)
        elif kind == "bool":
            result[name] = np.frombuffer(data, dtype=np.bool_)
        elif kind == "optbool":
            result[name] = np.array(data, dtype=object)
        else:
            result[name] = np.array(data, dtype=str)
    return result


def check(study: Study) -> Dict[str, Any]:
    """Validate a study and return the resolved plan in SI (what ``critspeed check`` prints).

    The dict has the study file's sections and keys (``"wheelset"``, ``"suspension"``,
    ``"contact"``, ``"flange"`` when present, ``"linear"``, ``"bifurcation"`` when present),
    every quantity a number in SI, every default filled in. For the ``cone`` and
    ``cone-on-arc`` geometries it is itself a valid study dict (``check(check(s)) ==
    check(s)``). The ``[sweep]`` and ``[trade]`` sections, when present, are validated (every
    sweep value must give a valid study) and returned as written.

    Values outside their plausible ranges are issued as :class:`CritspeedWarning`.

    Raises :class:`StudyError` naming the key, the value and the rule.
    """
    kind, value = _study(study)
    plan = _native.check(kind, value)
    return _warned((plan, plan.pop("warnings", [])))


def linear(study: Study, *, out: Optional[PathLike] = None) -> Dict[str, Any]:
    """Linear stability: the object ``critspeed linear STUDY --json`` prints, as a dict.

    Keys: ``"study"``, ``"kind"``, ``"speed_range_m_s"``, ``"creep_law"``,
    ``"critical_speeds"`` (Kalker crossings: a list of dicts with ``"speed_m_s"``,
    ``"speed_km_h"``, ``"frequency_hz"``, ``"wavelength_m"``, ``"direction"``
    (``"onset"``/``"recovery"``), ``"bracket_m_s"``), ``"creep_law_hopf_speeds"`` (the same
    for the study's creep law), ``"linear_critical_speed_m_s"`` (the first Kalker onset, or
    ``None``), ``"creep_law_hopf_speed_m_s"``, ``"centre_conicity"``,
    ``"klingel_wavelength_m"``, ``"wheelset_conicities"`` (each wheelset's, front to rear),
    ``"kalker"``, ``"creep_law_details"`` and ``"notes"`` (what the linearisation replaced: a
    damper's force–velocity curve by its slope at zero; that the wheelsets' conicities differ).

    With ``out``, writes ``linear.json``, ``spectrum.csv`` and the figures to
    ``out/<name>/``.
    """
    kind, value = _study(study)
    return _warned(_native.linear(kind, value, _out(out)))


def bifurcation(study: Study, *, out: Optional[PathLike] = None) -> Dict[str, Any]:
    """The branch of hunting limit cycles: ``critspeed bifurcation STUDY --json``'s object.

    Keys as the command prints them (``"nonlinear_critical_speed_m_s"``, ``"hopf_speed_m_s"``,
    ``"hopf_type"``, ``"special_points"``, ``"stop_reason"``, ``"cycles"``, ...), plus
    ``"branch"``: ``{column of branch.csv: numpy array}`` with one entry per cycle
    (``speed_m_s``, ``amplitude_y_m``, ``amplitude_psi_rad``, ``period_s``,
    ``frequency_hz``, ``stable`` (bool), ``max_multiplier_abs``, ... ``mu4_im``), the very
    numbers of the CSV.

    Studies without a ``[bifurcation]`` section use its defaults. A study with an
    ``[attractors]`` section runs the attractor search too, as the command does, and the
    object carries the one V_NL of both (``"nonlinear_sources"``). Releases the GIL; Ctrl-C
    stops it between continuation steps (``KeyboardInterrupt``). With ``out``, writes
    ``bifurcation.json``, ``branch.csv`` and ``bifurcation.svg`` (and ``attractors.json``,
    ``attractors.csv``, ``attractors.svg`` after a search).
    """
    kind, value = _study(study)
    report, cols = _warned(_native.bifurcation(kind, value, _out(out)))
    report["branch"] = _columns(cols)
    return report


def curve(study: Study, *, out: Optional[PathLike] = None) -> Dict[str, Any]:
    """Critical speeds as curves over the study's ``[curve]`` key: ``critspeed curve STUDY
    --json``'s object, as a dict.

    Keys as the command prints them: ``"key"``, ``"unit"``, ``"from"``, ``"to"``,
    ``"curves"`` (a list of dicts with ``"kind"`` (``"hopf"``), ``"creep_law"``, ``"label"``
    (``"V_L"`` or ``"V_H"``), ``"stops"`` and ``"points"``: dicts with ``"parameter"`` (the
    key's value, SI), ``"speed_m_s"``, ``"frequency_hz"``, ``"amplitude_m"``,
    ``"first_lyapunov_coefficient"`` (1/m²), ``"hopf_type"``, ``"stable_side"``),
    ``"special_points"`` (Bautin, double Hopf, zero-Hopf, Bogdanov-Takens), ``"notes"``,
    plus ``"points"``: ``{column of curve.csv: numpy array}`` with one entry per point of
    every curve (``curve``, ``kind``, ``creep_law``, ``label``, the key's column,
    ``speed_m_s``, ``frequency_hz``, ...), the very numbers of the CSV.

    Releases the GIL; Ctrl-C stops it between continuation steps (``KeyboardInterrupt``).
    With ``out``, writes ``curve.json``, ``curve.csv`` and ``curve.svg``.
    """
    kind, value = _study(study)
    report, cols = _warned(_native.curve(kind, value, _out(out)))
    report["points"] = _columns(cols)
    return report


def attractors(study: Study, *, out: Optional[PathLike] = None) -> Dict[str, Any]:
    """Every hunting attractor and the one nonlinear critical speed: ``critspeed attractors
    STUDY --json``'s object, as a dict.

    Keys as the command prints them: ``"nonlinear_critical_speed_m_s"`` (the lowest over the
    continuation with branch switching and the search), ``"nonlinear_critical_speed_sources"``
    (each method's lowest candidate: ``"method"``, ``"what"``, ``"speed_m_s"``,
    ``"bracket_m_s"``), ``"search_critical_speed_m_s"`` and ``"bracket_m_s"`` (the search's own),
    ``"attractors"`` (``"kind"``, ``"speed_range_m_s"``, ``"dies_bracket_m_s"``, ``"fate"``,
    ``"path"`` with the amplitudes of every body at each speed), ``"speeds"`` (the basin
    fractions at each speed of the grid), ``"notes"``, ``"disagreement"``; plus ``"motions"``:
    ``{column of attractors.csv: numpy array}``.

    Studies without an ``[attractors]`` section use its defaults. Releases the GIL; Ctrl-C
    stops it between continuation steps and simulations (``KeyboardInterrupt``). With ``out``,
    writes the continuation's files and ``attractors.json``, ``attractors.csv``,
    ``attractors.svg``.
    """
    kind, value = _study(study)
    report, cols = _warned(_native.attractors(kind, value, _out(out)))
    report["motions"] = _columns(cols)
    return report


def simulate(
    study: Study,
    speeds: Union[Quantity, Sequence[Quantity]],
    *,
    y0: Optional[Quantity] = None,
    duration: Quantity = "30 s",
    dt: Quantity = "2 ms",
    out: Optional[PathLike] = None,
    start_from: Optional[str] = None,
    kick: Optional[Sequence[str]] = None,
    rtol: Optional[float] = None,
) -> Dict[str, np.ndarray]:
    """Time histories at constant speeds from y(0) = ``y0``: ``{column of simulate.csv: array}``.

    ``y0`` defaults to 5 mm, or to 0 with ``start_from`` or ``kick``. ``start_from`` is
    ``"PATH:N"``: attractor N of an ``attractors.json``, each speed starting from the state of
    its path nearest that speed (as ``critspeed simulate --from``); ``kick`` lists
    displacements added to the start, ``"BODY.COORD=VALUE"`` (``"wheelset-3.y=6 mm"``), as
    ``--kick``. ``rtol`` is the integrator's relative tolerance, in [1e-12, 1e-4] (the
    absolute tolerance is a thousandth of it), default 1e-9, as ``--rtol``.

    Columns ``speed_m_s``, ``time_s``, ``y_m``, ``psi_rad``, ``ydot_m_s``, ``psidot_rad_s``;
    the runs follow one another (select one with ``r["speed_m_s"] == v``). Each argument is a
    number in SI or a string with a unit (``speeds=["30 m/s", "200 km/h"]``). The rules of
    ``critspeed simulate`` apply (positive speeds and duration, 0 < dt <= duration, at most
    5e6 samples per speed). Ctrl-C stops it between speeds.
    """
    if isinstance(speeds, (str, int, float, np.number)):
        speeds = [speeds]
    v = [_quantity("speeds", s, "speed") for s in speeds]
    kind, value = _study(study)
    if y0 is None:
        y0 = 0.0 if (start_from is not None or kick) else "5 mm"
    y = _quantity("y0", y0, "length")
    cols = _native.simulate(
        kind,
        value,
        v,
        y,
        _quantity("duration", duration, "time"),
        _quantity("dt", dt, "time"),
        _out(out),
        start_from,
        list(kick) if kick else None,
        _rtol(rtol),
    )
    return _columns(_warned(cols))


def _rtol(rtol: Optional[float]) -> Optional[float]:
    """A tolerance argument as a float (None stays None): a bool or a non-number raises
    :class:`StudyError`; the range is checked by the library."""
    if rtol is None:
        return None
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float, np.number)):
        raise StudyError(f"rtol = {rtol!r}: must be a number in [1e-12, 1e-4]")
    return float(rtol)


def sweep(
    study: Study, *, threads: Optional[int] = None, out: Optional[PathLike] = None
) -> Dict[str, np.ndarray]:
    """The study's ``[sweep]``: ``{column of sweep.csv: numpy array}``, one entry per point.

    Columns ``point_id``, one per axis (named with its unit, e.g.
    ``suspension.lateral_stiffness_n_per_m``), ``kalker_critical_speed_m_s``, ``hopf_speed_m_s``,
    ``nonlinear_critical_speed_m_s`` (NaN where not computed or not found), ``status``
    (strings), ``kalker_frequency_hz``, ``hopf_frequency_hz``, ``nonlinear_located``,
    ``stable_up_to_m_s``. A column's type follows its cells: numbers (empty = NaN), booleans,
    optional booleans (object array with ``None``) or strings.

    ``threads`` sets the size of the sweep's own thread pool (default: all cores); the results
    do not depend on it. With ``out``, the sweep is resumable exactly as ``critspeed sweep``
    (records file ``out/<name>/sweep.records.csv``) and writes ``sweep.csv`` and its figures.
    Ctrl-C stops it between points.
    """
    if threads is not None and (isinstance(threads, bool) or threads < 1):
        raise StudyError(f"threads = {threads!r}: must be at least 1")
    kind, value = _study(study)
    return _columns(_warned(_native.sweep(kind, value, threads, _out(out))))


def uncertainty(
    study: Study, *, threads: Optional[int] = None, out: Optional[PathLike] = None
) -> Dict[str, Any]:
    """The study's ``[uncertainty]``: ``critspeed uncertainty STUDY --json``'s object, as a dict.

    Keys as the command prints them: ``"study"``, ``"samples"`` (evaluations run),
    ``"base_samples"`` (N), ``"method"``, ``"seed"``, ``"operating_speed_m_s"`` (when set),
    ``"nonlinear_method"`` (``"search"`` or ``"descents"``, when V_NL is computed),
    ``"parameters"`` (``"key"``, ``"distribution"``, ``"unit"``) and ``"quantities"``: one
    dict per computed speed with ``"name"`` (``"kalker"``, ``"hopf"``, ``"nonlinear"``),
    ``"mean_m_s"``, ``"std_m_s"``, ``"quantiles_m_s"`` (keys ``"0.05"``, ``"0.5"``,
    ``"0.95"``), ``"failed"``, ``"failures"`` (``"evaluation"``, ``"reason"``),
    ``"above_range"``, ``"probability_below_operating_speed"`` (with an operating speed),
    ``"indices"`` (per parameter ``"key"``, ``"first_order"``, ``"first_order_ci"``,
    ``"total"``, ``"total_ci"``; ``*_ci`` = [low, high], 95 %) and ``"notes"``.

    Plus ``"evaluations"``: ``{column of uncertainty.csv: numpy array}``, one entry per
    evaluation: ``evaluation_id``, ``block`` (strings: ``"A"``, ``"B"``, ``"AB1"`` ...), one
    column per parameter named by its key (SI), ``kalker_critical_speed_m_s``,
    ``hopf_speed_m_s``, ``nonlinear_critical_speed_m_s`` (NaN where not computed, failed or
    above range), ``status`` (strings) and ``stable_up_to_m_s``.

    ``threads`` sets the size of the evaluations' own thread pool (default: all cores); the
    results do not depend on it. With ``out``, the study is resumable exactly as ``critspeed
    uncertainty`` (records file ``out/<name>/uncertainty.records.csv``) and writes
    ``uncertainty.json``, ``uncertainty.csv`` and ``uncertainty.svg``. Ctrl-C stops it between
    evaluations (``KeyboardInterrupt``).

    Raises :class:`StudyError` naming the key, the value and the rule for a bad
    ``[uncertainty]`` section (e.g. ``std`` not positive, ``from`` not below ``to``,
    ``choice`` weights not summing to a positive number, a key that cannot vary, ``samples``
    below 2 or, for ``"sobol"``, not a power of two).
    """
    if threads is not None and (isinstance(threads, bool) or threads < 1):
        raise StudyError(f"threads = {threads!r}: must be at least 1")
    kind, value = _study(study)
    report, cols = _warned(_native.uncertainty(kind, value, threads, _out(out)))
    report["evaluations"] = _columns(cols)
    return report


def conicity(
    study: Optional[Study] = None,
    *,
    delta_r: Optional[Tuple[Sequence[float], Sequence[float]]] = None,
    amplitudes: Optional[Sequence[Quantity]] = None,
    out: Optional[PathLike] = None,
) -> Dict[str, Any]:
    """EN 15302 equivalent conicity against amplitude: ``critspeed conicity --json``'s object.

    ``{"amplitude_m": [...], "equivalent_conicity": [...]}``, from the study's contact
    geometry, or from a rolling-radius-difference table ``delta_r=(y, dr)`` (both in metres,
    dr = r_R - r_L at each lateral displacement y). Without ``amplitudes``: 0.5 mm to 10 mm by
    0.5 mm as far as the table reaches; given amplitudes (numbers in m or strings with a
    unit) must all fit. With ``out``, writes ``conicity.csv`` and ``conicity.svg`` to
    ``out/<name>/`` (``out/delta_r/`` for a table).
    """
    if (study is None) == (delta_r is None):
        raise StudyError("give a study or delta_r=(y, dr), not both and not neither")
    amps = None
    if amplitudes is not None:
        amps = [_quantity("amplitudes", a, "length") for a in amplitudes]
    table = None
    kind, value = "text", ""
    if delta_r is not None:
        y, dr = delta_r
        table = ([float(v) for v in y], [float(v) for v in dr])
    else:
        kind, value = _study(study)
    return _warned(_native.conicity(kind, value, amps, _out(out), table))


def geometry(study: Study, *, out: Optional[PathLike] = None) -> Dict[str, np.ndarray]:
    """The contact geometry table: ``{column of geometry.csv: numpy array}``.

    Rolling radii, contact angles, roll, Hertz patch and creep coefficients against the
    lateral displacement ``y_m`` (the table ``critspeed geometry`` writes).
    """
    kind, value = _study(study)
    return _columns(_warned(_native.geometry(kind, value, _out(out))))
