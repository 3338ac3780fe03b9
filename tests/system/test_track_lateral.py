"""The rails' lateral bending (tb_exudyn.system.track_bridge, ``lateral=True``): each rail bends about its
vertical axis (the rail's I_lateral) on the pad's lateral spring, the half sleeper (slab share), and the
ballast's (mortar's) lateral spring to the ground off the bridge or to the deck's lateral rail level on it.

The case: the tests' 10 m span of the VBI-2D girder (tests/builder/test_track_scenario.py), 6 m of
approach, the deck's modes up to 1 kHz, the body reduced to its modes up to 2 kHz as a run does. The static
flexibility of the body's lateral rail shape y (the rails' centre line: a lateral force there loads each rail
by half) is sum_i y_i(x)^2 / omega_i^2 over the kept modes.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "builder"))
from test_track_scenario import _scenario, series, winkler_deflection  # noqa: E402

from tb_exudyn.builder.model import bridge_modes  # noqa: E402
from tb_exudyn.system.track_bridge import scenario_extent, track_and_deck  # noqa: E402


def _case(structure: str, stiff: bool, lateral_scale: float = 1.0):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sc = _scenario(stiff_deck=stiff, mode_max_frequency=1000.0)
        girder = sc.bridge.girder.replace(I_z=sc.bridge.girder.I_z * lateral_scale)
        sc = sc.replace(bridge=sc.bridge.replace(girder=girder), track=sc.track.replace(structure=structure))
        deck = bridge_modes(sc).on_track(1)
    ts, x0, n = scenario_extent(sc)
    return sc, deck, ts, x0, n


def _flexibility(body, xs: np.ndarray, row: str = "y") -> np.ndarray:  # noqa: ANN001
    return np.sum(getattr(body.rail_shapes(xs), row) ** 2 / body.omega ** 2, axis=1)


def _rail_winkler(ts) -> float:  # noqa: ANN001
    """Closed form: each rail an infinite beam (E I_lateral) on the lateral pad and ballast (mortar) in series
    per spacing; a unit force on the centre line puts 1/2 on each rail: y = (1/2) P beta / (2 k)."""
    lat = ts.lateral()
    k = series(*(k for k, _, _ in lat.chain("rigid"))) / ts.spacing
    return 0.5 * winkler_deflection(1.0, k, lat.rail.E * lat.rail.I)


@pytest.mark.parametrize("structure", ["ballasted_uic60", "slab_track"])
def test_the_static_lateral_rail_deflection_on_a_rigid_deck_and_off_it_against_a_winkler_beam(structure):
    """Above a sleeper on the deck (its girder 100 times stiffer: laterally rigid), mid-bay beside it, and
    above a sleeper 5 m before the bridge, against the Winkler beam of the lateral springs in series.
    Tolerance 3 %: the discrete supports against the smeared foundation (the vertical rail: about 1 %,
    docs/track.md 2; the lateral rail is softer in bending, so the position within a bay shows more) and the
    modes above 2 kHz left out (-0.3 % here against all modes). Measured (ballasted): -1.28 % above the sleeper
    on the deck, +1.42 % mid-bay, -1.27 % off the bridge; slab: -1.12 %, +1.61 %, -1.12 %."""
    sc, deck, ts, x0, n = _case(structure, stiff=True)
    a = ts.spacing
    on = x0 + (np.floor((5.0 - x0) / a) + 0.5) * a
    xs = np.array([on, on + 0.5 * a, x0 + (np.floor((-5.0 - x0) / a) + 0.5) * a])
    body = track_and_deck(ts, deck, x0, n, sc.track.half_gauge, lateral=True).bridge
    ratio = _flexibility(body, xs) / _rail_winkler(ts)
    assert np.all(np.abs(ratio - 1) < 0.03), ratio - 1
    assert ratio[1] > ratio[0]  # softer between the sleepers than above one


def test_the_lateral_rails_end_on_the_decks_lateral_rail_level():
    """The girder's lateral I_z / 300 (first lateral mode 5.6 Hz: the deck's lateral flexibility at mid-span
    8.95e-9 m/N, the rail's on rigid ground 1.33e-8): a lateral force on the rails at mid-span reaches the deck
    whole through the ballast, so the flexibility is the rail's plus the deck's point flexibility (the spread
    over about 1 m of a 10 m span changes the deck's by well under 1 %). Tolerance 3 %, as the rigid deck's;
    measured -1.0 % (2 kHz; -0.8 % with all modes). A ballast ending on rigid ground would miss the deck's 40 %.
    The vertical rail's static flexibility is that of the model without the lateral rails (the two directions
    meet only in the deck's modes): measured 5e-12 apart, asserted within 1e-6."""
    sc, deck, ts, x0, n = _case("ballasted_uic60", stiff=False, lateral_scale=1 / 300)
    a = ts.spacing
    xs = np.array([x0 + (np.floor((5.0 - x0) / a) + 0.5) * a])
    d = deck.rail_shapes(xs)
    f_deck = float(np.sum(d.y ** 2 / deck.omega ** 2))
    assert f_deck > 0.5 * _rail_winkler(ts)  # the deck's part is not negligible
    both = track_and_deck(ts, deck, x0, n, sc.track.half_gauge, lateral=True).bridge
    ratio = _flexibility(both, xs)[0] / (_rail_winkler(ts) + f_deck)
    assert abs(ratio - 1) < 0.03, ratio - 1
    vertical = track_and_deck(ts, deck, x0, n, sc.track.half_gauge).bridge
    assert _flexibility(both, xs, "z")[0] == pytest.approx(_flexibility(vertical, xs, "z")[0], rel=1e-6)
