"""The PEM frequency grid and its quadrature weights.

The grid is temporal frequency f [Hz] (what users see). A run at speed v excites spatial frequency
Omega = 2 pi f / v [rad/m], i.e. wavelength v / f. Each grid point carries a width df (its quadrature
weight) so that the band variance of a spectrum S is sum_k S_hz(f_k) df_k: the trapezoid rule, so the
band is exactly [freq_min, freq_max] (the two end nodes carry half a spacing). The irregularity is
taken as zero outside the track's wavelength band [wavelength_min, wavelength_max], which is stated
with every sigma.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SettingError
from ..scenario import Scenario, ScenarioError
from ..system.conventions import spatial_frequency
from ..track import quadrature_weights


@dataclass(frozen=True)
class FrequencyGrid:
    """Frequencies [Hz], their quadrature widths [Hz], and the spatial equivalents at speed v."""

    f: np.ndarray
    df: np.ndarray
    speed: float
    rule: str = "trapezoid"

    @property
    def omega_spatial(self) -> np.ndarray:
        """Spatial circular frequencies [rad/m]."""
        return spatial_frequency(self.f, self.speed)

    @property
    def d_omega_spatial(self) -> np.ndarray:
        """Spatial quadrature widths [rad/m]."""
        return spatial_frequency(self.df, self.speed)

    @property
    def band(self) -> tuple[float, float]:
        """The band the quadrature covers [Hz]."""
        if self.rule == "trapezoid" and self.f.size > 1:
            return float(self.f[0]), float(self.f[-1])
        return float(self.f[0] - self.df[0] / 2), float(self.f[-1] + self.df[-1] / 2)


def frequency_grid(
    f_min: float, f_max: float, n: int, speed: float, spacing: str = "linear", given: np.ndarray | None = None
) -> FrequencyGrid:
    """A grid of n frequencies from f_min to f_max (nodes include both ends), or the ``given`` one.

    'linear': equally spaced; 'log': equally spaced in log f. Widths: trapezoid rule.
    A single frequency gets the width f_max - f_min (or f_min if they are equal) as a mid-point cell.
    """
    if given is not None and len(given):
        f = np.asarray(given, dtype=float)
    elif n == 1:
        f = np.array([f_min])
    elif spacing == "linear":
        f = np.linspace(f_min, f_max, n)
    elif spacing == "log":
        f = np.geomspace(f_min, f_max, n)
    else:
        raise SettingError("frequency_grid", "spacing", spacing, "'linear' or 'log'")
    if f.size == 1:
        return FrequencyGrid(f=f, df=np.array([f_max - f_min if f_max > f_min else f_min]), speed=float(speed),
                             rule="midpoint")
    return FrequencyGrid(f=f, df=quadrature_weights(f, "trapezoid"), speed=float(speed), rule="trapezoid")


def scenario_grid(scenario: Scenario) -> FrequencyGrid:
    """The scenario's PEM grid (Analysis.freq_min, freq_max, n_freq, freq_spacing)."""
    a = scenario.analysis
    return frequency_grid(a.freq_min, a.freq_max, a.n_freq, scenario.speed, a.freq_spacing)


def band_mask(grid: FrequencyGrid, scenario: Scenario) -> np.ndarray:
    """True where the grid's wavelength v / f lies in the track's wavelength band."""
    wavelength = grid.speed / grid.f
    t = scenario.track
    return (wavelength >= t.wavelength_min * (1 - 1e-12)) & (wavelength <= t.wavelength_max * (1 + 1e-12))


def check_grid_against_spectra(grid: FrequencyGrid, scenario: Scenario, spectra: dict) -> None:
    """Every spectrum must be valid over the part of the grid inside the wavelength band.

    Raises ScenarioError naming the scenario key, before any run starts.
    """
    mask = band_mask(grid, scenario)
    if not mask.any():
        raise ScenarioError(
            None, "analysis.freq_min", scenario.analysis.freq_min,
            f"a band that overlaps the track's wavelengths {scenario.track.wavelength_min:g}-"
            f"{scenario.track.wavelength_max:g} m at {scenario.speed:.4g} m/s, i.e. "
            f"{scenario.speed / scenario.track.wavelength_max:.4g}-{scenario.speed / scenario.track.wavelength_min:.4g} Hz",
            "no PEM frequency inside the wavelength band",
        )
    omega = grid.omega_spatial[mask]
    for name, spectrum in spectra.items():
        lo, hi = spectrum.validity
        if omega.min() < lo * (1 - 1e-9) or omega.max() > hi * (1 + 1e-9):
            raise ScenarioError(
                None, "track.wavelength_min", scenario.track.wavelength_min,
                f"wavelengths within the validity of {name}: {2 * math.pi / hi:.4g}-{2 * math.pi / lo:.4g} m",
                "frequency band outside the spectrum's validity",
            )
