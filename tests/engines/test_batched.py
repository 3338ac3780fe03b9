"""The batched PEM engine (tb_exudyn.engines.batched) against the Exudyn engine, its reference.

Agreement is measured per channel as max_t |sigma_batched - sigma_exudyn| / max_t sigma_exudyn
(and likewise for the PSD map, relative to the channel's largest PSD value); the acceptance bound
is 1e-6.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tb_exudyn.engines.alpha import GeneralizedAlpha
from tb_exudyn.errors import SettingError

from ..methods.test_pem import sprung_mass_scenario


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """Largest over channels (first axis) of max |a - b| / max |b|."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)  # float32 PSD: 1e-300 would underflow
    axes = tuple(range(1, b.ndim))
    return float(np.max(np.abs(a - b).max(axis=axes) / np.maximum(np.abs(b).max(axis=axes), 1e-300)))


def _quick_car15(track_offset: float | None = None, n_freq: int = 2):
    """One ICE motor car (car15) over one 32 m span at 250 km/h (scenario 'quick'), all channels."""
    import tb_exudyn as tbx

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("*",), n_freq=n_freq, freq_spacing="linear"))
    if track_offset is not None:
        sc = sc.replace(bridge=sc.bridge.replace(track_offset=track_offset))
    return sc


def _exudyn_reference(scenario, amplitude: float = 1e-5, rel: float = 1e-10, abs_: float = 1e-8):
    """sigma (n_ch, n_t), PSD (n_ch, n_f, n_t) and channels from the Exudyn engine (two real runs per
    type and frequency, from rest without gravity) at a working amplitude of 1e-5 m and Newton
    tolerances 1e-10 (relative) / 1e-8 N (absolute)."""
    from tb_exudyn.engines.exudyn_runs import SolverSettings
    from tb_exudyn.methods import run_pem

    sc = scenario.replace(analysis=scenario.analysis.replace(pem_amplitude=amplitude))
    r = run_pem(sc, workers=1, progress=False, engine="exudyn",
                options=SolverSettings(newton_relative_tolerance=rel, newton_absolute_tolerance=abs_), psd_channels="all")
    return r.std, r.psd, r.channels


# ------------------------------------------------------------------------------ no Exudyn needed
def test_batched_generalized_alpha_is_exudyns_scheme():
    """Problem: one undamped oscillator, one step of Exudyn's generalized-alpha (Arnold & Bruls'
    algorithm 1 as in CSolverImplicitSecondOrderTimeInt) written out in full: algorithmic
    acceleration, predictor, exact solve for the increment, corrector.

    References: (1) the Chung-Hulbert property of the parameter set alpha_m = (2 rho - 1) / (rho + 1),
    alpha_f = rho / (rho + 1): the spectral radius of the step's amplification matrix tends to rho
    for omega h -> infinity and to 1 for omega h -> 0 (checked at 1e6 and 1e-3: 1e-3 tolerance,
    the radius approaches rho like 1 / (omega h)^2 ... measured 7e-5); rho = 1 is the trapezoidal rule
    (alpha_m = alpha_f = gamma = 1/2, beta = 1/4, exact). (2) The engine's fused update (corrector
    plus next predictor) against the unfused step over 50 steps with forcing: equal to 1e-12
    relative (round-off of the rearranged sums).
    """
    for rho in (0.0, 0.5, 0.9, 1.0):
        ga = GeneralizedAlpha(rho, 1e-3)

        def step(s, k, f=0.0):
            q, v, qdd, a = s
            ap = (ga.alpha_f * qdd - ga.alpha_m * a) / (1 - ga.alpha_m)
            qp = q + ga.h * v + ga.h**2 * (0.5 - ga.beta) * a + ga.h**2 * ga.beta * ap
            vp = v + ga.h * (1 - ga.gamma) * a + ga.h * ga.gamma * ap
            d = (f - k * qp) / (ga.beta_p + k)
            qdd1 = ga.beta_p * d
            return np.array([qp + d, vp + ga.gamma_p * d, qdd1, ap + (1 - ga.alpha_f) / (1 - ga.alpha_m) * qdd1])

        for wh, expected in ((1e6, rho), (1e-3, 1.0)):
            k = (wh / ga.h) ** 2
            T = np.column_stack([step(e, k) for e in np.eye(4)])
            assert abs(np.abs(np.linalg.eigvals(T)).max() - expected) < 1e-3, (rho, wh)
        # fused update: state (q~, v~, a~) and Delta
        k, s = (2 * math.pi * 7.0) ** 2, np.array([0.0, 0.0, 0.0, 0.0])
        nu_a, nu_d, rho_a, rho_d, mu_a, mu_d = ga.update_coefficients()
        qp, vp, ap = ga.first_predictor(np.array(0.0))
        for n in range(1, 51):
            f = math.sin(0.3 * n)
            s = step(s, k, f)
            d = (f - k * qp) / (ga.beta_p + k)
            assert abs(qp + d - s[0]) <= 1e-12 * max(1e-12, abs(s[0])) + 1e-18
            qp, vp, ap = qp + ga.h * vp + nu_a * ap + nu_d * d, vp + rho_a * ap + rho_d * d, mu_a * ap + mu_d * d
    ga = GeneralizedAlpha(1.0, 1e-3)
    assert (ga.alpha_m, ga.alpha_f, ga.gamma, ga.beta) == (0.5, 0.5, 0.5, 0.25)


def test_run_pem_rejects_an_unknown_engine():
    """Problem: run_pem(engine="fast"). Reference: the documented values. Exact (an error)."""
    from tb_exudyn.methods import run_pem

    with pytest.raises(SettingError, match="'exudyn' or 'batched' or 'dense'"):
        run_pem(sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=2,
                                     channels=("*",)), engine="fast")


# ---------------------------------------------------------------------------------- with Exudyn
@pytest.mark.exudyn
def test_batched_components_of_the_eccentric_car():
    """Problem: the car15 over the span (scenario 'quick'), the track 2.5 m off the girder axis.

    Reference: the physics: the eccentric track couples the vertical and lateral motions, so the
    whole car and the bridge are one component that every kind excites; the longitudinal, wheelset
    spin and yaw coordinates (held by decoupled weak springs) are reached by no input and dropped.
    Exact (a partition).
    """
    from tb_exudyn.engines.batched import BatchedEngine

    engine = BatchedEngine(_quick_car15())
    assert len(engine.components) == 1 and engine.components[0].kinds == (0, 1, 2)
    assert engine.components[0].size < engine.lin.n


@pytest.mark.exudyn
def test_components_are_kept_by_their_inputs_and_found_again_when_these_change(monkeypatch):  # noqa: ANN001
    """Problem: find_components keeps its last results by a digest of its inputs (M, K0, D0, the
    bridge and wheel indices, the times, the coupling object), so a run's damping guard and its
    engine share one search. Reference: the search itself (_find_components). Exact: the same
    inputs give the same (immutable) components; changed matrices, other times or another coupling
    are searched again (here: K0 with a coupling term between a body coordinate and a wheelset's,
    which joins components, and half the times). The search's pass over the bridge parts is kept
    by what it reads (the coupling, the times, the indices): other matrices reuse it, other times
    do not (counted calls of the pass)."""
    import dataclasses

    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.system import components as C

    engine = BatchedEngine(_quick_car15(track_offset=0.0))
    lin, times = engine.lin, engine.output_time
    scans = []
    original = C._scan

    def counted(*args):  # noqa: ANN002, ANN202
        scans.append(1)
        return original(*args)

    monkeypatch.setattr(C, "_scan", counted)
    monkeypatch.setattr(C, "_SCANNED", type(C._SCANNED)())
    monkeypatch.setattr(C, "_FOUND", type(C._FOUND)())
    first = C.find_components(lin, times)
    again = C.find_components(lin, times)
    assert again == first and all(a is b for a, b in zip(again, first))
    assert repr(first) == repr(C._find_components(lin, times))
    assert not first[0].coords.flags.writeable
    K0 = lin.K0.copy()
    a, b = int(first[0].coords[-1]), int(first[1].coords[-1])  # one coordinate of each component
    K0[a, b] = K0[b, a] = 1e3 * max(abs(K0[a, a]), 1.0)
    joined = dataclasses.replace(lin, K0=K0)
    assert len(scans) == 1  # one pass for the search and the uncached search of the same inputs
    assert len(C.find_components(joined, times)) == len(C._find_components(joined, times)) < len(first)
    assert len(scans) == 1  # other matrices, the same coupling and times: the kept pass
    half = C.find_components(lin, times[: times.size // 2])
    assert len(scans) == 2
    assert repr(half) == repr(C._find_components(lin, times[: times.size // 2]))


@pytest.mark.exudyn
def test_batched_sprung_mass_over_span_agrees_with_exudyn_engine():
    """Problem: the damped VBI-2D sprung mass crosses the 25 m beam at 300 km/h after 60 m of
    approach (German low-interference vertical profile, 12 frequencies 1-20 Hz, every channel).

    Reference: run_pem with the Exudyn engine (default settings, working amplitude 1e-4 m; the
    model has no rotations, so it is linear). Tolerance 1e-6 of each channel's largest sigma
    (and PSD): what remains is Exudyn's Newton tolerance (relative 1e-8 on the residual); measured
    1.3e-7 (sigma) and 2e-7 (PSD, incl. its float32 transport). The batched engine's mean (its
    linear model under the gravity load, the default) against Exudyn's deterministic run: the
    same tolerance for the same reason (measured 1e-8); with the option mean = "exudyn" it is that
    very run (bitwise).
    """
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    sc = sprung_mass_scenario(lead_in=60.0, run_out=10.0, f_min=1.0, f_max=20.0, n_freq=12, channels=("*",))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_pem(sc, workers=1, progress=False, engine="exudyn", psd_channels="all")
        got = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all")
        exu = run_pem(sc.replace(analysis=sc.analysis.replace(n_freq=2)), workers=1, progress=False, engine="batched",
                      options=BatchedOptions(mean="exudyn"))
    assert got.channels == ref.channels and np.array_equal(got.time, ref.time)
    # the Sperling indices' PEM value includes the random part's power: compared as sigma is
    index = np.array([c.endswith((".sperling_z", ".sperling_y")) for c in ref.channels])
    assert _relative(got.mean[~index], ref.mean[~index]) < 1e-6  # the linear mean (measured 1e-8)
    assert np.array_equal(exu.mean[~index], ref.mean[~index]) and exu.provenance["mean_engine"] == "exudyn"
    finite = np.isfinite(ref.mean[index])
    assert np.array_equal(finite, np.isfinite(got.mean[index]))
    assert np.max(np.abs(got.mean[index][finite] / ref.mean[index][finite] - 1)) < 1e-6
    assert _relative(got.std, ref.std) < 1e-6
    assert _relative(got.psd, ref.psd) < 1e-6
    assert _relative(got.var_by_type, ref.var_by_type) < 2e-6
    assert got.provenance["engine"] == "batched" and got.provenance["mean_engine"].startswith("batched")


@pytest.mark.exudyn
def test_batched_car15_over_span_agrees_with_exudyn():
    """Problem: one ICE motor car (15-DOF car body and bogies, four wheelsets) over one 32 m span with
    the track 2.5 m off the girder axis, 250 km/h (scenario 'quick'), German low-interference vertical,
    alignment and cross-level spectra at 2 frequencies (0.6 and 30 Hz), all 120 channels.

    Reference: the Exudyn engine's pseudo-runs (real and imaginary run per type and frequency, reduced
    as run_pem does) at a working amplitude of 1e-5 m with Newton tolerances 1e-10 / 1e-8 N. At the
    default 1e-4 m the rigid bodies' nonlinearity (it scales with the amplitude) makes Exudyn differ
    from any linear model by up to 3.3e-6 (bogie accelerations), and the default Newton tolerances
    leave 4e-6 at 1e-5 m; tighter tolerances make Newton fail. Tolerance 1e-6 of each channel's
    largest sigma and PSD; measured 2.9e-7 (bridge torsion at midspan).
    """
    from tb_exudyn.methods import run_pem

    sc = _quick_car15()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        std, psd, names = _exudyn_reference(sc)
        got = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all")
    assert got.channels == names
    assert _relative(got.std, std) < 1e-6
    assert _relative(got.psd, psd) < 1e-6


@pytest.mark.exudyn
def test_batched_symmetric_car_splits_into_in_plane_and_out_of_plane_components():
    """Problem: as above with the track on the girder axis (track offset 0): a symmetric car on a
    symmetric track, whose vertical in-plane motion is independent of the lateral
    out-of-plane motion (left and right wheels' cross terms cancel).

    Reference: (1) the physics: the vertical profile excites only the in-plane part, alignment and
    cross-level only the out-of-plane part; (2) Exudyn pseudo-runs as in the previous test.
    Tolerance 1e-6 as there (measured 1.7e-7); the contact forces of the vertical contacts, shared
    by both components, carry the input once. (With the 0.6 Hz frequency alone the reference itself
    is uncertain to 2.5e-6 at best: Newton's absolute tolerance on the tiny bridge accelerations
    against the nonlinearity, 9e-6 at 1e-5 m, 7e-6 at 1e-4 m.)
    """
    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.methods import run_pem

    sc = _quick_car15(track_offset=0.0)
    engine = BatchedEngine(sc)
    assert sorted(c.kinds for c in engine.components) == [(0,), (1, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        std, psd, _ = _exudyn_reference(sc)
        got = run_pem(sc, workers=1, progress=False, engine="batched", psd_channels="all")
    assert _relative(got.std, std) < 1e-6
    assert _relative(got.psd, psd) < 1e-6


@pytest.mark.exudyn
def test_batched_result_is_the_same_for_workers_checkpoints_and_resume(tmp_path):
    """Problem: the sprung mass over the span, 6 frequencies, the mean and two column slices.

    Reference: the in-process run (workers=1). The slicing depends on neither workers nor
    executor, and the reduction is in task order, so results must be bitwise equal (tolerance
    zero): with 2 worker processes, when every task (the mean too) is read back from the checkpoint
    folder, and when one slice is missing and recomputed.
    """
    from tb_exudyn.methods import run_pem

    sc = sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6,
                              channels=("bridge.span1.mid.acc_z", "car1.body.acc_z", "car1.axle1.force_z"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        keep = {"keep_checkpoint": True, "psd_channels": "all"}
        ref = run_pem(sc, engine="batched", workers=1, progress=False, out=tmp_path, slices=(1, 1), **keep)
        again = run_pem(sc, engine="batched", workers=1, progress=False, out=tmp_path, resume=True, slices=(1, 1), **keep)
        # every task from the checkpoint: the mean, the 2 slices and the local grid-error estimate's
        # midpoint sweep of the cells it refines in 2 slices (its node sums come with the grid's slices)
        assert again.provenance["tasks_from_checkpoint"] == ref.provenance["tasks_run"] == 5
        sorted((tmp_path / "checkpoint" / "tasks").glob("*.npz"))[0].unlink()
        part = run_pem(sc, engine="batched", workers=1, progress=False, out=tmp_path, resume=True, slices=(1, 1), **keep)
        assert part.provenance["tasks_run"] == 1
        pool = run_pem(sc, engine="batched", workers=2, progress=False, slices=(1, 1), psd_channels="all")
        no_psd = run_pem(sc, engine="batched", workers=1, progress=False, slices=(1, 1), keep_psd=False)
    for r in (again, part, pool):
        for name in ("time", "mean", "std", "psd", "var_by_type"):
            assert np.array_equal(getattr(r, name), getattr(ref, name)), name
    assert no_psd.psd is None and np.array_equal(no_psd.std, ref.std)


@pytest.mark.exudyn
def test_batched_dask_executor_gives_the_same_result():
    """Problem: as above, on a Dask LocalCluster (2 worker processes) instead of the local pool.

    Reference: the in-process run; the tasks and their reduction order are the same, so the result
    must be bitwise equal (tolerance zero).
    """
    distributed = pytest.importorskip("distributed", reason="the 'dask' extra is not installed")
    from tb_exudyn.methods import run_pem

    sc = sprung_mass_scenario(lead_in=20.0, run_out=5.0, f_min=2.0, f_max=20.0, n_freq=6,
                              channels=("bridge.span1.mid.acc_z", "car1.body.acc_z"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_pem(sc, engine="batched", workers=1, progress=False, slices=(1, 1), psd_channels="all")
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster:
            with distributed.Client(cluster) as client:
                got = run_pem(sc, engine="batched", executor=client.get_executor(), progress=False, slices=(1, 1), psd_channels="all")
    for name in ("time", "mean", "std", "psd", "var_by_type"):
        assert np.array_equal(getattr(got, name), getattr(ref, name)), name


def test_grid_error_midpoints_in_float32_change_the_estimate_by_round_off_only():
    """The grid error's midpoint sweep runs in ``BatchedOptions.grid_error_precision`` (default
    float32; the grid's own columns stay float64).

    Problem: scenario 'quick' (one ICE motor car over one 32 m span, 250 km/h, its 51 channels) on a
    linear grid of 24 frequencies, PEM with the grid-error estimate, once with the midpoints in
    float64 (the reference) and once in float32. Expected: the grid's sigma bitwise the same (its
    columns are float64 in both), and the refined largest sigma per channel within 1e-4 of the
    float64 one. Tolerance: float32 round-off (6e-8) grows in the step's remainder of nearly balanced
    forces to about 1e-5 of a channel's largest sigma (1.1e-5 measured on the reference study,
    docs/speed.md); 1e-4 is a 10x margin and still 100x below the 1 % the estimate is read against.
    The float32 run must differ from float64 at all (else the option did nothing)."""
    import tb_exudyn as tbx
    from tb_exudyn.engines.batched import BatchedOptions

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(n_freq=24, freq_spacing="linear"))
    runs = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for p in ("float64", "float32"):
            runs[p] = tbx.run_pem(sc, engine="batched", workers=1, progress=False, grid_error=True,
                                  options=BatchedOptions(grid_error_precision=p))
    ref, f32 = runs["float64"], runs["float32"]
    np.testing.assert_array_equal(f32.std, ref.std)
    e64, e32 = (r.provenance["grid_error"]["channels"] for r in (ref, f32))
    assert f32.provenance["grid_error"]["method"].endswith("(the midpoints in float32)")
    assert ref.provenance["grid_error"]["method"].endswith("(the midpoints in float64)")
    # refined max sigma = max sigma / (1 + rel_error): compare the refined values relative to themselves
    s = ref.std.max(axis=1)
    refined = {p: s / (1.0 + np.array([e[c]["rel_error_max_sigma"] for c in ref.channels])) for p, e in
               (("float64", e64), ("float32", e32))}
    rel = np.abs(refined["float32"] - refined["float64"]) / np.maximum(refined["float64"], 1e-300)
    assert rel.max() < 1e-4
    assert rel.max() > 1e-12  # the midpoints did run in float32


def test_grid_error_precision_must_be_a_known_precision():
    """An unknown grid_error_precision is refused, naming the key and what is allowed."""
    from tb_exudyn.engines.batched import BatchedOptions

    with pytest.raises(SettingError, match="grid_error_precision.*float64.*float32"):
        BatchedOptions(grid_error_precision="float16")
