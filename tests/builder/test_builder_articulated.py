"""The articulated set (vehicle kind ``articulated``): car bodies sharing their bogies (Jacobs bogies).

Problem: a set of 3 equal bodies (30 000 kg) on 4 bogies (2 500 kg) with
8 wheelsets (1 500 kg), the ICE trailer's suspension and inertia data, half pivot spacing 9.35 m
(pivots 18.7 m apart), half wheelbase 1.5 m, standing on the rigid approach track in static equilibrium
under g = 9.81 m/s^2 (the start of a deterministic run).
Reference: hand statics. A rigid body on two ends at +-9.35 m from its centre of gravity puts half its
weight on each end (moments about either end), whatever the springs (the two sides of an end carry
equal loads by the lateral symmetry); an end bogie then carries half a body, an inner bogie one half of
each neighbour, plus its own mass; its two axles, symmetric about its centre, share that equally, and
each wheelset adds its own weight: axle loads (15 000 + 2 500) g / 2 + 1 500 g = 100.55 kN at the end
bogies, (30 000 + 2 500) g / 2 + 1 500 g = 174.13 kN at the inner ones; each wheel half of that.
The same loads as the train view of codes.trains (an articulated set of axle loads).
Tolerance 1e-9 of the axle load: round-off of the static solve (a linear solve of the stiff contact and
suspension matrix, condition ~1e6, at ~1e-16).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("exudyn")

from tb_exudyn.builder import build_model  # noqa: E402
from tb_exudyn.engines.exudyn_runs import run_model  # noqa: E402
from tb_exudyn.scenario import Analysis, BeamSection, Scenario, SimpleBeam, Track, Train  # noqa: E402
from tb_exudyn.scenario.model import ArticulatedSet  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

G = 9.81
BODY, BOGIE, WHEELSET = 30000.0, 2500.0, 1500.0


def _set(ice_trailer) -> ArticulatedSet:
    g = ice_trailer.geometry.replace(half_bogie_spacing=9.35, half_wheelbase=1.5, length=3 * 18.7 + 3.0 + 4.0)
    return ArticulatedSet(
        name="three_bodies", bodies=3, body=ice_trailer.body.replace(mass=BODY),
        bogie=ice_trailer.bogie.replace(mass=BOGIE), wheelset=ice_trailer.wheelset.replace(mass=WHEELSET),
        geometry=g, primary=ice_trailer.primary, secondary=ice_trailer.secondary)


def _scenario(veh) -> Scenario:
    section = BeamSection(E=3.45e10, G=1.4375e10, area=8.9, I_y=10.947, I_z=86.216, J=22.65,
                          mass_per_length=3.39e4, rot_mass_per_length=3.8e5)
    return Scenario(name="articulated", speed_kmh=200.0, train=Train(vehicles=(veh,)),
                    bridge=SimpleBeam(name="span32", spans=(32.0,), girder=section),
                    track=Track(lead_in=80.0, run_out=10.0), analysis=Analysis(gravity=G, mode_max_frequency=60.0))


def test_static_axle_loads_of_shared_bogies(ice_trailer):
    veh = _set(ice_trailer)
    assert veh.axle_offsets == pytest.approx((0.0, 3.0, 18.7, 21.7, 37.4, 40.4, 56.1, 59.1), abs=1e-12)
    sc = _scenario(veh)
    modes = simply_supported_modes((32.0,), 3.45e10 * 10.947, 3.45e10 * 86.216, 1.4375e10 * 22.65, 3.39e4, 3.8e5,
                                   0.0, 60.0)
    model = build_model(sc, modal_bridge=modes, warn=False)
    names = [b.name for b in model.parts.bodies]
    assert [n for n in names if ".body" in n] == ["car1.body1", "car1.body2", "car1.body3"]
    assert sum(".bogie" in n for n in names) == 4 and sum(".axle" in n for n in names) == 8
    th, _ = run_model(model, None, gravity=True, initial="static", duration=0.02)
    end, inner = ((BODY / 2 + BOGIE) / 2 + WHEELSET) * G, ((BODY + BOGIE) / 2 + WHEELSET) * G
    want = [end] * 2 + [inner] * 4 + [end] * 2
    got = [th[f"car1.axle{k}.left.force_z"][0] + th[f"car1.axle{k}.right.force_z"][0] for k in range(1, 9)]
    np.testing.assert_allclose(got, want, rtol=1e-9)
    for k in range(1, 9):  # left and right alike (lateral symmetry)
        assert th[f"car1.axle{k}.left.force_z"][0] == pytest.approx(th[f"car1.axle{k}.right.force_z"][0], rel=1e-9)
    assert sum(got) == pytest.approx(sc.train.mass * G, rel=1e-12)


def test_labels_of_an_articulated_set():
    from tb_exudyn.system.labels import channel_label

    assert channel_label("car1.body2.acc_z") == "car 1, body 2, vertical acceleration"
    assert channel_label("car1.bogie3.disp_y") == "car 1, bogie 3, lateral displacement"
