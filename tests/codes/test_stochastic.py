"""The stochastic column of the EN 1991-2 check (tb_exudyn.codes.stochastic, issue 25 item 4).

The problem of every test: one ICE motor car (models/vehicles/ice_motor, a one-car train file written
here) and HSLM-A1 over single_span_32m (nominal mass case only) at a line speed of 250 km/h; the stochastic
rows at one speed, 250 km/h (not in the code's series: added to it), with the track and analysis of the
`quick` scenario (german_low vertical, alignment, cross-level; 120 adaptive frequencies; about 3 s per PEM
run). The references: the same scenario run by ``run_pem`` with the check's engine options (its columns in
float32, stochastic.PRECISION: the same code path, so the numbers agree to round-off: 1e-9) and by ``tb-exudyn
run`` (float64: within float32's error, FLOAT32), the first-passage probability at the level the check reports
(the root finder's definition), the Annex C formula, and the check's own inputs.
"""

from __future__ import annotations

import math

import pytest

from tb_exudyn.cli import main
from tb_exudyn.codes import check
from tb_exudyn.codes import stochastic as stoch
from tb_exudyn.methods import run_pem
from tb_exudyn.results import load_random_response
from tb_exudyn.scenario import load_scenario, scenario_to_toml

SPEED = 250.0
TRAIN = "one_ice_motor"
CRITERION = "en1990_deck/deck_acc_ballasted"
#: the row equals the same scenario's PEM by construction; the slicing of the frequency columns may
#: differ between run_sweep and run_pem, which changes sums at round-off only (methods/pem.py)
SAME_PATH = 1e-9
#: the check's float32 columns against float64 (``tb-exudyn run``): the engine states sigma within 1e-5 of a
#: channel's largest sigma (docs/speed.md section 1), and the level at the target probability scales with sigma
#: (the mean is float64 in both): 1e-5 relative. The probability at the limit moves by ((b - mean) / sigma)^2
#: times sigma's relative error (Rice's rate, exp(-(b - mean)^2 / 2 sigma^2)); b / sigma is 14 here: 200 x 1e-5
#: (measured: the level 1.3e-8 and the probability 2.0e-6 apart)
FLOAT32 = 1e-5
FLOAT32_P = 200 * FLOAT32


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    folder = tmp_path_factory.mktemp("train")
    path = folder / "one_car.toml"
    path.write_text(f'name = "{TRAIN}"\ndescription = "one ICE motor car"\n[[cars]]\nvehicle = "ice_motor"\n')
    with pytest.warns(UserWarning, match="lightly damped mode"):  # the PEM runs' warnings, carried
        return check("single_span_32m", 250.0, trains=[str(path), "HSLM-A1"], cases=["nominal"], stochastic=True,
                     stochastic_speeds=[SPEED], stochastic_scenario="quick", workers=1)


@pytest.fixture(scope="module")
def row(result):
    rows = result.stochastic_rows()
    assert len(rows) == 1
    return rows[0]


@pytest.fixture(scope="module")
def pem(result):
    with pytest.warns(UserWarning, match="lightly damped mode"):
        return run_pem(result.stochastic_scenario(TRAIN, SPEED), workers=1, progress=False, keep_psd=False,
                       options=stoch.engine_options("batched"))


def _worst(table):
    return next(r for r in table.worst() if r.criterion == CRITERION)


def test_only_the_vehicle_train_at_the_chosen_speed_has_stochastic_columns(result, row):
    """HSLM-A1 is moving forces and the other speeds were not chosen: their stochastic columns are None
    (empty in the CSV); the chosen 250 km/h was added to the series of the vehicle train only."""
    assert row["train"] == TRAIN and row["speed_kmh"] == SPEED and row["case"] == "nominal"
    others = [r for r in result.rows if r is not row]
    assert others and all(r[c] is None for r in others for c in stoch.COLUMNS)
    assert SPEED in [r["speed_kmh"] for r in result.rows if r["train"] == TRAIN]
    assert SPEED not in [r["speed_kmh"] for r in result.rows if r["train"] == "HSLM-A1"]
    csv_row = [line for line in result.csv_text().splitlines() if line.startswith("HSLM-A1,")][0]
    assert csv_row.endswith("," * len(stoch.COLUMNS))  # the stochastic columns, empty


def test_the_row_equals_run_pem_of_its_scenario(row, pem):
    """p_exceed, level_at_target, the location and the mean there equal ``run_pem`` of the row's
    scenario with the check's engine options and its checks (the verdicts' machinery) to SAME_PATH."""
    ref = _worst(pem.checks())
    assert row["stochastic_location"] == ref.channel
    assert row["p_exceed"] == pytest.approx(ref.probability, rel=SAME_PATH, abs=0.0)
    assert row["level_at_target"] == pytest.approx(ref.estimate, rel=SAME_PATH, abs=0.0)
    assert row["stochastic_verdict"] == ref.verdict
    i = pem.index(ref.channel)
    assert row["stochastic_mean_acc"] == pytest.approx(float(abs(pem.mean[i]).max()), rel=SAME_PATH, abs=0.0)
    assert math.isfinite(row["level_at_target"]) and row["level_at_target"] > 0.0


def test_the_row_equals_tb_exudyn_run_of_its_scenario_file(result, row, tmp_path, capsys):
    """The row's scenario written as TOML and run by ``tb-exudyn run`` (PEM, batched engine, float64) gives the
    same location, the level within FLOAT32 and the probability within FLOAT32_P (the check's columns are
    float32): the file round-trips the scenario."""
    path = tmp_path / "row.toml"
    path.write_text(scenario_to_toml(result.stochastic_scenario(TRAIN, SPEED)))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-figures", "--no-progress", "--workers", "1"]) == 0
    assert "warning: lightly damped mode at 5.12 Hz" in capsys.readouterr().err  # the same warnings as the row's
    ref = _worst(load_random_response(out / "pem").checks())
    assert row["stochastic_location"] == ref.channel
    assert row["p_exceed"] == pytest.approx(ref.probability, rel=FLOAT32_P, abs=0.0)
    assert row["level_at_target"] == pytest.approx(ref.estimate, rel=FLOAT32, abs=0.0)
    assert row["p_exceed"] != ref.probability  # float32 columns indeed (a check in float64 would be equal)


def test_p_exceed_at_level_at_target_is_the_target(result, row, pem):
    """At its location the probability of leaving [-level_at_target, level_at_target] in the passage is
    the target probability (2.74e-5): Brent's root to 1e-12 of the response's scale moves P by about
    (b / sigma)^2 x 1e-12 relative (b / sigma of order 10 here), so 1e-8. And p_exceed is the probability
    at the limit: below the target exactly when the limit lies above the level."""
    target = result.target_probability
    assert target == pytest.approx(2.74e-5, rel=1e-12)
    level = row["level_at_target"]
    p = pem.exceedance_probability(row["stochastic_location"], upper=level, lower=-level).probability
    assert p == pytest.approx(target, rel=1e-8)
    limit = row["limit"]
    p_limit = pem.exceedance_probability(row["stochastic_location"], upper=limit, lower=-limit).probability
    assert row["p_exceed"] == pytest.approx(p_limit, rel=SAME_PATH)
    assert (row["p_exceed"] < target) == (limit > level)


def test_the_deterministic_value_with_phi2_is_annex_c(result):
    """max_deck_acc_z_with_phi2 = max_deck_acc_z x (1 + phi''/2) (careful maintenance, Annex C) on every
    row, from the row's own columns (exact up to one rounding)."""
    for r in result.rows:
        assert r["max_deck_acc_z_with_phi2"] == pytest.approx(r["max_deck_acc_z"] * (1.0 + 0.5 * r["phi_irregularity"]),
                                                               rel=1e-15)


def test_the_scenario_is_the_checks_bridge_the_trains_vehicles_and_the_named_track(result):
    """The scenario: the check's bridge (64 elements per span, nominal case) at the check's damping
    (Table 6.6: 1 % for a 32 m prestressed girder), the train's vehicles, quick's track, its analysis
    with the modes up to MODE_MARGIN x the cut-off (quick's 60 Hz is above 1.05 x 46.1 Hz: kept)."""
    base = result.stochastic_scenarios[TRAIN]
    quick = load_scenario("quick")
    assert base.bridge.damping_ratio == result.damping_ratio == 0.01
    assert base.bridge.elements_per_span == 64 and base.bridge.name == "single_span_32m"
    assert [v.name for v in base.train.vehicles] == ["ice_motor"]
    assert base.track == quick.track
    assert base.analysis.mode_max_frequency == max(quick.analysis.mode_max_frequency, 1.05 * result.cutoff_hz)
    sc = result.stochastic_scenario(TRAIN, SPEED)
    assert sc.speed_kmh == SPEED and sc.analysis.channels == stoch.CHANNELS
    assert "HSLM-A1" not in result.stochastic_scenarios


def test_a_speed_not_sampled_estimates_its_grid_error_only_where_it_could_turn_the_row(result, row, pem, monkeypatch,
                                                                                     tmp_path):
    """The check estimates the grid error at every GRID_ERROR_EVERY-th speed; another speed runs its PEM without
    the estimate and again with it when a grid error of GRID_ERROR_TURN could turn its row. Here the row's margin
    (limit 3.5 m/s^2 against a level of about 0.9) is far above 25 %: the speed as a non-sampled task gives the
    same row to the bit (sigma and mean do not depend on the estimate, which only adds a caveat) and no grid error
    (NaN). With GRID_ERROR_TURN raised to 1e9 every row could turn: the worker runs the speed again with the
    estimate, whose grid error equals run_pem's (same path: SAME_PATH) and whose sigma is the first run's bitwise."""
    import dataclasses
    import numpy as np
    from tb_exudyn.codes.check_plan import plan_check
    from tb_exudyn.execution import Task
    from tb_exudyn.methods import check as method
    from tb_exudyn.methods import sweep

    path = tmp_path / "one_car.toml"
    path.write_text(f'name = "{TRAIN}"\ndescription = "one ICE motor car"\n[[cars]]\nvehicle = "ice_motor"\n')
    setup = plan_check("single_span_32m", 250.0, trains=[str(path)], cases=["nominal"], stochastic=True,
                       stochastic_speeds=[SPEED], stochastic_scenario="quick")
    (task,), _, _ = method._stochastic_tasks(setup)
    assert task.data.speed.grid_error is None  # the only speed is sampled (the first and the last)
    task = Task(task.key, dataclasses.replace(task.data, speed=dataclasses.replace(task.data.speed, grid_error=False)))
    runs = []
    real = sweep.SpeedWorker.work
    monkeypatch.setattr(sweep.SpeedWorker, "work", lambda self, m, t: runs.append(real(self, m, t)) or runs[-1])
    plain = method.CheckWorker().work(None, task)
    assert len(runs) == 1 and np.isnan(plain["grid_error"]).all()
    one = stoch.stochastic_run(result.stochastic_scenarios[TRAIN], [(SPEED, plain)], "ballasted", TRAIN).values
    (values,) = one.values()
    assert (values.p_exceed, values.level_at_target, values.location) == (
        row["p_exceed"], row["level_at_target"], row["stochastic_location"])

    monkeypatch.setattr(stoch, "GRID_ERROR_TURN", 1e9)
    full = method.CheckWorker().work(None, task)
    assert len(runs) == 3 and np.array_equal(runs[1]["max_sigma"], full["max_sigma"])
    assert np.array_equal(plain["max_sigma"], full["max_sigma"]) and np.array_equal(plain["max_abs_mean"], full["max_abs_mean"])
    names = [str(c) for c in full["channels"]]
    i = names.index(row["stochastic_location"])
    assert full["grid_error"][i] == pytest.approx(sweep.grid_errors(pem)[pem.index(row["stochastic_location"])],
                                                  rel=SAME_PATH, abs=1e-12)


def test_the_pem_warnings_are_in_the_result(result, pem):
    """The damping guard's warning on the bridge's first mode (1 % damping: decay time 3.1 s, longer than
    the 2.1 s run) is in the result's warnings, naming the speed."""
    assert any("lightly damped mode at 5.12 Hz" in w and f"(at {SPEED:g} km/h)" in w for w in result.warnings)
    assert any("lightly damped mode at 5.12 Hz" in w for w in pem.provenance["warnings"])
    assert "stochastic rows" in result.summary()


# ------------------------------------------------------------------------------------ the page
def test_the_page_opens_with_the_verdict_and_holds_the_figure_and_the_folded_table(result, row):
    """tb_exudyn.report.check: after the title, the navigation and the criteria's verdicts comes the verdict, naming the
    deciding train, speed, case, location and margin of the row with the largest peak deck acceleration
    (CheckResult.deciding_row, the reference); the figure is embedded (no external resource); the whole
    table is inside <details>; the stochastic row's numbers are shown as the table's (3 decimals)."""
    from tb_exudyn.codes import CHECK_PAGE
    from tb_exudyn.report import CHECK_REPORT, render_check_report

    assert CHECK_REPORT == CHECK_PAGE == "check.html"
    page = render_check_report(result, b"\x89PNG fake bytes")
    sections = page.split("<section ")
    # issue 48: the page opens with one verdict per criterion, the deck acceleration's first; then its details
    assert sections[1].startswith('id="criteria"') and "deck_acceleration" in sections[1]
    assert sections[2].startswith('id="verdict"')
    top = result.deciding_row()
    margin = result.limit - top["max_deck_acc_z"]
    for text in (top["train"], f"{top['speed_kmh']:g} km/h", top["case"], top["max_deck_acc_z_location"],
                 f"{margin:+.3f} m/s^2", "met"):
        assert text in sections[2], text
    assert 'src="data:image/png;base64,' in page and "http" not in page.replace("https://", "").split("<body>")[0]
    assert not any(f'{attr}="http' in page for attr in ("src", "href"))
    table = page.split('<section id="table">')[1]
    assert table.index("<details>") < table.index('<table id="check-table">') < table.index("</details>")
    stochastic = page.split('<section id="stochastic">')[1].split("</section>")[0]
    for value in (row["level_at_target"], row["max_deck_acc_z_with_phi2"], row["stochastic_mean_acc"]):
        assert f"{value:.3f}" in stochastic
    assert "lightly damped mode at 5.12 Hz" in stochastic  # the PEM runs' warnings


def test_tb_exudyn_check_writes_the_page_beside_the_table(tmp_path, capsys):
    """`tb-exudyn check` writes DIR/check.html with check.csv (HSLM-A1, figures off: the page says the
    figure was not drawn and has no stochastic rows), and refuses to replace it without --overwrite."""
    out = tmp_path / "chk"
    argv = ["check", "single_span_32m", "--line-speed-kmh", "250", "--trains", "HSLM-A1", "--out", str(out),
            "--no-figures"]
    assert main(argv) == 0
    assert "check.html" in capsys.readouterr().out
    page = (out / "check.html").read_text()
    assert "Not drawn (--no-figures)" in page and "Not computed (tb-exudyn check --stochastic" in page
    assert sorted(p.name for p in out.iterdir()) == ["check.csv", "check.html"]
    assert main(argv) == 2 and "--overwrite" in capsys.readouterr().err


def test_speeds_sharing_a_task_label_run_in_separate_sweeps(monkeypatch):
    """run_sweep names its tasks by speed_label (6 significant digits) and refuses two equal names: 250 and
    250.0001 km/h (distinct rows of the check) must go to separate sweeps, each speed's values kept.
    The sweep is replaced by a recorder that refuses repeated labels as run_sweep does (the numbers are
    not the point here: the batching is)."""
    import types

    import numpy as np

    from tb_exudyn.methods import sweep as real
    from tb_exudyn.results.sweep import CriterionValues, checks_text

    calls = []

    def run_sweep(base, speeds, **_):
        labels = [real.speed_label(v) for v in speeds]
        assert len(set(labels)) == len(labels), labels
        calls.append(list(speeds))
        crit = "en1990_deck/deck_acc_ballasted"
        summaries = [{"checks": np.array(checks_text({crit: CriterionValues(
                          math.nan, v * 1e-9, v / 100, 3.5, "m/s^2", "bridge.span1.mid.acc_z_en1990", "OK")})),
                      "channels": np.array(["bridge.span1.mid.acc_z_en1990"]), "max_abs_mean": np.array([1.0]),
                      "n_freq": np.array(7), "warnings": np.array([], dtype=str)} for v in speeds]
        return types.SimpleNamespace(speeds=tuple(speeds), summaries=tuple(summaries))

    monkeypatch.setattr(stoch, "_sweep", lambda: types.SimpleNamespace(speed_label=real.speed_label,
                                                                      run_sweep=run_sweep))
    run = stoch.run_stochastic(load_scenario("quick"), [250.0, 250.0001, 260.0], "ballasted")
    assert calls == [[250.0, 260.0], [250.0001]]
    assert {k: v.level_at_target for k, v in run.values.items()} == {250.0: 2.5, 250.0001: 2.500001, 260.0: 2.6}


def test_the_column_states_its_grid_error_estimates_and_warns_when_they_come_near_the_turn():
    """stochastic_run on three speeds' summaries (made here: the deck criterion at its channel, a grid error on
    two, NaN on the third, which ran without the estimate): the column states the largest estimate and where
    (2 of 3 speeds); at 0.2 of sigma (>= GRID_ERROR_TURN / 2 = 0.125) it warns that the speed without an
    estimate may miss a caveat, at 0.01 it does not; with every speed estimated no warning whatever the value
    (each row carries its own caveat then)."""
    import numpy as np

    from tb_exudyn.results.sweep import CriterionValues, checks_text

    channel = "bridge.span1.mid.acc_z_en1990"

    def summary(v, ge):
        crit = {"en1990_deck/deck_acc_ballasted": CriterionValues(math.nan, 1e-9, 1.0, 3.5, "m/s^2", channel, "OK")}
        return {"checks": np.array(checks_text(crit)), "channels": np.array([channel]), "max_abs_mean": np.array([0.1]),
                "n_freq": np.array(7), "warnings": np.array([], dtype=str), "grid_error": np.array([ge]),
                "seconds": np.array(1.0)}

    base = load_scenario("quick")
    run = stoch.stochastic_run(base, [(250.0, summary(250.0, 0.01)), (260.0, summary(260.0, math.nan)),
                                      (270.0, summary(270.0, 0.2))], "ballasted")
    assert run.grid_error == "grid error of the deciding channel estimated at 2 of 3 speeds: at most 20 % (at 270 km/h)"
    assert any("reaches 20 % at 270 km/h" in w and "25 %" in w for w in run.warnings)
    quiet = stoch.stochastic_run(base, [(250.0, summary(250.0, 0.01)), (260.0, summary(260.0, math.nan))], "ballasted")
    assert quiet.grid_error.endswith("at most 1 % (at 250 km/h)") and not quiet.warnings
    every = stoch.stochastic_run(base, [(250.0, summary(250.0, 0.3))], "ballasted")
    assert "1 of 1 speeds" in every.grid_error and not every.warnings
