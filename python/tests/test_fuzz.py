"""Bad input, fuzzed, through the Python functions: every shipped study, mutated (keys and
sections deleted, NaN, inf, negatives, zero, huge and tiny magnitudes, wrong or missing units,
wrong types, None, unknown keys and sections, wrong table and profile files), given as a dict
and as TOML text, must end in a result, a ``StudyError`` or a ``ComputationError``: never a
``PanicException``, never an internal error. A ``StudyError`` names a key the case touched.

Bounded by time: ``FUZZ_SECONDS`` (default 20); ``FUZZ_SEED`` picks the cases (default 0, so a
failure is reproducible; the failing case is printed)."""

import copy
import math
import os
import random
import time
import warnings

import pytest

import critspeed
from conftest import REPO, STUDIES

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

FILES = [
    "tables/cubic-fold.csv",
    "tables/dtu-rsgeo-1o40.csv",
    "profiles/s1002.csv",
    "profiles/uic60_1in40.csv",
    "seed.toml",
    "missing.csv",
    "",
]
UNITS = ["furlongs", "kg", "m", "mm", "N/mm", "N s/m", "GPa", "km/h", "", "1:20"]


def leaves(d, path=()):
    """Paths of every value that is not a dict (list elements included)."""
    for k, v in d.items():
        p = path + (k,)
        if isinstance(v, dict):
            yield from leaves(v, p)
        else:
            yield p
            if isinstance(v, list):
                for i, x in enumerate(v):
                    if isinstance(x, dict):
                        yield from leaves(x, p + (i,))
                    else:
                        yield p + (i,)


def sections(d, path=()):
    for k, v in d.items():
        if isinstance(v, dict):
            yield path + (k,)
            yield from sections(v, path + (k,))


def holder(d, path):
    for k in path[:-1]:
        d = d[k]
    return d


def dotted(path):
    s = ""
    for k in path:
        s += f"[{k}]" if isinstance(k, int) else (f".{k}" if s else k)
    return s


def number(v):
    if isinstance(v, bool):
        return 1.0, ""
    if isinstance(v, (int, float)):
        return float(v), ""
    if isinstance(v, str):
        head, _, unit = v.strip().partition(" ")
        try:
            return float(head), unit
        except ValueError:
            return 1.0, ""
    return 1.0, ""


def bad_value(rng, old, path):
    n, unit = number(old)
    choices = [
        lambda: math.nan,
        lambda: math.inf,
        lambda: -math.inf,
        lambda: -n if not unit else f"{-n} {unit}",
        lambda: 0,
        lambda: rng.choice([-1.0, 1.0]) * float(f"1e{rng.randint(-330, 330)}"),
        lambda: f"{n * float(f'1e{rng.randint(-20, 20)}')} {unit}".strip(),
        lambda: f"{n} {rng.choice(UNITS)}".strip(),
        lambda: str(n),
        lambda: rng.choice(["lots", True, [n, n], {}, None, [], "", n + 0.5, 2**70]),
        lambda: rng.choice(FILES),
    ]
    return rng.choice(choices)()


def mutate(rng, d):
    """Applies one mutation to ``d`` in place; returns the dotted key it touched."""
    kind = rng.random()
    paths = list(leaves(d))
    if kind < 0.15:
        secs = list(sections(d))
        if rng.random() < 0.3 and secs:
            p = rng.choice(secs)
        else:
            p = rng.choice(paths)
        h = holder(d, p)
        if isinstance(h, list):
            h.pop(p[-1])
        else:
            h.pop(p[-1], None)
        return dotted(p)
    if kind < 0.22:
        secs = [()] + list(sections(d))
        p = rng.choice(secs)
        holder(d, p + ("x",))["bogus_key"] = 1.0
        return "bogus_key"
    p = rng.choice(paths)
    h = holder(d, p)
    h[p[-1]] = bad_value(rng, h[p[-1]], p)
    return dotted(p)


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f'"{k}" = {toml_value(x)}' for k, x in v.items()) + "}"
    return '"?"'  # None has no TOML form


def to_toml(d):
    """A study dict as TOML text: top-level values, then one table per top-level dict."""
    out = [f'"{k}" = {toml_value(v)}' for k, v in d.items() if not isinstance(v, dict)]
    for k, v in d.items():
        if isinstance(v, dict):
            out.append(f'["{k}"]')
            out += [f'"{kk}" = {toml_value(x)}' for kk, x in v.items()]
    return "\n".join(out) + "\n"


def names_a_key(message, touched):
    for k in touched:
        plain = "".join(part.split("]", 1)[-1] if i else part for i, part in enumerate(k.split("[")))
        leaf = plain.rsplit(".", 1)[-1]
        element = k[: k.rfind("]") + 1] if "]" in k else None
        if k in message or plain in message or leaf in message or (element and element in message):
            return True
    return False


def run(fn, study):
    """``fn(study)``: "ok", or the error's class and message; anything else fails the test."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fn(study)
            end = ("ok", "")
        except critspeed.StudyError as e:
            end = ("study", str(e))
        except critspeed.ComputationError as e:
            assert "panicked" not in str(e), str(e)
            end = ("computation", str(e))
    for w in caught:
        assert issubclass(w.category, critspeed.CritspeedWarning), str(w.message)
    return end


def bounded_bifurcation(study):
    """``bifurcation`` on a short branch (at most 6 cycles)."""
    if isinstance(study, dict):
        study = copy.deepcopy(study)
        b = study.setdefault("bifurcation", {})
        if isinstance(b, dict):
            b["max_points"] = 6
    return critspeed.bifurcation(study)


def test_mutated_studies_end_in_a_result_or_a_named_error(monkeypatch):
    seconds = float(os.environ.get("FUZZ_SECONDS", "20"))
    rng = random.Random(int(os.environ.get("FUZZ_SEED", "0")))
    # dict and text studies take their relative paths from the current directory
    monkeypatch.chdir(REPO / "studies")
    corpus = []
    for p in STUDIES:
        with open(p, "rb") as f:
            d = tomllib.load(f)
        d.setdefault("linear", {})["spectrum_points"] = 24
        corpus.append((p.name, d))
    ends = {}
    start, cases = time.monotonic(), 0
    while time.monotonic() - start < seconds:
        name, base = rng.choice(corpus)
        d = copy.deepcopy(base)
        touched = [mutate(rng, d) for _ in range(rng.randint(1, 3))]
        fns = [critspeed.check, critspeed.linear, critspeed.geometry]
        if rng.random() < 0.1 and name.startswith("seed"):
            fns.append(bounded_bifurcation)
        as_text = rng.random() < 0.3
        study = to_toml(d) if as_text else d
        for fn in fns:
            where = f"case {cases}: {fn.__name__} on {name} ({'text' if as_text else 'dict'}), touched {touched}"
            try:
                kind, message = run(fn, study)
            except AssertionError as e:
                pytest.fail(f"{where}: {e}\n{d!r}")
            ends[(fn.__name__, kind)] = ends.get((fn.__name__, kind), 0) + 1
            if kind == "study":
                assert names_a_key(message, touched), f"{where}: {message}\n{d!r}"
        cases += 1
    print(f"python fuzz: {cases} cases in {time.monotonic() - start:.0f} s: {sorted(ends.items())}")
    assert cases >= 20, cases


def test_implausible_values_and_empty_figures_warn_and_compute(tmp_path):
    with open(REPO / "studies" / "seed.toml", "rb") as f:
        d = tomllib.load(f)
    d["suspension"]["lateral_damping"] = 1e9  # meaningful, not plausible: overdamped
    with pytest.warns(critspeed.CritspeedWarning) as caught:
        plan = critspeed.check(d)
    assert "warnings" not in plan  # the plan stays a study
    assert any("suspension.lateral_damping = 1e9 N s/m" in str(w.message) for w in caught)
    with pytest.warns(critspeed.CritspeedWarning) as caught:
        r = critspeed.linear(d, out=tmp_path)
    messages = [str(w.message) for w in caught]
    assert any(m.startswith("root_locus.svg has nothing to draw") for m in messages), messages
    assert "linear_critical_speed_m_s" in r
    assert "nothing to draw" in (tmp_path / "seed" / "root_locus.svg").read_text()
    d["wheelset"]["mass"] = 1e19  # not meaningful: refused before computing
    with pytest.raises(critspeed.StudyError, match=r"wheelset.mass = 1e19 kg: must lie in"):
        critspeed.linear(d)
