"""The cheaper set-up of a run with a track (issue 47, docs/track.md 7): the track model's linear system with the
body's known blocks inserted, the component scan that skips the couplings inside the track's modes, and the rail
shapes tabulated in the batched engine's basis. Each against the way it was computed before, on a small model.

The case: an ICE trailer (car15, li_zhu_2011's) over the tests' 10 m span with the ballasted track reaching 3 m
beyond it and its modes cut at 100 Hz (tests/engines/test_track_car15.py: about 120 modes), 220 km/h.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import exudyn as exu
import numpy as np
import pytest

from tb_exudyn.builder.linear import linear_system
from tb_exudyn.builder.model import build_model
from tb_exudyn.system import components
from tb_exudyn.system.conventions import scenario_steps

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "engines"))
from test_track_car15 import _case  # noqa: E402


@pytest.fixture(scope="module")
def model():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return build_model(_case("car15"), warn=False)


def test_the_track_bodys_known_blocks_give_exudyns_linearisation(model):
    """Reference: Exudyn's ComputeLinearizedSystem of the whole model, the body's object differentiated by Exudyn
    (what linearized_system returned before), at rest and about the static state (the coupling frozen at t = 0).
    The body's forces are linear, so Exudyn's finite differences of them are exact to round-off: measured 2.4e-19
    (K) and 3e-21 (D) of the largest entry at rest and about the static state alike; 1e-15 allows the round-off of
    a sum of a few entries. M is Exudyn's own in both (0 difference)."""
    assert model.bridge.coupled_damping is not None
    q_static = model.static_state(0.0)
    for state in (None, q_static):
        M, K, D = model.linearized_system(0.0, state)
        model._set_initial(np.zeros(model.n_ode2) if state is None else state, np.zeros(model.n_ode2))
        with model.coupling.frozen(0.0):
            ref = [np.asarray(a) for a in model.mbs.ComputeLinearizedSystem(exu.SimulationSettings())]
        model.reset("rest")
        for X, R in zip((M, K, D), ref):
            assert np.max(np.abs(X - R)) <= 1e-15 * np.max(np.abs(R))
    # the kept linearisation is handed out as a copy
    M, K, D = model.linearized_system(0.0)
    K[:] = 0.0
    assert np.max(np.abs(model.linearized_system(0.0)[1])) > 0.0


def test_the_scan_without_the_tracks_inner_couplings_finds_the_same_components(model, monkeypatch):
    """Reference: the scan summing every bridge-bridge coupling (``_joined_bridge`` returning None, as before).
    The components are compared exactly (coordinates, rows, vehicles, kinds): the same graph decides them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lin = linear_system(model)
    times = scenario_steps(model.scenario).output_times
    new = components._find_components(lin, times)
    monkeypatch.setattr(components, "_joined_bridge", lambda base, bridge: None)
    old = components._find_components(lin, times)
    assert len(new) == len(old) >= 1 and any(c.coupled for c in new)
    for a, b in zip(new, old):
        assert np.array_equal(a.coords, b.coords) and np.array_equal(a.rows, b.rows)
        assert (a.vehicles, a.kinds, a.coupled, a.n_bridge) == (b.vehicles, b.kinds, b.coupled, b.n_bridge)


def test_the_rail_shapes_in_a_basis_are_the_shapes_times_it(model):
    """Reference: the rail shapes of the modes times a basis X, S(x) X, at points on the rails, between their
    ends and beyond them (zero there). ``in_basis`` multiplies the rails' FE rows by X instead: the same sums in
    another order, so round-off: measured 4.6e-15 of the largest entry of a row kind (1e-13: the products' sums
    over 125 modes and 7 columns)."""
    fn = model.bridge.rail_shape_function
    rng = np.random.default_rng(5)
    X = rng.standard_normal((model.bridge.n_modes, 7))
    x = np.linspace(-20.0, 40.0, 301)
    a, b = fn(x), fn.in_basis(X)(x)
    for name in ("y", "z", "rx", "dy", "dz", "drx"):
        ref = getattr(a, name) @ X
        assert np.max(np.abs(getattr(b, name) - ref)) <= 1e-13 * max(np.max(np.abs(ref)), 1e-300)
