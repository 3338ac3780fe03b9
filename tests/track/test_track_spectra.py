"""Spectra: point values, variances, conversions, registry (tb_exudyn.track)."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from tb_exudyn.track import (HALF_RAIL_DISTANCE, band_from_wavelengths, band_variance, closed_form_variance,
                             get_spectrum, spectrum_names, temporal_psd_hz, temporal_psd_rad, user_table_spectrum)

EXAMPLE_TABLE = Path(__file__).resolve().parents[2] / "models" / "spectra" / "example_user_table.csv"
OMEGAS = np.array([1e-3, 0.0206, 0.1, 0.4380, 0.8246, 2.0, 6.0, 20.0])  # rad/m, incl. the corner frequencies


@pytest.mark.parametrize("level, a_v, a_a, a_g", [("low", 4.032e-7, 2.119e-7, 5.32e-8),
                                                  ("high", 1.080e-6, 6.125e-7, 1.032e-7)])
def test_german_point_values(level, a_v, a_a, a_g):
    """German S_v, S_a, S_c (angle and height), S_g at 8 frequencies vs the formulas of
    docs/references.md (track spectra).

    Reference: the formulas with the coefficients typed here from the reference table (not read
    from the code). Tolerance 1e-9 relative: both sides are the same few floating-point operations,
    so only rounding (~1e-15) separates them; 1e-9 leaves room for reordering only.
    """
    oc, o_r, o_s, b = 0.8246, 0.0206, 0.4380, 0.75
    o2 = OMEGAS**2
    base = oc**2 / ((o2 + o_r**2) * (o2 + oc**2))
    expected = {
        "vertical": a_v * base,
        "alignment": a_a * base,
        "cross_level": a_v / b**2 * base * o2 / (o2 + o_s**2),
        "cross_level_height": a_v / b**2 * base * o2 / (o2 + o_s**2) * (2 * b) ** 2,
        "gauge": a_g * base * o2 / (o2 + o_s**2),
    }
    for suffix, ref in expected.items():
        np.testing.assert_allclose(get_spectrum(f"german_{level}.{suffix}").psd(OMEGAS), ref, rtol=1e-9, atol=0)


def test_german_full_band_variance_closed_form():
    """Full-band (0..inf) variance of German low vertical: quadrature vs pi A_v Oc / (2 Or (Or + Oc)).

    Reference: closed form of docs/references.md (track spectra) with typed coefficients. Tolerance 1e-10 relative:
    band_variance promises 1e-10 (quad at epsrel 1e-12 per piece), the closed form is exact.
    """
    a_v, oc, o_r = 4.032e-7, 0.8246, 0.0206
    ref = math.pi * a_v * oc / (2 * o_r * (o_r + oc))
    s = get_spectrum("german_low.vertical")
    assert band_variance(s, 0.0, math.inf) == pytest.approx(ref, rel=1e-10, abs=0)
    assert closed_form_variance(s, 0.0, math.inf) == pytest.approx(ref, rel=1e-12, abs=0)


def _with_closed_form():
    names = [n for n in spectrum_names() if not n.startswith("fryba")]
    return [get_spectrum(n) for n in names] + [
        user_table_spectrum(EXAMPLE_TABLE, "vertical", "m")]


@pytest.mark.parametrize("spectrum", _with_closed_form(), ids=lambda s: s.name)
def test_band_variance_quadrature_matches_closed_forms(spectrum):
    """band_variance (adaptive quadrature) vs the analytic band integral on the default band and a sub-band.

    Reference: partial fractions with arctan terms (rational spectra), segment-wise power-law
    integrals (TB/T 3352, log-log tables), independent of the quadrature. Tolerance 1e-10 relative,
    the accuracy band_variance promises.
    """
    lo, hi = spectrum.default_band
    for a, b in [(lo, hi), (lo * 1.7, math.sqrt(lo * hi))]:
        assert band_variance(spectrum, a, b) == pytest.approx(closed_form_variance(spectrum, a, b), rel=1e-10, abs=0)


@pytest.mark.parametrize("name", ["chinese_tbt3352.vertical", "chinese_tbt3352.alignment",
                                  "chinese_tbt3352.cross_level_height", "chinese_tbt3352.gauge"])
def test_chinese_continuous_at_breaks(name):
    """TB/T 3352 piecewise power law is continuous within 0.5 % at each break frequency.

    Reference: the standard's segments join to 0.4 % (docs/references.md, track spectra); a transcription error in A
    or k typically makes a jump of tens of percent. PSD evaluated 1e-9 (relative) either side of each
    break, where the smooth variation (~k * 2e-9) is negligible against 0.5 %.
    """
    s = get_spectrum(name)
    for omega_b in s.breakpoints():
        left, right = s.psd([omega_b * (1 - 1e-9), omega_b * (1 + 1e-9)])
        assert abs(right / left - 1) < 5e-3


def test_chinese_unit_conversion():
    """TB/T 3352 vertical at n = 0.1 1/m (segment 3): S(O) = 1e-6 A n^-k / (2 pi) m^2/(rad/m), O = 2 pi n.

    Reference: A = 1.9784e-2, k = 1.3643 typed from TB/T 3352-2014 (docs/references.md); mm^2 -> m^2
    and cycles/m -> rad/m done here by hand. Tolerance 1e-12 relative (rounding only).
    """
    n = 0.1
    ref = 1e-6 * 1.9784e-2 / n**1.3643 / (2 * math.pi)
    assert float(get_spectrum("chinese_tbt3352.vertical").psd(2 * math.pi * n)) == pytest.approx(ref, rel=1e-12)
    h, a = get_spectrum("chinese_tbt3352.cross_level_height"), get_spectrum("chinese_tbt3352.cross_level")
    assert h.unit == "m" and a.unit == "rad"
    assert float(a.psd(0.5) * (2 * HALF_RAIL_DISTANCE) ** 2) == pytest.approx(float(h.psd(0.5)), rel=1e-12)


def test_fra_point_values_both_forms():
    """FRA class 3: rad/m form (cm^2 -> m^2) and Fryba's cycles/m form (S(O) = S(n)/(2 pi)) at O = 0.5 rad/m.

    Reference: formulas of docs/references.md (track spectra) with coefficients typed here. Tolerance 1e-12 relative
    (rounding only).
    """
    o, oc = 0.5, 0.8245
    ref_v = 0.25 * 0.6816 * oc**2 / (o**2 * (o**2 + oc**2)) * 1e-4
    ref_a = 0.25 * 0.4128 * oc**2 / (o**2 * (o**2 + oc**2)) * 1e-4
    ref_c = 4 * 0.25 * 0.6816 * oc**2 / ((o**2 + oc**2) * (o**2 + 0.8520**2)) * 1e-4
    assert float(get_spectrum("fra_class3.vertical").psd(o)) == pytest.approx(ref_v, rel=1e-12)
    assert float(get_spectrum("fra_class3.alignment").psd(o)) == pytest.approx(ref_a, rel=1e-12)
    assert float(get_spectrum("fra_class3.cross_level_height").psd(o)) == pytest.approx(ref_c, rel=1e-12)
    assert float(get_spectrum("fra_class3.cross_level").psd(o)) == pytest.approx(ref_c / 1.5**2, rel=1e-12)
    n, n1, n2 = o / (2 * math.pi), 23.3e-3, 13.1e-2
    ref_f = 4.92e-8 * n2**2 * (n**2 + n1**2) / (n**4 * (n**2 + n2**2)) / (2 * math.pi)
    assert float(get_spectrum("fryba_fra_class3.vertical").psd(o)) == pytest.approx(ref_f, rel=1e-12)


def test_registry_has_the_scenario_names_and_conventions():
    """Every name the scenario files use exists, with the documented kind and unit; [check] values say so.

    Reference: the names and units fixed in issue 3 and docs/references.md (track spectra). Exact
    comparisons (strings).
    """
    names = set(spectrum_names())
    for level in ("low", "high"):
        for suffix, kind, unit in [("vertical", "vertical", "m"), ("alignment", "alignment", "m"),
                                   ("cross_level", "cross_level", "rad"), ("cross_level_height", "cross_level", "m"),
                                   ("gauge", "gauge", "m")]:
            s = get_spectrum(f"german_{level}.{suffix}")
            assert (s.kind, s.unit) == (kind, unit)
    for k in range(1, 7):
        assert {f"fra_class{k}.vertical", f"fra_class{k}.alignment", f"fra_class{k}.cross_level",
                f"fryba_fra_class{k}.vertical"} <= names
        assert "[check]" in get_spectrum(f"fra_class{k}.alignment").source
        assert "[check]" in get_spectrum(f"fra_class{k}.cross_level").source
        assert "[check" in get_spectrum(f"fryba_fra_class{k}.vertical").source
    assert {f"chinese_tbt3352.{s}" for s in ("vertical", "alignment", "cross_level_height", "gauge")} <= names
    assert "height difference in mm" in get_spectrum("chinese_tbt3352.cross_level_height").source
    line = get_spectrum("german_low.vertical").describe()
    assert "\n" not in line and line.startswith("vertical [m]") and "1-120 m" in line
    assert "[check]" in get_spectrum("fra_class2.cross_level").describe()


def test_temporal_conversion_preserves_variance():
    """Spatial -> temporal at v = 83.3 m/s: integral of S_t d omega_t and of S_hz df equal the spatial variance.

    Problem: German high alignment on 2-80 m wavelengths. Reference: band_variance (itself checked
    against closed forms to 1e-10); the temporal integrals are done here with scipy quad over the
    mapped band. Tolerance 1e-8 relative: quad accuracy of this test's own integration.
    """
    s, v = get_spectrum("german_high.alignment"), 300 / 3.6
    lo, hi = band_from_wavelengths(2.0, 80.0)
    ref = band_variance(s, lo, hi)
    var_rad = quad(lambda w: float(temporal_psd_rad(s, w, v)), v * lo, v * hi, epsrel=1e-12, limit=200)[0]
    var_hz = quad(lambda f: float(temporal_psd_hz(s, f, v)), v * lo / (2 * math.pi), v * hi / (2 * math.pi),
                  epsrel=1e-12, limit=200)[0]
    assert var_rad == pytest.approx(ref, rel=1e-8) and var_hz == pytest.approx(ref, rel=1e-8)
    # point value: S_hz(f) = 2 pi S(2 pi f / v) / v
    assert float(temporal_psd_hz(s, 5.0, v)) == pytest.approx(2 * math.pi * float(s.psd(2 * math.pi * 5 / v)) / v,
                                                               rel=1e-14)


def test_example_table_reproduces_german_low_vertical():
    """models/spectra/example_user_table.csv against the German low vertical formula.

    Reference: formula with typed coefficients. At the nodes the table holds values rounded to 6
    significant digits: tolerance 1e-5 relative. Between nodes the log-log interpolation error of this
    node spacing is at most about 2.1 % (largest where the slope changes near Oc): tolerance 3 %.
    """
    s = user_table_spectrum(EXAMPLE_TABLE, "vertical", "m")
    lam = np.array([1, 1.5, 2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100, 120.0])
    o = 2 * math.pi / lam
    ref = 4.032e-7 * 0.8246**2 / ((o**2 + 0.0206**2) * (o**2 + 0.8246**2))
    np.testing.assert_allclose(s.psd(o), ref, rtol=1e-5, atol=0)
    om = np.geomspace(o.min(), o.max(), 400)
    ref_m = 4.032e-7 * 0.8246**2 / ((om**2 + 0.0206**2) * (om**2 + 0.8246**2))
    np.testing.assert_allclose(s.psd(om), ref_m, rtol=0.03, atol=0)
    assert s.validity == pytest.approx((o.min(), o.max()), rel=1e-14)
