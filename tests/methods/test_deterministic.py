"""run_deterministic, TimeHistory files, summarize, solver settings and bad input."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("exudyn")

from tb_exudyn.scenario import ScenarioError
from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.results import TimeHistory, load_results  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, Scenario, SimpleBeam, SprungMass, Track, Train, load_vehicle  # noqa: E402
from tb_exudyn.engines.exudyn_runs import SimulationIncomplete, SolverSettings  # noqa: E402
from tb_exudyn.methods import run_deterministic, summarize  # noqa: E402
from tb_exudyn.system.conventions import number_of_steps  # noqa: E402

pytestmark = pytest.mark.exudyn


def _bridge() -> SimpleBeam:
    section = BeamSection(E=3.45e10, G=1.4375e10, area=8.9, I_y=10.947, I_z=86.216, J=22.65,
                          mass_per_length=3.39e4, rot_mass_per_length=3.8e5)
    return SimpleBeam(name="span32", spans=(32.0,), girder=section, damping_ratio=0.02, track_offset=2.5,
                      track_height=1.64)


def _scenario(vehicle=None, lead_in=50.0, **analysis) -> Scenario:
    vehicle = vehicle or SprungMass(name="sm", mass=20000.0, stiffness=2.0e6, damping=5.0e4, wheel_mass=1500.0,
                                    length=10.0)
    settings = dict(output_step=0.01, mode_max_frequency=40.0)
    settings.update(analysis)
    return Scenario(name="det", speed_kmh=180.0, train=Train(vehicles=(vehicle,)), bridge=_bridge(),
                    track=Track(lead_in=lead_in, run_out=5.0), analysis=Analysis(**settings))


def test_deterministic_run_gives_channels_units_provenance_and_files(tmp_path: Path):
    """A deterministic run of one sprung mass (with a wheel mass in stiff contact) over a 32 m span:
    output on the output grid up to a whole number of output steps covering the crossing, every
    channel with its unit, provenance with versions and steps; saved as npz (read with
    allow_pickle=False) + JSON and loaded back equal; summarize lists the peaks by group."""
    sc = _scenario(channels=("bridge.span1.mid.*", "car1.*"))
    th = run_deterministic(sc)
    assert isinstance(th, TimeHistory)
    n_out = number_of_steps(sc.duration, sc.analysis.output_step)
    assert th.time.size == n_out + 1
    assert np.allclose(th.time, np.arange(n_out + 1) * 0.01, atol=1e-12)
    assert th.provenance["steps"] == n_out * 10 and th.provenance["end_time_s"] == pytest.approx(n_out * 0.01)
    assert th.provenance["end_time_s"] >= sc.duration
    assert set(th.provenance["versions"]) >= {"tb_exudyn", "exudyn", "numpy", "scipy", "python"}
    assert th.names[0].startswith("bridge.span1.mid.") and "car1.axle1.force_z" in th.names
    assert th.units["car1.axle1.force_z"] == "N" and th.units["bridge.span1.mid.acc_rx"] == "rad/s^2"
    # the wheel carries the vehicle's weight at the start; the bridge sags under it later
    assert th["car1.axle1.force_z"][0] == pytest.approx(21500.0 * 9.81, rel=1e-9)
    assert th["bridge.span1.mid.disp_z"].min() < 0.0

    folder = th.save(tmp_path / "det")
    assert sorted(p.name for p in folder.iterdir()) == ["arrays.npz", "meta.json"]
    with np.load(folder / "arrays.npz", allow_pickle=False) as data:
        assert data["values"].shape == (len(th.names), th.time.size)
    meta = json.loads((folder / "meta.json").read_text())
    assert meta["format"] == "tb_exudyn.time_history/1"
    back = load_results(folder)
    assert isinstance(back, TimeHistory) and back.scenario == sc and back.names == th.names
    assert all(np.array_equal(back[n], th[n]) for n in th.names) and back.units == dict(th.units)

    text = summarize(th)
    assert "bridge.span1.mid:" in text and "car1.axle1:" in text and "car1.axle1.force_z" in text
    assert "us/step" in text


def test_model_reuse_and_scenario_mismatch():
    """run_deterministic re-runs a given built model (same result as building it anew); a model
    built from another scenario is refused."""
    sc = _scenario(channels=("car1.body.*",))
    model = build_model(sc, warn=False)
    a = run_deterministic(sc, model=model)
    b = run_deterministic(sc)
    assert all(np.allclose(a[n], b[n], rtol=0, atol=1e-12 * max(1.0, np.abs(b[n]).max())) for n in a.names)
    with pytest.raises(ValueError, match="a model built from this scenario"):
        run_deterministic(sc.replace(speed_kmh=200.0), model=model)


def test_run_that_stops_early_raises_a_clear_error():
    """Exudyn may stop a run before its end time (Newton failing); the run must say so with the
    time reached instead of returning a short history. Provoked with unreachable Newton tolerances."""
    sc = _scenario(channels=("car1.body.*",))
    impossible = SolverSettings(newton_relative_tolerance=1e-14, newton_absolute_tolerance=1e-14,
                                max_newton_iterations=2)
    with pytest.raises(SimulationIncomplete, match="before its end time"):
        run_deterministic(sc, settings=impossible)


def test_time_step_that_cannot_resolve_the_contact_is_warned_about():
    """A contact stiffness of 2e10 N/m per wheel gives the wheelset contact modes up to 690 Hz
    (roll on the two wheels, sqrt(2 k b^2 / I_roll) / 2 pi): fewer than 4 steps of 1 ms per period.
    The build warns, naming the frequency and the time step that would resolve it; the default
    2e9 N/m (218 Hz, 4.6 steps) passes without a warning."""
    motor = load_vehicle("ice_motor")
    sc = _scenario(motor, lead_in=100.0, contact_stiffness_z=2e10, contact_stiffness_y=2e10)
    with pytest.warns(UserWarning, match=r"wheel-rail contact mode.*Hz.*use analysis.time_step <="):
        build_model(sc)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_model(_scenario(motor, lead_in=100.0))  # the defaults are resolved: no warning


def test_scenario_without_lead_in_is_rejected_and_a_short_one_warned_about():
    """A train whose first axle reaches the bridge within 10 time steps has no approach to start
    on: rejected with a message naming track.lead_in and a sufficient length. A lead-in shorter than
    one period of the slowest vehicle mode is accepted with a warning (runs starting at rest do not
    settle before the bridge)."""
    motor = load_vehicle("ice_motor")
    with pytest.raises(ScenarioError, match=r"'track.lead_in' = 0.1.*no approach track.*allowed: >= "):
        build_model(_scenario(motor, lead_in=0.1))
    with pytest.warns(UserWarning, match=r"track.lead_in = 20 m.*slowest vehicle mode"):
        build_model(_scenario(motor, lead_in=20.0))


def test_solver_settings_are_validated():
    """Bad solver settings are refused with the name of the setting."""
    with pytest.raises(ValueError, match="newton_relative_tolerance"):
        SolverSettings(newton_relative_tolerance=0.0)
