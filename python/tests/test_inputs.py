"""Study inputs (path, TOML text, dict; SI numbers or unit strings), errors that name the key,
the GIL and Ctrl-C."""

import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

import pytest

import critspeed
from conftest import REPO, cli, same

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

SEED_HUNTING = REPO / "studies" / "seed-hunting.toml"


def as_dict(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def test_path_text_dict_and_pathlike_give_the_same_results():
    text = SEED_HUNTING.read_text()
    results = [
        critspeed.linear(study)
        for study in (str(SEED_HUNTING), SEED_HUNTING, text, as_dict(SEED_HUNTING))
    ]
    for r in results[1:]:
        same(r, results[0])
    bif = [critspeed.bifurcation(s) for s in (SEED_HUNTING, text, as_dict(SEED_HUNTING))]
    for b in bif[1:]:
        assert b["branch"].keys() == bif[0]["branch"].keys()
        for k in b["branch"]:
            assert b["branch"][k].tobytes() == bif[0]["branch"][k].tobytes(), k
        same({k: v for k, v in b.items() if k != "branch"},
             {k: v for k, v in bif[0].items() if k != "branch"})


def test_relative_paths_in_a_study_file_are_taken_from_its_folder(monkeypatch, tmp_path):
    # s1002-uic60 reads its profiles from studies/profiles/: from any working directory
    monkeypatch.chdir(tmp_path)
    study = REPO / "studies" / "s1002-uic60.toml"
    same(critspeed.conicity(study), critspeed.conicity(os.path.relpath(study, tmp_path)))


def test_unit_strings_and_si_numbers_give_the_same_plan_and_results():
    d = as_dict(SEED_HUNTING)
    assert isinstance(d["suspension"]["lateral_stiffness"], str)  # "300 N/mm" in the file
    si = critspeed.check(d)
    # the resolved plan (all numbers, SI) is itself a study, and resolves to itself
    same(critspeed.check(si), si)
    same(critspeed.linear(si), critspeed.linear(d))
    for value in ("300 N/mm", "300 kN/m", "0.3 MN/m", 300e3, 300000):
        d["suspension"]["lateral_stiffness"] = value
        assert critspeed.check(d)["suspension"]["lateral_stiffness"] == 300e3, value
    d["wheelset"]["mass"] = "1.25 t"
    assert critspeed.check(d)["wheelset"]["mass"] == 1250.0
    d["linear"] = {"speed_range": ["36 km/h", "100 m/s"]}
    assert critspeed.check(d)["linear"]["speed_range"] == [10.0, 100.0]


def cli_error(tmp_path, text):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    p = cli("check", f, check=False)
    assert p.returncode == 2, p.stderr
    return p.stderr.strip().removeprefix("error: ")


@pytest.mark.parametrize(
    "section,key,value,words",
    [
        ("suspension", "lateral_damping", "8 N/mm", ["'N/mm' is a unit of stiffness"]),
        ("wheelset", "mass", -1250.0, ["must be positive"]),
        ("contact", "friction", "lots", ["friction"]),
        ("contact", "creep_law", "magic", ["is not one of"]),
        ("suspension", "lateral_stifness", 1.0, ["unknown field"]),
        ("suspension", "bump_stop_clearance", "-3 mm", ["must be positive"]),
    ],
)
def test_bad_input_raises_the_cli_message_naming_the_key(tmp_path, section, key, value, words):
    d = as_dict(SEED_HUNTING)
    d[section][key] = value
    with pytest.raises(critspeed.StudyError) as e:
        critspeed.linear(d)
    msg = str(e.value)
    assert key in msg
    for w in words:
        assert w in msg
    # the same message as the command line's for the same study (but the file's name)
    text = SEED_HUNTING.read_text()
    rendered = f'"{value}"' if isinstance(value, str) else repr(value)
    lines = [l for l in text.splitlines() if not l.startswith(f"{key} =")]
    i = next(i for i, l in enumerate(lines) if l.startswith(f"[{section}]"))
    lines.insert(i + 1, f"{key} = {rendered}")
    want = cli_error(tmp_path, "\n".join(lines) + "\n")
    if "TOML parse error" in want:
        # a syntax error quotes the source's line, and the dict's TOML is laid out otherwise
        assert key in want
    else:
        assert msg == want


def test_study_error_is_a_value_error_and_computation_error_a_runtime_error():
    assert issubclass(critspeed.StudyError, ValueError)
    assert issubclass(critspeed.ComputationError, RuntimeError)
    with pytest.raises(ValueError):
        critspeed.check({"name": "x"})


def test_bad_arguments_raise_study_errors_naming_them(tmp_path):
    with pytest.raises(critspeed.StudyError, match="speeds"):
        critspeed.simulate(SEED_HUNTING, [-3.0])
    with pytest.raises(critspeed.StudyError, match=r"y0 \"5 kg\""):
        critspeed.simulate(SEED_HUNTING, [30.0], y0="5 kg")
    with pytest.raises(critspeed.StudyError, match="threads"):
        critspeed.sweep(SEED_HUNTING, threads=0)
    with pytest.raises(critspeed.StudyError, match="no \\[sweep\\] section"):
        critspeed.sweep(SEED_HUNTING)
    with pytest.raises(critspeed.StudyError, match="amplitude"):
        critspeed.conicity(SEED_HUNTING, amplitudes=["1 m"])
    with pytest.raises(critspeed.StudyError, match="cannot read study file"):
        critspeed.linear(tmp_path / "missing.toml")
    with pytest.raises(critspeed.StudyError, match="not both"):
        critspeed.conicity(SEED_HUNTING, delta_r=([0.0], [0.0]))
    with pytest.raises(critspeed.StudyError, match="wheelset.mass"):
        d = as_dict(SEED_HUNTING)
        d["wheelset"]["mass"] = None
        critspeed.linear(d)
    with pytest.raises(TypeError):
        critspeed.linear(42)


def test_long_calls_release_the_gil():
    # while bifurcation() computes on this thread, another Python thread keeps running
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    # small continuation steps, so that the call lasts long enough to tell (about a second;
    # at the default steps seed-hunting's branch takes under 0.1 s)
    slow = Path(SEED_HUNTING).read_text() + "\n[bifurcation]\nds_max = 0.05\n"
    t = threading.Thread(target=tick)
    t.start()
    try:
        start = time.perf_counter()
        critspeed.bifurcation(slow)
        end = time.perf_counter()
    finally:
        stop.set()
        t.join()
    during = [x for x in ticks if start < x < end]
    # a held GIL would leave at most a tick or two at the ends of a call of ~1 s
    assert end - start > 0.1 and len(during) > 20, (end - start, len(during))


SLOW = """
import critspeed, sys
extra = chr(10).join(["", "[bifurcation]", 'max_amplitude = "30 mm"', "ds_max = 0.002",
                      "max_points = 100000", ""])
text = open(sys.argv[1]).read() + extra
print("started", flush=True)
try:
    critspeed.bifurcation(text)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(3)
"""


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT")
def test_ctrl_c_stops_a_long_continuation(tmp_path):
    # ds_max 0.002 and 1e5 points: this branch would take many minutes
    p = subprocess.Popen([sys.executable, "-c", SLOW, str(SEED_HUNTING)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.0)
    sent = time.perf_counter()
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        pytest.fail("the computation did not stop within 30 s of Ctrl-C")
    waited = time.perf_counter() - sent
    assert p.returncode == 3 and "interrupted" in out, (p.returncode, out, err)
    assert waited < 5.0, waited


def test_an_interrupted_sweep_resumes_from_its_records(tmp_path):
    # interrupt from a timer thread the way Ctrl-C would: SIGINT to this process
    if sys.platform == "win32" or threading.current_thread() is not threading.main_thread():
        pytest.skip("needs SIGINT on the main thread")
    d = as_dict(SEED_HUNTING)
    d["name"] = "resume"
    count = 120
    d["sweep"] = {
        "axes": [{"key": "suspension.lateral_stiffness", "from": "200 N/mm",
                  "to": "800 N/mm", "count": count}],
        "compute": ["kalker", "hopf", "nonlinear"],
    }
    d["bifurcation"] = {"max_amplitude": "1 mm"}
    records_file = tmp_path / "resume" / "sweep.records.csv"
    stop = threading.Event()

    def interrupt_after_first_point():
        # Ctrl-C once the first point is on record, whatever the machine's speed
        while not stop.is_set():
            if records_file.exists() and any(
                l[:1].isdigit() for l in records_file.read_text().splitlines()
            ):
                os.kill(os.getpid(), signal.SIGINT)
                return
            time.sleep(0.002)

    watcher = threading.Thread(target=interrupt_after_first_point)
    watcher.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            critspeed.sweep(d, threads=1, out=tmp_path)
    finally:
        stop.set()
        watcher.join()
    records = records_file.read_text().splitlines()
    done = [l for l in records if l[:1].isdigit()]
    assert 0 < len(done) < count
    assert not (tmp_path / "resume" / "sweep.csv").exists()
    whole = critspeed.sweep(d, threads=1, out=tmp_path)
    fresh = critspeed.sweep(d, threads=2)
    for k in fresh:
        assert list(map(str, whole[k])) == list(map(str, fresh[k])), k


def test_a_numerical_failure_raises_computation_error_with_the_cli_message(tmp_path):
    # S1002 on UIC60 with the taping lines 70 mm inside their place: the wheels reach the rail
    # heads, but the contact point leaves the wheel's running part at the centre (the CLI
    # exits with 1)
    text = (REPO / "studies" / "s1002-uic60.toml").read_text()
    text = text.replace('"profiles/', f'"{REPO / "studies" / "profiles"}/')
    narrow = text.replace('half_contact_distance = "750 mm"', 'half_contact_distance = "680 mm"')
    f = tmp_path / "narrow.toml"
    f.write_text(narrow)
    p = cli("linear", f, "--out", tmp_path, check=False)
    assert p.returncode == 1, p.stderr
    with pytest.raises(critspeed.ComputationError) as e:
        critspeed.linear(f)
    assert "leaves the wheel profile's running part" in str(e.value)
    assert p.stderr.strip() == "computation failed: " + str(e.value)
    assert not (tmp_path / "s1002-uic60").exists()
    # at a 1200 mm gauge the wheels cannot reach the rails at all: refused before computing
    gauge = tmp_path / "gauge.toml"
    gauge.write_text(text.replace('track_gauge = "1435 mm"', 'track_gauge = "1200 mm"'))
    assert cli("linear", gauge, "--out", tmp_path, check=False).returncode == 2
    with pytest.raises(critspeed.StudyError, match="wheels cannot touch the rails"):
        critspeed.linear(gauge)
