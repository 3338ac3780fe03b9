"""Static equilibrium: the start of every deterministic run, and a car standing on the bridge."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("exudyn")

from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, Scenario, SimpleBeam, SprungMass, Track, Train  # noqa: E402
from tb_exudyn.engines.exudyn_runs import run_model  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

L, EI, MU, G = 32.0, 3.45e10 * 10.947, 3.39e4, 9.81
F_MAX = 200.0


def _bridge() -> SimpleBeam:
    section = BeamSection(E=3.45e10, G=1.4375e10, area=8.9, I_y=10.947, I_z=86.216, J=22.65,
                          mass_per_length=MU, rot_mass_per_length=3.8e5)
    return SimpleBeam(name="span32", spans=(L,), girder=section)


def _modes():
    return simply_supported_modes((L,), EI, 3.45e10 * 86.216, 1.4375e10 * 22.65, MU, 3.8e5, 0.0, F_MAX)


def _scenario(vehicles, lead_in=60.0, channels=("*",)) -> Scenario:
    return Scenario(name="static", speed_kmh=200.0, train=Train(vehicles=tuple(vehicles)), bridge=_bridge(),
                    track=Track(lead_in=lead_in, run_out=10.0),
                    analysis=Analysis(gravity=G, mode_max_frequency=F_MAX, channels=channels))


def test_static_start_carries_the_train_weight_and_does_not_bounce(ice_motor, ice_trailer):
    """Exact problem: an ICE motor car and a trailer standing on the rigid approach track in
    static equilibrium (the initial state of a deterministic run), then 0.1 s of the run on the
    approach. Reference: statics: the vertical wheel loads sum to the train's weight
    (48000 + 2 3200 + 4 2400 + 44000 + 2 2400 + 4 2400) g, and a true equilibrium does not move.
    Tolerance: 1e-9 of the weight (round-off of the linear solve); motion below 1e-9 m and
    1e-6 m/s^2 (Newton's residual tolerance)."""
    sc = _scenario([ice_motor, ice_trailer])
    model = build_model(sc, modal_bridge=_modes(), warn=False)
    th, _ = run_model(model, None, gravity=True, initial="static", duration=0.1)
    loads = sum(th[n] for n in th.select("*.force_z"))
    weight = sc.train.mass * G
    assert np.abs(loads - weight).max() <= 1e-9 * weight
    assert len(th.select("*.force_z")) == 16
    for name in th.select("car*.disp_*"):
        assert np.abs(th[name] - th[name][0]).max() <= 1e-9, name
    for name in th.select("car*.acc_*"):
        assert np.abs(th[name]).max() <= 1e-6, name
    # the bodies really sag: the body rests on both suspension stages in series
    k_series = 1.0 / (1.0 / (4 * 4.0e5) + 1.0 / (8 * 1.04e6))
    assert th["car1.body.disp_z"][0] < -0.9 * 48000 * G / k_series
    # the bridge starts (and stays, with every wheel on the approach) unloaded at rest
    assert all(np.all(th[n] == 0.0) for n in th.select("bridge.*"))


def test_sprung_mass_standing_at_midspan_deflects_as_the_modal_static_solution():
    """Exact problem: one sprung mass (5750 kg, wheel mass 500 kg) standing at midspan of a simply
    supported 32 m span; the midspan deflection. Reference: the static modal solution with the
    same modes, written here: w = sum_j phi_j(L/2)^2 P / omega_j^2, phi_j = sqrt(2/(m L))
    sin(j pi x / L), P = (5750 + 500) g (statically determinate); and, as a check of the modes,
    P L^3 / (48 EI) within the truncation of the vertical modes below 200 Hz. Tolerance 1e-9
    relative (a linear solve; round-off), 2 % against the infinite series."""
    veh = SprungMass(name="sm", mass=5750.0, stiffness=1.6e6, wheel_mass=500.0, length=10.0)
    sc = _scenario([veh], lead_in=20.0)
    model = build_model(sc, modal_bridge=_modes(), warn=False)
    t_mid = (sc.track.lead_in + L / 2) / sc.speed
    u = model.static_state(t_mid)
    q = u[model.node_indices(model.bridge_node)]
    mid = model.bridge.station_names.index("span1.mid")
    w_model = model.bridge.station_shapes[mid, 1] @ q
    P = (5750.0 + 500.0) * G
    j = np.arange(1, 200)
    om = (j * math.pi / L) ** 2 * math.sqrt(EI / MU)
    keep = om / (2 * math.pi) <= F_MAX
    phi_mid = math.sqrt(2.0 / (MU * L)) * np.sin(j * math.pi / 2)
    w_ref = -np.sum((phi_mid**2 * P / om**2)[keep])
    assert w_model == pytest.approx(w_ref, rel=1e-9)
    assert w_model == pytest.approx(-P * L**3 / (48 * EI), rel=0.02)


def _planar_car_on_beam(car, x_centre: float, k_contact: float) -> float:
    """Independent static reference: the car's vertical plane (body z and pitch, bogies z and
    pitch, four wheelsets z) on springs (secondary 2 k_z per bogie, primary 2 k_z per axle, contact
    2 k_c per wheelset) over the modal beam (vertical modes <= F_MAX, closed form written here);
    gravity on every mass. Returns the midspan deflection [m]."""
    g = car.geometry
    s, a = g.half_bogie_spacing, g.half_wheelbase
    j = np.arange(1, 200)
    om = (j * math.pi / L) ** 2 * math.sqrt(EI / MU)
    j, om = j[om / (2 * math.pi) <= F_MAX], om[om / (2 * math.pi) <= F_MAX]
    phi = lambda x: math.sqrt(2.0 / (MU * L)) * np.sin(j * math.pi * x / L)  # noqa: E731
    nb = j.size
    n = 10 + nb  # zc, pc, zt1, pt1, zt2, pt2, zw1..zw4, q
    K = np.zeros((n, n))
    F = np.zeros(n)

    def spring(k: float, row: np.ndarray) -> None:
        K[:, :] += k * np.outer(row, row)

    x_bogie = (s, -s)
    for i, xb in enumerate(x_bogie):
        r = np.zeros(n)
        r[0], r[1], r[2 + 2 * i] = 1.0, xb, -1.0  # body point above bogie i minus bogie centre
        spring(2 * car.secondary.k_z, r)
        for m, xa in enumerate((a, -a)):
            w = 6 + 2 * i + m
            r = np.zeros(n)
            r[2 + 2 * i], r[3 + 2 * i], r[w] = 1.0, xa, -1.0
            spring(2 * car.primary.k_z, r)
            r = np.zeros(n)
            r[w] = 1.0
            r[10:] = -phi(x_centre + xb + xa)
            spring(2 * k_contact, r)
    K[10:, 10:] += np.diag(om**2)
    F[0] = -car.body.mass * G
    F[2] = F[4] = -car.bogie.mass * G
    F[6:10] = -car.wheelset.mass * G
    u = np.linalg.solve(K, F)
    return float(phi(L / 2) @ u[10:])


def test_car_standing_at_midspan_deflects_as_the_modal_static_solution(ice_motor):
    """Exact problem: an ICE motor car standing with its centre at midspan of a simply supported
    32 m span (track on the girder axis), contact stiffness 2e9 N/m per wheel; the midspan
    deflection. Reference: the independent planar static model above (same vertical modes,
    statically indeterminate: the axle loads follow from the suspension and contact stiffness).
    Tolerance 1e-8 relative: both are exact linear solves of the same linear problem, the Exudyn
    stiffness coming from its own linearisation (round-off of a K with entries from 1e5 to 1e10)."""
    sc = _scenario([ice_motor], lead_in=20.0)
    model = build_model(sc, modal_bridge=_modes(), warn=False)
    centre_offset = ice_motor.geometry.half_bogie_spacing + ice_motor.geometry.half_wheelbase
    t = (sc.track.lead_in + centre_offset + L / 2) / sc.speed
    u = model.static_state(t)
    q = u[model.node_indices(model.bridge_node)]
    mid = model.bridge.station_names.index("span1.mid")
    w_model = model.bridge.station_shapes[mid, 1] @ q
    w_ref = _planar_car_on_beam(ice_motor, L / 2, sc.analysis.contact_stiffness_z)
    assert w_model == pytest.approx(w_ref, rel=1e-8)
    # the car's weight is on the bridge: about the central load's deflection
    P = (48000.0 + 2 * 3200.0 + 4 * 2400.0) * G
    assert 0.5 < w_model / (-P * L**3 / (48 * EI)) < 1.0


def test_static_start_on_an_irregular_track_starts_without_a_contact_jolt(ice_motor):
    """Exact problem: the ICE motor car starting in static equilibrium on the approach track with a
    vertical profile and an alignment of 1 mm amplitude under its wheels (a Monte Carlo sample's
    start). Reference: statics: at t = 0 the vertical wheel loads still sum to the weight, and the
    lateral ones to zero, because the wheels start moving with the rail (no damper force from the
    input rate; a wheel at rest on a sloped profile would see c v slope = 1.5e6 * 0.04 = 60 kN).
    Tolerance 1e-6 of the weight (Newton's residual in the first step does not enter t = 0).
    The irregularity taper is switched off (taper_length = 0) so that the input is not zero at t = 0."""
    from tb_exudyn.builder import ProfileExcitation

    om = 2 * math.pi / 10.0
    exc = ProfileExcitation(vertical=lambda x: (1e-3 * np.sin(om * x), 1e-3 * om * np.cos(om * x)),
                            alignment=lambda x: (1e-3 * np.cos(om * x), -1e-3 * om * np.sin(om * x)))
    sc = _scenario([ice_motor])
    sc = sc.replace(track=sc.track.replace(taper_length=0.0))
    model = build_model(sc, modal_bridge=_modes(), warn=False)
    th, _ = run_model(model, exc, gravity=True, initial="static", duration=0.02)
    weight = sc.train.mass * G
    assert abs(sum(th[n][0] for n in th.select("*.force_z")) - weight) <= 1e-6 * weight
    assert abs(sum(th[n][0] for n in th.select("*.force_y"))) <= 1e-6 * weight
    assert np.abs(th["car1.axle1.vel_z"][0]) > 1e-3  # the wheel really starts moving with the rail
