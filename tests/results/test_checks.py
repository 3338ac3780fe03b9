"""The checks table (tb_exudyn.results.checks) and the exceedance API of RandomResponse.

Problem of most tests: the reference study's Monte Carlo check shortened (one ICE motor car over one
32 m span at 220 km/h, 50 m approach, German low vertical, alignment and cross-level, 40 frequencies
0.5-25 Hz, batched PEM): its bogie yaw modes have no yaw damper (damping ratio 1e-4), which the
damping guard reports for every car1 channel.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
import warnings

import numpy as np
import pytest

import tb_exudyn as tbx
from tb_exudyn.errors import ResultsError, ScenarioError, SettingError
from tb_exudyn.methods import run_pem
from tb_exudyn.results import load_random_response
from tb_exudyn.results.checks import DEFAULT_TARGET_PROBABILITY, checks, grid_error_of, static_axle_load, verdict_lines
from tb_exudyn.scenario import model_files

pytestmark = pytest.mark.exudyn


@pytest.fixture(scope="module")
def lateral():
    sc = tbx.load_scenario("li_zhu_2011_mc_check")
    sc = sc.replace(track=sc.track.replace(lead_in=50.0, run_out=20.0),
                    analysis=sc.analysis.replace(n_freq=40, freq_min=0.5, freq_max=25.0,
                                                 channels=("bridge.span1.mid.*", "car1.body.*", "car1.axle1.*")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_pem(sc, workers=1, progress=False, engine="batched")


@pytest.fixture(scope="module")
def creep():
    """The same problem with the ICE motor creep car (wheelsets guided by creep forces)."""
    sc = tbx.load_scenario("li_zhu_2011_mc_check")
    sc = sc.replace(train=sc.train.replace(vehicles=(tbx.load_vehicle("ice_motor_creep"),)),
                    track=sc.track.replace(lead_in=50.0, run_out=20.0),
                    analysis=sc.analysis.replace(n_freq=40, freq_min=0.5, freq_max=25.0,
                                                 channels=("bridge.span1.mid.*", "car1.body.*", "car1.axle1.*")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_pem(sc, workers=1, progress=False, engine="batched")


RUNNING_SAFETY = ("running_safety/derailment", "running_safety/unloading", "running_safety/lateral_force")


def test_running_safety_is_not_evaluated_where_the_wheelsets_follow_the_rail(lateral, creep):
    """Exact problem: the fixture's car15 (wheelsets follow the rail; bogie yaw damping ratio 1e-4)
    and the same run with the creep car. Reference: the model requirement of the checks (running
    safety needs creep-guided wheelsets): every running-safety row of car15 is NOT EVALUATED, its
    first caveat saying why and naming the creep cars' scenario, no probability, not conditional;
    on the creep car the same criteria are evaluated (OK or EXCEEDS, a probability, no such caveat).
    Exact (verdicts and texts)."""
    table = lateral.checks()
    rows = [r for r in table.rows if r.criterion.startswith(RUNNING_SAFETY)]
    assert rows and {r.criterion.split("/")[1].split("_")[0] for r in rows} >= {"derailment", "unloading", "lateral"}
    for r in rows:
        assert r.verdict == "NOT EVALUATED" and not r.conditional and r.probability is None, r
        assert r.caveats[0].kind == "model" and "creep" in r.caveats[0].text and "li_zhu_2011_creep" in r.caveats[0].text
    lines = verdict_lines(lateral)
    assert lines[0].startswith("code checks (pem, target P <= 2.74e-05")
    # the criteria not evaluated: one heading line, wrapped at 100 characters under it (17 spaces)
    start = next(i for i, ln in enumerate(lines) if ln.startswith("  NOT EVALUATED  "))
    block = [lines[start]] + [ln for ln in lines[start + 1:] if ln.startswith(" " * 17)][:10]
    assert any("lateral_force_prudhomme" in ln for ln in block) and max(map(len, lines)) <= 105
    rows = [r for r in creep.checks().rows if r.criterion.startswith(RUNNING_SAFETY)]
    assert rows
    for r in rows:
        assert not any(c.kind == "model" for c in r.caveats)
        if r.statistic == "sliding_mean_max_abs":  # EN 14363's sliding mean: no such channel yet, on any model
            assert r.verdict == "NOT EVALUATED" and r.caveats[-1].kind == "statistic"
        else:
            assert r.verdict in ("OK", "EXCEEDS") and r.probability is not None, r


def test_a_caveat_is_a_condition_only_where_its_own_numbers_can_turn_the_verdict(lateral):
    """Exact problem: the fixture's rows with the damping guard's caveat (the bogie yaw mode, whose
    sigma grows by about 65 % on the bridge). Reference: the rule written here, |estimate| x effect
    >= |limit - estimate| with effect the mode's growth (a Sperling index: (1 + growth)^0.3 - 1, the
    index's 0.3 power of the acceleration). A row is conditional exactly when that holds, and the
    caveat's text gives both percentages. No deck row carries the caveat (its patterns are car1.*)."""
    table = lateral.checks()
    growth = {f"{w['frequency']:.4g}": w["growth_on_bridge"] for w in lateral.provenance["damping_warnings"]}
    seen = 0
    for r in table.rows:
        if r.channel.startswith("bridge."):
            assert not any(c.kind == "lightly_damped_mode" for c in r.caveats)
        if r.verdict == "NOT EVALUATED":
            continue
        for c in r.caveats:
            if c.kind != "lightly_damped_mode":
                continue
            g = growth[c.text.split(" Hz")[0].split()[-1]]
            e = (1 + g) ** 0.3 - 1 if "sperling" in r.channel else g
            assert c.changes_verdict == (abs(r.estimate) * e >= abs(r.limit - r.estimate)), (r.channel, c.text)
            assert f"up to {100 * e:.2g} %" in c.text and "between the estimate and the limit" in c.text
            seen += 1
    assert seen > 0


def test_limits_from_data_speed_bands_and_static_loads(lateral):
    """Reference: docs/references.md, code limits, typed here: Prud'homme H <= 0.85 (10 kN + P/3) with P the
    static axle load, here the ICE motor car's weight (48000 + 2 x 3200 + 4 x 2400 kg,
    models/vehicles/ice_motor.toml) x g / 4 = 156.9 kN; the model's static wheel loads at t = 0 (what the
    check uses) equal it to 1e-6 (a symmetric car in static equilibrium on rigid track). The twist limit at
    220 km/h is the 1.5 mm band."""
    table = lateral.checks()
    row = next(r for r in table.rows if r.criterion == "running_safety/lateral_force_prudhomme")
    ice = tbx.scenario.load_vehicle("ice_motor")
    p_st = (ice.body.mass + 2 * ice.bogie.mass + 4 * ice.wheelset.mass) * lateral.scenario.analysis.gravity / 4
    load, source = static_axle_load(lateral, 1, 1)
    assert abs(load / p_st - 1) < 1e-6 and "t = 0" in source
    assert abs(row.limit / (0.85 * (10e3 + p_st / 3)) - 1) < 1e-6
    twist = next(r for r in table.rows if r.criterion == "en1990_deck/deck_twist_3m")
    assert twist.limit == 1.5e-3 and "220" in twist.limit_text


def test_verdict_follows_probability_and_never_hides_a_changing_caveat(lateral):
    """Verdicts: OK iff P <= target (PEM); a row is conditional exactly when one of its caveats can
    turn the verdict; a grid error above 1 % (the hook reads provenance['grid_error'] in the
    grid-error estimate's form) is a caveat, a condition only where its size reaches the limit."""
    for target in (DEFAULT_TARGET_PROBABILITY, 0.2):
        table = checks(lateral, probability=target)
        for r in table.rows:
            if r.probability is not None and r.verdict != "NOT EVALUATED":
                assert r.verdict == ("OK" if r.probability <= target else "EXCEEDS")
            # conditional: a verdict a caveat could turn (a row NOT EVALUATED has none to turn)
            assert r.conditional == (r.verdict != "NOT EVALUATED" and any(c.changes_verdict for c in r.caveats))
    ch = "bridge.span1.mid.acc_z_en1990"
    prov = dict(lateral.provenance)
    prov["grid_error"] = {"method": "test", "channels": {ch: {"rel_error_max_sigma": -0.03, "rel_deviation": 0.01,
                                                              "time_of_deviation_s": 1.0}}}
    assert grid_error_of(prov, ch) == 0.03 and grid_error_of(prov, "car1.body.acc_z") is None
    # a grid error is a condition only where it can carry the estimate across the limit: 3 % cannot
    # (the deck's estimate is far below its limit), 3000 % can
    for error, conditional in ((-0.03, False), (-30.0, True)):
        prov["grid_error"]["channels"][ch]["rel_error_max_sigma"] = error
        with_error = dataclasses.replace(lateral, provenance=prov)
        rows = [r for r in checks(with_error).rows if r.channel == ch]
        assert rows
        for r in rows:
            cav = [c for c in r.caveats if c.kind == "grid_error"]
            assert len(cav) == 1 and cav[0].changes_verdict == conditional and r.conditional == conditional
            assert (abs(r.estimate) * abs(error) >= abs(r.limit - r.estimate)) == conditional


def test_checks_table_text_and_plain_data(lateral):
    table = lateral.checks()
    data = json.loads(json.dumps(table.to_dict()))
    assert data["target"] == DEFAULT_TARGET_PROBABILITY and len(data["rows"]) == len(table.rows)
    first = data["rows"][0]
    assert {"criterion", "channel", "estimate", "limit", "probability", "verdict", "caveats", "conditional"} <= set(first)
    text = table.text(worst_only=True)
    assert text.splitlines()[0].startswith("checks of li_zhu_2011_mc_check (pem, 220 km/h")
    assert "target probability per passage 2.74e-05" in text
    counts = table.counts()
    assert sum(counts.values()) == len(table.rows)


def test_bad_limit_file_is_a_one_line_error(lateral, tmp_path):
    """A limit file with an unknown quantity (or a missing clause) gives the loader's one-line
    ScenarioError naming the file and the key, before any check."""
    data = tomllib.loads(model_files("limits")["ride_comfort"].read_text(encoding="utf-8"))
    data["criteria"][0]["quantity"] = "body_jerk"
    bad = tmp_path / "bad.toml"
    lines = [f'name = "bad"', f'description = "d"', f'source = "s"']
    c = data["criteria"][0]
    lines += ["[[criteria]]"] + [f"{k} = {json.dumps(v)}" for k, v in c.items() if k != "limit"]
    lines += ["[criteria.limit]"] + [f"{k} = {json.dumps(v)}" for k, v in c["limit"].items()]
    bad.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(ScenarioError) as err:
        checks(lateral, limits=bad)
    message = str(err.value)
    assert "bad.toml" in message and "criteria[0].quantity" in message and "\n" not in message
    with pytest.raises(SettingError, match="probability"):
        checks(lateral, probability=0.0)


def test_exceedance_api_refuses_what_it_cannot_answer(lateral, tmp_path):
    with pytest.raises(SettingError, match="windowed index"):
        lateral.exceedance_probability("car1.body.sperling_z", upper=2.0)
    p = lateral.exceedance_probability("car1.body.acc_z", upper=0.3, lower=-0.3)
    pv = lateral.exceedance_probability("car1.body.acc_z", upper=0.3, lower=-0.3, method="vanmarcke")
    assert 0 < pv.probability <= p.probability < 1 and p.method == "poisson"
    lev = lateral.exceedance_level("car1.body.acc_z", p.probability)
    assert abs(lev.level - 0.3) < 1e-6
    # saved and loaded: format 2 keeps the exceedance arrays
    lateral.save(tmp_path / "pem")
    back = load_random_response(tmp_path / "pem")
    for name in ("mean_rate", "std_rate", "rho", "bandwidth"):
        assert np.array_equal(getattr(back, name), getattr(lateral, name)), name
    meta = json.loads((tmp_path / "pem" / "meta.json").read_text())
    assert meta["format"] == "tb_exudyn.random_response/2"
    # a format-1 result (no derivative statistics) loads, and says why it cannot answer
    old = dataclasses.replace(lateral, mean_rate=None, std_rate=None, rho=None, bandwidth=None)
    old.save(tmp_path / "old")
    meta = json.loads((tmp_path / "old" / "meta.json").read_text())
    meta["format"] = "tb_exudyn.random_response/1"
    (tmp_path / "old" / "meta.json").write_text(json.dumps(meta))
    with pytest.raises(ResultsError, match="derivative statistics"):
        load_random_response(tmp_path / "old").exceedance_probability("car1.body.acc_z", upper=0.3)
    assert math.isfinite(p.expected_outcrossings)


def test_checks_of_one_deterministic_run(lateral):
    """A TimeHistory (the mean run) is checked by its statistic of the values: max |value| against
    the limit, no probability, the row's caveat saying it is one run."""
    from tb_exudyn.methods import run_deterministic

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        th = run_deterministic(lateral.scenario)
    table = checks(th)
    assert table.method == "deterministic" and table.rows
    for r in table.rows:
        if r.verdict == "NOT EVALUATED":
            continue
        assert r.probability is None and any(c.text.startswith("one deterministic run") for c in r.caveats)
        v = th[r.channel]
        if r.statistic == "max_abs":
            assert r.estimate == float(np.nanmax(np.abs(v)))
            assert r.verdict == ("OK" if r.estimate <= r.limit else "EXCEEDS")
    assert verdict_lines(th)[0].startswith("code checks (deterministic")


def test_shown_probability_has_a_floor_but_the_data_keeps_the_value(lateral):
    """Problem: one check row's probability set to 1e-30, 1e-9 and 3.14159e-4. Reference: the display
    rule of tb_exudyn.results.checks_table.format_probability (3 significant digits, "< 1e-09" below
    SMALLEST_SHOWN: a Gaussian tail that far out describes the model, not the bridge). Exact strings;
    the plain data keeps the unrounded value."""
    from tb_exudyn.results.checks_table import SMALLEST_SHOWN, format_probability

    row = next(r for r in lateral.checks().rows if r.probability is not None)
    tiny = dataclasses.replace(row, probability=1e-30, interval=None)
    assert format_probability(tiny) == "< 1e-09"
    assert format_probability(dataclasses.replace(tiny, probability=SMALLEST_SHOWN)) == "1e-09"
    assert format_probability(dataclasses.replace(tiny, probability=3.14159e-4)) == "0.000314"
    assert dataclasses.asdict(tiny)["probability"] == 1e-30
