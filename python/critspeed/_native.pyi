"""Type stubs of the extension module critspeed._native (private: use the functions of
``critspeed``, which document the API). ``kind`` is "path", "text" or "dict"; columns come as
``[(name, kind, data)]`` with kind "f64"/"bool" (data: a bytearray of native float64/uint8
values) or "optbool"/"str" (data: a list). Each computing function returns its result with the
warnings (messages) last."""

from typing import Any, Dict, List, Optional, Tuple, Union

Columns = List[Tuple[str, str, Union[bytearray, List[Any]]]]
Warnings = List[str]

class StudyError(ValueError):
    """A bad study or argument: the message names the key, the value and the rule."""

class ComputationError(RuntimeError):
    """A numerical failure (e.g. a contact solve that does not converge), or an output failure."""

def version() -> str:
    """The library's version."""

def quantity(name: str, text: str, dim: str) -> float:
    """A number (SI) or a string with a unit of ``dim`` ("speed", "length", "time"), in SI."""

def check(kind: str, value: Any) -> Dict[str, Any]:
    """The resolved plan with the [sweep]/[trade] sections as written, and ``warnings``."""

def linear(kind: str, value: Any, out: Optional[str] = None) -> Tuple[Dict[str, Any], Warnings]:
    """``linear --json``'s object."""

def bifurcation(
    kind: str, value: Any, out: Optional[str] = None
) -> Tuple[Dict[str, Any], Columns, Warnings]:
    """``bifurcation --json``'s object and the columns of branch.csv."""

def curve(
    kind: str, value: Any, out: Optional[str] = None
) -> Tuple[Dict[str, Any], Columns, Warnings]:
    """``curve --json``'s object and the columns of curve.csv."""

def attractors(
    kind: str, value: Any, out: Optional[str] = None
) -> Tuple[Dict[str, Any], Columns, Warnings]:
    """``attractors --json``'s object and the columns of attractors.csv."""

def simulate(
    kind: str,
    value: Any,
    speeds: List[float],
    y0: float,
    duration: float,
    dt: float,
    out: Optional[str] = None,
    start_from: Optional[str] = None,
    kick: Optional[List[str]] = None,
) -> Tuple[Columns, Warnings]:
    """The columns of simulate.csv."""

def sweep(
    kind: str, value: Any, threads: Optional[int] = None, out: Optional[str] = None
) -> Tuple[Columns, Warnings]:
    """The columns of sweep.csv."""

def uncertainty(
    kind: str, value: Any, threads: Optional[int] = None, out: Optional[str] = None
) -> Tuple[Dict[str, Any], Columns, Warnings]:
    """``uncertainty --json``'s object and the columns of uncertainty.csv."""

def conicity(
    kind: str,
    value: Any,
    amplitudes: Optional[List[float]] = None,
    out: Optional[str] = None,
    table: Optional[Tuple[List[float], List[float]]] = None,
) -> Tuple[Dict[str, Any], Warnings]:
    """``conicity --json``'s object, from a study or a Δr table (y, dr in metres)."""

def geometry(kind: str, value: Any, out: Optional[str] = None) -> Tuple[Columns, Warnings]:
    """The columns of geometry.csv."""
