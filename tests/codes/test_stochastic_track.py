"""The check's stochastic column on a track structure (issue 47, docs/track.md section 8).

The problem: the EN 1991-2 check of the tests' 10 m span of the VBI-2D girder (tests/builder/test_track_scenario.py;
its nominal mass case, prestressed concrete) at a line speed of 200 km/h for a one-car train, the ICE trailer (car15:
a wheel on each rail and a lateral contact), with the stochastic rows at 200 km/h on the scenario of
tests/engines/test_track_car15.py: the ballasted UIC60 track reaching 3 m before and after the span, its modes cut at
100 Hz, li_zhu_2011's three irregularities, here 2 frequencies. The reference: ``run_pem`` of the row's scenario with
the check's engine options (float32 columns), which solves its own track. About 3 s of CPU.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import pytest

from tb_exudyn.codes import check
from tb_exudyn.codes import stochastic as stoch
from tb_exudyn.execution.threads import single_threaded_blas
from tb_exudyn.methods import run_pem
from tb_exudyn.system import track_bridge

from ..recording import counted_track_solves

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "engines"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "builder"))
from test_track_car15 import _case  # noqa: E402

SPEED = 200.0
TRAIN = "one_trailer"
CRITERION = "en1990_deck/deck_acc_ballasted"
#: the row is run_pem of its scenario by construction (the same track, once kept by the check's plan, once solved
#: anew: the same code on the same data); the column slices of the check's run and of run_pem may differ, which
#: changes PEM's sums at round-off only (tests/codes/test_stochastic.py's SAME_PATH); measured: equal, bitwise
SAME_PATH = 1e-9


def _source():  # noqa: ANN202
    sc = _case("car15")
    return sc.replace(analysis=sc.analysis.replace(n_freq=2))


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    path = tmp_path_factory.mktemp("train") / "one_trailer.toml"
    path.write_text(f'name = "{TRAIN}"\ndescription = "one ICE trailer"\n[[cars]]\nvehicle = "ice_trailer"\n')
    source = _source()
    with counted_track_solves() as solved:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = check(source.bridge, SPEED, trains=[str(path)], cases=["nominal"], stochastic=True,
                           stochastic_speeds=[SPEED], stochastic_scenario=source, workers=1,
                           construction="prestressed_concrete")
    return result, solved


def test_the_row_with_a_track_equals_run_pem_of_its_scenario(checked):
    """The row's p_exceed, level_at_target, location and mean there against ``run_pem`` of the row's scenario (the
    track kept, 3 m of approach, 100 Hz) with the check's engine options, to SAME_PATH; the plan and the row's PEM
    (in this process) solved the track once."""
    result, solved = checked
    (row,) = result.stochastic_rows()
    sc = result.stochastic_scenario(TRAIN, SPEED)
    assert sc.track.structure == "ballasted_uic60" and sc.track.structure_approach == 3.0
    assert len(solved) == 1, solved
    track_bridge._LAST.clear()
    # the check solves the track while it plans, on one BLAS thread: the reference does too. On the default
    # threads the track's eigenvectors differ at round-off, which the float32 columns and the far tail
    # amplify (measured: p_exceed 6.5622e-36 against 6.5625e-36, 4.6e-5 relative; the same path, not the same bits)
    with warnings.catch_warnings(), single_threaded_blas():
        warnings.simplefilter("ignore")
        pem = run_pem(sc, workers=1, progress=False, options=stoch.engine_options("batched"))
    ref = next(r for r in pem.checks().worst() if r.criterion == CRITERION)
    assert row["stochastic_location"] == ref.channel
    assert row["p_exceed"] == pytest.approx(ref.probability, rel=SAME_PATH, abs=0.0)
    assert row["level_at_target"] == pytest.approx(ref.estimate, rel=SAME_PATH, abs=0.0)
    i = pem.index(ref.channel)
    assert row["stochastic_mean_acc"] == pytest.approx(float(abs(pem.mean[i]).max()), rel=SAME_PATH, abs=0.0)
    assert row["level_at_target"] > 0.0


def test_the_track_defaults_the_rows_take_are_said_and_carried(checked):
    """The scenario sets the track's cut-off and reach: no note. Left at their defaults (2000 Hz, rails under the
    whole run) the note names both keys, and a row's run carries it in its warnings (the check's output)."""
    result, _ = checked
    base = result.stochastic_scenarios[TRAIN]
    assert stoch.track_note(base) == ""
    assert not any("take the defaults" in w for w in result.warnings)
    default = base.replace(track=base.track.replace(structure_approach=0.0),
                           analysis=base.analysis.replace(track_mode_max_frequency=2000.0))
    note = stoch.track_note(default)
    assert "analysis.track_mode_max_frequency" in note and "track.structure_approach" in note, note
    assert "structure_approach" not in stoch.track_note(default.replace(track=base.track))
    assert stoch.track_note(default.replace(track=default.track.replace(structure=""))) == ""
    assert note in stoch.stochastic_run(default, [(SPEED, _summary(result))], "ballasted", TRAIN).warnings


def _summary(result):  # noqa: ANN001, ANN202
    """The row's speed summary again (the check keeps only its values): its PEM, as the check's task runs it."""
    from tb_exudyn.methods.sweep import SpeedTask, SpeedWorker, SWEEP_SLICES
    from tb_exudyn.execution import Task

    st = SpeedTask(result.stochastic_scenario(TRAIN, SPEED), "batched", stoch.engine_options("batched"), None, False,
                   SWEEP_SLICES, grid_error=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return SpeedWorker().work(None, Task("speed", st))
