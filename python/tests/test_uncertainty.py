"""critspeed.uncertainty(): the object `critspeed uncertainty --json` prints and the rows of
uncertainty.csv, to the last bit; bad [uncertainty] sections raise StudyError with the CLI's
message; Ctrl-C stops it and it resumes from its records."""

import os
import signal
import sys
import threading
import time

import numpy as np
import pytest

import critspeed
from conftest import REPO, cli, cli_json, same, same_as_csv

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

# The seed-hunting wheelset (V_L near 69 m/s) with four uncertain parameters, one of each
# distribution: 64 x (4 + 2) = 384 evaluations of V_L, well under a second.
SECTION = """
[uncertainty]
samples = 64
method = "sobol"
seed = 3
compute = ["kalker"]
operating_speed = "250 km/h"

[[uncertainty.parameter]]
key = "suspension.lateral_stiffness"
distribution = "uniform"
from = "240 N/mm"
to = "360 N/mm"

[[uncertainty.parameter]]
key = "contact.conicity"
distribution = "lognormal"
median = 0.15
factor = 1.1

[[uncertainty.parameter]]
key = "suspension.longitudinal_stiffness"
distribution = "normal"
mean = "850 N/mm"
std = "60 N/mm"
from = "600 N/mm"

[[uncertainty.parameter]]
key = "suspension.lateral_damping"
distribution = "choice"
values = ["6 N s/mm", "8 N s/mm", "10 N s/mm"]
weights = [0.25, 0.5, 0.25]
"""


def study_text(section=SECTION, name="small-uncertainty"):
    text = (REPO / "studies" / "seed-hunting.toml").read_text()
    return text.replace('name = "seed-hunting"', f'name = "{name}"') + section


def small_study(tmp_path, section=SECTION, name="small-uncertainty"):
    path = tmp_path / f"{name}.toml"
    path.write_text(study_text(section, name))
    return path


def test_uncertainty_equals_cli_json_and_csv(tmp_path):
    study = small_study(tmp_path)
    want = cli_json("uncertainty", study, "--json", "--threads", "2", "--out", tmp_path / "cli")
    got = critspeed.uncertainty(study, threads=1)
    rows = got.pop("evaluations")
    same(got, want)
    same_as_csv(rows, tmp_path / "cli" / "small-uncertainty" / "uncertainty.csv")
    # the contract's keys
    assert got["samples"] == 64 * (4 + 2) == len(rows["evaluation_id"])
    [q] = got["quantities"]
    assert q["name"] == "kalker" and q["failed"] == 0
    assert sorted(q["quantiles_m_s"]) == ["0.05", "0.5", "0.95"]
    assert 0.0 < q["probability_below_operating_speed"] < 1.0
    keys = [p["key"] for p in got["parameters"]]
    assert [i["key"] for i in q["indices"]] == keys
    for i in q["indices"]:
        assert set(i) == {"key", "first_order", "first_order_ci", "total", "total_ci"}
        assert i["total_ci"][0] <= i["total_ci"][1]
    # the columns: one per parameter named by its key (SI), the speeds, strings for the text
    assert list(rows)[:2] == ["evaluation_id", "block"] and list(rows)[2:6] == keys
    assert rows["block"].dtype.kind == "U" and rows["status"].dtype.kind == "U"
    assert sorted(set(rows["block"])) == ["A", "AB1", "AB2", "AB3", "AB4", "B"]
    assert set(rows["suspension.lateral_damping"]) <= {6e3, 8e3, 10e3}
    assert np.isnan(rows["hopf_speed_m_s"]).all()  # not computed
    # the mean is that of the A and B rows of the CSV
    ab = np.isin(rows["block"], ["A", "B"])
    speeds = rows["kalker_critical_speed_m_s"][ab]
    assert abs(speeds.mean() - q["mean_m_s"]) <= 1e-12 * q["mean_m_s"]


def test_path_text_dict_and_threads_give_the_same_result(tmp_path):
    study = small_study(tmp_path)
    with open(study, "rb") as f:
        as_dict = tomllib.load(f)
    results = [
        critspeed.uncertainty(s, threads=t)
        for s, t in ((study, 2), (study.read_text(), 1), (as_dict, None))
    ]
    for r in results[1:]:
        rows, rows0 = r.pop("evaluations"), results[0]["evaluations"]
        assert list(rows) == list(rows0)
        for k in rows:
            if rows[k].dtype == np.float64:
                assert rows[k].tobytes() == rows0[k].tobytes(), k
            else:
                assert list(rows[k]) == list(rows0[k]), k
        same(r, {k: v for k, v in results[0].items() if k != "evaluations"})


def test_out_writes_the_cli_files_byte_for_byte(tmp_path):
    study = small_study(tmp_path)
    cli("uncertainty", study, "--out", tmp_path / "cli")
    got = critspeed.uncertainty(study, out=tmp_path / "py")
    cli_dir, py_dir = tmp_path / "cli" / "small-uncertainty", tmp_path / "py" / "small-uncertainty"
    names = sorted(p.name for p in cli_dir.iterdir())
    assert names == sorted(p.name for p in py_dir.iterdir())
    for n in ("uncertainty.json", "uncertainty.csv", "uncertainty.svg"):
        assert (cli_dir / n).read_bytes() == (py_dir / n).read_bytes(), n
    assert (py_dir / "uncertainty.records.csv").is_file()
    # a second call resumes every evaluation from the records and returns the same
    again = critspeed.uncertainty(study, out=tmp_path / "py")
    a, b = got.pop("evaluations"), again.pop("evaluations")
    same(again, got)
    assert all(list(map(str, a[k])) == list(map(str, b[k])) for k in a)


# each bad section: (replace this, by that, the key the message names, words of the rule)
BAD = [
    ('std = "60 N/mm"', 'std = 0',
     "uncertainty.parameter[2].std (suspension.longitudinal_stiffness)", "must be positive"),
    ('std = "60 N/mm"', 'std = "-10 N/mm"',
     "uncertainty.parameter[2].std (suspension.longitudinal_stiffness)", "must be positive"),
    ('to = "360 N/mm"', 'to = "240 N/mm"',
     "uncertainty.parameter[0].from (suspension.lateral_stiffness)", "from must be below to"),
    ('weights = [0.25, 0.5, 0.25]', 'weights = [0, 0, 0]',
     "uncertainty.parameter[3].weights (suspension.lateral_damping)",
     "weights must sum to a positive number"),
    ('key = "suspension.lateral_stiffness"', 'key = "suspension.lateral_stifness"',
     "uncertainty.parameter[0].key", "is not a key that can vary"),
    ('key = "contact.conicity"', 'key = "contact.creep_law"',
     "uncertainty.parameter[1].key", "is not a key that can vary"),
    ('samples = 64', 'samples = 1', "uncertainty.samples", "must be at least 2"),
    ('samples = 64', 'samples = 48', "uncertainty.samples",
     'must be a power of two for method "sobol"'),
    ('factor = 1.1', 'factor = 0.9', "uncertainty.parameter[1].factor (contact.conicity)",
     "above 1"),
]


@pytest.mark.parametrize("old,new,key,rule", BAD, ids=[b[1] for b in BAD])
def test_bad_section_raises_the_cli_message_naming_the_key(tmp_path, old, new, key, rule):
    assert old in SECTION
    section = SECTION.replace(old, new, 1)
    with pytest.raises(critspeed.StudyError) as e:
        critspeed.uncertainty(study_text(section))
    msg = str(e.value)
    assert msg.startswith(key + " = "), msg
    assert rule in msg, msg
    # the command line's message, word for word (exit 2)
    p = cli("uncertainty", small_study(tmp_path, section), "--out", tmp_path, check=False)
    assert p.returncode == 2, p.stderr
    assert p.stderr.strip().splitlines()[-1] == f"error: {msg}"


def test_bad_arguments_and_missing_section_raise_study_errors(tmp_path):
    with pytest.raises(critspeed.StudyError, match="threads"):
        critspeed.uncertainty(study_text(), threads=0)
    with pytest.raises(critspeed.StudyError, match=r"no \[uncertainty\] section"):
        critspeed.uncertainty(REPO / "studies" / "seed-hunting.toml")
    # sampled values outside a key's valid range are refused before anything is computed
    with pytest.raises(critspeed.StudyError, match="uncertainty.parameter"):
        critspeed.uncertainty(study_text(SECTION.replace('from = "240 N/mm"', 'from = "-10 N/mm"')))


def test_an_interrupted_study_resumes_from_its_records(tmp_path):
    # interrupt from a timer thread the way Ctrl-C would: SIGINT to this process
    if sys.platform == "win32" or threading.current_thread() is not threading.main_thread():
        pytest.skip("needs SIGINT on the main thread")
    # V_L and V_H on 128 x 6 evaluations, on one thread: long enough to be interrupted
    section = SECTION.replace("samples = 64", "samples = 128").replace(
        'compute = ["kalker"]', 'compute = ["kalker", "hopf"]')
    text = study_text(section, name="resume")
    records_file = tmp_path / "resume" / "uncertainty.records.csv"
    stop = threading.Event()

    def interrupt_after_first_evaluation():
        while not stop.is_set():
            if records_file.exists() and any(
                l[:1].isdigit() for l in records_file.read_text().splitlines()
            ):
                os.kill(os.getpid(), signal.SIGINT)
                return
            time.sleep(0.002)

    watcher = threading.Thread(target=interrupt_after_first_evaluation)
    watcher.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            critspeed.uncertainty(text, threads=1, out=tmp_path)
    finally:
        stop.set()
        watcher.join()
    done = [l for l in records_file.read_text().splitlines() if l[:1].isdigit()]
    assert 0 < len(done) < 128 * 6
    assert not (tmp_path / "resume" / "uncertainty.json").exists()
    whole = critspeed.uncertainty(text, threads=2, out=tmp_path)
    fresh = critspeed.uncertainty(text, threads=2)
    a, b = whole.pop("evaluations"), fresh.pop("evaluations")
    same(whole, fresh)
    for k in b:
        assert list(map(str, a[k])) == list(map(str, b[k])), k
