"""Issue 27 (tests/reliability/cases_bounds.py): every case ends in exit status 2 with one line naming
the option (or the file and key), no traceback, and nothing written; and the bounds themselves, at
their edges: what is accepted just inside and refused just outside (exact: the bounds are numbers
stated in the code, compared without tolerance)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tb_exudyn.errors import ScenarioError, SettingError
from tb_exudyn.execution.output import removed_if_left_empty
from tb_exudyn.methods.sweep import (EN1991_SPEED_FACTOR, MAX_SPEEDS, SPEED_CHECK, check_speeds, en1991_speeds,
                                     parse_speeds)
from tb_exudyn.scenario import RigidBodyInertia, Suspension, load_scenario
from tb_exudyn.scenario.schema import VEHICLE_DAMPING, VEHICLE_STIFFNESS

from .cases import snapshot
from .cases_bounds import CASES_BOUNDS, run_refused_by_memory_in_new_folder, run_refused_in_new_folder
from .test_cases import assert_one_clear_error, run_case


@pytest.mark.parametrize("case", CASES_BOUNDS, ids=[c.id for c in CASES_BOUNDS])
def test_bounds_case_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_speed_series_bounds_at_their_edges():
    """Exact problem: the speed series typed on the command line at the edges of the rules: speeds in
    the scenario's range of speed_kmh (> 0, <= 1000 km/h), at most MAX_SPEEDS = 1000 of them, no two
    with the same folder name. References: the rules as stated in tb_exudyn/methods/sweep.py and
    schema.py; the counts by hand (1:1000:1 is 1000 speeds; 1:1000:0.999 is 1001, the last 1000.0)."""
    assert SPEED_CHECK.high == 1000.0 and MAX_SPEEDS == 1000
    assert parse_speeds("1000") == (1000.0,)
    assert len(parse_speeds("1:1000:1")) == MAX_SPEEDS
    with pytest.raises(SettingError, match="1001 speeds") as info:
        parse_speeds("1:1000:0.999", where="command line")
    assert info.value.key == "speeds_kmh" and info.value.where == "command line"  # the command line's table: the flag
    for bad in ("1000.001", "0", "-1", "inf", "nan", "200,nan", "1:1000.001:1", "1:2:inf", "1:2:nan", "1:2:-1"):
        with pytest.raises(SettingError, match="'speeds_kmh'"):
            parse_speeds(bad)
    # equal after the 6 significant digits of the speed folders ('100'), distinct at 100.001
    with pytest.raises(SettingError, match=r"100\.0 and 100\.0000001 are the same speed '100'"):
        parse_speeds("100,100.0000001")
    with pytest.raises(SettingError, match="same speed"):
        parse_speeds("100:100.00001:0.000001")
    assert parse_speeds("100,100.001") == (100.0, 100.001)
    with pytest.raises(SettingError, match="same speed") as info:
        check_speeds((200.0, 200.0))
    assert info.value.where == "run_sweep" and info.value.key == "speeds_kmh"


def test_en1991_series_bounds_at_their_edges():
    """Exact problem: EN 1991-2's series (up to 1.2 x the line speed V) at the edges: the top speed 1.2 V
    at most 1000 km/h (V = 1000 / 1.2 accepted, a little more refused), the step finite and > 0 with at
    most 1000 speeds (from 150 to 360 km/h: a step of (360 - 150) / 999 km/h gives 1000 speeds,
    half of it 1999, refused), a step larger than the top speed giving the top speed alone. Reference:
    EN 1991-2 6.4.6.2 (speeds up to 1.2 V, the last exactly 1.2 V), the bounds as stated in sweep.py."""
    top_line = SPEED_CHECK.high / EN1991_SPEED_FACTOR
    assert en1991_speeds(top_line, 10.0)[-1] == round(EN1991_SPEED_FACTOR * top_line, 9)
    with pytest.raises(SettingError, match="'line_speed_kmh'"):
        en1991_speeds(top_line + 1e-6, 10.0)
    step = (360.0 - 150.0) / 999
    assert len(en1991_speeds(300.0, step, start_kmh=150.0)) == MAX_SPEEDS
    with pytest.raises(SettingError, match="'step_kmh'"):
        en1991_speeds(300.0, step / 2, start_kmh=150.0)
    for bad_step in (0.0, -10.0, math.nan, math.inf):
        with pytest.raises(SettingError, match="command line: key 'step_kmh'"):
            en1991_speeds(300.0, bad_step, where="command line")
    assert en1991_speeds(100.0, 500.0) == (120.0,)


def test_vehicle_bounds_at_their_edges():
    """Exact problem: a suspension stage, a car body and a scenario at the schema's stated bounds
    (springs > 0 and <= 1e10 N/m, dampers >= 0 and <= 1e9 N s/m, masses <= 1e6 kg, inertias <= 1e9
    kg m^2, speed <= 1000 km/h): the bound itself accepted, the next double above it refused, naming
    the key. Reference: the bounds in tb_exudyn/scenario/schema.py."""
    assert VEHICLE_STIFFNESS.high == 1e10 and VEHICLE_DAMPING.high == 1e9
    ok = Suspension(k_z=1e10, k_y=1e10, c_z=1e9, c_y=0.0)
    assert ok.c_z == 1e9
    with pytest.raises(ScenarioError, match="'c_z'"):
        ok.replace(c_z=math.nextafter(1e9, math.inf))
    with pytest.raises(ScenarioError, match="'k_y'"):
        ok.replace(k_y=math.nextafter(1e10, math.inf))
    body = RigidBodyInertia(mass=1e6, inertia_roll=1e9, inertia_pitch=1e9, inertia_yaw=1e9)
    with pytest.raises(ScenarioError, match="'mass'"):
        body.replace(mass=math.nextafter(1e6, math.inf))
    with pytest.raises(ScenarioError, match="'inertia_yaw'"):
        body.replace(inertia_yaw=math.nextafter(1e9, math.inf))
    sc = load_scenario("quick")
    assert sc.replace(speed_kmh=1000.0).speed_kmh == 1000.0
    with pytest.raises(ScenarioError, match="'speed_kmh'"):
        sc.replace(speed_kmh=math.nextafter(1000.0, math.inf))


def test_removed_if_left_empty(tmp_path: Path):
    """Behaviour: on an error in the block the folder and the parents it lacked are removed if empty;
    a folder that holds a file, a folder that existed, and a folder after a block without error are
    kept."""
    new = tmp_path / "a" / "b" / "out"
    with pytest.raises(SettingError):
        with removed_if_left_empty(new):
            new.mkdir(parents=True)
            raise SettingError("command line", "--x", 1, "2")
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    with pytest.raises(SettingError):
        with removed_if_left_empty(new):
            new.mkdir(parents=True)
            (new / "keep.txt").write_text("x")
            raise SettingError("command line", "--x", 1, "2")
    assert (new / "keep.txt").is_file()
    existing = tmp_path / "existing"
    existing.mkdir()
    with pytest.raises(KeyboardInterrupt):
        with removed_if_left_empty(existing):
            raise KeyboardInterrupt
    assert existing.is_dir()
    with removed_if_left_empty(tmp_path / "done"):
        (tmp_path / "done").mkdir()
    assert (tmp_path / "done").is_dir()


@pytest.mark.parametrize("build", [run_refused_in_new_folder, run_refused_by_memory_in_new_folder],
                         ids=["no irregularities", "--max-memory 1KB"])
def test_run_refused_after_creating_out_leaves_no_new_folder(build, tmp_path, capsys, monkeypatch):
    """Behaviour: ``run fryba_moving_force --out work/new/out`` (PEM of a scenario without track
    irregularities: refused by run_pem after the command created --out and its parent) and ``run quick
    --max-memory 1KB --out work/new/out`` (refused when the tasks are set up, after --out/checkpoint/
    was opened, no task finished) give the one-line error, and both new folders are removed again (the
    scratch folder holds what it held before; its modification time changes, so these are not cases of
    the list, whose snapshot compares times too)."""
    work, cwd = tmp_path / "work", tmp_path / "cwd"
    work.mkdir()
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    run = build(work)
    before = sorted(snapshot(tmp_path))
    code, err = run_case(run, cwd, capsys, monkeypatch)
    errors = [line for line in err.splitlines() if line.startswith("tb-exudyn: error:")]
    assert code == 2 and "Traceback" not in err and len(errors) == 1, err  # (quick's damping guard warns first)
    for text in run.expect:
        assert text in errors[0], f"{text!r} not in {errors[0]!r}"
    assert sorted(snapshot(tmp_path)) == before


def test_removed_if_left_empty_after_a_refusal_with_an_unstarted_checkpoint(tmp_path: Path):
    """Behaviour: a new folder holding only a checkpoint manifest and an empty tasks/ is removed after a
    refusal (UserError); with a finished task, or after an interruption (not a refusal), it is kept."""
    def opened(folder: Path, task: bool = False) -> None:
        (folder / "checkpoint" / "tasks").mkdir(parents=True)
        (folder / "checkpoint" / "manifest.json").write_text("{}")
        if task:
            (folder / "checkpoint" / "tasks" / "t.npz").write_bytes(b"x")

    new = tmp_path / "new" / "out"
    with pytest.raises(SettingError):
        with removed_if_left_empty(new):
            opened(new)
            raise SettingError("command line", "--max-memory", "1KB", "more")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(SettingError):
        with removed_if_left_empty(new):
            opened(new, task=True)
            raise SettingError("command line", "--max-memory", "1KB", "more")
    assert (new / "checkpoint" / "tasks" / "t.npz").is_file()
    other = tmp_path / "other"
    with pytest.raises(KeyboardInterrupt):
        with removed_if_left_empty(other):
            opened(other)
            raise KeyboardInterrupt
    assert (other / "checkpoint" / "manifest.json").is_file()
    # an existing folder: the unstarted checkpoint the refused block made is removed, what was there is kept
    kept = tmp_path / "kept"
    kept.mkdir()
    (kept / "notes.txt").write_text("mine")
    with pytest.raises(SettingError):
        with removed_if_left_empty(kept):
            opened(kept)
            raise SettingError("command line", "--max-memory", "1KB", "more")
    assert sorted(p.name for p in kept.iterdir()) == ["notes.txt"]


def test_a_speed_whose_sweep_scenario_is_invalid_is_named():
    """Exact problem: quick with time_step = output_step = 0.05 s, so that the highest frequency the step
    resolves is 0.1 / 0.05 = 2 Hz; at speed v the sweep's band starts at v / wavelength_max = v / 120 m,
    empty from 240 m/s = 864 km/h on. Reference: the band rule of sweep_scenario (module docstring).
    check_sweep accepts 200 km/h and refuses 900 km/h naming the argument speeds_kmh and the speed
    (not the derived scenario's key alone, as '<scenario>: key freq_min' did)."""
    from tb_exudyn.methods.sweep import check_sweep

    sc = load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(time_step=0.05, output_step=0.05, freq_min=0.5, freq_max=2.0,
                                                 freq_spacing="linear"))
    assert check_sweep(sc, [200.0, 860.0]) == (200.0, 860.0)
    with pytest.raises(SettingError, match=r"run_sweep: key 'speeds_kmh' = 900\.0: at 900 km/h freq_min") as info:
        check_sweep(sc, [200.0, 900.0])
    assert "empty frequency band" in str(info.value)


def test_a_speed_whose_crossing_is_too_long_is_refused_before_any_work():
    """Exact problem: quick's crossing is 85 m lead-in + 32 m bridge + 19.875 m axle spread + 10 m run-out
    = 146.875 m, in steps of 1 ms, at most MAX_STEPS = 1e7 of them (execution/resources.py): the
    slowest speed is 146.875 m / (1e-3 s x 1e7) = 0.0146875 m/s = 0.052875 km/h. Reference: that
    arithmetic (the sweep keeps the base's lead-in below the base speed). check_sweep accepts 0.053 km/h
    (9.98e6 steps) and refuses 0.0528 km/h (1.0014e7 steps) naming speeds_kmh, the speed and the bound,
    before any folder (the speed's task refused it after checkpoint-sweep/ was written)."""
    from tb_exudyn.methods.sweep import check_sweep

    sc = load_scenario("quick")
    assert check_sweep(sc, [0.053, 200.0]) == (0.053, 200.0)
    with pytest.raises(SettingError, match=r"key 'speeds_kmh' = 0\.0528: at 0\.0528 km/h the crossing of 146\.9 m "
                                           r".*here from 0\.0529 km/h"):
        check_sweep(sc, [200.0, 0.0528])
