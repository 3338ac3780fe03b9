"""Speed sweeps (tb_exudyn.methods.sweep): a sweep's result at a speed is a separate run's; resume
per speed; the speed series, the per-speed scenario and the resonance speeds; the command."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tb_exudyn.errors import SettingError
from tb_exudyn.methods import run_pem
from tb_exudyn.methods.pem import default_slices
from tb_exudyn.methods.sweep import (EN1991_SPEED_FACTOR, SWEEP_SLICES, en1991_speeds, parse_speeds, resonance_speeds,
                                     run_sweep, speed_label, sweep_scenario)
from tb_exudyn.results import load_results

from .test_pem import sprung_mass_scenario

CHANNELS = ("bridge.*.mid.acc_z", "car*.body.acc_z")


def _base():
    """The sprung mass over the 25 m beam (tests/methods/test_pem.py), 6 frequencies, short approach."""
    return sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6, channels=("*",))


def test_speed_series_and_en1991_convention():
    """Exact problem: the speed series of the command. References: the definitions: START:STOP:STEP
    with STOP included; EN 1991-2 6.4.6.2, speeds up to 1.2 x the line speed (the last one exactly
    1.2 V). Exact (a grid of decimal numbers: compared to 1e-9 km/h)."""
    assert parse_speeds("160:350:10") == tuple(float(v) for v in range(160, 351, 10))
    assert len(parse_speeds("160:350:10")) == 20
    assert parse_speeds("160,220.5") == (160.0, 220.5)
    for bad in ("350:160:10", "160:350:0", "a:b:c", "", "-5,10"):
        with pytest.raises(SettingError, match="'speeds_kmh'"):  # the library's key (the CLI prints its flag)
            parse_speeds(bad)
    s = en1991_speeds(300.0, 10.0)
    assert s[0] == 150.0 and abs(s[-1] - EN1991_SPEED_FACTOR * 300.0) < 1e-9 and np.allclose(np.diff(s), 10.0)
    s = en1991_speeds(250.0, 20.0, start_kmh=200.0)
    assert s[:-1] == (200.0, 220.0, 240.0, 260.0, 280.0) and s[-1] == 300.0


def test_sweep_scenario_follows_the_speed():
    """Exact problem: the scenario of a sweep at 200, 450 and 1000 km/h from the base at 300 km/h (band
    2-20 Hz, 20 m approach, time step 1 ms). Reference: the speed rule (tb_exudyn.scenario.speed_rule):
    the band times r = v / 300 (at most 0.1 / time_step = 100 Hz: at 1000 km/h 6.67-66.7 Hz, not capped;
    the cap is checked on a 10 ms step below), the base's n_freq and spacing, lead_in = 20 m x max(1, r);
    at the base's own speed the base itself. Exact (the same arithmetic: equal floats)."""
    from tb_exudyn.scenario.speed_rule import at_speed, capped

    base = _base()
    assert at_speed(base, 300.0) is base
    for v in (200.0, 450.0, 1000.0):
        sc = sweep_scenario(base, v, CHANNELS)
        r = v / 300.0
        assert sc.speed_kmh == v and sc.analysis.channels == CHANNELS and sc.analysis.n_freq == 6
        assert sc.analysis.freq_min == 2.0 * r and sc.analysis.freq_max == 20.0 * r and not capped(base, sc)
        assert sc.track.lead_in == 20.0 * max(1.0, r)
        assert "Speed rule" in sc.notes and f"at {v:g} km/h from pem_test at 300 km/h" in sc.notes
    coarse = base.replace(analysis=base.analysis.replace(time_step=0.01, output_step=0.01, freq_max=10.0))
    sc = sweep_scenario(coarse, 450.0, CHANNELS)  # 2-10 Hz x 1.5 = 3-15 Hz, capped at 0.1 / 0.01 s = 10 Hz
    assert (sc.analysis.freq_min, sc.analysis.freq_max) == (3.0, 10.0) and capped(coarse, sc)
    assert sweep_scenario(base, 200.0, CHANNELS, n_freq=9).analysis.n_freq == 9
    assert sweep_scenario(base, 200.0, CHANNELS, freq_spacing="adaptive").analysis.freq_spacing == "adaptive"
    assert sweep_scenario(base, 200.0, CHANNELS).analysis.freq_spacing == base.analysis.freq_spacing
    with pytest.raises(SettingError, match="freq_spacing.*adaptive"):
        run_sweep(base, (200.0,), freq_spacing="uniform", workers=1, progress=False)


@pytest.mark.exudyn
def test_adaptive_sweep_takes_at_each_speed_the_least_count_its_grid_needs():
    """Problem: the sprung mass at 200 and 320 km/h with freq_spacing 'adaptive' and n_freq 6, far
    below what the adaptive rules need. Reference: run_pem itself: at each speed the count the sweep
    used (its result's scenario) is the smallest that run_pem accepts (one node fewer is the
    ScenarioError naming analysis.n_freq), and run_pem with that count gives the sweep's sigma
    bitwise (tolerance zero: the same tasks in the same order). The table carries that count and,
    per key quantity, the largest grid error of its channels as the result's provenance states it."""
    from tb_exudyn.errors import ScenarioError
    from tb_exudyn.methods.sweep import grid_errors

    base = _base()
    speeds = (200.0, 320.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sweep = run_sweep(base, speeds, workers=1, progress=False, channels=CHANNELS, freq_spacing="adaptive",
                          slices=default_slices(2))
        for v, row in zip(speeds, sweep.rows()):
            sc = sweep_scenario(base, v, CHANNELS, freq_spacing="adaptive")
            n = row["n_freq"]
            assert n > 6
            with pytest.raises(ScenarioError, match="analysis.n_freq"):
                run_pem(sc.replace(analysis=sc.analysis.replace(n_freq=n - 1)), engine="batched", workers=1,
                        progress=False, keep_psd=False)
            ref = run_pem(sc.replace(analysis=sc.analysis.replace(n_freq=n)), engine="batched", workers=1,
                          progress=False, keep_psd=False, slices=default_slices(2))
            assert ref.freq.size == n
            i = ref.channels.index("bridge.span1.mid.acc_z")
            assert row["deck_acc_z_max_sigma"] == ref.std[i].max()
            errors = grid_errors(ref)
            ge = ref.provenance["grid_error"]["channels"]["bridge.span1.mid.acc_z"]
            assert errors[i] == max(abs(ge["rel_error_max_sigma"]), ge["rel_deviation"])
            assert row["deck_acc_z_grid_error"] == errors[i]
            assert row["channels_grid_error_over_tolerance"] == int(np.sum(errors > 0.01))


@pytest.mark.exudyn
def test_sweep_equals_separate_runs_bitwise(tmp_path):
    """Problem: the sprung mass at 250 and 320 km/h, 6 frequencies each. Reference: separate
    run_pem calls on the sweep's scenarios (sweep_scenario) with the sweep's column slices
    (SWEEP_SLICES: one per speed). A speed is one task that runs the same PEM tasks in the same
    order, so the results must be bitwise equal (tolerance zero), for the sweep in this process and
    on 2 workers."""
    base = _base()
    speeds = (250.0, 320.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        one = run_sweep(base, speeds, workers=1, out=tmp_path / "a", progress=False, channels=CHANNELS)
        two = run_sweep(base, speeds, workers=2, out=tmp_path / "b", progress=False, channels=CHANNELS)
        for v in speeds:
            ref = run_pem(sweep_scenario(base, v, CHANNELS), engine="batched", workers=1, progress=False,
                          keep_psd=False, slices=SWEEP_SLICES)
            for folder in ("a", "b"):
                got = load_results(tmp_path / folder / speed_label(v) / "pem")
                for name in ("time", "mean", "std", "var_by_type"):
                    assert np.array_equal(getattr(got, name), getattr(ref, name)), (folder, v, name)
    for a, b in zip(one.summaries, two.summaries):
        for key in ("max_abs_mean", "max_sigma", "max_design"):
            assert np.array_equal(a[key], b[key])
    rows = one.rows()
    assert [r["speed_kmh"] for r in rows] == list(speeds)
    for r, v in zip(rows, speeds):
        ref = load_results(tmp_path / "a" / speed_label(v) / "pem")
        i = ref.channels.index("bridge.span1.mid.acc_z")
        assert r["deck_acc_z_max_sigma"] == ref.std[i].max()
        assert r["deck_acc_z_max_abs_mean_plus_3sigma"] == (np.abs(ref.mean[i]) + 3 * ref.std[i]).max()
    assert (tmp_path / "a" / "speed_sweep.csv").read_text().count("\n") == 3


@pytest.mark.exudyn
def test_sweep_resumes_per_speed(tmp_path):
    """Problem: a sweep of three speeds interrupted: one speed never finished (its summary and
    one of its PEM tasks deleted). Reference: the uninterrupted sweep. On resume the other two
    speeds come from the sweep's checkpoint, the third resumes within its own checkpoint (one PEM
    task run again), and every result is bitwise the uninterrupted one (tolerance zero)."""
    base = _base()
    speeds = (240.0, 280.0, 320.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_sweep(base, speeds, workers=1, out=tmp_path, progress=False, channels=CHANNELS, keep_checkpoint=True)
        (tmp_path / "checkpoint-sweep" / "tasks" / "speed-280.npz").unlink()
        tasks = sorted((tmp_path / "280" / "checkpoint" / "tasks").glob("pemb-*.npz"))
        tasks[0].unlink()
        (tmp_path / "280" / "pem" / "meta.json").unlink()
        again = run_sweep(base, speeds, workers=1, out=tmp_path, progress=False, channels=CHANNELS, resume=True)
    assert again.provenance["tasks_from_checkpoint"] == 2 and again.provenance["tasks_run"] == 1
    redone = load_results(tmp_path / "280" / "pem")
    assert redone.provenance["tasks_run"] == 1 and redone.provenance["tasks_from_checkpoint"] >= 2
    for a, b in zip(ref.summaries, again.summaries):
        for key in ("max_abs_mean", "max_sigma", "max_design"):
            assert np.array_equal(a[key], b[key])


@pytest.mark.exudyn
def test_sweep_overwrite_removes_the_old_figure_and_page(tmp_path):
    """A sweep's figure and page are drawn from its table: without --overwrite a folder holding an
    earlier sweep is refused and nothing changes; with it the old figure and page go (a new sweep
    through run_sweep writes neither: they would describe the old one) and the new table is written."""
    from tb_exudyn.errors import OutputFolderError

    base = _base()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_sweep(base, (250.0,), workers=1, out=tmp_path, progress=False, channels=CHANNELS)
        for name in ("speed_sweep.png", "speed_sweep.html"):
            (tmp_path / name).write_text("old")
        with pytest.raises(OutputFolderError, match="overwrite"):
            run_sweep(base, (300.0,), workers=1, out=tmp_path, progress=False, channels=CHANNELS)
        assert (tmp_path / "speed_sweep.html").read_text() == "old"
        run_sweep(base, (300.0,), workers=1, out=tmp_path, progress=False, channels=CHANNELS, overwrite=True)
    assert not (tmp_path / "speed_sweep.png").exists() and not (tmp_path / "speed_sweep.html").exists()
    assert "300" in (tmp_path / "speed_sweep.csv").read_text().splitlines()[1]


def test_resonance_speeds_of_a_simple_span():
    """Exact problem: the resonance speeds of the sprung mass's 25 m simply supported beam. Reference:
    v = f1 d / i with the closed-form first bending frequency of the scenario's beam,
    f1 = (pi / (2 L^2)) sqrt(EI / m), and d the vehicle's length; tolerance 1e-3 relative (the
    finite-element f1 of the beam against the closed form)."""
    base = _base()
    beam = base.bridge
    L, EI, m = beam.spans[0], beam.girder.E * beam.girder.I_y, beam.girder.mass_per_length
    f1 = math.pi / (2 * L**2) * math.sqrt(EI / m)
    res = [r for r in resonance_speeds(base) if r.direction == "vertical" and r.distance_name == "car length"]
    assert [r.order for r in res] == [1, 2, 3]
    for r in res:
        assert abs(r.frequency - f1) < 1e-3 * f1
        assert abs(r.speed_kmh - r.frequency * r.distance / r.order * 3.6) < 1e-9 * r.speed_kmh


@pytest.mark.exudyn
def test_sweep_command(tmp_path, capsys):
    """The command on two speeds writes the table, the figure and each speed's result; a malformed
    speed series is a one-line error (exit 2)."""
    from tb_exudyn.cli import main
    from tb_exudyn.scenario import save_scenario

    path = tmp_path / "sc.toml"
    save_scenario(_base(), path)
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--speeds-kmh", "250:300:50", "--out", str(out), "--workers", "1",
                 "--no-progress", "--channels", *CHANNELS]) == 0
    for name in ("speed_sweep.csv", "speed_sweep.png", "speed_sweep.html", "250/pem/meta.json", "300/pem/meta.json"):
        assert (out / name).exists(), name
    page = (out / "speed_sweep.html").read_text()
    assert "<h2>Frequency grid by speed</h2>" in page and "data:image/png;base64," in page
    assert main(["sweep", str(path), "--speeds-kmh", "300:250:10", "--out", str(out)]) == 2
    assert "speeds-kmh" in capsys.readouterr().err


@pytest.mark.exudyn
def test_a_sweeps_row_is_the_run_at_that_speed(tmp_path, capsys, monkeypatch):
    """Problem: quick (its own speed 250 km/h) swept at 200 and 300 km/h with 8 linear frequencies and
    the default key quantities (`tb-exudyn sweep`), and `tb-exudyn run quick --speed-kmh V --n-freq 8
    --freq-spacing linear --channels <the sweep's patterns>` at each speed. Reference: the run. Both
    scenarios come from the one speed rule (speed_rule.at_speed), so the band, the approach and the
    grid are equal exactly, and each channel's PEM is the same computation up to the order in which
    the column slices are summed (other task sizes): every number of the sweep's row (each key
    quantity's max |mean|, max sigma and max |mean| + 3 sigma; each criterion's estimate) within 1e-9
    of the run's, relative (round-off of a few sums is about 1e-15), each criterion's verdict equal.
    The deck criterion is among them by default (its channels bridge.*.acc_z_en1990 are a key
    quantity), and the terminal's table gives forces in kN with the units in its header, its warnings
    once per kind with the speeds, every line at most 100 characters."""
    import fnmatch

    from tb_exudyn import cli
    from tb_exudyn.methods.sweep import KEY_QUANTITIES

    monkeypatch.setattr(cli, "_SHOWN", set())
    grid = ["--n-freq", "8", "--freq-spacing", "linear", "--workers", "1", "--no-progress", "--no-figures"]
    assert cli.main(["sweep", "quick", "--speeds-kmh", "200,300", "--out", str(tmp_path / "sw"), *grid]) == 0
    terminal = capsys.readouterr()
    lines = (terminal.out + terminal.err).splitlines()
    assert max(len(line) for line in lines if str(tmp_path) not in line) <= 100  # (a path is as long as it is)
    kinds = [line for line in terminal.err.splitlines() if line.startswith("tb-exudyn: warning:")]
    assert kinds and all("at every speed (200-300 km/h)" in k for k in kinds) and len(kinds) == len(set(kinds))
    assert any("[kN]" in line for line in lines) and any(line.strip().startswith("speed") for line in lines)
    assert any(line.strip().startswith("en1990_deck/deck_acc_ballasted: OK") for line in lines)
    rows = {r["speed_kmh"]: r for r in _csv_rows(tmp_path / "sw" / "speed_sweep.csv")}
    page = (tmp_path / "sw" / "speed_sweep.html").read_text()
    assert "follows the speed rule" in page and "approach [m]" in page and '<td class="num">102</td>' in page
    assert float(rows[300.0]["lead_in_m"]) == 102.0 and float(rows[200.0]["lead_in_m"]) == 85.0
    patterns = [q[1] for q in KEY_QUANTITIES]
    for v in (200.0, 300.0):
        out = tmp_path / f"run{v:g}"
        assert cli.main(["run", "quick", "--speed-kmh", f"{v:g}", "--out", str(out), "--channels", *patterns,
                         *grid]) == 0
        capsys.readouterr()
        run = load_results(out / "pem")
        swept = load_results(tmp_path / "sw" / speed_label(v) / "pem")
        a, b = run.scenario.analysis, swept.scenario.analysis
        assert (a.freq_min, a.freq_max, a.n_freq, a.freq_spacing) == (b.freq_min, b.freq_max, b.n_freq, b.freq_spacing)
        assert run.scenario.track.lead_in == swept.scenario.track.lead_in == 85.0 * max(1.0, v / 250.0)
        row = rows[v]
        for key, pattern, _ in KEY_QUANTITIES:
            idx = [i for i, c in enumerate(run.channels) if fnmatch.fnmatchcase(c, pattern)]
            assert idx, pattern
            expect = {"max_abs_mean": np.abs(run.mean[idx]).max(), "max_sigma": run.std[idx].max(),
                      "max_abs_mean_plus_3sigma": (np.abs(run.mean[idx]) + 3 * run.std[idx]).max()}
            for name, value in expect.items():
                assert abs(float(row[f"{key}_{name}"]) - value) <= 1e-9 * abs(value), (v, key, name)
        worst = {r.criterion: r for r in run.checks().worst()}
        assert "en1990_deck/deck_acc_ballasted" in worst
        for c, r in worst.items():
            assert row[f"{c}_verdict"] == r.verdict, (v, c)
            if math.isfinite(r.estimate):
                assert abs(float(row[f"{c}_estimate"]) - r.estimate) <= 1e-9 * abs(r.estimate), (v, c)
        assert fnmatch.fnmatchcase(row["en1990_deck/deck_acc_ballasted_channel"], "bridge.*.acc_z_en1990")


def _csv_rows(path):
    import csv

    with open(path, newline="") as f:
        return [{k: (float(x) if k == "speed_kmh" else x) for k, x in r.items()} for r in csv.DictReader(f)]


@pytest.mark.exudyn
def test_a_requested_channel_is_never_dropped():
    """Problem: quick's sweep with the key quantities given as patterns. Reference: quick's model, whose
    derived channels include bridge.span1.{q1,mid,q3}.acc_z_en1990 and which has no 'acc_z_en1991'. A
    derived pattern is kept as its own quantity (it was dropped: only the plain channels were looked
    at), a pattern that matches nothing is refused naming it, never left out; default quantities the
    model lacks are left out and listed (the sprung mass has no car body lateral channel)."""
    from tb_exudyn.methods.sweep import check_sweep, key_patterns, model_channel_names
    from tb_exudyn.scenario import load_scenario

    quick = load_scenario("quick")
    assert "bridge.span1.mid.acc_z_en1990" in model_channel_names(quick)
    kept = key_patterns(quick, ["bridge.*.acc_z_en1990", "car*.body.acc_z"])
    assert [q[0] for q in kept] == ["deck_acc_z_en1990", "body_acc_z"]
    with pytest.raises(SettingError, match=r"channels.*'bridge\.\*\.acc_z_en1991' matches no channel"):
        key_patterns(quick, ["bridge.*.acc_z_en1990", "bridge.*.acc_z_en1991"])
    with pytest.raises(SettingError, match="matches no channel"):
        check_sweep(quick, [250.0], channels=["bridge.*.acc_z_en1991"])
    names = model_channel_names(_base())
    default = [q[1] for q in key_patterns(_base(), names=names)]
    assert "bridge.*.acc_z_en1990" in default and "car*.body.acc_y" not in default


def test_warnings_are_grouped_by_kind_with_their_speeds():
    """Exact problem: a hand-made sweep at 160, 170, 180 and 250 km/h whose speeds raised a lightly
    damped mode warning each (its percentage varying with the speed), a grid-error warning at 160-180
    km/h and two notes on different scenario keys at 250 km/h. Reference: the grouping's definition
    (sweep.grouped_warnings): one warning per kind (the class; a note per scenario key) in the order
    first raised, with the speeds as runs of the sweep's neighbours, the first message, and the count
    of distinct messages of that kind; compared as exact strings."""
    from tb_exudyn.methods.common import LightlyDampedModeWarning
    from tb_exudyn.results.sweep import SweepResult, grouped_warnings, speeds_text

    speeds = (160.0, 170.0, 180.0, 250.0)
    assert speeds_text((160.0, 170.0, 180.0, 250.0), speeds) == "every speed (160-250 km/h)"
    assert speeds_text((160.0, 170.0, 250.0), speeds) == "160-170, 250 km/h"
    light = "tb_exudyn.methods.common:LightlyDampedModeWarning"
    grid = "tb_exudyn.methods.pem:GridErrorWarning"
    note = "builtins:UserWarning"

    def summary(v, items):
        return {"warnings": np.array([f"{m} (at {v:g} km/h)" for m, _ in items], dtype=str),
                "warning_kinds": np.array([k for _, k in items], dtype=str)}

    summaries = tuple(summary(v, [(f"mode at 8.3 Hz grows by {20 + i} %", light)]
                                 + ([("grid too coarse", grid)] if v < 200 else [])
                                 + ([("track.lead_in = 85 m: short", note), ("track.taper_length = 90 m: long", note)]
                                    if v == 250 else []))
                      for i, v in enumerate(speeds))
    sweep = SweepResult(base=_base(), speeds=speeds, summaries=summaries, quantities=(), resonances=())
    got = grouped_warnings(sweep)
    assert [(c.__name__, m) for c, m in got] == [
        (LightlyDampedModeWarning.__name__,
         "lightly damped mode at every speed (160-250 km/h), 4 messages: mode at 8.3 Hz grows by 20 %"),
        ("GridErrorWarning", "grid error at 160-180 km/h: grid too coarse"),
        ("UserWarning", "note at 250 km/h: track.lead_in = 85 m: short"),
        ("UserWarning", "note at 250 km/h: track.taper_length = 90 m: long")]
    assert got[0][0] is LightlyDampedModeWarning


@pytest.mark.exudyn
def test_an_adaptive_run_at_a_speed_gets_the_sweeps_grid(tmp_path, capsys):
    """Problem: quick (adaptive grid) at 350 km/h with --n-freq 20, far below what its adaptive rules
    need there, by `tb-exudyn run --speed-kmh 350` and by a one-speed sweep. Reference: the sweep's
    speed result. The run raises the count as the sweep does (sweep.with_least_count, the same
    analysis_setup(least_count=True)), so both grids have the same nodes, exactly, and the deck's
    mid-span sigma agrees to 1e-9 relative (the column slices' sums in another order)."""
    from tb_exudyn import cli

    common = ["--n-freq", "20", "--freq-spacing", "adaptive", "--workers", "1", "--no-progress", "--no-figures"]
    assert cli.main(["sweep", "quick", "--speeds-kmh", "350", "--out", str(tmp_path / "sw"), "--channels",
                     "bridge.*.mid.acc_z", *common]) == 0
    assert cli.main(["run", "quick", "--speed-kmh", "350", "--out", str(tmp_path / "run"), "--channels",
                     "bridge.*.mid.acc_z", *common]) == 0
    out = capsys.readouterr().out
    assert "speed rule: at 350 km/h from quick at 250 km/h" in out
    swept, run = load_results(tmp_path / "sw" / "350" / "pem"), load_results(tmp_path / "run" / "pem")
    assert swept.freq.size > 20 and np.array_equal(swept.freq, run.freq)
    i, j = swept.channels.index("bridge.span1.mid.acc_z"), run.channels.index("bridge.span1.mid.acc_z")
    assert np.max(np.abs(swept.std[i] - run.std[j])) <= 1e-9 * swept.std[i].max()
