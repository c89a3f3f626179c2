"""Results equal the command line's to the last bit: the JSON it prints and the CSV files it
writes, on every shipped study."""

import json

import numpy as np
import pytest

import critspeed
from conftest import REPO, STUDIES, cli, cli_json, read_csv, same, same_as_csv

IDS = [s.stem for s in STUDIES]


def test_there_are_studies_to_compare():
    assert len(STUDIES) >= 8, STUDIES


def test_version_is_the_cli_version():
    out = cli("--version").stdout.split()
    assert out == ["critspeed", critspeed.__version__]


@pytest.mark.parametrize("study", STUDIES, ids=IDS)
def test_linear_equals_cli_json(study, tmp_path):
    want = cli_json("linear", study, "--json", "--out", tmp_path)
    same(critspeed.linear(study), want)


# every study whose diagram runs in seconds to a minute; the passenger car's (its study and its
# yaw-damper map, whose diagram `bifurcation` draws with the defaults) takes over 20 minutes
# (docs/vehicles.md, "A modern passenger car"), twice here (the command and the call)
DIAGRAM_STUDIES = [s for s in STUDIES if not s.stem.startswith("passenger-car")]


@pytest.mark.parametrize("study", DIAGRAM_STUDIES, ids=[s.stem for s in DIAGRAM_STUDIES])
def test_bifurcation_equals_cli_json_and_branch_csv(study, tmp_path):
    want = cli_json("bifurcation", study, "--json", "--out", tmp_path)
    got = critspeed.bifurcation(study)
    branch = got.pop("branch")
    same(got, want)
    name = want["study"]
    same_as_csv(branch, tmp_path / name / "branch.csv")
    assert len(branch["speed_m_s"]) == want["cycles"]
    assert branch["stable"].dtype == np.bool_


CURVE_STUDIES = [s for s in STUDIES if "\n[curve]" in s.read_text()]


def test_there_are_curve_studies():
    assert len(CURVE_STUDIES) >= 2, CURVE_STUDIES


@pytest.mark.parametrize("study", CURVE_STUDIES, ids=[s.stem for s in CURVE_STUDIES])
def test_curve_equals_cli_json_and_curve_csv(study, tmp_path):
    want = cli_json("curve", study, "--json", "--out", tmp_path)
    got = critspeed.curve(study)
    points = got.pop("points")
    same(got, want)
    same_as_csv(points, tmp_path / want["study"] / "curve.csv")
    assert len(points["speed_m_s"]) == sum(len(c["points"]) for c in want["curves"])
    assert points["label"].dtype == object or points["label"].dtype.kind == "U"


@pytest.mark.parametrize("study", STUDIES, ids=IDS)
def test_conicity_equals_cli_json(study, tmp_path):
    want = cli_json("conicity", study, "--json", "--out", tmp_path)
    same(critspeed.conicity(study), want)


def test_conicity_of_a_delta_r_table_equals_cli(tmp_path):
    # a table in metres (header y_m,delta_r_m) so that both read the same numbers
    y = np.linspace(-8e-3, 8e-3, 33)
    dr = 2 * 0.05 * y + 40 * y**3
    f = tmp_path / "wear.csv"
    f.write_text("y_m,delta_r_m\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(y, dr)))
    amps = ["1 mm", "2.5 mm", "4 mm"]
    want = cli_json("conicity", "--delta-r", f, "--amplitudes", ",".join(amps), "--json",
                    "--out", tmp_path)
    same(critspeed.conicity(delta_r=(y, dr), amplitudes=amps), want)


def test_check_holds_the_plan_the_cli_prints(tmp_path):
    study = REPO / "studies" / "seed-hunting.toml"
    plan = critspeed.check(study)
    text = cli("check", study).stdout
    # every SI value of the table is in the dict under its dotted key, bit for bit
    for key, value in [
        ("suspension.lateral_stiffness", plan["suspension"]["lateral_stiffness"]),
        ("wheelset.yaw_inertia", plan["wheelset"]["yaw_inertia"]),
        ("contact.rail_head_radius", plan["contact"]["rail_head_radius"]),
        ("contact.young_modulus", plan["contact"]["young_modulus"]),
    ]:
        line = next(l for l in text.splitlines() if l.split()[:1] == [key])
        assert float(line.split()[1]) == value, line
    # the seed-hunting file gives the lateral stiffness as "300 N/mm"
    assert plan["suspension"]["lateral_stiffness"] == 300e3


def test_simulate_equals_cli_csv(tmp_path):
    study = REPO / "studies" / "seed.toml"
    cli("simulate", study, "--speed", "10,30,40", "--duration", "2s", "--y0", "3mm",
        "--out", tmp_path)
    got = critspeed.simulate(study, [10, "30 m/s", 40.0], y0="3 mm", duration=2)
    same_as_csv(got, tmp_path / "seed" / "simulate.csv")
    assert sorted(set(got["speed_m_s"])) == [10.0, 30.0, 40.0]


def test_simulate_rtol_equals_cli_and_is_checked(tmp_path):
    study = REPO / "studies" / "seed-hunting.toml"
    cli("simulate", study, "--speed", "75", "--duration", "1s", "--rtol", "1e-6",
        "--out", tmp_path)
    got = critspeed.simulate(study, 75, duration=1, rtol=1e-6)
    same_as_csv(got, tmp_path / "seed-hunting" / "simulate.csv")
    tight = critspeed.simulate(study, 75, duration=1)
    assert not np.array_equal(got["y_m"], tight["y_m"])
    for bad in (1e-3, 0, float("nan")):
        with pytest.raises(critspeed.StudyError, match=r"rtol .*\[1e-12, 1e-4\]"):
            critspeed.simulate(study, 75, duration=0.1, rtol=bad)
    with pytest.raises(critspeed.StudyError, match="rtol = 'tight'"):
        critspeed.simulate(study, 75, duration=0.1, rtol="tight")


def test_simulate_from_an_attractor_with_kicks_equals_cli(tmp_path):
    study = REPO / "studies" / "dtu-cooperrider-car.toml"
    state = [0.0] * 28
    state[0] = 0.004
    (tmp_path / "attractors.json").write_text(json.dumps(
        {"attractors": [{"id": 2, "path": [{"speed_m_s": 120.0, "state": state}]}]}))
    start = f"{tmp_path / 'attractors.json'}:2"
    kicks = ["wheelset-3.y=6mm", "frame_2.psi=2 mrad"]
    cli("simulate", study, "--speed", "100", "--duration", "0.2s", "--from", start,
        "--kick", kicks[0], "--kick", kicks[1], "--out", tmp_path)
    got = critspeed.simulate(study, 100, duration="0.2 s", start_from=start, kick=kicks)
    same_as_csv(got, tmp_path / "dtu-cooperrider-car" / "simulate.csv")
    assert got["y_wheelset_1_m"][0] == 0.004
    assert got["y_wheelset_3_m"][0] == 0.006
    assert got["psi_frame_2_rad"][0] == 0.002
    with pytest.raises(critspeed.StudyError, match="no attractor 9"):
        critspeed.simulate(study, 100, duration=0.1, start_from=f"{tmp_path / 'attractors.json'}:9")
    with pytest.raises(critspeed.StudyError, match="no body"):
        critspeed.simulate(study, 100, duration=0.1, kick=["wheel-9.y=1mm"])


SWEEP = """
[bifurcation]
max_amplitude = "1 mm"

[sweep]
axes = [ { key = "contact.conicity", from = 0.03, to = 0.2, count = 3 },
         { key = "suspension.lateral_stiffness", from = "200 N/mm", to = "800 N/mm", count = 2, spacing = "log" } ]
compute = ["kalker", "hopf", "nonlinear"]
"""


def small_sweep(tmp_path):
    text = (REPO / "studies" / "seed-hunting.toml").read_text().replace(
        'name = "seed-hunting"', 'name = "small-sweep"') + SWEEP
    path = tmp_path / "small-sweep.toml"
    path.write_text(text)
    return path


def test_sweep_equals_cli_csv_with_1_and_2_threads(tmp_path):
    study = small_sweep(tmp_path)
    cli("sweep", study, "--out", tmp_path / "cli")
    one = critspeed.sweep(study, threads=1)
    two = critspeed.sweep(study, threads=2)
    same_as_csv(one, tmp_path / "cli" / "small-sweep" / "sweep.csv")
    assert list(one) == list(two)
    for k in one:
        assert one[k].dtype == two[k].dtype, k
        if one[k].dtype == np.float64:
            assert one[k].tobytes() == two[k].tobytes(), k
        else:
            assert list(one[k]) == list(two[k]), k
    assert len(one["point_id"]) == 6
    # the low-conicity points have no Hopf point below 150 m/s: NaN, not a number made up
    assert np.isnan(one["hopf_speed_m_s"]).any() and not np.isnan(one["hopf_speed_m_s"]).all()


def test_out_writes_the_cli_files_byte_for_byte(tmp_path):
    study = REPO / "studies" / "seed-hunting.toml"
    cli("linear", study, "--out", tmp_path / "cli")
    critspeed.linear(study, out=tmp_path / "py")
    cli_dir, py_dir = tmp_path / "cli" / "seed-hunting", tmp_path / "py" / "seed-hunting"
    names = sorted(p.name for p in cli_dir.iterdir())
    assert names == sorted(p.name for p in py_dir.iterdir())
    assert "linear.json" in names and "spectrum.csv" in names
    for n in names:
        assert (cli_dir / n).read_bytes() == (py_dir / n).read_bytes(), n
    assert json.loads((py_dir / "linear.json").read_text()) == critspeed.linear(study)
    header, rows = read_csv(py_dir / "spectrum.csv")
    assert len(rows) == 600 and header[0] == "creep_law"  # 300 speeds x (Kalker, Shen)


def test_nothing_is_written_without_out(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    study = REPO / "studies" / "seed-hunting.toml"
    critspeed.linear(study)
    critspeed.bifurcation(study)
    critspeed.conicity(study)
    critspeed.simulate(study, 30, duration=0.5)
    critspeed.sweep(small_sweep(tmp_path))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["small-sweep.toml"]
