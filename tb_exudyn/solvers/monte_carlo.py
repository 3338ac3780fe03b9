"""Monte Carlo simulation on the Exudyn model: many runs on sampled irregularity profiles.

Each sample k draws one profile of every spectrum in ``scenario.track.irregularities`` from the
generator ``sample_rng(seed, k)`` (so a sample never depends on the worker that ran it), over the
whole stretch of track the wheels see, and runs the model WITH gravity from static equilibrium on
that track. The samples are reduced in sample order (Welford's running mean and sum of squared
deviations), so the result is bitwise the same for any number of workers, any executor and after a
resume.

Discretisation of a spectrum S (one-sided, rad/m):

- ``"pem_grid"`` (default): exactly the discretised spectrum PEM analyses, a harmonic sum over the
  PEM grid frequencies f_k inside the wavelength band,
  r(x) = sum_k sqrt(2 S(Omega_k) dOmega_k) cos(Omega_k x + phi_k), Omega_k = 2 pi f_k / v,
  dOmega_k = 2 pi df_k / v, phi_k ~ U[0, 2 pi). Then E[r^2] = sum_k S dOmega_k, and for the linear
  system PEM gives the exact sigma of this very process (validation_cases.md, section 5). On a
  linear grid the sample repeats itself (up to one phase shift common to all harmonics) every
  v / df metres (``profile_period_m`` in the provenance; 204 m for the reference study's grid),
  which may be shorter than the track: that is the process PEM analyses too.
- ``"fft"``: one FFT sample per spectrum (``tb_exudyn.track.fft_profile``) with frequencies
  spaced 2 pi / (track length) over the wavelength band: fast for long tracks, not periodic over
  the track, but a different discretisation from PEM's grid.

Start: the model tapers every input in over ``track.taper_length`` after the first axle's start
(see ``tb_exudyn.system.excitation``), so a sample starts in static equilibrium with zero input,
exactly as PEM's runs start at rest: both analyse the same process from t = 0.

Speed: the profile is evaluated at every wheel at every time step, so each sample's profile is
computed once on a uniform grid of ``POINTS_PER_WAVELENGTH`` points per shortest wavelength and
interpolated by cubic splines (:class:`SplineProfile`: Horner evaluation of the splines' pieces,
value and slope of all kinds in one call per time step, about 35 us for three kinds). On the PEM
grid the profiles are summed with a per-worker table of cos/sin(Omega x), one matrix-vector
product per spectrum (1 ms instead of 70 ms of cosines per spectrum for the verification case).
For a harmonic of wavelength lambda sampled at h = lambda / n, the spline's errors relative to its
amplitude (value) and to amplitude x 2 pi / lambda (slope) are bounded by (5/384) (2 pi / n)^4 and
(1/24) (2 pi / n)^3: 7.9e-6 and 1.6e-4 at n = 40; measured 1.6e-6 and 3.1e-5 (a test pins them),
far below the statistical error of any practical sample count.

Linearity guard: every sample reports its minimum vertical wheel-rail force (channels ``*.force_z``,
compressive wheel load, positive = pressing) over the output times. A value <= 0 is a loss of
contact, which the linear contact model turns into tension: such samples are counted in the
provenance, listed in ``min_wheel_force``, and a :class:`LossOfContactWarning` is issued, because
PEM assumes a linear system and the comparison no longer holds.
"""

from __future__ import annotations

import math
import time as _time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from ..system.excitation import KINDS, ProfileExcitation
from ..results.random_response import RandomResponse
from ..results.storage import check_writable
from ..scenario import Scenario, ScenarioError, scenario_to_toml
from ..track import HarmonicProfile, band_from_wavelengths, fft_profile, get_spectrum, sample_rng
from .grid import band_mask, check_grid_against_spectra, scenario_grid
from .pem import ENGINES, kind_and_unit
from .tasks import Checkpoint, Task, fingerprint, run_tasks

Discretisation = Literal["pem_grid", "fft"]
DISCRETISATIONS: tuple[str, ...] = ("pem_grid", "fft")
#: grid points per shortest wavelength of the sampled profiles (cubic-spline interpolation)
POINTS_PER_WAVELENGTH = 40
#: largest table of cos/sin values (grid points x 2 frequencies) kept per worker (128 MB)
TRIG_TABLE_MAX = 16_000_000
#: two-sided 95 % normal quantile
Z95 = 1.959963984540054


class LossOfContactWarning(UserWarning):
    """Some Monte Carlo samples lost wheel-rail contact (the linear model no longer holds)."""


# ---------------------------------------------------------------------------------- profiles
class SplineProfile:
    """Fast profile callable ``x -> (value, slope)``: cubic splines through values on a uniform grid.

    The not-a-knot splines of ``scipy.interpolate.CubicSpline`` evaluated piecewise by Horner's rule,
    value and slope in one call. ``values`` is one profile (n,) or several on the same grid (k, n);
    the result has the same leading shape. With several rows, ``row(i)`` gives a callable for
    profile i alone: the rows share one evaluation per position array (the last result is kept), so
    the three irregularity kinds cost one spline evaluation per time step, not three. Evaluation
    outside [x_start, x_start + (n - 1) dx] raises ValueError: the sampled track must cover every
    wheel.
    """

    def __init__(self, x_start: float, dx: float, values: ArrayLike) -> None:
        v = np.asarray(values, dtype=float)
        if v.ndim not in (1, 2) or v.shape[-1] < 4 or not dx > 0:
            raise ValueError("a spline profile needs dx > 0 and at least 4 values per row (1-D or 2-D array)")
        self.x_start, self.dx, self.n, self.rows = float(x_start), float(dx), v.shape[-1], v.ndim == 2
        self.x_end = self.x_start + self.dx * (self.n - 1)
        self._inv_dx = 1.0 / self.dx
        spline = CubicSpline(self.x_start + self.dx * np.arange(self.n), np.atleast_2d(v), axis=1)
        self._c = np.ascontiguousarray(np.moveaxis(spline.c, 1, 0))  # (n - 1, 4, k): powers 3, 2, 1, 0
        self._last: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None = None

    def __call__(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        x = np.asarray(x, dtype=float)
        s = (x.ravel() - self.x_start) * self._inv_dx
        if s.size and not (s.min() >= -1e-9 and s.max() <= self.n - 1 + 1e-9):
            raise ValueError(f"x in [{x.min():g}, {x.max():g}] m outside the sampled track "
                             f"[{self.x_start:g}, {self.x_end:g}] m")
        i = np.minimum(s.astype(np.intp), self.n - 2)  # floor (s >= 0 up to round-off)
        t = ((s - i) * self.dx)[:, None]
        c = self._c[i]  # (m, 4, k)
        c0, c1, c2 = c[:, 0], c[:, 1], c[:, 2]
        value = ((c0 * t + c1) * t + c2) * t + c[:, 3]
        slope = (3.0 * c0 * t + 2.0 * c1) * t + c2
        if self.rows:  # (k, shape of x)
            return value.T.reshape((-1,) + x.shape), slope.T.reshape((-1,) + x.shape)
        return value[:, 0].reshape(x.shape), slope[:, 0].reshape(x.shape)

    def row(self, index: int):
        """Profile ``index`` alone as a callable ``x -> (value, slope)`` sharing evaluations."""

        def profile(x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
            last = self._last
            if last is None or last[0].shape != np.shape(x) or not (last[0] == x).all():
                x_copy = np.array(x, dtype=float)
                value, slope = self(x_copy)
                self._last = last = (x_copy, value.reshape((-1,) + x_copy.shape), slope.reshape((-1,) + x_copy.shape))
            return last[1][index], last[2][index]

        return profile


def track_range(scenario: Scenario) -> tuple[float, float]:
    """The stretch of track [x_lo, x_hi] (m, x = 0 at the bridge start) every wheel sees in a run.

    From the last axle's start (-lead_in - train length) to the first axle's end (bridge length +
    run_out + train length), widened by one output step of travel (the run ends on a whole output
    step) plus 1 m.
    """
    margin = scenario.speed * scenario.analysis.output_step + 1.0
    lo = -scenario.track.lead_in - scenario.train.length - margin
    hi = scenario.bridge.length + scenario.track.run_out + scenario.train.length + margin
    return lo, hi


@dataclass(frozen=True)
class _Harmonics:
    """The frequencies and amplitudes of one spectrum on the PEM grid (pem_grid discretisation)."""

    omega: NDArray[np.float64]
    amplitude: NDArray[np.float64]


class ProfileSampler:
    """Draws the irregularity of one Monte Carlo sample (all spectra) on a fixed grid.

    Built from the scenario alone (the same in every worker); ``excitation(rng)`` draws, spectrum by
    spectrum in the order of ``scenario.track.irregularities``, and returns a ProfileExcitation.
    Raises ScenarioError (before any run) for spectra the model cannot take or a band outside a
    spectrum's validity.
    """

    def __init__(self, scenario: Scenario, discretisation: Discretisation = "pem_grid",
                 points_per_wavelength: int = POINTS_PER_WAVELENGTH) -> None:
        if discretisation not in DISCRETISATIONS:
            raise ScenarioError(None, "discretisation", discretisation, " or ".join(DISCRETISATIONS),
                                "unknown Monte Carlo discretisation")
        names = scenario.track.irregularities
        if not names:
            raise ScenarioError(None, "track.irregularities", [], "at least one spectrum name",
                                "no irregularity to sample")
        self.scenario, self.discretisation = scenario, discretisation
        self.spectra = tuple(get_spectrum(n) for n in names)
        self.kinds = tuple(kind_and_unit(n) for n in names)  # (kind, "angle" | "height")
        xl_units = {u for k, u in self.kinds if k == "cross_level"}
        #: cross-level as given if all spectra agree, else heights are converted to angles
        self.cross_level_unit = xl_units.pop() if len(xl_units) == 1 else "angle"
        self._scale = tuple(
            1.0 / (2.0 * scenario.track.half_gauge) if k == "cross_level" and u != self.cross_level_unit else 1.0
            for k, u in self.kinds
        )
        v, tr = scenario.speed, scenario.track
        if discretisation == "pem_grid":
            grid = scenario_grid(scenario)
            check_grid_against_spectra(grid, scenario, dict(zip(names, self.spectra)))
            mask = band_mask(grid, scenario)
            omega, d_omega = grid.omega_spatial[mask], grid.d_omega_spatial[mask]
            self.harmonics = tuple(_Harmonics(omega, np.sqrt(2.0 * np.asarray(s.psd(omega)) * d_omega))
                                   for s in self.spectra)
            self.band = grid.band
            self.shortest_wavelength = 2 * math.pi / float(omega.max())
            self.n_frequencies = int(omega.size)
            df = np.diff(grid.f)
            linear = grid.f.size > 1 and np.allclose(df, df[0], rtol=1e-9)
            self.period = v / float(df[0]) if linear else math.inf
        else:
            self.omega_band = band_from_wavelengths(tr.wavelength_min, tr.wavelength_max)
            self.band = (v / tr.wavelength_max, v / tr.wavelength_min)
            self.shortest_wavelength = tr.wavelength_min
            self.n_frequencies = 0
            self.period = math.inf
        lo, hi = track_range(scenario)
        self.dx = self.shortest_wavelength / points_per_wavelength
        self.n_points = int(math.ceil((hi - lo) / self.dx)) + 1
        self.x_start = lo
        self.x = lo + self.dx * np.arange(self.n_points)
        self._table: NDArray[np.float64] | None = None
        if discretisation == "fft":  # fail now, not in a worker, if the band is outside a spectrum's validity
            for s in self.spectra:
                fft_profile(s, np.random.default_rng(0), self.x[-1] - lo, self.dx, self.omega_band, lo)

    def _trig_table(self) -> NDArray[np.float64] | None:
        """[cos(Omega x) | sin(Omega x)] on the grid (pem_grid: every spectrum shares the frequencies),
        computed on first use and kept (None above TRIG_TABLE_MAX elements: summed in chunks then)."""
        if self._table is None and 2 * self.n_points * self.n_frequencies <= TRIG_TABLE_MAX:
            arg = np.outer(self.x, self.harmonics[0].omega)
            self._table = np.hstack((np.cos(arg), np.sin(arg)))
        return self._table

    def grids(self, rng: np.random.Generator) -> dict[str, NDArray[np.float64]]:
        """One sample: the summed values of every irregularity kind on the grid ``self.x``.

        Cross-level in ``self.cross_level_unit``. Kinds without a spectrum are absent.
        """
        out: dict[str, NDArray[np.float64]] = {}
        for i, (s, (kind, _)) in enumerate(zip(self.spectra, self.kinds)):
            if self.discretisation == "pem_grid":
                h = self.harmonics[i]
                phase = rng.uniform(0.0, 2 * math.pi, h.omega.size)
                table = self._trig_table()
                if table is not None:  # sum_k a_k cos(w_k x + phi_k) = [cos | sin](w x) @ [a cos phi; -a sin phi]
                    coef = np.concatenate((h.amplitude * np.cos(phase), -h.amplitude * np.sin(phase)))
                    values = np.einsum("ij,j->i", table, coef)  # numpy's own loop: no BLAS threads
                else:
                    values = HarmonicProfile(unit=s.unit, kind=kind, omega=h.omega, amplitude=h.amplitude,
                                             phase=phase).value(self.x)
            else:
                values = np.array(fft_profile(s, rng, self.x[-1] - self.x_start, self.dx, self.omega_band,
                                              self.x_start, interpolation="linear").values)
            values = values * self._scale[i]
            out[kind] = out[kind] + values if kind in out else values
        return out

    def grids_batch(self, seed: int, indices: Sequence[int]) -> dict[str, NDArray[np.float64]]:
        """Samples ``indices`` of a run seeded with ``seed`` at once: kind -> (n_points, n) values on the
        grid ``self.x``, column j being ``grids(sample_rng(seed, indices[j]))[kind]`` (the same draws;
        on the PEM grid the harmonic sums are one matrix product per spectrum instead of one per
        sample, equal to round-off)."""
        rngs = [sample_rng(seed, int(k)) for k in indices]
        table = self._trig_table() if self.discretisation == "pem_grid" else None
        if table is None:
            per_sample = [self.grids(rng) for rng in rngs]
            return {kind: np.stack([g[kind] for g in per_sample], axis=1) for kind in per_sample[0]} if rngs else {}
        phases = [[rng.uniform(0.0, 2 * math.pi, h.omega.size) for h in self.harmonics] for rng in rngs]
        out: dict[str, NDArray[np.float64]] = {}
        for i, (kind, _) in enumerate(self.kinds):
            a = self.harmonics[i].amplitude[:, None]
            phase = np.stack([p[i] for p in phases], axis=1)  # (n_frequencies, n)
            values = table @ np.concatenate((a * np.cos(phase), -a * np.sin(phase))) * self._scale[i]
            out[kind] = out[kind] + values if kind in out else values
        return out

    def excitation(self, rng: np.random.Generator) -> ProfileExcitation:
        """One sample as an excitation of the model (cubic-spline profiles, one evaluation per step)."""
        grids = self.grids(rng)
        kinds = [k for k in KINDS if k in grids]
        if len(kinds) == 1:
            profiles = {kinds[0]: SplineProfile(self.x_start, self.dx, grids[kinds[0]])}
        else:
            spline = SplineProfile(self.x_start, self.dx, np.stack([grids[k] for k in kinds]))
            profiles = {k: spline.row(i) for i, k in enumerate(kinds)}
        return ProfileExcitation(**profiles, cross_level_unit=self.cross_level_unit)  # type: ignore[arg-type]

    def describe(self) -> dict[str, Any]:
        """Provenance of the sampling."""
        return {
            "discretisation": self.discretisation,
            "n_frequencies_in_band": self.n_frequencies,
            "profile_period_m": self.period,
            "profile_grid": {"x_start_m": self.x_start, "dx_m": self.dx, "points": self.n_points},
            "profile_interpolation": f"cubic spline, {self.shortest_wavelength / self.dx:g} points per "
                                     f"shortest wavelength ({self.shortest_wavelength:.4g} m)",
            "cross_level_unit": self.cross_level_unit,
        }


def sample_excitation(scenario: Scenario, seed: int, index: int,
                      discretisation: Discretisation = "pem_grid") -> ProfileExcitation:
    """The irregularity of Monte Carlo sample ``index`` of a run seeded with ``seed``.

    ``run_deterministic(scenario, sample_excitation(scenario, seed, k))`` reproduces sample k.
    """
    return ProfileSampler(scenario, discretisation).excitation(sample_rng(seed, index))


# ---------------------------------------------------------------------------------- worker side
def _setup(scenario: Scenario, discretisation: Discretisation) -> tuple[Any, ProfileSampler]:
    """Build the Exudyn model and the sampler once per worker (warnings were shown by the driver)."""
    from ..builder import build_model

    return build_model(scenario, warn=False), ProfileSampler(scenario, discretisation)


def _work(state: tuple[Any, ProfileSampler], task: Task) -> dict[str, np.ndarray]:
    """One sample: draw the profiles, run with gravity from static equilibrium, return the channels
    (nc, nt), the output times and the minimum vertical wheel-rail force."""
    from .deterministic import run_model

    model, sampler = state
    seed, index = task.data
    th, info = run_model(model, sampler.excitation(sample_rng(seed, index)), gravity=True, initial="static")
    names = [c.name for c in model.selected]
    wheel = [c.name for c in model.channels if c.name.endswith(".force_z")]
    if all(w in th.channels for w in wheel):
        forces = [th.channels[w] for w in wheel]
    else:
        forces = list(model.channel_values(model.recording(), ("*.force_z",)).values())
    min_force = min((float(np.min(f)) for f in forces), default=math.nan)
    return {
        "y": np.stack([th.channels[n] for n in names]),
        "time": th.time,
        "min_wheel_force": np.array(min_force),
        "run_time": np.array(info.wall_time),
    }


# ---------------------------------------------------------------------------------- statistics
STATISTICS_PROVENANCE = {
    "std_estimator": "sample standard deviation (ddof = 1)",
    "confidence": "95 %: mean +- 1.96 s/sqrt(N); std: chi-square interval",
}


def sample_statistics(mean: NDArray[np.float64], m2: NDArray[np.float64], n: int
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Sample standard deviation (ddof = 1) from the sum of squared deviations ``m2`` of ``n``
    samples, and the 95 % confidence intervals (2, ...) of the mean (normal) and of the std
    (chi-square)."""
    std = np.sqrt(m2 / (n - 1))
    half = Z95 * std / math.sqrt(n)
    mean_ci = np.stack([mean - half, mean + half])
    from scipy.stats import chi2  # here: importing scipy.stats costs 0.3 s per worker process

    q_hi, q_lo = chi2.ppf([0.975, 0.025], n - 1)
    std_ci = np.stack([std * math.sqrt((n - 1) / q_hi), std * math.sqrt((n - 1) / q_lo)])
    return std, mean_ci, std_ci


def warn_loss_of_contact(min_force: NDArray[np.float64]) -> NDArray[np.int64]:
    """Indices of the samples whose minimum vertical wheel force is <= 0, with a
    :class:`LossOfContactWarning` when there are any."""
    lost = np.flatnonzero(min_force <= 0.0)
    if lost.size:
        warnings.warn(
            f"{lost.size} of {min_force.size} Monte Carlo samples lost wheel-rail contact (minimum vertical wheel "
            f"force {np.nanmin(min_force):.4g} N <= 0; first samples {lost[:5].tolist()}): the linear contact pulls "
            "the wheel back, so these samples, and a comparison with PEM (which assumes a linear system), "
            "are not reliable", LossOfContactWarning, stacklevel=3,
        )
    return lost


def contact_provenance(min_force: NDArray[np.float64], lost: NDArray[np.int64]) -> dict[str, Any]:
    return {
        "samples_with_loss_of_contact": int(lost.size),
        "min_wheel_force_N": float(np.nanmin(min_force)) if np.isfinite(min_force).any() else None,
    }


def positive_int(value: Any, key: str, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise ScenarioError(None, key, value, f"an integer >= {low}", "bad value")
    return int(value)


def prepare_monte_carlo(scenario: Scenario, n_samples: int | None, seed: int | None, discretisation: Discretisation,
                        out: str | Path | None, resume: bool, identity: dict[str, Any], folder: str
                        ) -> tuple[int, int, ProfileSampler, Path | None, Checkpoint | None]:
    """Checks shared by the Monte Carlo engines, before any run: N >= 2, seed >= 0, the spectra and band
    (the sampler), the output folder writable; the checkpoint ``out/folder``, whose fingerprint is
    ``identity`` plus the scenario (without N: a larger N with resume reuses the samples run), the seed
    and the sampling. Returns N, seed, sampler, out, checkpoint."""
    n = positive_int(scenario.analysis.n_samples if n_samples is None else n_samples, "n_samples", 2)
    seed = positive_int(scenario.analysis.seed if seed is None else seed, "seed", 0)
    sampler = ProfileSampler(scenario, discretisation)  # every check on spectra and band, before any run
    checkpoint = None
    if out is not None:
        out = check_writable(out)
        key_scenario = scenario.replace(analysis=scenario.analysis.replace(n_samples=1, seed=seed))
        fp = fingerprint({**identity, "scenario": scenario_to_toml(key_scenario), "seed": seed,
                          "discretisation": discretisation, "points_per_wavelength": POINTS_PER_WAVELENGTH})
        checkpoint = Checkpoint(out / folder, fp, resume)
    elif resume:
        raise ScenarioError(None, "resume", True, "resume only together with an output folder",
                            "nothing to resume from")
    return n, seed, sampler, out, checkpoint


# ---------------------------------------------------------------------------------- driver
def run_monte_carlo(
    scenario: Scenario,
    n_samples: int | None = None,
    seed: int | None = None,
    workers: int | None = None,
    executor: Any = None,
    out: str | Path | None = None,
    resume: bool = False,
    progress: bool = True,
    keep_samples: bool = False,
    discretisation: Discretisation = "pem_grid",
    engine: str = "exudyn",
    linearization: str | None = None,
) -> RandomResponse:
    """Sample mean and standard deviation of every channel over sampled irregularity profiles.

    Parameters
    ----------
    scenario : the scenario (its track.irregularities are sampled independently)
    n_samples : number of samples N >= 2 (default ``scenario.analysis.n_samples``)
    seed : seed of the run (default ``scenario.analysis.seed``); sample k uses ``sample_rng(seed, k)``
    workers : processes of the local pool (None: all cores; 1: in this process)
    executor : any ``concurrent.futures.Executor`` to use instead (e.g. a Dask client's executor)
    out : folder for checkpoints (``out/checkpoint-mc``) and the result (``out/mc``); checked writable
        before any run. The checkpoint does not depend on N, so a larger N with ``resume=True``
        reuses the samples already run.
    resume : reuse samples already finished in ``out/checkpoint-mc``
    progress : show a progress bar with the time left
    keep_samples : keep every sample's channels, (N, nc, nt), in ``samples``
    discretisation : "pem_grid" (the PEM grid's discretised spectrum: comparable with PEM exactly)
        or "fft" (FFT profiles over the wavelength band, for long tracks)
    engine : "exudyn" (one Exudyn run per sample: the reference) or "batched" (the same samples on the
        linear model, all integrated together by the batched engine: method "monte_carlo_linear",
        see :mod:`.batched_mc`)
    linearization : with the batched engine, "rest" (default: PEM's model) or "static" (about the
        static equilibrium under gravity); the Exudyn engine runs the full model and takes none

    Returns
    -------
    RandomResponse (method "monte_carlo", or "monte_carlo_linear" with the batched engine) with the sample mean, the sample standard deviation
    (ddof = 1), their 95 % confidence intervals ``mean_ci`` (mean +- 1.96 s / sqrt(N)) and ``std_ci``
    (chi-square interval), ``min_wheel_force`` per sample and, if asked, the samples.

    Warns
    -----
    LossOfContactWarning when a sample's minimum vertical wheel-rail force is <= 0.
    """
    from ..builder import build_model
    from .deterministic import versions

    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(repr(e) for e in ENGINES)}, got {engine!r}")
    if engine == "batched":
        from .batched_mc import run_monte_carlo_linear

        return run_monte_carlo_linear(scenario, n_samples=n_samples, seed=seed, workers=workers, executor=executor,
                                      out=out, resume=resume, progress=progress, keep_samples=keep_samples,
                                      discretisation=discretisation, linearization=linearization or "rest")
    if linearization is not None:
        raise ScenarioError(None, "linearization", linearization, "none with engine 'exudyn' (or engine 'batched')",
                            "the Exudyn Monte Carlo runs the full model, it linearises nothing")
    t0 = _time.perf_counter()
    n, seed, sampler, out, checkpoint = prepare_monte_carlo(
        scenario, n_samples, seed, discretisation, out, resume, {"method": "monte_carlo"}, "checkpoint-mc")

    model = build_model(scenario)  # shows the scenario's warnings once; names and units of the channels
    channels = tuple(c.name for c in model.selected)
    units = tuple(c.unit for c in model.selected)
    warnings_ = list(model.warnings)
    del model
    tasks = [Task(f"mc-{k:07d}", (seed, k)) for k in range(n)]
    acc: dict[str, Any] = {"time": None, "mean": None, "m2": None}
    min_force = np.empty(n)
    run_times = np.empty(n)
    samples: np.ndarray | None = None

    def reduce(i: int, task: Task, result: dict[str, np.ndarray]) -> None:
        nonlocal samples
        y = result["y"]
        if acc["mean"] is None:
            if y.shape[0] != len(channels):
                raise RuntimeError(f"task {task.key}: {y.shape[0]} channels, expected {len(channels)}")
            acc["time"], acc["mean"], acc["m2"] = result["time"], np.zeros_like(y), np.zeros_like(y)
            if keep_samples:
                samples = np.empty((n,) + y.shape)
        elif y.shape != acc["mean"].shape:
            raise RuntimeError(f"task {task.key}: response shape {y.shape}, expected {acc['mean'].shape}")
        delta = y - acc["mean"]  # Welford, in sample order
        acc["mean"] += delta / (i + 1)
        acc["m2"] += delta * (y - acc["mean"])
        min_force[i] = float(result["min_wheel_force"])
        run_times[i] = float(result["run_time"])
        if samples is not None:
            samples[i] = y

    stats = run_tasks(
        tasks, setup=_setup, setup_args=(scenario, discretisation), work=_work, reduce=reduce,
        workers=workers, executor=executor, checkpoint=checkpoint, progress=progress, desc="Monte Carlo",
    )
    mean = acc["mean"]
    std, mean_ci, std_ci = sample_statistics(mean, acc["m2"], n)
    lost = warn_loss_of_contact(min_force)
    provenance = {
        "engine": "exudyn",
        "method": "monte_carlo",
        "versions": versions(),
        "seconds": _time.perf_counter() - t0,
        "seed": seed,
        "n_samples": n,
        "gravity": True,
        "initial_state": "static",
        "sample_run_time_median_s": float(np.median(run_times)),
        **contact_provenance(min_force, lost),
        **STATISTICS_PROVENANCE,
        "warnings": warnings_,
        **sampler.describe(),
        **stats,
    }
    result = RandomResponse(
        method="monte_carlo", time=acc["time"], channels=channels, units=units, mean=mean, std=std,
        band=tuple(float(b) for b in sampler.band),  # type: ignore[arg-type]
        scenario=scenario.replace(analysis=scenario.analysis.replace(n_samples=n, seed=seed)),
        types=tuple(scenario.track.irregularities), std_ci=std_ci, mean_ci=mean_ci, n_samples=n,
        min_wheel_force=min_force, samples=samples, provenance=provenance,
    )
    if out is not None:
        result.save(out / "mc")
    return result
