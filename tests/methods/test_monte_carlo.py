"""Monte Carlo on the Exudyn model: agreement with PEM and the deterministic run, reproducibility.

Problem for the Exudyn tests (unless a test says otherwise): the damped VBI-2D sprung mass (5750 kg,
1.595e6 N/m, 4.0e5 N s/m, no wheel mass) at 300 km/h over the 25 m VBI-2D beam (modes to 80 Hz,
5 % damping), 40 m approach with the default 20 m taper, 5 m run-out, German low-interference
vertical profile, wavelengths 1-120 m, 8 PEM frequencies 1-20 Hz (all inside the band), time step
2 ms (10 steps per period at 50 Hz; PEM and Monte Carlo integrate the same discrete system, so the
comparison does not depend on the step), output every 10 ms.
"""

from __future__ import annotations

import math
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from scipy.stats import chi2

from tb_exudyn.errors import SettingError
from tb_exudyn.scenario import ScenarioError, save_scenario
from tb_exudyn.results.compare import compare
from tb_exudyn.methods import run_monte_carlo
from tb_exudyn.methods.monte_carlo import LossOfContactWarning
from tb_exudyn.methods.sampling import ProfileSampler, sample_excitation, track_range
from tb_exudyn.system.columns import SplineProfile
from tb_exudyn.track import sample_rng

from .test_pem import sprung_mass_scenario

CHANNELS = ("bridge.span1.mid.disp_z", "bridge.span1.mid.acc_z", "car1.body.disp_z", "car1.body.acc_z",
            "car1.axle1.force_z")
N_LARGE = 400


def mc_scenario(channels=CHANNELS, speed_kmh=300.0, irregularities=("german_low.vertical",), lead_in=40.0):
    sc = sprung_mass_scenario(lead_in=lead_in, run_out=5.0, f_min=1.0, f_max=20.0, n_freq=8, channels=channels)
    return sc.replace(speed_kmh=speed_kmh, analysis=sc.analysis.replace(time_step=2e-3),
                      track=sc.track.replace(irregularities=irregularities))


@pytest.fixture(scope="module")
def scenario():
    return mc_scenario()


@pytest.fixture(scope="module")
def pem(scenario):
    from tb_exudyn.methods import run_pem

    return run_pem(scenario, workers=2, progress=False, engine="exudyn")


@pytest.fixture(scope="module")
def mc_large(scenario):
    start = time.perf_counter()
    result = run_monte_carlo(scenario, n_samples=N_LARGE, seed=1, workers=2, progress=False, engine="exudyn")
    result.provenance["test_wall_time_s"] = time.perf_counter() - start
    return result


@pytest.fixture(scope="module")
def small(scenario):
    """Six samples in this process, with the samples kept: the reference of the execution tests."""
    return run_monte_carlo(scenario, n_samples=6, seed=3, workers=1, progress=False, keep_samples=True, engine="exudyn")


def _same(a, b, samples=True):
    assert a.channels == b.channels
    for name in ("time", "mean", "std", "mean_ci", "std_ci", "min_wheel_force") + (("samples",) if samples else ()):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


# ------------------------------------------------------------------------------ against PEM
@pytest.mark.exudyn
def test_sigma_agrees_with_pem_within_the_sampling_error(pem, mc_large):
    """Monte Carlo with N = 400 samples (seed 1, 2 workers) on the same discretised spectrum as PEM
    (harmonic sum over PEM's 8 grid frequencies, amplitudes sqrt(2 S dOmega), random phases).

    Reference: PEM (same model, same grid), exact for this discrete process because the system is
    linear and, with the taper, both methods start in equilibrium with zero input
    (docs/references.md, validation case 5). Tolerance: the sample sigma's relative standard error is
    about 1/sqrt(2N) for a Gaussian response (smaller for a random-phase sum, whose tails are
    lighter), so each time point lies within 3/sqrt(2N) = 10.6 % with probability >= 99.7 %; the
    points are correlated in time, so we ask 95 % of the time points where sigma_PEM exceeds 5 % of
    its maximum, over the whole run (t >= 0). Measured: 100 % for every channel, median ratios
    0.997-1.032. A missing sqrt(2) in the amplitudes (ratio 0.71) or a wrong grid would fail.
    """
    comparison = compare(pem, mc_large, k=3.0, threshold=0.05, t_min=0.0)
    for row in comparison.rows:
        assert row.n_times > 20, row
        assert row.inside >= 0.95, comparison.table()
        assert abs(row.ratio_median - 1) < 3 / math.sqrt(2 * N_LARGE), comparison.table()
    assert {r.channel for r in comparison.rows} == set(CHANNELS)
    # the linearity guard: German low interference at 300 km/h keeps the wheel pressed
    assert mc_large.provenance["samples_with_loss_of_contact"] == 0
    assert mc_large.min_wheel_force.shape == (N_LARGE,) and np.all(mc_large.min_wheel_force > 0)
    print(f"\n{N_LARGE} samples on 2 workers: {mc_large.provenance['test_wall_time_s']:.1f} s")


@pytest.mark.exudyn
def test_sample_mean_agrees_with_the_deterministic_run(pem, mc_large):
    """The sample mean of the 400 samples against the deterministic run (gravity, smooth track),
    which is PEM's mean and the exact mean of a linear system (the irregularity has zero mean; the
    static start state is linear in it). Measured nonlinearity of this model: y(+r) + y(-r) - 2 y(0)
    is 1e-6 of the response.

    Tolerance: z(t) = (mean_MC - mean_det) / (s / sqrt(N)) is about N(0, 1) at each time, so
    |z| <= 3 with probability 99.7 %. z(t) is strongly correlated in time (the response is narrow
    band), so excursions come in clusters of a few output steps: we ask |z| <= 3 at 90 % of the
    compared times and |z| <= 5 everywhere (probability 6e-7 per point). Measured: max |z| 3.8,
    >= 94 % within 3. A bias (gravity off, a wrong start state) gives |z| >> 5.
    """
    comparison = compare(pem, mc_large, k=3.0, t_min=0.0)
    for row in comparison.rows:
        assert row.mean_inside >= 0.90, comparison.table()
        assert row.mean_z_max <= 5.0, comparison.table()
    i = mc_large.index("car1.axle1.force_z")  # the mean wheel load is the weight, 5750 kg x 9.81
    assert abs(mc_large.mean[i, 0] - 5750 * 9.81) < 1e-6 * 5750 * 9.81


@pytest.mark.exudyn
def test_reduction_and_confidence_intervals_match_numpy_on_the_kept_samples(small):
    """The running (Welford) reduction against numpy on the kept samples: mean and sample standard
    deviation (ddof = 1) to round-off (1e-12 of the channel's scale); the 95 % intervals by their
    definitions, mean +- 1.959964 s / sqrt(N) and s sqrt((N - 1) / chi2_{0.975, 0.025}(N - 1))."""
    y, n = small.samples, small.n_samples
    assert y.shape == (6, len(CHANNELS), small.time.size)
    scale = np.abs(y).max(axis=(0, 2))[:, None]
    assert np.all(np.abs(small.mean - y.mean(axis=0)) <= 1e-12 * scale)
    assert np.all(np.abs(small.std - y.std(axis=0, ddof=1)) <= 1e-12 * scale)
    half = 1.959964 * small.std / math.sqrt(n)
    assert np.allclose(small.mean_ci, [small.mean - half, small.mean + half], rtol=1e-6, atol=0)
    lo = small.std * math.sqrt((n - 1) / chi2.isf(0.025, n - 1))
    hi = small.std * math.sqrt((n - 1) / chi2.isf(0.975, n - 1))
    assert np.allclose(small.std_ci, [lo, hi], rtol=1e-12, atol=0)
    assert np.all(small.std_ci[0] <= small.std) and np.all(small.std <= small.std_ci[1])


# ------------------------------------------------------------------------------ reproducibility
@pytest.mark.exudyn
def test_same_seed_same_result_and_workers_do_not_matter(scenario, small):
    """Same seed, 2 workers instead of 1: bitwise the same result (tolerance zero: runs are
    deterministic and the reduction is in sample order). Another seed gives another result."""
    _same(run_monte_carlo(scenario, n_samples=6, seed=3, workers=2, progress=False, keep_samples=True, engine="exudyn"), small)
    other = run_monte_carlo(scenario, n_samples=6, seed=4, workers=1, progress=False, engine="exudyn")
    assert not np.allclose(other.std, small.std)


@pytest.mark.exudyn
def test_sample_k_depends_on_seed_and_index_only(scenario, small):
    """Sample 4 as run by the pool equals a fresh single run on ``sample_excitation(scenario, 3, 4)``
    (a new model in this process). Tolerance 1e-9 of the channel's scale: the pool's workers use
    single-threaded BLAS for the static start state, this process maybe not."""
    from tb_exudyn.methods import run_deterministic

    th = run_deterministic(scenario, sample_excitation(scenario, 3, 4))
    for j, name in enumerate(small.channels):
        ref = th.channels[name]
        assert np.allclose(small.samples[4, j], ref, rtol=0, atol=1e-9 * np.abs(ref).max()), name


@pytest.mark.exudyn
def test_fft_discretisation_runs_and_reproduces(scenario):
    """Two samples with FFT profiles: the result states the wavelength band in Hz (v / 120 m to
    v / 1 m) and sample 1 is a single run on ``sample_excitation(scenario, 9, 1, "fft")``
    (tolerance as above)."""
    from tb_exudyn.methods import run_deterministic

    mc = run_monte_carlo(scenario, n_samples=2, seed=9, workers=1, progress=False, keep_samples=True,
                         discretisation="fft", engine="exudyn")
    assert mc.band == pytest.approx((300 / 3.6 / 120, 300 / 3.6)) and mc.provenance["discretisation"] == "fft"
    th = run_deterministic(scenario, sample_excitation(scenario, 9, 1, "fft"))
    ref = th.channels["car1.body.acc_z"]
    assert np.allclose(mc.samples[1, mc.index("car1.body.acc_z")], ref, rtol=0, atol=1e-9 * np.abs(ref).max())


@pytest.mark.exudyn
def test_killed_run_resumes_to_the_same_result(scenario, tmp_path):
    """A run of 8 samples in another process is killed (SIGKILL) once two samples are on disk;
    resuming runs only the rest and gives bitwise the uninterrupted result. Asking then for 10
    samples with resume reuses the 8 (the checkpoint does not depend on N)."""
    out = tmp_path / "run"
    code = textwrap.dedent(f"""
        import os, signal
        import tb_exudyn as tbx
        from tb_exudyn.execution.checkpoint import Checkpoint
        from tb_exudyn.methods import run_monte_carlo
        save, saved = Checkpoint.save, []
        def counted(self, task, result):  # killed right after its second sample is on disk: exact under any load
            save(self, task, result)
            saved.append(task.key)
            if len(saved) == 2:
                os.kill(os.getpid(), signal.SIGKILL)
        Checkpoint.save = counted
        run_monte_carlo(tbx.load_scenario({str(save_scenario(scenario, tmp_path / 's.toml'))!r}), n_samples=8,
                        seed=5, workers=1, out={str(out)!r}, progress=False, engine="exudyn")
    """)
    proc = subprocess.run([sys.executable, "-c", code], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr[-2000:]
    tasks = out / "checkpoint-mc" / "tasks"
    done = len(list(tasks.glob("*.npz")))
    assert done == 2, f"killed after its second sample, {done} on disk"
    resumed = run_monte_carlo(scenario, n_samples=8, seed=5, workers=1, out=out, resume=True, progress=False,
                              engine="exudyn", keep_checkpoint=True)  # kept for the 10 samples below
    assert (resumed.provenance["tasks_from_checkpoint"], resumed.provenance["tasks_run"]) == (done, 8 - done)
    _same(resumed, run_monte_carlo(scenario, n_samples=8, seed=5, workers=1, progress=False, engine="exudyn"), samples=False)
    more = run_monte_carlo(scenario, n_samples=10, seed=5, workers=1, out=out, resume=True, progress=False, engine="exudyn")
    assert more.provenance["tasks_from_checkpoint"] == 8 and more.n_samples == 10
    assert not (out / "checkpoint-mc").exists()  # removed after the result was saved
    from tb_exudyn.results import load_results

    _same(load_results(out / "mc"), more, samples=False)


# ------------------------------------------------------------------------------ linearity guard
@pytest.mark.exudyn
def test_loss_of_contact_is_flagged():
    """The sprung mass at 400 km/h on the German HIGH-interference profile: the damper force
    c v dr/dx exceeds the weight in some samples. Only the body acceleration is an output channel,
    so the wheel force is evaluated separately. Reference: the minimum of ``car1.axle1.force_z``
    of a deterministic run on the same sample's profile (channel selected there). Every flagged
    sample and only those are counted; a LossOfContactWarning is issued."""
    from tb_exudyn.methods import run_deterministic

    sc = mc_scenario(channels=("car1.body.acc_z",), speed_kmh=400.0, irregularities=("german_high.vertical",),
                     lead_in=45.0)
    with pytest.warns(LossOfContactWarning, match="lost wheel-rail contact"):
        mc = run_monte_carlo(sc, n_samples=8, seed=1, workers=1, progress=False, engine="exudyn")
    lost = mc.min_wheel_force <= 0
    assert 0 < lost.sum() < 8 and mc.provenance["samples_with_loss_of_contact"] == lost.sum()
    sc_f = sc.replace(analysis=sc.analysis.replace(channels=("car1.axle1.force_z",)))
    for k in (int(np.argmin(mc.min_wheel_force)), int(np.argmax(mc.min_wheel_force))):
        ref = run_deterministic(sc_f, sample_excitation(sc, 1, k)).channels["car1.axle1.force_z"].min()
        assert abs(mc.min_wheel_force[k] - ref) <= 1e-9 * 5750 * 9.81


# ------------------------------------------------------------------------------ sampling, checks
def test_pem_grid_profiles_have_the_discretised_band_variance(scenario):
    """The pem_grid sampler's harmonics: frequencies Omega_k = 2 pi f_k / v and amplitudes sqrt(2 S(Omega_k)
    dOmega_k) with the German low-interference vertical spectrum typed in here (docs/references.md, track
    spectra: A_v Oc^2 / ((O^2 + Or^2)(O^2 + Oc^2)), A_v = 4.032e-7, Oc = 0.8246, Or = 0.0206) and trapezoid
    widths on the grid 1-20 Hz (8 points), so sum of a_k^2 / 2 is PEM's sum S dOmega (to 1e-12). Ensemble over
    4000 samples at 3 points: variance within 4 standard errors (sqrt(2/n) relative for a near-Gaussian
    sum: 9 %)."""
    v = 300 / 3.6
    f = np.linspace(1.0, 20.0, 8)
    df = np.full(8, f[1] - f[0])
    df[[0, -1]] /= 2
    om, dom = 2 * np.pi * f / v, 2 * np.pi * df / v
    s = 4.032e-7 * 0.8246**2 / ((om**2 + 0.0206**2) * (om**2 + 0.8246**2))
    sampler = ProfileSampler(scenario, "pem_grid")
    h = sampler.harmonics[0]
    assert np.allclose(h.omega, om, rtol=1e-14) and np.allclose(h.amplitude, np.sqrt(2 * s * dom), rtol=1e-12)
    assert sampler.period == pytest.approx(v / df[1])
    lo, hi = track_range(scenario)
    assert lo <= -40.0 - 0.0 and hi >= 25.0 + 5.0  # last axle start, first axle end (one axle)
    assert sampler.x[0] == lo and sampler.x[-1] >= hi
    idx = [100, 350, 600]
    draws = np.array([sampler.grids(sample_rng(7, k))["vertical"][idx] for k in range(4000)])
    assert np.all(np.abs(draws.var(axis=0) / np.sum(s * dom) - 1) < 4 * math.sqrt(2 / 4000))


def test_fft_profiles_have_the_band_variance(scenario):
    """The fft sampler over the wavelength band 1-120 m against the band variance of the spectrum
    (scipy quad of the formula typed in as above). Statistic: the mean square over every grid point
    of 200 samples (stable to 0.1 % between seeds). Tolerance: 7 % below, 1 % above: on this short
    track (74 m) the FFT's bins are 2 pi / (N dx) = 0.085 rad/m wide, coarse where the spectrum
    falls steeply at the band's low end, so its discrete variance is 6.2 % below the integral
    (measured 0.9385; the pem_grid option uses PEM's own grid instead). A wrong band or amplitude
    is off by far more."""
    from scipy.integrate import quad

    sampler = ProfileSampler(scenario, "fft")
    psd = lambda o: 4.032e-7 * 0.8246**2 / ((o**2 + 0.0206**2) * (o**2 + 0.8246**2))  # noqa: E731
    band = quad(psd, 2 * np.pi / 120, 2 * np.pi, limit=200)[0]
    draws = np.array([sampler.grids(sample_rng(2, k))["vertical"] for k in range(200)])
    assert 0.93 < np.mean(draws**2) / band < 1.01
    assert sampler.band == pytest.approx((300 / 3.6 / 120, 300 / 3.6))


def test_spline_profile_interpolation_error():
    """The cubic spline through 40 points per wavelength of cos(2 pi x / 2 + 0.3), against the
    exact function at 20000 random points away from the ends. Tolerance: the classical bounds for
    cubic spline interpolation of a function with |f''''| = omega^4 A (Hall and Meyer 1976):
    (5/384) (omega h)^4 A in value and (1/24) (omega h)^3 omega A in slope, 7.9e-6 and 1.6e-4
    (measured 1.6e-6 and 3.1e-5). Evaluation off the sampled track raises."""
    lam, n = 2.0, 40
    om, h = 2 * np.pi / lam, lam / n
    x = np.arange(-10.0, 110.0 + h / 2, h)
    profile = SplineProfile(x[0], h, np.cos(om * x + 0.3))
    xx = np.random.default_rng(0).uniform(0.0, 100.0, 20000)
    value, slope = profile(xx)
    assert np.abs(value - np.cos(om * xx + 0.3)).max() < 5 / 384 * (om * h) ** 4
    assert np.abs(slope / om + np.sin(om * xx + 0.3)).max() < (om * h) ** 3 / 24
    with pytest.raises(ValueError, match="outside the sampled track"):
        profile(np.array([x[-1] + h]))


def test_bad_settings_fail_before_any_run(scenario):
    """Bad arguments are SettingErrors naming the function and the argument (a user error, exit 2 in
    the CLI), raised before any run; a scenario without irregularity is a ScenarioError."""
    with pytest.raises(SettingError, match="run_monte_carlo: key 'discretisation'"):
        run_monte_carlo(scenario, n_samples=4, discretisation="sobol", progress=False, engine="exudyn")  # type: ignore[arg-type]
    with pytest.raises(SettingError, match="run_monte_carlo: key 'n_samples'"):
        run_monte_carlo(scenario, n_samples=1, progress=False, engine="exudyn")
    with pytest.raises(SettingError, match="run_monte_carlo: key 'resume'"):
        run_monte_carlo(scenario, n_samples=4, resume=True, progress=False, engine="exudyn")
    with pytest.raises(ScenarioError, match="irregularit"):
        run_monte_carlo(scenario.replace(track=scenario.track.replace(irregularities=())), n_samples=4, progress=False, engine="exudyn")
