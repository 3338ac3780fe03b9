"""The speed sweep's HTML report (tb_exudyn.report.sweep) on a sweep result built by hand: what each
section shows, in display units, with the warnings grouped by message and every text escaped.

The numbers of the page are the table's (SweepResult.rows()) converted by the display-unit
convention (N -> kN: factor 1e-3) and printed by format_number: the test writes the expected
strings with the same two functions applied to the hand-made values, so a wrong column, unit or
speed shows as a missing string (exact string comparison; no tolerance is involved).
"""

from __future__ import annotations

import html
import math

import numpy as np

from tb_exudyn.methods.sweep import KEY_QUANTITIES
from tb_exudyn.results.sweep import CriterionValues, Resonance, SweepResult, checks_text
from tb_exudyn.report.sweep import SWEEP_REPORT, render_sweep_report, write_sweep_report
from tb_exudyn.system.labels import format_number

from ..methods.test_pem import sprung_mass_scenario


def _summary(speed: float, force: float, grid_error: tuple[float, float], warnings: list[str], checks: dict) -> dict:
    return {
        "channels": np.array(["bridge.span1.mid.acc_z", "car1.axle1.left.force_z"]),
        "units": np.array(["m/s^2", "N"]),
        "grid_error": np.array(grid_error),
        "max_abs_mean": np.array([0.1, force]), "max_sigma": np.array([0.2, 0.1 * force]),
        "max_design": np.array([0.7, 1.3 * force]), "band": np.array([0.5, 50.0]), "n_freq": np.array(120),
        "seconds": np.array(1.5), "checks": np.array(checks_text(checks)),
        "warnings": np.array([f"{w} (at {speed:g} km/h)" for w in warnings], dtype=str),
    }


def _sweep() -> SweepResult:
    base = sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6, channels=("*",))
    base = base.replace(description="beam <script>alert(1)</script> & co")
    quantities = tuple(q for q in KEY_QUANTITIES if q[0] in ("deck_acc_z", "wheel_force_z"))
    light = "lightly damped mode at 8.342 Hz <b>: sigma grows by about {} % on the bridge"
    nan = math.nan
    checks = [{"deck/acc_z": CriterionValues(0.4, 1e-12, 0.7, 1.75, "m/s^2", "", "OK"),
               "force/y": CriterionValues(nan, nan, nan, 62e3, "N", "", "NOT EVALUATED",
                                          reason="no such channel <yet>")},
              {"deck/acc_z": CriterionValues(1.25, 0.2, 2.1875, 1.75, "m/s^2", "", "EXCEEDS", title="deck acceleration",
                                             caveats="lightly_damped_mode"),
               "force/y": CriterionValues(0.5, 1e-3, 31e3, 62e3, "N", "", "OK")}]
    summaries = (
        _summary(200.0, 60e3, (0.002, 0.004), [light.format(69)], checks[0]),
        _summary(300.0, 80e3, (0.03, math.nan), [light.format(50), "grid error 3 % on car1.axle1.left.force_z"],
                 checks[1]),
    )
    res = (Resonance("vertical", 4.2, "car length", 26.4, 1, 4.2 * 26.4 * 3.6),)
    return SweepResult(base=base, speeds=(200.0, 300.0), summaries=summaries, quantities=quantities, resonances=res,
                       provenance={"seconds": 3.0, "engine": "batched", "tasks_from_checkpoint": 0})


def test_sweep_report_sections_numbers_and_escaping(tmp_path):
    sweep = _sweep()
    text = render_sweep_report(sweep, figure_png=b"\x89PNG fake", tolerance=0.01)
    for heading in ("Verdicts by speed", "Key quantities by speed", "Resonance speeds", "Frequency grid by speed",
                    "Warnings", "Scenario"):
        assert f"<h2>{heading}</h2>" in text, heading
    # the wheel force in kN: max |mean| + 3 sigma and sigma at both speeds
    for force in (60e3, 80e3):
        assert f"<td class=\"num\">{format_number(1.3 * force * 1e-3)}</td>" in text
        assert f"<td class=\"num\">{format_number(0.1 * force * 1e-3)}</td>" in text
    assert "wheel_force_z [kN]" in text and "deck_acc_z [m/s^2]" in text
    # grid: the 300 km/h speed has one channel above 1 % (NaN is not counted), shown as exceeding
    assert "1 of 2" in text and "0 of 2" in text
    assert '<span class="exceeds">3 %' in text
    assert "Not converged at 1 of 2 speeds</b> (300 km/h)" in text
    # verdicts: the utilisation above 1 marked by its verdict, conditional (a caveat), its probability
    # shown; below SMALLEST_SHOWN as "< 1e-09"; a criterion not evaluated says so
    assert '<span class="exceeds">1.25</span> &dagger;<br><small>P = 0.2</small>' in text
    assert '<span class="ok">0.4</span><br><small>P &lt; 1e-09</small>' in text
    assert '<span class="not-evaluated">not evaluated</span>' in text
    assert "force/y not evaluated: no such channel &lt;yet&gt;" in text
    assert "1 of 2" in text and "deck/acc_z: deck acceleration" in text
    # the criterion's table: estimate and limit in display units (kN for the force)
    assert "<td class=\"num\">31</td><td class=\"num\">62</td>" in text and "estimate [kN]" in text
    assert "lightly damped mode" in text.split("deck/acc_z: deck acceleration")[1].split("</details>")[0]
    # warnings: one message that differs only in its percentages, with the speeds, as first raised; escaped
    assert text.count("lightly damped mode at 8.342 Hz") == 1
    assert ("lightly damped mode at 8.342 Hz &lt;b&gt;: sigma grows by about 69 % on the bridge <small>(at all "
            "speeds; as raised at 200 km/h: the percentages vary with the speed)</small>") in text
    assert "<small>(at 300 km/h)</small>" in text
    assert "<script>alert" not in text and html.escape("<script>alert(1)</script>") in text
    assert "data:image/png;base64," in text
    assert format_number(4.2 * 26.4 * 3.6) in text  # the resonance speed
    # without the figure the page says so; the file is written atomically in the folder given
    assert "Not drawn" in render_sweep_report(sweep, None)
    path = write_sweep_report(sweep, tmp_path, None)
    assert path == tmp_path / SWEEP_REPORT and path.read_text().startswith("<!DOCTYPE html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == [SWEEP_REPORT]


def test_sweep_figure_in_display_units_with_unconverged_speeds_marked():
    """The figure of the hand-made sweep: the wheel force drawn in kN (its points are the table's
    values times 1e-3, exactly), the unit on the axis and not the SI one of the description, and the
    only speed whose deck grid error exceeds 1 % (300 km/h: 3 %; NaN, not estimated, is not marked)
    crossed out; the wheel force, not estimated at 300 km/h and 0.4 % at 200 km/h, has no mark."""
    sweep = _sweep()
    fig = sweep.plot()
    deck, force = fig.axes[:2]
    line = next(ln for ln in force.get_lines() if ln.get_label() == "max |mean| + 3 sigma")
    assert np.array_equal(line.get_ydata(), np.array([1.3 * 60e3, 1.3 * 80e3]) * 1e-3)
    assert force.get_ylabel() == "wheel_force_z [kN]" and "[N]" not in force.get_title()
    marks = [ln for ln in deck.get_lines() if ln.get_gid() == "grid_error"]
    assert len(marks) == 1 and list(marks[0].get_xdata()) == [300.0]
    assert not [ln for ln in force.get_lines() if ln.get_gid() == "grid_error"]
