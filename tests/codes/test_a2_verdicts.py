"""`check` gives one verdict per EN 1990 A2.4.4 criterion, on the terminal and in the report.

Problem: single_span_32m at a line speed of 200 km/h under HSLM-A1, nominal mass case. What is checked: every
criterion of models/criteria/en1990_a2.toml (and the deck acceleration) has a verdict line naming its clause;
the static values are those of tb_exudyn.codes.deformation times alpha (1) and Phi_2 (careful maintenance,
L_Phi = 32 m, hand value 1.44 / (sqrt(32) - 0.2) + 0.82 = 1.0840); the deck acceleration line is the rows'
largest value; the comfort criterion is evaluated at 200 km/h (within the digitised figure) against the
figure's limit for one span.
"""

import html
import math

import pytest

from tb_exudyn.codes import check
from tb_exudyn.codes.comfort_deflection import comfort_limit
from tb_exudyn.codes.criteria import load_criteria
from tb_exudyn.codes.deformation import static_deformations
from tb_exudyn.report.check import render_check_report
from tb_exudyn.scenario.io import load_bridge


@pytest.fixture(scope="module")
def result():
    return check("single_span_32m", 200.0, trains=["HSLM-A1"], cases=["nominal"])


def test_one_verdict_per_criterion(result):
    ids = [c.criterion for c in result.criteria]
    assert ids[0].startswith("deck_acceleration")
    expected = {c.id for c in load_criteria().criteria} - {"horizontal_radius_multi_deck"}  # one span
    assert set(ids[1:]) == expected
    assert result.criteria[0].value == max(result.column("max_deck_acc_z"))
    text = result.summary()
    page = render_check_report(result)
    for c in result.criteria:  # the terminal: the short name and clause; the report: all of it
        assert f"  {c.criterion.split(' (')[0]}: " in text and f"[{c.short_clause}]" in text
        assert all(html.escape(x) in page for x in (c.criterion, c.clause, c.case, c.location, c.caveats or "-"))


def test_criteria_lines_are_an_engineers(result):
    """The terminal's criteria block (issue 49, every command's terminal): speeds to 0.1 km/h, deflections and
    twists in mm and rotations in mrad (tb_exudyn.system.labels.display_unit, the project's one convention),
    stations in words ('span 1 at 5/8', not 'span1.x5/8'), one line of at most 160 characters per criterion."""
    import re
    text = result.summary()
    block = text.split("\n")[1:1 + len(result.criteria)]
    assert len(block) == len(result.criteria) and all(len(ln) <= 160 for ln in block)
    speeds = re.findall(r"(\d+(?:\.\d+)?) km/h", "\n".join(block))
    assert speeds and all(re.fullmatch(r"\d+\.\d", s) for s in speeds), speeds
    assert "span1.x" not in text and "e-0" not in "\n".join(block) and "e+0" not in "\n".join(block)
    v = {c.criterion: c for c in result.criteria}
    line = {c.criterion: ln for c, ln in zip(result.criteria, block)}
    deflection = v["vertical_deflection"]
    assert f"({1e3 * deflection.value:.4g} mm <= {1e3 * deflection.limit:.4g} mm)" in line["vertical_deflection"]
    assert " mm <= 3 mm)" in line["deck_twist_3m"] and " mrad <= " in line["deck_end_rotation"]
    assert re.search(r"\(\d+ m >= 6000 m\)", line["horizontal_radius_single_deck"])  # whole metres
    assert re.search(r"span 1 at \d/8 \(\d+ m\)|span 1, mid-span", v[result.criteria[0].criterion].location)


def test_static_values_are_lm71_times_phi(result):
    phi2 = 1.44 / (math.sqrt(32.0) - 0.2) + 0.82
    b = load_bridge("single_span_32m").replace(elements_per_span=64)
    sd = static_deformations(b)
    v = {c.criterion: c for c in result.criteria}
    assert v["vertical_deflection"].value == pytest.approx(phi2 * sd.deflection[0][0], rel=1e-12)
    assert v["vertical_deflection"].limit == pytest.approx(32.0 / 600.0)
    assert v["deck_twist_3m"].value == pytest.approx(phi2 * sd.twist[0], rel=1e-12)
    assert v["deck_twist_3m"].limit == 3.0e-3  # 120 < V <= 200 km/h
    assert v["comfort_deflection"].limit == pytest.approx(comfort_limit(32.0, 200.0, 1), rel=1e-12)
    assert v["comfort_deflection"].verdict in ("ok", "exceeds")
    assert v["dynamic_factor_envelope"].verdict == "comparison"


def test_alpha_scales_the_classified_loads(result):
    """alpha = 1.21 multiplies LM71 and the nosing force (classified loads, EN 1991-2 6.3.2(3)) in the static
    criteria, not the comfort criterion (alpha = 1 there, A2.4.4.3.2); a value outside the list is refused."""
    from tb_exudyn.errors import SettingError
    r = check("single_span_32m", 200.0, trains=["HSLM-A1"], cases=["nominal"], alpha=1.21)
    a, b = {c.criterion: c for c in result.criteria}, {c.criterion: c for c in r.criteria}
    assert b["vertical_deflection"].value == pytest.approx(1.21 * a["vertical_deflection"].value, rel=1e-12)
    assert b["horizontal_rotation"].value == pytest.approx(1.21 * a["horizontal_rotation"].value, rel=1e-12)
    assert b["comfort_deflection"].value == pytest.approx(a["comfort_deflection"].value, rel=1e-12)
    assert "not given" in a["vertical_deflection"].caveats and "not given" not in b["vertical_deflection"].caveats
    with pytest.raises(SettingError, match="alpha"):
        check("single_span_32m", 200.0, trains=["HSLM-A1"], alpha=1.2)


def test_comfort_takes_lm71_only_on_a_continuous_girder():
    """A2.4.4.3.2 loads LM71 x Phi (alpha = 1), not SW/0: on continuous_3x32m the comfort criterion reads the
    LM71-only envelope, the L/600 criterion the envelope of LM71 and SW/0. Phi_2 with L_Phi = 1.3 x 32 m."""
    from tb_exudyn.codes.deformation import LM71
    r = check("continuous_3x32m", 200.0, trains=["HSLM-A1"], cases=["nominal"])
    v = {c.criterion: c for c in r.criteria}
    b = load_bridge("continuous_3x32m").replace(elements_per_span=64)
    phi2 = 1.44 / (math.sqrt(1.3 * 32.0) - 0.2) + 0.82
    lm71 = static_deformations(b, (LM71,))
    both = static_deformations(b)
    assert v["comfort_deflection"].value == pytest.approx(phi2 * lm71.deflection[0].max(), rel=1e-12)
    assert v["vertical_deflection"].value == pytest.approx(phi2 * both.deflection[0].max(), rel=1e-12)
    assert v["comfort_deflection"].limit == pytest.approx(comfort_limit(32.0, 200.0, 3, continuous=True), rel=1e-12)
    assert v["deck_end_rotation_between_decks"].verdict == "not evaluated"


def test_comfort_above_the_digitised_figure_says_why_and_what_instead():
    """Figure A2.3 goes on to 350 km/h but only its curves up to 220 km/h are digitised (a third-party reading;
    none found above): at a line speed of 250 km/h the comfort criterion is not evaluated (never clamped to the
    220 km/h curve, whose L/delta is lower than a faster curve's, so unsafe), and the verdict says why and
    names A2.4.4.3.3's dynamic analysis of the car-body acceleration as the way to check it."""
    r = check("single_span_32m", 250.0, trains=["HSLM-A1"], cases=["nominal"])
    v = {c.criterion: c for c in r.criteria}["comfort_deflection"]
    assert math.isnan(v.value) and math.isnan(v.limit) and v.verdict == "not evaluated"
    assert "250 km/h: Figure A2.3's curves above 220 km/h are not digitised" in v.caveats
    assert "A2.4.4.3.3" in v.caveats
