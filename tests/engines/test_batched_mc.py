"""Monte Carlo of the linear model on the batched engine (tb_exudyn.methods.monte_carlo, engine "batched").

The linear Monte Carlo draws exactly the Exudyn Monte Carlo's samples (same sampler, same
``sample_rng(seed, k)``), so most checks compare sample by sample with Exudyn runs. Differences are
measured per channel as max over samples and times of |y_linear - y_exudyn| / (the Exudyn
channel's largest sigma, or its largest response for single runs).

Problem for most tests: the damped VBI-2D sprung mass over the 25 m VBI-2D beam at 300 km/h on
the German low-interference vertical profile (``mc_scenario`` of test_monte_carlo: 8 PEM
frequencies 1-20 Hz, time step 2 ms). Its Exudyn model has no rotations, so it is exactly linear:
the two engines differ only by Exudyn's Newton tolerance.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.stats import chi2

from tb_exudyn.results.compare import compare
from tb_exudyn.errors import SettingError
from tb_exudyn.methods import run_monte_carlo
from tb_exudyn.methods.monte_carlo import LossOfContactWarning, integrate_samples, sample_blocks
from tb_exudyn.methods.sampling import ProfileSampler

from ..methods.test_monte_carlo import CHANNELS, mc_scenario

N_LARGE = 400
#: derived channels that are not linear in the irregularity (tb_exudyn.system.derived)
NONLINEAR_DERIVED = (".unloading", ".derailment", ".sperling_z", ".sperling_y")


def _worst(a: np.ndarray, b: np.ndarray, scale: np.ndarray) -> tuple[float, int]:
    """Largest over channels of max |a - b| (over samples and times) / scale; and its channel."""
    d = np.abs(a - b).max(axis=(0, 2)) / np.maximum(scale, 1e-300)
    d = np.where(scale > 0, d, 0.0)
    return float(d.max()), int(np.argmax(d))


@pytest.fixture(scope="module")
def scenario():
    return mc_scenario()


@pytest.fixture(scope="module")
def small(scenario):
    """Six samples in this process, samples kept, three blocks (tasks) of two."""
    return run_monte_carlo(scenario, n_samples=6, seed=3, workers=1, progress=False, keep_samples=True,
                           slices=(1, 1, 1), engine="batched")


def _same(a, b, samples=True):
    assert a.channels == b.channels
    for name in ("time", "mean", "std", "mean_ci", "std_ci", "min_wheel_force") + (("samples",) if samples else ()):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


# ------------------------------------------------------------------------------ against Exudyn
@pytest.mark.exudyn
def test_linear_samples_are_the_exudyn_samples_of_the_sprung_mass():
    """Problem: as the module's, all 31 channels, samples 0-4 of seed 3.

    Reference: the Exudyn Monte Carlo with the same seed (one Exudyn run per sample, gravity, static
    start). The sprung-mass model is linear, so every sample must agree; tolerance 1e-5 of each
    channel's largest sigma: what remains is Exudyn's Newton tolerance (relative 1e-8 of the residual,
    which includes the 56 kN weight). Measured 1.7e-6 (midspan acceleration), below 4e-7 elsewhere.
    The sample mean, sigma and each sample's minimum wheel force agree alike (the linear engine's
    mean is its own linear model under the gravity load, the default: exact for this linear model).
    """
    sc = mc_scenario(channels=("*",))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_monte_carlo(sc, n_samples=5, seed=3, workers=1, progress=False, keep_samples=True, engine="exudyn")
        lin = run_monte_carlo(sc, n_samples=5, seed=3, workers=1, progress=False, keep_samples=True, engine="batched")
    assert lin.method == "monte_carlo_linear" and ref.method == "monte_carlo"
    assert lin.channels == ref.channels and np.array_equal(lin.time, ref.time)
    scale = ref.std.max(axis=1)
    worst, i = _worst(lin.samples, ref.samples, scale)
    assert worst < 1e-5, (ref.channels[i], worst)
    assert _worst(lin.std[None], ref.std[None], scale)[0] < 1e-5
    assert _worst(lin.mean[None], ref.mean[None], scale)[0] < 1e-5
    assert np.allclose(lin.min_wheel_force, ref.min_wheel_force, rtol=0, atol=1e-8 * 5750 * 9.81)
    p = lin.provenance
    assert p["engine"] == "batched" and p["mean_engine"].startswith("batched") and p["model"].startswith("linear")


@pytest.mark.exudyn
def test_car15_sample_is_exudyns_tangent_model():
    """Problem: one ICE motor car (car15, 15 DOF plus wheelsets) over one 32 m span with the track
    2.5 m off the girder axis at 250 km/h (scenario 'quick'), German low vertical, alignment and
    cross-level profiles: sample 0 of seed 5, all 120 channels and the linear and weighted derived ones.

    Reference: Exudyn runs from rest without gravity on the same sample's profiles scaled by s = 0.1
    and 0.01 (divided by s), the linear model being Exudyn's model linearised about that rest state.
    The rigid bodies' finite rotations make Exudyn differ from its tangent model in proportion to the
    amplitude: measured 2.8e-2 of the largest response (bogie pitch acceleration) at the sample's
    full amplitude, 2.8e-3 at s = 0.1 and 2.8e-4 at s = 0.01. Tolerance: below 1e-3 at s = 0.01, and
    the ratio of the differences at 0.1 and 0.01 within 10 +- 1.5 (a first-order, not a zeroth-order,
    difference: a wrong input, sign or slope would not shrink with s).
    """
    import tb_exudyn as tbx
    from tb_exudyn.builder import build_model
    from tb_exudyn.system.excitation import ProfileExcitation
    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.engines.exudyn_runs import run_model

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("*",), freq_spacing="linear", n_freq=16))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bm = BatchedEngine(sc, wheel_forces=True)
        sampler = ProfileSampler(sc)
        y_lin = integrate_samples(bm, sampler, 5, [0], keep_samples=True)["samples"][0]
        model = build_model(sc, warn=False)
    exc = sampler.columns(5, [0]).excitation(0)

    def scaled(profile, s):
        return lambda x: tuple(s * a for a in profile(x))

    diff = {}
    for s in (0.1, 0.01):
        e = ProfileExcitation(**{k: scaled(getattr(exc, k), s) for k in ("vertical", "alignment", "cross_level")},
                              cross_level_unit=exc.cross_level_unit)
        th, _ = run_model(model, e, gravity=False, initial="rest")
        # the ratios (Q/P, dP/P: no wheel load without gravity) and Sperling indices are not linear in s
        keep = [k for k, n in enumerate(th.names) if not n.endswith(NONLINEAR_DERIVED)]
        y = np.stack([th.channels[th.names[k]] for k in keep]) / s
        diff[s] = _worst(y_lin[None, keep], y[None], np.abs(y).max(axis=1))
    assert diff[0.01][0] < 1e-3, diff
    assert 8.5 < diff[0.1][0] / diff[0.01][0] < 11.5, diff


# ------------------------------------------------------------------------------ against PEM
@pytest.mark.exudyn
def test_sigma_agrees_with_pem_within_the_sampling_error(scenario):
    """N = 400 samples (seed 1, 2 workers) against PEM (batched engine, same grid): the sampled
    process is the discretised spectrum PEM analyses exactly. Tolerance as for the Exudyn Monte
    Carlo (test_monte_carlo): each time point within 3/sqrt(2N) = 10.6 % with probability >= 99.7 %,
    asked at 95 % of the compared times (they are correlated), median ratio within 3/sqrt(2N) of 1.
    The sample mean against the deterministic run: |z| <= 3 at 90 % of the times and <= 5 everywhere.
    These samples are the Exudyn Monte Carlo's, so the measured figures equal that test's.
    """
    from tb_exudyn.methods import run_pem

    pem = run_pem(scenario, workers=2, progress=False, engine="batched")
    mc = run_monte_carlo(scenario, n_samples=N_LARGE, seed=1, workers=2, progress=False, engine="batched")
    comparison = compare(pem, mc, k=3.0, threshold=0.05, t_min=0.0)
    for row in comparison.rows:
        assert row.n_times > 20, row
        assert row.inside >= 0.95, comparison.table()
        assert abs(row.ratio_median - 1) < 3 / math.sqrt(2 * N_LARGE), comparison.table()
        assert row.mean_inside >= 0.90 and row.mean_z_max <= 5.0, comparison.table()
    assert {r.channel for r in comparison.rows} == set(CHANNELS)
    assert mc.provenance["samples_with_loss_of_contact"] == 0 and np.all(mc.min_wheel_force > 0)


# ------------------------------------------------------------------------------ reduction, execution
@pytest.mark.exudyn
def test_reduction_matches_numpy_on_the_kept_samples(small):
    """The blockwise reduction (two-pass per block, merged in block order) against numpy on the kept
    samples: mean and std (ddof = 1) to 1e-12 of the channel's scale; intervals by definition."""
    y, n = small.samples, small.n_samples
    assert y.shape == (6, len(CHANNELS), small.time.size) and small.provenance["sample_blocks"] == [[0, 2], [2, 4], [4, 6]]
    scale = np.abs(y).max(axis=(0, 2))[:, None]
    assert np.all(np.abs(small.mean - y.mean(axis=0)) <= 1e-12 * scale)
    assert np.all(np.abs(small.std - y.std(axis=0, ddof=1)) <= 1e-12 * scale)
    half = 1.959964 * small.std / math.sqrt(n)
    assert np.allclose(small.mean_ci, [small.mean - half, small.mean + half], rtol=1e-6, atol=0)
    lo = small.std * math.sqrt((n - 1) / chi2.isf(0.025, n - 1))
    assert np.allclose(small.std_ci[0], lo, rtol=1e-12, atol=0)
    force = y[:, small.index("car1.axle1.force_z")].min(axis=1)
    assert np.array_equal(small.min_wheel_force, force)


@pytest.mark.exudyn
def test_workers_checkpoints_and_resume_give_the_same_result(scenario, small, tmp_path):
    """Same blocks on 2 workers, and a resume that recomputes one deleted block: bitwise the same
    (tolerance zero: the blocks are deterministic and merged in order). An odd sample count pads a
    zero sample that is not counted. Other blocks change the result at round-off only."""
    kw = dict(n_samples=6, seed=3, progress=False, keep_samples=True, slices=(1, 1, 1), engine="batched")
    _same(run_monte_carlo(scenario, workers=2, **kw), small)
    out = tmp_path / "run"
    first = run_monte_carlo(scenario, workers=1, out=out, keep_checkpoint=True, **kw)
    _same(first, small)
    (out / "checkpoint-mc-linear" / "tasks" / "mcl-0000002-0000003.npz").unlink()
    again = run_monte_carlo(scenario, workers=1, out=out, resume=True, **kw)
    assert (again.provenance["tasks_from_checkpoint"], again.provenance["tasks_run"]) == (3, 1)
    _same(again, small)
    assert (out / "mc_linear" / "meta.json").exists()
    odd = run_monte_carlo(scenario, n_samples=5, seed=3, workers=1, progress=False, keep_samples=True,
                          slices=(1,), engine="batched")
    assert np.allclose(odd.samples, small.samples[:5], rtol=0, atol=1e-12 * np.abs(small.samples).max())
    other = run_monte_carlo(scenario, workers=1, **{**kw, "slices": (2, 1)})
    assert np.allclose(other.std, small.std, rtol=1e-12, atol=1e-12 * small.std.max())


@pytest.mark.exudyn
def test_loss_of_contact_is_flagged_by_the_linear_engine():
    """As test_monte_carlo's: the sprung mass at 400 km/h on the German high-interference profile,
    only the body acceleration selected (the wheel force is output internally). Reference: the
    Exudyn Monte Carlo of the same samples; the same samples are flagged, with minimum forces equal
    to 1e-6 of the weight."""
    sc = mc_scenario(channels=("car1.body.acc_z",), speed_kmh=400.0, irregularities=("german_high.vertical",),
                     lead_in=45.0)
    with pytest.warns(LossOfContactWarning, match="lost wheel-rail contact"):
        lin = run_monte_carlo(sc, n_samples=8, seed=1, workers=1, progress=False, engine="batched")
    with pytest.warns(LossOfContactWarning):
        ref = run_monte_carlo(sc, n_samples=8, seed=1, workers=1, progress=False, engine="exudyn")
    assert np.array_equal(lin.min_wheel_force <= 0, ref.min_wheel_force <= 0)
    assert lin.provenance["samples_with_loss_of_contact"] == ref.provenance["samples_with_loss_of_contact"] > 0
    assert np.allclose(lin.min_wheel_force, ref.min_wheel_force, rtol=0, atol=1e-6 * 5750 * 9.81)
    assert lin.channels == ("car1.body.acc_z",)


def test_sample_blocks_cover_the_samples_within_the_memory_cap():
    assert sample_blocks(500, (1, 1, 0.5), 10_000) == [(0, 200), (200, 400), (400, 500)]
    blocks = sample_blocks(500, (1, 1, 0.5), 64)
    assert blocks[0] == (0, 50) and blocks[-1][1] == 500
    assert all(b - a <= 64 for a, b in blocks) and all(p[1] == q[0] for p, q in zip(blocks, blocks[1:]))
    assert sample_blocks(3, (1, 1, 0.5), 64) == [(0, 1), (1, 2), (2, 3)]


def test_unknown_engine_is_refused(scenario):
    with pytest.raises(SettingError, match="key 'engine' = 'fast' \\(allowed: 'exudyn' or 'batched' or 'dense'\\)"):
        run_monte_carlo(scenario, n_samples=4, engine="fast", progress=False)


@pytest.mark.exudyn
def test_static_linearization_adds_the_preload_stiffness_of_the_exudyn_model():
    """Problem: scenario 'quick' (one ICE motor car, 250 km/h, track 2.5 m off the girder axis), all
    channels, samples 0-3 of seed 1, German low vertical, alignment and cross-level profiles.

    Reference: the Exudyn Monte Carlo (full model, gravity, static start). Its suspensions carry the
    car's weight, whose geometric stiffness (the body's weight acting above its springs: roll
    stiffness lowered by m g h) the model linearised about rest lacks: measured, sample by sample,
    0.54 of the largest sigma in the body roll displacement, 0.065 in the body lateral acceleration.
    Linearised about the static equilibrium under gravity the differences fall to 0.006 and 0.0014;
    what remains (largest 0.036, bogie pitch acceleration) is the finite-rotation nonlinearity, in
    proportion to the amplitude (test_car15_sample_is_exudyns_tangent_model). Tolerances: rest above
    0.3 for the roll (the effect exists), static below 0.02 for the roll and below 0.06 everywhere.
    """
    import tb_exudyn as tbx

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("*",), freq_spacing="linear", n_freq=16))
    kw = dict(n_samples=4, seed=1, workers=1, progress=False, keep_samples=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = run_monte_carlo(sc, engine="exudyn", **kw)
        rest = run_monte_carlo(sc, engine="batched", **kw)
        static = run_monte_carlo(sc, engine="batched", linearization="static", **kw)
    scale = ref.std.max(axis=1)
    roll = ref.index("car1.body.disp_rx")

    def diff(lin, i):
        return float(np.abs(lin.samples[:, i] - ref.samples[:, i]).max() / scale[i])

    assert diff(rest, roll) > 0.3 and diff(static, roll) < 0.02
    worst, i = _worst(static.samples, ref.samples, scale)
    assert worst < 0.06, (ref.channels[i], worst)
    assert static.provenance["linearization"] == "static" and rest.provenance["linearization"] == "rest"


def test_linearization_is_refused_where_it_does_not_apply(scenario):
    """Capability and argument errors are user errors naming the key, before any run."""
    from tb_exudyn.errors import CapabilityError
    from tb_exudyn.methods import run_pem

    with pytest.raises(CapabilityError, match="cannot linearise about 'static'.*engine 'batched' or 'dense' can"):
        run_pem(scenario, engine="exudyn", linearization="static", progress=False)
    with pytest.raises(CapabilityError, match="runs the full model"):
        run_monte_carlo(scenario, n_samples=4, linearization="rest", progress=False, engine="exudyn")
    with pytest.raises(SettingError, match="run_monte_carlo: key 'linearization' = 'mean': unknown linearization point"):
        run_monte_carlo(scenario, n_samples=4, engine="batched", linearization="mean", progress=False)


@pytest.mark.exudyn
def test_fft_profiles_run_on_the_linear_engine_too(scenario):
    """Samples 0-2 of seed 9 with FFT profiles (one sample at a time, not the PEM grid's matrix
    product) against the Exudyn Monte Carlo's: the same 1e-5 of each channel's largest sigma as the
    PEM-grid samples; measured 4.9e-7."""
    kw = dict(n_samples=3, seed=9, workers=1, progress=False, keep_samples=True, discretisation="fft")
    ref = run_monte_carlo(scenario, engine="exudyn", **kw)
    lin = run_monte_carlo(scenario, engine="batched", **kw)
    assert lin.provenance["discretisation"] == "fft" and lin.band == ref.band
    worst, i = _worst(lin.samples, ref.samples, ref.std.max(axis=1))
    assert worst < 1e-5, (ref.channels[i], worst)


@pytest.mark.exudyn
def test_cross_level_as_a_height_difference_is_converted_as_exudyn_does():
    """Problem: scenario 'quick' with the German low cross-level given as a height difference
    (``german_low.cross_level_height``, m; the coupling takes an angle: height / 2b), sample 0 of
    seed 5 at a hundredth of its amplitude (the linear regime, see the car15 test).

    Reference: the Exudyn run from rest without gravity on the same profile. The roll channels and
    the wheel forces, which the cross-level drives, agree to 1e-4 of their largest value (measured
    2e-6); a missing or doubled 1/2b would give 0.3 or more. (Channels that only the finite
    rotations reach, such as bogie pitch at 1e-7 rad, are not compared: the linear model gives zero.)
    """
    import tb_exudyn as tbx
    from tb_exudyn.builder import build_model
    from tb_exudyn.system.excitation import ProfileExcitation
    from tb_exudyn.engines.batched import BatchedEngine
    from tb_exudyn.engines.exudyn_runs import run_model

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(channels=("*.disp_rx", "*.force_z", "*.force_y"),
                                                 freq_spacing="linear", n_freq=16),
                    track=sc.track.replace(irregularities=("german_low.cross_level_height",)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sampler = ProfileSampler(sc)
        assert sampler.cross_level_unit == "height"
        y_lin = integrate_samples(BatchedEngine(sc, wheel_forces=True), sampler, 5, [0], keep_samples=True)["samples"][0]
        exc = sampler.columns(5, [0]).excitation(0)
        s = 0.01
        e = ProfileExcitation(cross_level=lambda x: tuple(s * a for a in exc.cross_level(x)), cross_level_unit="height")
        th, _ = run_model(build_model(sc, warn=False), e, gravity=False, initial="rest")
    names = [n for n in th.names if n.startswith("car1.")]
    y = np.stack([th.channels[n] for n in names]) / s
    y_lin = y_lin[[th.names.index(n) for n in names]]
    worst, i = _worst(y_lin[None], y[None], np.abs(y).max(axis=1))
    assert worst < 1e-4, (names[i], worst)
