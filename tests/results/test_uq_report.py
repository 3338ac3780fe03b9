"""The page of an uncertainty study (tb_exudyn/report/uq.py, issue 46) on a result built here by hand,
so that every number it must show is known: two criteria, one whose P_f = 1e-3 is above the target
probability 2.74e-5 per passage (EXCEEDS) and one whose P_f = 1e-7 is below it (OK), one quantity
whose leave-one-out error (3 %) is above the 1 % warning threshold, and a warning. The verdict's
reference is its definition (P_f against the target); the page must open with it."""

from __future__ import annotations

import html
import re

import numpy as np

from tb_exudyn.cli.uq import summary_lines
from tb_exudyn.report.uq import UQ_REPORT, render_uq_report, write_uq_report
from tb_exudyn.results.checks import DEFAULT_TARGET_PROBABILITY
from tb_exudyn.results.uq import UqResult, pf_verdicts

from ..methods.test_uq_sprung_mass import scenario as sprung_mass_scenario

CRITERIA = ("ride_comfort/body_acc_z_en1990", "en1990_deck/deck_acc_ballasted")
PF = (1e-3, 1e-7)
WARNING = "the polynomial chaos surrogate's leave-one-out error is above 1 % for 1 of 5 quantities"


def result() -> UqResult:
    nt, nn = 4, 3
    quantities = ("max_sigma:car1.body.acc_z",) + tuple(f"probability:{c}" for c in CRITERIA) + tuple(
        f"estimate:{c}" for c in CRITERIA)
    nq = len(quantities)
    band = np.stack([np.full((1, nt), 0.9), np.full((1, nt), 1.0), np.full((1, nt), 1.1)])
    node_q = np.array([[1.0, 0.5e-3, 0.5e-7, 1.0, 0.5], [1.1, 1e-3, 1e-7, 1.1, 0.6], [1.2, 1.5e-3, 1.5e-7, 1.2, 0.7]])
    data = {"time": np.linspace(0.0, 3.0, nt), "mean_sigma": np.ones((1, nt)), "std_sigma": np.full((1, nt), 0.1),
            "mean_response": np.zeros((1, nt)), "sigma_band": band,
            "quantity_mean": np.array([1.1, PF[0], PF[1], 1.1, 0.6]), "quantity_std": np.full(nq, 0.08),
            "quantity_band": np.array([[1.0, 0.5e-3, 0.5e-7, 1.0, 0.5], [1.1, 1e-3, 1e-7, 1.1, 0.6],
                                       [1.2, 1.5e-3, 1.5e-7, 1.2, 0.7]]),
            "sobol_first": np.full((1, nq), 0.97), "sobol_total": np.ones((1, nq)),
            "loo": np.array([0.03, 0.002, 0.004, 0.005, np.nan]), "pf": np.array(PF),
            "node_values": np.array([[3.2e5], [4.0e5], [4.8e5]]), "node_weights": np.array([1 / 6, 2 / 3, 1 / 6]),
            "node_quantities": node_q}
    keys = ({"key": "train.vehicles.0.damping", "distribution": "uniform", "mean": 4.0e5, "std": 4.6e4,
             "low": 3.2e5, "high": 4.8e5},)
    assert data["node_quantities"].shape == (nn, nq)
    return UqResult(scenario=sprung_mass_scenario(), keys=keys, channels=("car1.body.acc_z",), units=("m/s^2",),
                    quantities=quantities, criteria=CRITERIA, data=data,
                    provenance={"order": 2, "design": "tensor", "n_nodes": nn, "seconds": 3.8, "engine": "batched",
                                "warnings": [WARNING]})


def test_verdict_is_p_f_against_the_target():
    rows = {r["criterion"]: r for r in pf_verdicts(result())}
    assert rows[CRITERIA[0]]["verdict"] == "EXCEEDS" and rows[CRITERIA[1]]["verdict"] == "OK"
    assert rows[CRITERIA[0]]["target"] == DEFAULT_TARGET_PROBABILITY
    assert rows[CRITERIA[0]]["node_max"] == 1.5e-3 and rows[CRITERIA[1]]["estimate_mean"] == 0.6
    assert rows[CRITERIA[1]]["estimate_band"] == (0.5, 0.6, 0.7)
    assert {r["verdict"] for r in pf_verdicts(result(), target=1e-2)} == {"OK"}


def test_page_opens_with_the_verdict_names_each_criterion_and_holds_the_loo_error(tmp_path):
    page = write_uq_report(result(), tmp_path)
    assert page == tmp_path / UQ_REPORT
    text = page.read_text()
    sections = re.findall(r'<section id="([a-z]+)">', text)
    assert sections[0] == "verdict", sections
    verdict = text[text.index('<section id="verdict">'):text.index("</section>")]
    for c, pf in zip(CRITERIA, PF):
        assert html.escape(c) in verdict and f"{pf:.3g}" in verdict
    assert "1 of 2 criteria EXCEED" in verdict and "2.74e-05" in verdict
    loo = text[text.index('<section id="loo">'):]
    assert '<span class="exceeds">3 %</span>' in loo and "0.5 %" in loo and "not estimated" in loo
    assert html.escape(WARNING) in text[text.index('<section id="warnings">'):]


def test_page_without_figures_says_so_and_terminal_fits():
    text = render_uq_report(result())
    assert "Not drawn (--no-figures)" in text
    lines = summary_lines(result())
    assert all(len(ln) <= 200 for ln in lines)
    assert any(CRITERIA[0] in ln and "EXCEEDS" in ln and "0.001" in ln for ln in lines), lines
    assert any(ln.startswith("car1.body.acc_z [m/s^2]") and "3 %" in ln for ln in lines), lines


def test_warnings_alike_are_one_and_the_terminal_stays_on_a_screen():
    """30 nodes raising the same warning with another percentage are one group (terminal and page);
    8 other warnings beyond the terminal's 6 rows are counted, not printed; the page holds all."""
    import dataclasses

    from tb_exudyn.cli.uq import WARNING_ROWS

    alike = [f"2 lightly damped modes at 8.342 Hz: sigma grows about {10 + i} % on the bridge" for i in range(30)]
    other = [f"warning number {w}" for w in ("one", "two", "three", "four", "five", "six", "seven", "eight")]
    r = result()
    r = dataclasses.replace(r, provenance={**r.provenance, "warnings": [WARNING] + alike + other})
    lines = summary_lines(r)
    assert len(lines) <= 60 and all(len(ln) <= 200 for ln in lines)
    assert sum(ln.startswith("warning") for ln in lines) == WARNING_ROWS
    assert any("(30 messages like it)" in ln and "about 10 %" in ln for ln in lines), lines
    assert lines[-1] == f"... and {1 + 1 + 8 - WARNING_ROWS} more warnings (uq.html)"
    text = render_uq_report(r)
    assert "30 messages like it" in text and all(w in text for w in other) and "about 39 %" in text


def test_page_and_figures_are_one_group_and_a_later_study_removes_the_earlier_figures(tmp_path):
    """save_figures writes the bars, the band and uq.html; again with --no-figures (a study redone
    with --overwrite) it leaves the page only, not figures of the earlier study beside it."""
    from tb_exudyn.cli.uq import save_figures

    names = sorted(p.name for p in save_figures(result(), tmp_path))
    assert names == ["uq.html", "uq_band.car1.body.acc_z.png", "uq_sobol.png"]
    assert "data:image/png;base64," in (tmp_path / UQ_REPORT).read_text()
    assert [p.name for p in save_figures(result(), tmp_path, figures=False)] == [UQ_REPORT]
    assert sorted(p.name for p in tmp_path.iterdir()) == [UQ_REPORT]


def test_verdict_names_what_each_criterion_checks_and_its_limit():
    """The deck criterion's row: its title and its limit, 3.5 m/s^2 (EN 1990 A2.4.4.2.1, ballasted
    track, the default limits' value), from the limits the nodes were checked against."""
    from tb_exudyn.results.uq import criteria_info

    title, unit, limit = criteria_info()[CRITERIA[1]]
    assert limit == 3.5 and unit == "m/s^2"
    text = render_uq_report(result())
    verdict = text[text.index('<section id="verdict">'):text.index("</section>")]
    assert html.escape(title) in verdict and '<td class="num">3.5</td>' in verdict


def test_a_surrogate_without_any_leave_one_out_error_is_warned_about():
    """One key on a 3-point Gauss quadrature at order 2: as many nodes as basis terms, no residual, so
    every LOO is NaN (tb_exudyn.methods.uq.pce.loo_error); the terminal and the page must say that the
    surrogate's accuracy is unknown instead of showing nothing."""
    import dataclasses

    r = result()
    r = dataclasses.replace(r, data={**r.data, "loo": np.full(len(r.quantities), np.nan)},
                            provenance={**r.provenance, "warnings": []})
    lines = summary_lines(r)
    note = [ln for ln in lines if "surrogate's error is unknown" in ln]
    assert len(note) == 1 and len(note[0]) <= 200 and "3 nodes, tensor design" in note[0], lines
    assert "surrogate&#x27;s error is unknown" in render_uq_report(r)
    assert not any("unknown" in ln for ln in summary_lines(result()))
