"""Sampled irregularity profiles of Monte Carlo: what sample k of a run seeded with s is.

Each sample k draws one profile of every spectrum in ``scenario.track.irregularities`` from the
generator ``sample_rng(seed, k)`` (so a sample never depends on the worker that ran it), over the
whole stretch of track the wheels see (:func:`track_range`), on a uniform grid of
``POINTS_PER_WAVELENGTH`` points per shortest wavelength; the engines interpolate it by cubic splines
(:class:`~tb_exudyn.system.columns.ProfileColumns`).

Discretisation of a spectrum S (one-sided, rad/m):

- ``"pem_grid"`` (default): exactly the discretised spectrum PEM analyses, a harmonic sum over the
  PEM grid frequencies f_k inside the wavelength band,
  r(x) = sum_k sqrt(2 S(Omega_k) dOmega_k) cos(Omega_k x + phi_k), Omega_k = 2 pi f_k / v,
  dOmega_k = 2 pi df_k / v, phi_k ~ U[0, 2 pi). Then E[r^2] = sum_k S dOmega_k, and for the linear
  system PEM gives the exact sigma of this very process (docs/references.md, validation case 5). On a
  linear grid the sample repeats itself (up to one phase shift common to all harmonics) every
  v / df metres (``profile_period_m`` in the provenance; 204 m for the reference study's grid),
  which may be shorter than the track: that is the process PEM analyses too. The harmonic sums use
  a per-worker table of cos/sin(Omega x): one matrix product per spectrum and block of samples.
- ``"pem_grid_gaussian"``: the same harmonic sum on the same frequencies with Gaussian coefficients,
  r(x) = sum_k sqrt(S(Omega_k) dOmega_k) (xi_k cos(Omega_k x) + eta_k sin(Omega_k x)), xi_k, eta_k ~
  N(0, 1) (Rayleigh amplitudes, uniform phases): the same E[r^2] and discrete spectrum, but an exactly
  Gaussian process. The random-phase sum of ``"pem_grid"`` is Gaussian only in the limit of many
  harmonics: a response dominated by the few grid frequencies near a resonance (a car body's
  bounce on a linear grid) has lighter tails than Gaussian, so its exceedance probabilities at 3 to
  4 sigma come out low (measured by half on the ICE car body at 3.4 sigma); compare exceedance
  probabilities with PEM's Gaussian ones on this discretisation.
- ``"fft"``: one FFT sample per spectrum (``tb_exudyn.track.fft_profile``) with frequencies
  spaced 2 pi / (track length) over the wavelength band: fast for long tracks, not periodic over
  the track, but a different discretisation from PEM's grid.

Spline interpolation: for a harmonic of wavelength lambda sampled at h = lambda / n, the spline's
errors relative to its amplitude (value) and to amplitude x 2 pi / lambda (slope) are bounded by
(5/384) (2 pi / n)^4 and (1/24) (2 pi / n)^3: 7.9e-6 and 1.6e-4 at n = 40; measured 1.6e-6 and
3.1e-5 (a test pins them), far below the statistical error of any practical sample count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import SettingError
from ..scenario import Scenario, ScenarioError
from ..system.columns import ProfileColumns
from ..system.excitation import ProfileExcitation
from ..track import HarmonicProfile, band_from_wavelengths, fft_profile, sample_rng, track_spectrum
from .grid import FrequencyGrid, band_mask, check_grid_against_spectra, scenario_grid
from .pem import kind_and_unit

Discretisation = Literal["pem_grid", "pem_grid_gaussian", "fft"]
DISCRETISATIONS: tuple[str, ...] = ("pem_grid", "pem_grid_gaussian", "fft")
#: the discretisations that sum harmonics on the PEM grid
ON_PEM_GRID: tuple[str, ...] = ("pem_grid", "pem_grid_gaussian")
#: grid points per shortest wavelength of the sampled profiles (cubic-spline interpolation)
POINTS_PER_WAVELENGTH = 40
#: largest table of cos/sin values (grid points x 2 frequencies) kept per worker (128 MB)
TRIG_TABLE_MAX = 16_000_000


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

    def __init__(self, scenario: Scenario, discretisation: Discretisation = "pem_grid", grid: FrequencyGrid | None = None,
                 points_per_wavelength: int = POINTS_PER_WAVELENGTH) -> None:
        if discretisation not in DISCRETISATIONS:
            raise SettingError("run_monte_carlo", "discretisation", discretisation, " or ".join(DISCRETISATIONS),
                               "unknown Monte Carlo discretisation")
        names = scenario.track.irregularities
        if not names:
            raise ScenarioError(scenario.where, "track.irregularities", [], "at least one spectrum name",
                                "no irregularity to sample")
        self.scenario, self.discretisation = scenario, discretisation
        self.spectra = tuple(track_spectrum(n, scenario.track.irregularity_level) for n in names)
        self.kinds = tuple(kind_and_unit(n, scenario.where) for n in names)  # (kind, "angle" | "height")
        xl_units = {u for k, u in self.kinds if k == "cross_level"}
        #: cross-level as given if all spectra agree, else heights are converted to angles
        self.cross_level_unit = xl_units.pop() if len(xl_units) == 1 else "angle"
        self._scale = tuple(
            1.0 / (2.0 * scenario.track.half_gauge) if k == "cross_level" and u != self.cross_level_unit else 1.0
            for k, u in self.kinds
        )
        v, tr = scenario.speed, scenario.track
        if discretisation in ON_PEM_GRID:
            grid = scenario_grid(scenario) if grid is None else grid
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

    def _draw(self, rng: np.random.Generator, h: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Amplitudes and phases of one sample's harmonics (module docstring): the fixed amplitudes with
        uniform phases ("pem_grid"), or sqrt(S dOmega) |xi + i eta| with the phase of xi + i eta
        ("pem_grid_gaussian")."""
        if self.discretisation == "pem_grid_gaussian":
            z = rng.standard_normal(h.omega.size) + 1j * rng.standard_normal(h.omega.size)
            return h.amplitude / math.sqrt(2.0) * np.abs(z), np.angle(z)
        return np.broadcast_to(h.amplitude, h.omega.shape), rng.uniform(0.0, 2 * math.pi, h.omega.size)

    def grids(self, rng: np.random.Generator) -> dict[str, NDArray[np.float64]]:
        """One sample: the summed values of every irregularity kind on the grid ``self.x``.

        Cross-level in ``self.cross_level_unit``. Kinds without a spectrum are absent.
        """
        out: dict[str, NDArray[np.float64]] = {}
        for i, (s, (kind, _)) in enumerate(zip(self.spectra, self.kinds)):
            if self.discretisation in ON_PEM_GRID:
                h = self.harmonics[i]
                amplitude, phase = self._draw(rng, h)
                table = self._trig_table()
                if table is not None:  # sum_k a_k cos(w_k x + phi_k) = [cos | sin](w x) @ [a cos phi; -a sin phi]
                    coef = np.concatenate((amplitude * np.cos(phase), -amplitude * np.sin(phase)))
                    values = np.einsum("ij,j->i", table, coef)  # numpy's own loop: no BLAS threads
                else:
                    values = HarmonicProfile(unit=s.unit, kind=kind, omega=h.omega, amplitude=amplitude,
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
        table = self._trig_table() if self.discretisation in ON_PEM_GRID else None
        if table is None:
            per_sample = [self.grids(rng) for rng in rngs]
            return {kind: np.stack([g[kind] for g in per_sample], axis=1) for kind in per_sample[0]} if rngs else {}
        draws = [[self._draw(rng, h) for h in self.harmonics] for rng in rngs]
        out: dict[str, NDArray[np.float64]] = {}
        for i, (kind, _) in enumerate(self.kinds):
            a = np.stack([d[i][0] for d in draws], axis=1)  # (n_frequencies, n)
            phase = np.stack([d[i][1] for d in draws], axis=1)
            values = table @ np.concatenate((a * np.cos(phase), -a * np.sin(phase))) * self._scale[i]
            out[kind] = out[kind] + values if kind in out else values
        return out

    def columns(self, seed: int, indices: Sequence[int]) -> ProfileColumns:
        """Samples ``indices`` of a run seeded with ``seed`` as the engines' columns."""
        return ProfileColumns(self.grids_batch(seed, indices), self.x_start, self.dx, self.cross_level_unit,
                              self.scenario.track.half_gauge)

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
    return ProfileSampler(scenario, discretisation).columns(seed, [index]).excitation(0)


__all__ = ["DISCRETISATIONS", "Discretisation", "ON_PEM_GRID", "POINTS_PER_WAVELENGTH", "ProfileSampler", "sample_excitation",
           "track_range"]
