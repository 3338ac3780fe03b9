"""Track irregularity library: spectra, conversions, sampling, pseudo-excitation, estimation.

Pure numpy/scipy (no Exudyn). Spectra are one-sided in spatial circular frequency [rad/m].
"""

from .bands import band_variance, check_band, closed_form_variance, temporal_psd_hz, temporal_psd_rad
from .estimate import welch_psd
from .pseudo import pseudo_excitation, pseudo_excitation_hz, quadrature_weights
from .sampling import (CombinedProfile, GridProfile, HarmonicProfile, TrackProfile, fft_bins, fft_profile,
                       harmonic_profile, rail_profiles, sample_rng)
from .spectra import (HALF_RAIL_DISTANCE, FrybaSpectrum, PowerLawSpectrum, RationalSpectrum, Spectrum,
                      SpectrumError, TableSpectrum, band_from_wavelengths, get_spectrum, spectrum_names,
                      track_spectrum, wavelengths_from_band)
from .table import user_table_spectrum

__all__ = [
    "HALF_RAIL_DISTANCE", "CombinedProfile", "FrybaSpectrum", "GridProfile", "HarmonicProfile",
    "PowerLawSpectrum", "RationalSpectrum", "Spectrum", "SpectrumError", "TableSpectrum", "TrackProfile",
    "band_from_wavelengths", "band_variance", "check_band", "closed_form_variance", "fft_bins", "fft_profile",
    "get_spectrum", "harmonic_profile", "pseudo_excitation", "pseudo_excitation_hz", "quadrature_weights",
    "rail_profiles", "sample_rng", "spectrum_names", "temporal_psd_hz", "track_spectrum", "temporal_psd_rad",
    "user_table_spectrum", "wavelengths_from_band", "welch_psd",
]
