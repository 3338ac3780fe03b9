"""Bad input raises clear SpectrumError / ValueError messages (tb_exudyn.track). One test per class."""

import math

import numpy as np
import pytest

from tb_exudyn.track import (SpectrumError, band_from_wavelengths, band_variance, fft_profile, get_spectrum,
                             harmonic_profile, pseudo_excitation, quadrature_weights, user_table_spectrum)

GERMAN = get_spectrum("german_low.vertical")
CHINESE = get_spectrum("chinese_tbt3352.vertical")


def test_spectrum_error_is_a_value_error():
    """SpectrumError subclasses ValueError so generic handlers catch it (issue 3)."""
    assert issubclass(SpectrumError, ValueError)


def test_negative_band():
    """A negative lower band limit or wavelength is refused, naming the value."""
    with pytest.raises(SpectrumError, match=r"lower limit.*-0\.1"):
        band_variance(GERMAN, -0.1, 1.0)
    with pytest.raises(SpectrumError, match="0 < lmin < lmax"):
        band_from_wavelengths(-1.0, 10.0)


def test_inverted_band():
    """omega_min >= omega_max (or lmin >= lmax) is refused, naming both limits."""
    with pytest.raises(SpectrumError, match=r"inverted or empty.*2.*1"):
        band_variance(GERMAN, 2.0, 1.0)
    with pytest.raises(SpectrumError, match="lmin=120"):
        band_from_wavelengths(120.0, 1.0)


def test_band_outside_validity():
    """TB/T 3352 is defined for 2-200 m; 1-120 m is refused, naming the spectrum and its validity."""
    with pytest.raises(SpectrumError, match=r"outside the validity.*chinese_tbt3352\.vertical"):
        band_variance(CHINESE, *band_from_wavelengths(1.0, 120.0))
    with pytest.raises(SpectrumError, match="validity"):
        harmonic_profile(CHINESE, np.random.default_rng(0), 10, band=band_from_wavelengths(1.0, 120.0))
    with pytest.raises(SpectrumError, match="validity"):
        pseudo_excitation(CHINESE, [0.01, 1.0], 0.01, 50.0, 0.0, [0.0])
    with pytest.raises(SpectrumError, match="Nyquist"):
        fft_profile(GERMAN, np.random.default_rng(0), 100.0, dx=1.0)  # 1 m waves need dx <= 0.5 m


def test_unknown_spectrum_name():
    """A misspelt name is refused, the message names it and lists the allowed names."""
    with pytest.raises(SpectrumError) as info:
        get_spectrum("german_low.vertcal")
    msg = str(info.value)
    assert "'german_low.vertcal'" in msg and "german_low.vertical" in msg and "chinese_tbt3352.gauge" in msg


@pytest.mark.parametrize("body, match", [
    ("wavelength,psd\n1,1e-9\n2,abc\n", r"line 3: column 'psd': 'abc' is not a number"),
    ("# comment\nwavelength,psd\n1,1e-9\n2\n", r"line 4: 1 fields, header has 2"),
    ("lambda,psd\n1,1e-9\n2,1e-8\n", r"has no column 'wavelength'"),
    ("wavelength,psd\n1,1e-9\n2,-1e-8\n", r"line 3: column 'psd': '-1e-8' must be finite and > 0"),
    ("wavelength,psd\n1,1e-9\n2,1e-8\n1,2e-9\n", r"line 4: duplicate wavelength"),
    ("wavelength,psd\n1,1e-9\n", r"at least two data rows"),
    ("# only comments\n\n", r"no header line"),
])
def test_malformed_csv(tmp_path, body, match):
    """Malformed spectrum tables: the message names the file, the line (where there is one) and the fault."""
    path = tmp_path / "bad_table.csv"
    path.write_text(body)
    with pytest.raises(SpectrumError, match=match) as info:
        user_table_spectrum(path, "vertical", "m")
    assert "bad_table.csv" in str(info.value)


def test_missing_table_file(tmp_path):
    """A table file that does not exist is reported with its path."""
    with pytest.raises(SpectrumError, match="missing.csv"):
        user_table_spectrum(tmp_path / "missing.csv", "vertical", "m")


def test_bad_quadrature_grid():
    """A decreasing grid or unknown rule is refused."""
    with pytest.raises(SpectrumError, match="strictly increasing"):
        quadrature_weights([1.0, 0.5, 2.0])
    with pytest.raises(SpectrumError, match="rule"):
        quadrature_weights([0.0, 1.0], "simpson")


def test_infinite_band_not_sampled():
    """Sampling needs a finite band (the variance integral may use inf, a sample may not)."""
    assert band_variance(GERMAN, 0.0, math.inf) > 0
    with pytest.raises(SpectrumError, match="finite band"):
        harmonic_profile(GERMAN, np.random.default_rng(0), 10, band=(0.1, math.inf))
