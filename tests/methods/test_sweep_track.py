"""The speed sweep with a track structure (issue 47, docs/track.md section 8).

The problem: the Yang & Yau sprung mass over the tests' 10 m span of the VBI-2D girder
(tests/builder/test_track_scenario.py), the ballasted UIC60 track reaching 3 m before and after the span
(``track.structure_approach``) with its modes cut at 100 Hz (the left-out modes' static flexibility in series
with the contact), PEM at 2 frequencies (20-40 Hz at 180 km/h), swept at 180 and 200 km/h on the batched engine.
The speed rule scales the lead-in (6 m -> 6.67 m), so the run's start moves; the cut rails are placed by the
bridge, so both speeds have the same track, which the sweep's parent solves once. About 2 s of CPU.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn import run_pem
from tb_exudyn.methods.sweep import SWEEP_SLICES, run_sweep, sweep_scenario
from tb_exudyn.system import track_bridge

from ..recording import counted_track_solves

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "builder"))
from test_track_scenario import _scenario  # noqa: E402

SPEEDS = (180.0, 200.0)
#: a sweep's row and run_pem at its speed are the same computation on the same track (the one the sweep's parent
#: solved, against the one run_pem solves anew: the same code on the same data in one process); what may differ is
#: round-off (BLAS kernels on another alignment): 1e-12 of each channel's value (measured: 0, bitwise)
ROUND_OFF = 1e-12


def _base():  # noqa: ANN202
    sc = _scenario(track_mode_max_frequency=100.0, n_freq=2, freq_min=20.0, freq_max=40.0).replace(speed_kmh=180.0)
    return sc.replace(track=sc.track.replace(structure_approach=3.0))


@pytest.fixture(scope="module")
def swept():
    with counted_track_solves() as solved:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sweep = run_sweep(_base(), SPEEDS, engine="batched", workers=1, progress=False)
    return sweep, solved


def test_the_speeds_share_one_track_solved_once(swept):
    """The lead-in differs between the speeds (the speed rule keeps its time), the cut track does not: the same
    extent at both, and the sweep (its parent's channel list and both speeds' PEM, in this process) solves the
    track-and-deck modes and the static correction once."""
    sweep, solved = swept
    base = _base()
    scenarios = [sweep_scenario(base, v) for v in SPEEDS]
    assert scenarios[0].track.lead_in != scenarios[1].track.lead_in
    extents = {track_bridge.scenario_extent(sc)[1:] for sc in scenarios}
    assert len(extents) == 1, extents
    assert len(solved) == 1, solved


def test_a_sweep_row_with_a_track_is_run_pem_at_its_speed(swept):
    """Each speed's row (max |mean|, max sigma, max |mean| + 3 sigma per channel) against ``run_pem`` of the
    sweep's scenario at that speed (the same slices), which solves its own track (the cache emptied): equal to
    ROUND_OFF. The rows see the track: the contact force's sigma differs between the speeds."""
    sweep, _ = swept
    patterns = [q[1] for q in sweep.quantities]
    sigma = []
    for v, s in zip(sweep.speeds, sweep.summaries):
        track_bridge._LAST.clear()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = run_pem(sweep_scenario(_base(), v, patterns), engine="batched", workers=1, progress=False,
                        slices=SWEEP_SLICES)
        names = [str(c) for c in s["channels"]]
        assert names == list(r.channels)
        for i, c in enumerate(names):
            ref = r[c]
            for got, want in ((s["max_sigma"][i], ref.std.max()), (s["max_abs_mean"][i], np.abs(ref.mean).max()),
                              (s["max_design"][i], (np.abs(ref.mean) + 3.0 * ref.std).max())):
                assert float(got) == pytest.approx(float(want), rel=ROUND_OFF, abs=0.0), (v, c)
        sigma.append(float(s["max_sigma"][names.index("car1.axle1.force_z")]))
    assert sigma[0] != sigma[1] and min(sigma) > 0.0


def test_a_workers_set_up_keeps_the_parents_track(monkeypatch):
    """What a worker process gets: the parent's track (``shared_tracks``, after the parent built the base's model),
    pickled as the pool sends it; after the worker's set-up (``SpeedWorker.setup``) a build at the other speed
    takes it and solves nothing. (In a spawned process the same was measured: 0 solves with it, 1 without.)"""
    import pickle

    from tb_exudyn.builder.model import build_model
    from tb_exudyn.methods.sweep import SpeedWorker, shared_tracks

    base = _base()
    monkeypatch.setattr(track_bridge, "_LAST", {})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        build_model(base, warn=False)
        entries = shared_tracks(base, [sweep_scenario(base, v) for v in SPEEDS])
        assert len(entries) == 1
        assert shared_tracks(base.replace(track=base.track.replace(structure="")), []) == ()
        track_bridge._LAST.clear()
        SpeedWorker(pickle.loads(pickle.dumps(entries))).setup()
        solved = []
        monkeypatch.setattr(track_bridge, "track_and_deck", lambda *a, **k: solved.append(1))
        model = build_model(sweep_scenario(base, SPEEDS[1]), warn=False)
    assert solved == [] and model is not None
    assert repr(SpeedWorker(entries)) == repr(SpeedWorker())  # the set-up cache's key: the track not in it
