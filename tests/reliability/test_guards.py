"""Hostile sizes and Python calls of issue 27 (tests/reliability/cases_guards.py): each ends in exit
status 2 with one line naming the file (or the function) and the key, no traceback, and nothing
written, moved or deleted under the scratch folder (the assertions of test_cases.py, on these cases).

The reference is the error contract of DEVELOPERS.md (one line, the file or option, the key and what
is allowed; exit 2; nothing written). The isolated cases run in a subprocess limited to 2 GB of
address space and 60 s, so a defence that failed shows as an allocation failure or a timeout, not as
a machine out of memory.
"""

from __future__ import annotations

import pytest

from .cases_guards import CASES_GUARDS
from .test_cases import assert_one_clear_error


@pytest.mark.parametrize("case", CASES_GUARDS, ids=[c.id for c in CASES_GUARDS])
def test_guarded_input_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    assert_one_clear_error(case, tmp_path, capsys, monkeypatch)


def test_the_cases_are_in_their_group():
    assert CASES_GUARDS and {c.group for c in CASES_GUARDS} == {"guards"}
    assert len({c.id for c in CASES_GUARDS}) == len(CASES_GUARDS)


# ------------------------------------------------------------------------------------ the estimates behind the cases
@pytest.mark.exudyn
@pytest.mark.parametrize("name", ["quick", "fryba_moving_force", "yang_yau_sprung_mass", "li_zhu_2011_creep"])
def test_vehicle_coordinates_are_those_of_the_built_model(name):
    """Problem: the library's scenarios with each vehicle kind (car15, moving force, sprung mass,
    creep car). Reference: the built model's ODE2 size minus its bridge modes, compared exactly (the
    system's memory check counts the coordinates before the vehicles are built)."""
    pytest.importorskip("exudyn")
    from tb_exudyn.builder import build_model
    from tb_exudyn.execution.resources import vehicle_coordinates
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario(name)
    model = build_model(sc, warn=False)
    assert model.n_ode2 - model.bridge.n_modes == sum(vehicle_coordinates(v) for v in sc.train.vehicles)


def test_system_size_names_the_vehicles_or_the_bridge_modes():
    """The dense n x n system at SYSTEM_BYTES_PER_ENTRY bytes per entry against a given limit: quick
    (42 car coordinates, 10 bridge modes) needs 80 x 52^2 = 216 kB; with 100 kB it is refused naming
    the vehicles (they hold most coordinates), with 500 bridge modes naming the bridge's modes."""
    from tb_exudyn.errors import ResourceError
    from tb_exudyn.execution.resources import SYSTEM_BYTES_PER_ENTRY, check_system_size
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario("quick")
    check_system_size(sc, 10, limit=SYSTEM_BYTES_PER_ENTRY * 52**2)  # exactly fits
    with pytest.raises(ResourceError, match=r"key 'train.vehicles'.*at most about 0 such vehicles"):
        check_system_size(sc, 10, limit=10**5)
    with pytest.raises(ResourceError, match=r"key 'analysis.mode_max_frequency'"):
        check_system_size(sc, 500, limit=10**6)


def test_damping_guard_refuses_a_run_too_long_before_building():
    """The library's damping guard follows the run's output times: a crawling train is refused as the
    run is (check_run_length), before a model is built (no model given, none made: it is quick)."""
    from tb_exudyn.errors import ResourceError
    from tb_exudyn.scenario import load_scenario

    pytest.importorskip("exudyn")
    from tb_exudyn.builder.system_modes import damping_guard

    with pytest.raises(ResourceError, match="speed_kmh"):
        damping_guard(load_scenario("quick").replace(speed_kmh=0.001))


def test_the_speed_a_refusal_names_is_allowed():
    """Problem: quick at 0.001 km/h (7e8 steps). The refusal names the least speed_kmh whose crossing
    takes at most MAX_STEPS steps (rounded up to 3 digits); that speed passes the same check."""
    import re

    from tb_exudyn.errors import ResourceError
    from tb_exudyn.execution.resources import check_run_length
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario("quick").replace(speed_kmh=0.001)
    with pytest.raises(ResourceError) as err:
        check_run_length(sc)
    least = float(re.search(r"speed_kmh >= ([0-9.e+-]+)", str(err.value)).group(1))
    check_run_length(sc.replace(speed_kmh=least))
    with pytest.raises(ResourceError):
        check_run_length(sc.replace(speed_kmh=least * 0.99))


def test_a_run_too_long_for_its_bridge_names_the_spans():
    """Problem: quick on a 2000 km span (valid data for the schema, 2.9e7 steps at 250 km/h). The run's
    length check names the key that makes it long, bridge.spans, not the time step."""
    from tb_exudyn.errors import ResourceError
    from tb_exudyn.execution.resources import check_run_length
    from tb_exudyn.scenario import load_scenario

    sc = load_scenario("quick")
    with pytest.raises(ResourceError, match=r"key 'bridge.spans' = \[2000000.0\]"):
        check_run_length(sc.replace(bridge=sc.bridge.replace(spans=(2e6,))))
