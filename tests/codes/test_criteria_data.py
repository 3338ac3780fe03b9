"""The A2.4.4 criteria file (models/criteria/en1990_a2.toml) and the deck limits' one source.

The file is read and checked as a whole; its values are compared with the recommended values of EN 1990
Annex A2 as the project's reference notes state them (Tables A2.7, A2.8, A2.4.4.2.3(1), A2.4.4.2.4(3)):
these tests fail if an edit of the data changes a recommended value without changing the test.
"""

import math

import pytest

from tb_exudyn.codes import en1991 as code
from tb_exudyn.codes import stochastic as stoch
from tb_exudyn.codes.criteria import criteria_path, load_criteria
from tb_exudyn.errors import ScenarioError
from tb_exudyn.results.checks import default_limits


def test_every_criterion_names_clause_load_model_and_where_it_is_read():
    s = load_criteria()
    ids = {c.id for c in s.criteria}
    assert {"deck_twist_3m", "vertical_deflection", "deck_end_rotation", "horizontal_rotation", "lateral_frequency",
            "comfort_deflection", "dynamic_factor_envelope"} <= ids
    for c in s.criteria:
        assert "A2.4.4" in c.clause or "6.4." in c.clause
        assert c.load_model and c.read_at and c.quantity and c.tracks


def test_recommended_values():
    s = load_criteria()
    twist = s.criterion("deck_twist_3m")
    assert [twist.limit_value(speed_kmh=v) for v in (120.0, 120.1, 200.0, 250.0)] == [4.5e-3, 3.0e-3, 3.0e-3, 1.5e-3]
    assert s.criterion("deck_twist_3m_total").limit_value() == 7.5e-3
    assert s.criterion("vertical_deflection").limit_value(span=30.0) == pytest.approx(0.05)
    rot = s.criterion("horizontal_rotation")
    assert [rot.limit_value(speed_kmh=v) for v in (100.0, 160.0, 300.0)] == [3.5e-3, 2.0e-3, 1.5e-3]
    lat = s.criterion("lateral_frequency")
    assert lat.bound == "lower" and lat.limit_value() == 1.2


def test_a_bad_value_names_the_file_and_key(tmp_path):
    text = criteria_path().read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("ratio = 600.0", "ratio = -600.0"))
    with pytest.raises(ScenarioError) as e:
        load_criteria(bad)
    assert "bad.toml" in str(e.value) and "ratio" in str(e.value)


def test_deck_limits_have_one_source():
    """The moving-force rows' limit is the value of the criterion the stochastic column reads (the check's
    records name it): one criterion of one file, nothing to reconcile at run time."""
    from tb_exudyn.codes.criteria import DECK_ACCELERATION_CRITERIA, DECK_LIMIT_SET, deck_criterion

    sets = {ls.name: ls for ls in default_limits()}
    deck = sets[DECK_LIMIT_SET]
    for track, crit in DECK_ACCELERATION_CRITERIA.items():
        assert code.deck_acceleration_limit(track) == deck.criterion(crit).limit_value()
        assert deck_criterion(track) == f"{deck.name}/{crit}"
    assert not hasattr(stoch, "check_limits") and not hasattr(stoch, "CRITERIA")
    assert code.deck_acceleration_limit("ballasted") == 3.5 and math.isclose(code.deck_acceleration_limit("direct"), 5.0)


def test_one_criterion_type_for_limit_files_and_the_check(tmp_path):
    """The A2.4.4 criteria and the limit files' criteria are one type (scenario.limits.Criterion): structural
    (a bound, no statistic) or on a result's channels (a statistic). A file of the other form is refused
    naming the criterion's statistic; a structural set is refused by the checks of a result."""
    from tb_exudyn.results.checks import checks
    from tb_exudyn.scenario.limits import Criterion, LimitSet, load_limits

    a2 = load_criteria()
    deck = load_limits("en1990_deck")
    assert isinstance(a2, LimitSet) and all(isinstance(c, Criterion) for c in (*a2.criteria, *deck.criteria))
    assert all(c.structural and c.bound for c in a2.criteria) and not any(c.structural for c in deck.criteria)
    assert deck.criteria[0].unit == "m/s^2" and deck.criteria[0].bound == ""  # a response criterion's: its quantity's
    bad = tmp_path / "a2.toml"
    bad.write_text(criteria_path().read_text().replace('bound = "upper"\n', 'bound = "upper"\nstatistic = "max"\n', 1))
    with pytest.raises(ScenarioError) as e:
        load_criteria(bad)
    assert e.value.key == "criteria[0].statistic" and "a2.toml" in str(e.value)
    with pytest.raises(ScenarioError, match="criteria\\[0\\].statistic"):
        load_limits(_without_statistic(tmp_path))
    with pytest.raises(Exception, match="structural criteria"):
        checks(None, a2)


def _without_statistic(tmp_path):
    from tb_exudyn.scenario.registry import models_dir

    text = (models_dir() / "limits" / "en1990_deck.toml").read_text()
    out = tmp_path / "deck.toml"
    lines = text.splitlines()
    first = next(i for i, ln in enumerate(lines) if ln.startswith("statistic"))
    out.write_text("\n".join(lines[:first] + lines[first + 1:]) + "\n")
    return out
