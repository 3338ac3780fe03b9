"""The bridges' EN 1991-2 data ([code] table: construction type, ballast) and the mass cases.

The mass cases of EN 1991-2 6.4.6.3.2 change the ballast's density: lower 1700, nominal 1800, upper
2000 kg/m^3 on the shipped bridges (EN 1991-1-1's range, recalled [check]).
"""

from __future__ import annotations

import math

import pytest

from tb_exudyn.errors import ScenarioError
from tb_exudyn.scenario import MASS_CASES, CodeData, load_bridge, models_dir, with_mass_case
from tb_exudyn.structure import modal_bridge


def test_shipped_girders_are_prestressed_concrete_with_their_ballast():
    """Exact: the data files' values (issue 25: the shipped bridges are prestressed concrete box
    girders); the two 32 m girders carry the study's added mass 1.1678e4 kg/m as ballast."""
    for name in ("li_zhu_2011_bridge", "single_span_32m", "xia_2003_50m"):
        assert load_bridge(name).code.construction == "prestressed_concrete", name
    for name in ("li_zhu_2011_bridge", "single_span_32m"):
        code = load_bridge(name).code
        assert code.ballast_mass_per_length == 11677.75
        assert (code.ballast_density_min, code.ballast_density, code.ballast_density_max) == (1700.0, 1800.0, 2000.0)
    assert load_bridge("yang_yau_1997_beam").code is None


@pytest.mark.parametrize("case, rho", [("lower", 1700.0), ("nominal", 1800.0), ("upper", 2000.0)])
def test_mass_case_changes_the_ballast_and_the_frequency_as_one_over_root_mass(case, rho):
    """Exact problem: single_span_32m (one simply supported 32 m span, Euler-Bernoulli girder of
    33 900 kg/m including 11 677.75 kg/m of ballast at 1800 kg/m^3) in each mass case. Reference,
    by hand: m = 33 900 + 11 677.75 (rho / 1800 - 1) kg/m, and the first vertical frequency of a
    uniform simply supported span goes as 1 / sqrt(m) (f1 = pi / (2 L^2) sqrt(E I / m)), so f1(case)
    / f1(nominal) = sqrt(33 900 / m). Tolerance 1e-9: the FE model's frequency is a fixed function of
    E I / m for a uniform beam (the same mesh), so the ratio is exact to round-off."""
    nominal = load_bridge("single_span_32m")
    bridge = with_mass_case(nominal, case)
    m = 33900.0 + 11677.75 * (rho / 1800.0 - 1.0)
    assert abs(bridge.girder.mass_per_length - m) <= 1e-9 * m
    assert bridge.code.ballast_density == pytest.approx(rho, rel=1e-12)
    f = {c: modal_bridge(b, 30.0).frequencies for c, b in (("case", bridge), ("nominal", nominal))}
    first = [min(fr) for fr in f.values()]
    assert abs(first[0] / first[1] - math.sqrt(33900.0 / m)) < 1e-9


def test_frame_mass_case_changes_the_added_mass():
    """Exact: li_zhu_2011_bridge carries its ballast in the added mass (1.1678e4 kg/m): the upper
    case adds 11 677.75 x (2000 / 1800 - 1) = 1297.53 kg/m there, the polar moment by the same ratio."""
    b = load_bridge("li_zhu_2011_bridge")
    up = with_mass_case(b, "upper")
    dm = 11677.75 * (2000.0 / 1800.0 - 1.0)
    assert up.added_mass.mass_per_length == pytest.approx(11677.75 + dm, rel=1e-12)
    ratio = up.added_mass.mass_per_length / b.added_mass.mass_per_length
    assert up.added_mass.rot_mass_per_length == pytest.approx(b.added_mass.rot_mass_per_length * ratio, rel=1e-12)
    assert up.girder == b.girder
    assert with_mass_case(b, "nominal") is b and MASS_CASES == ("nominal", "lower", "upper")


def test_bad_code_data_is_one_line_naming_the_key(tmp_path):
    """Exact: the schema's messages name the file or the key and what is allowed."""
    text = (models_dir() / "bridges" / "single_span_32m.toml").read_text()  # the shipped data, as a user's file
    bad = tmp_path / "wood.toml"
    bad.write_text(text.replace('construction = "prestressed_concrete"', 'construction = "wood"'))
    with pytest.raises(ScenarioError, match=r"wood\.toml.*code\.construction.*prestressed_concrete") as err:
        load_bridge(bad)
    assert len(str(err.value).splitlines()) == 1
    with pytest.raises(ScenarioError, match="ballast_density.*between"):
        CodeData(construction="prestressed_concrete", ballast_density=2500.0)
    b = load_bridge("single_span_32m")
    with pytest.raises(ScenarioError, match="ballast_mass_per_length.*at most girder.mass_per_length"):
        b.replace(code=b.code.replace(ballast_mass_per_length=5e4))
    with pytest.raises(ValueError, match="no code data"):
        with_mass_case(load_bridge("yang_yau_1997_beam"), "upper")
