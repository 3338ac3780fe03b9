"""Track irregularity spectra: immutable objects and the named registry.

Every spectrum is ONE-SIDED in spatial circular frequency ``omega`` [rad/m] on (0, inf):
``sigma^2 = integral S(omega) d omega``, with ``S`` in ``unit^2/(rad/m)``. Formulas, coefficients
and their provenance are in docs/references.md (track spectra); values tagged ``[check]``
there carry ``[check]`` in the ``source`` string here.

Cross-level comes in two forms, and the name says which:
``*.cross_level`` is the cross-level ANGLE [rad]; ``*.cross_level_height`` is the rail height
difference [m] = angle * 2b, with b = ``HALF_RAIL_DISTANCE`` = 0.75 m (PSD scales by (2b)^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import UserError

HALF_RAIL_DISTANCE = 0.75
"""b [m]: half the distance between the rail centres (cross-level angle <-> height difference)."""

KINDS = ("vertical", "alignment", "cross_level", "gauge")
UNITS = ("m", "rad")
TWO_PI = 2.0 * math.pi


class SpectrumError(UserError, ValueError):
    """Bad spectrum name, bad band, band outside validity, or malformed spectrum table (a user
    error: one line naming the file or the spectrum; the CLI exits 2 on it)."""


def band_from_wavelengths(lmin: float, lmax: float) -> tuple[float, float]:
    """Spatial-frequency band (omega_min, omega_max) [rad/m] for wavelengths lmin < lmax [m]."""
    if not (0.0 < lmin < lmax) or not math.isfinite(lmax):
        raise SpectrumError(f"wavelength band needs 0 < lmin < lmax < inf, got lmin={lmin!r}, lmax={lmax!r}")
    return TWO_PI / lmax, TWO_PI / lmin


def wavelengths_from_band(omega_min: float, omega_max: float) -> tuple[float, float]:
    """Wavelengths (lmin, lmax) [m] of a band (omega_min, omega_max) [rad/m]; lmax is inf at omega_min=0."""
    check_band_order(omega_min, omega_max)
    return TWO_PI / omega_max, (math.inf if omega_min == 0.0 else TWO_PI / omega_min)


def check_band_order(omega_min: float, omega_max: float) -> None:
    """Raise SpectrumError unless 0 <= omega_min < omega_max (omega_max may be inf)."""
    if not (math.isfinite(omega_min) and omega_min >= 0.0):
        raise SpectrumError(f"band lower limit must be finite and >= 0 rad/m, got {omega_min!r}")
    if not omega_max > omega_min:
        raise SpectrumError(f"band is inverted or empty: omega_min={omega_min!r} >= omega_max={omega_max!r} rad/m")


@dataclass(frozen=True, eq=False)
class Spectrum:
    """Base of all spectra: metadata plus ``psd``; subclasses implement ``_psd``.

    Attributes
    ----------
    name : registry name (e.g. ``german_low.vertical``).
    kind : one of ``KINDS``.
    unit : unit of the irregularity, ``"m"`` or ``"rad"``; the PSD is in unit^2/(rad/m).
    source : citation string (contains ``[check]`` where the reference marks a value so).
    default_band : (omega_min, omega_max) [rad/m] used when a caller gives no band.
    validity : (omega_min, omega_max) [rad/m] inside which the formula/table is defined.
    """

    name: str
    kind: str
    unit: str
    source: str
    default_band: tuple[float, float]
    validity: tuple[float, float]

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise SpectrumError(f"{self.name}: kind {self.kind!r} not in {KINDS}")
        if self.unit not in UNITS:
            raise SpectrumError(f"{self.name}: unit {self.unit!r} not in {UNITS}")

    def psd(self, omega: ArrayLike) -> NDArray[np.float64]:
        """One-sided PSD [unit^2/(rad/m)] at spatial frequencies ``omega`` [rad/m] (any shape)."""
        return self._psd(np.asarray(omega, dtype=float))

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        raise NotImplementedError

    def breakpoints(self) -> tuple[float, ...]:
        """Frequencies [rad/m] where the PSD or its slope changes character (helps quadrature)."""
        return ()

    def closed_form_variance(self, omega_min: float, omega_max: float) -> float:
        """Exact integral of the PSD over [omega_min, omega_max]; SpectrumError if none is coded."""
        raise SpectrumError(f"{self.name}: no closed-form variance; use band_variance (quadrature)")

    def describe(self) -> str:
        """One line for ``tb-exudyn list`` (without the name): kind, unit, default band, short source."""
        lmin, lmax = wavelengths_from_band(*self.default_band)
        short = self.source.split(";")[0]
        short += " [check]" if "[check" in self.source and "[check" not in short else ""
        kind = self.kind + ({"rad": " angle", "m": " height"}[self.unit] if self.kind == "cross_level" else "")
        return f"{kind} [{self.unit}], default band {lmin:g}-{lmax:g} m; {short}"


# ---------------------------------------------------------------------------------------------
# Rational spectra (German, FRA rad/m form): scale * C * omega^(2m) / prod(omega^2 + p_i^2)
# ---------------------------------------------------------------------------------------------

def _rational_band_integral(numerator_power: int, poles: tuple[float, ...], a: float, b: float) -> float:
    """Integral over [a, b] of omega^(2m) / prod_i(omega^2 + p_i^2), distinct p_i >= 0.

    Partial fractions in s = omega^2: residue r_i = (-p_i^2)^m / prod_{j!=i}(p_j^2 - p_i^2); the
    antiderivative of 1/(omega^2 + p^2) is arctan(omega/p)/p, and of 1/omega^2 (p = 0) is -1/omega.
    Requires m < len(poles) (integrable at infinity).
    """
    total = 0.0
    for i, p in enumerate(poles):
        others = [q for j, q in enumerate(poles) if j != i]
        r = (-p * p) ** numerator_power / math.prod(q * q - p * p for q in others)
        if p == 0.0:
            total += r * ((1.0 / a if a > 0 else math.inf) - (0.0 if math.isinf(b) else 1.0 / b))
        else:
            total += r * (math.atan(b / p) - math.atan(a / p)) / p
    return total


@dataclass(frozen=True, eq=False)
class RationalSpectrum(Spectrum):
    """S(omega) = coefficient * omega^(2 m) / prod_i (omega^2 + p_i^2) [unit^2/(rad/m)].

    Used for the German spectra and the FRA rad/m form; ``coefficient`` already contains the
    unit conversion and any cross-level scaling.
    """

    coefficient: float = 1.0
    numerator_power: int = 0
    poles: tuple[float, ...] = ()

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        o2 = omega * omega
        den = np.ones_like(o2)
        for p in self.poles:
            den = den * (o2 + p * p)
        with np.errstate(divide="ignore"):
            return self.coefficient * o2**self.numerator_power / den

    def breakpoints(self) -> tuple[float, ...]:
        return tuple(sorted(p for p in self.poles if p > 0))

    def closed_form_variance(self, omega_min: float, omega_max: float) -> float:
        return self.coefficient * _rational_band_integral(self.numerator_power, self.poles, omega_min, omega_max)


# ---------------------------------------------------------------------------------------------
# Spectra defined in cycles/m: S(omega) = scale * S_n(omega / 2 pi) / (2 pi)
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class FrybaSpectrum(Spectrum):
    """Fryba's FRA form in cycles/m, converted one-sidedly to rad/m.

    S(n) = A n2^2 (n^2 + n1^2) / (n^4 (n^2 + n2^2)) [m^2/(1/m)];  S(omega) = S(n)/(2 pi), n = omega/(2 pi).
    """

    a: float = 0.0
    n1: float = 23.3e-3
    n2: float = 13.1e-2

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        n2 = (omega / TWO_PI) ** 2
        with np.errstate(divide="ignore"):
            s_n = self.a * self.n2**2 * (n2 + self.n1**2) / (n2 * n2 * (n2 + self.n2**2))
        return s_n / TWO_PI

    def breakpoints(self) -> tuple[float, ...]:
        return (TWO_PI * self.n1, TWO_PI * self.n2)


@dataclass(frozen=True, eq=False)
class PowerLawSpectrum(Spectrum):
    """Piecewise power law in cycles/m: S(n) = A_i / n^k_i on segment i, times ``scale``.

    ``scale`` converts the S(n) unit to unit^2/(1/m) (1e-6 for mm^2, times (2b)^-2 for an angle);
    S(omega) = scale * S(n) / (2 pi), n = omega / (2 pi). ``breaks_n`` are the segment boundaries [1/m].
    """

    breaks_n: tuple[float, ...] = ()
    amplitudes: tuple[float, ...] = ()
    exponents: tuple[float, ...] = ()
    scale: float = 1.0

    def _segment(self, n: NDArray[np.float64]) -> NDArray[np.intp]:
        return np.searchsorted(np.asarray(self.breaks_n), n, side="right")

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        n = omega / TWO_PI
        seg = self._segment(n)
        a = np.asarray(self.amplitudes)[seg]
        k = np.asarray(self.exponents)[seg]
        with np.errstate(divide="ignore"):
            return self.scale * a / n**k / TWO_PI

    def breakpoints(self) -> tuple[float, ...]:
        return tuple(TWO_PI * n for n in self.breaks_n)

    def closed_form_variance(self, omega_min: float, omega_max: float) -> float:
        """Sum over segments of A (n_b^(1-k) - n_a^(1-k)) / (1 - k) (A log(n_b/n_a) for k = 1)."""
        edges = np.concatenate(([omega_min / TWO_PI], [b for b in self.breaks_n
                                                       if omega_min / TWO_PI < b < omega_max / TWO_PI],
                                [omega_max / TWO_PI]))
        total = 0.0
        for na, nb in zip(edges[:-1], edges[1:]):
            i = int(self._segment(np.array(0.5 * (na + nb))))
            a, k = self.amplitudes[i], self.exponents[i]
            total += a * (math.log(nb / na) if k == 1 else (nb ** (1 - k) - na ** (1 - k)) / (1 - k))
        return self.scale * total


@dataclass(frozen=True, eq=False)
class TableSpectrum(Spectrum):
    """PSD given at points, interpolated linearly in log(omega)-log(S); built by ``user_table_spectrum``.

    ``omega`` [rad/m] strictly increasing and positive, ``values`` [unit^2/(rad/m)] positive.
    Evaluation outside [omega[0], omega[-1]] raises SpectrumError (no extrapolation).
    """

    omega: tuple[float, ...] = ()
    values: tuple[float, ...] = ()

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        lo, hi = self.omega[0], self.omega[-1]
        # tolerate round-off at the ends (e.g. a band built from the table's own wavelengths)
        if np.any(omega < lo * (1 - 1e-12)) or np.any(omega > hi * (1 + 1e-12)):
            raise SpectrumError(f"{self.name}: omega outside the table range [{lo:g}, {hi:g}] rad/m")
        lw = np.log(np.clip(omega, lo, hi))
        return np.exp(np.interp(lw, np.log(self.omega), np.log(self.values)))

    def breakpoints(self) -> tuple[float, ...]:
        return tuple(self.omega)

    def closed_form_variance(self, omega_min: float, omega_max: float) -> float:
        """Exact integral of the log-log interpolant: each segment is a power law c * omega^s."""
        om, sv = np.asarray(self.omega), np.asarray(self.values)
        edges = np.unique(np.clip(np.concatenate(([omega_min, omega_max], om)), omega_min, omega_max))
        total = 0.0
        for a, b in zip(edges[:-1], edges[1:]):
            sa, sb = self._psd(np.array([a, b]))
            s = math.log(sb / sa) / math.log(b / a)
            total += sa * a * math.log(b / a) if abs(s + 1) < 1e-12 else sa * a * ((b / a) ** (s + 1) - 1) / (s + 1)
        return total


# ---------------------------------------------------------------------------------------------
# Named families
# ---------------------------------------------------------------------------------------------

_DEFAULT_BAND = band_from_wavelengths(1.0, 120.0)  # common for high-speed lines (reference file)

_GERMAN_SRC = ("German high-speed spectrum ({level} interference, ERRI B176 family); A_v, Oc, Or as in "
               "Guo, Xia, De Roeck & Liu, Comput. Struct. 112-113 (2012) 205-216; other coefficients "
               "agree across three public codes")
_GERMAN = {  # level: (A_v, A_a, A_g) [m^2 rad/m]
    "low": (4.032e-7, 2.119e-7, 5.32e-8),
    "high": (1.080e-6, 6.125e-7, 1.032e-7),
}
_G_OC, _G_OR, _G_OS = 0.8246, 0.0206, 0.4380


def _german(level: str) -> dict[str, Spectrum]:
    a_v, a_a, a_g = _GERMAN[level]
    b = HALF_RAIL_DISTANCE
    src = _GERMAN_SRC.format(level=level)
    two = (_G_OR, _G_OC)
    three = (_G_OR, _G_OC, _G_OS)
    oc2 = _G_OC**2
    rows = {  # suffix: (kind, unit, coefficient, numerator power, poles, note)
        "vertical": ("vertical", "m", a_v * oc2, 0, two, ""),
        "alignment": ("alignment", "m", a_a * oc2, 0, two, ""),
        "cross_level": ("cross_level", "rad", a_v / b**2 * oc2, 1, three, "; cross-level angle [rad]"),
        "cross_level_height": ("cross_level", "m", a_v / b**2 * oc2 * (2 * b) ** 2, 1, three,
                               f"; rail height difference [m] = angle * 2b, b = {b} m"),
        "gauge": ("gauge", "m", a_g * oc2, 1, three, ""),
    }
    out = {}
    for suffix, (kind, unit, coef, m, poles, note) in rows.items():
        name = f"german_{level}.{suffix}"
        out[name] = RationalSpectrum(name=name, kind=kind, unit=unit, source=src + note,
                                     default_band=_DEFAULT_BAND, validity=(0.0, math.inf),
                                     coefficient=coef, numerator_power=m, poles=poles)
    return out


_FRA_BAND = band_from_wavelengths(1.524, 304.8)  # FRA wavelengths 5-1000 ft
_FRA_AV = (1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339)  # cm^2 rad/m [code]
_FRA_AA = (3.3634, 1.2107, 0.4128, 0.3027, 0.0762, 0.0339)  # cm^2 rad/m [check]
_FRA_OS = (0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380)  # rad/m [check]
_FRA_OC, _FRA_K, _CM2 = 0.8245, 0.25, 1e-4
_FRA_SRC = ("US FRA class {k}, rad/m form of vehicle-dynamics texts (Garg & Dukkipati), k = 0.25, "
            "cm^2 converted to m^2; A_v and Oc = 0.8245 from public code")
_FRA_FRYBA_A = (15.53e-8, 8.85e-8, 4.92e-8, 2.75e-8, 1.57e-8, 0.98e-8)


def _fra(k: int) -> dict[str, Spectrum]:
    a_v, a_a, o_s = _FRA_AV[k - 1], _FRA_AA[k - 1], _FRA_OS[k - 1]
    src = _FRA_SRC.format(k=k)
    two_b2 = (2 * HALF_RAIL_DISTANCE) ** 2
    c_h = 4 * _FRA_K * a_v * _FRA_OC**2 * _CM2  # cross-level PSD is in cm^2/(rad/m): a height difference
    xl_note = (f"; Os = {o_s} [check]; the formula's cm^2/(rad/m) unit is read as a rail height difference "
               f"[check]")
    rows = {  # suffix: (kind, unit, coefficient, poles, note)
        "vertical": ("vertical", "m", _FRA_K * a_v * _FRA_OC**2 * _CM2, (0.0, _FRA_OC), ""),
        "alignment": ("alignment", "m", _FRA_K * a_a * _FRA_OC**2 * _CM2, (0.0, _FRA_OC),
                      f"; A_a = {a_a} cm^2 rad/m [check]"),
        "cross_level_height": ("cross_level", "m", c_h, (_FRA_OC, o_s), xl_note),
        "cross_level": ("cross_level", "rad", c_h / two_b2, (_FRA_OC, o_s),
                        xl_note + f"; angle = height / 2b, b = {HALF_RAIL_DISTANCE} m"),
    }
    out: dict[str, Spectrum] = {}
    for suffix, (kind, unit, coef, poles, note) in rows.items():
        name = f"fra_class{k}.{suffix}"
        out[name] = RationalSpectrum(name=name, kind=kind, unit=unit, source=src + note,
                                     default_band=_FRA_BAND, validity=_FRA_BAND,
                                     coefficient=coef, numerator_power=0, poles=poles)
    name = f"fryba_fra_class{k}.vertical"
    out[name] = FrybaSpectrum(
        name=name, kind="vertical", unit="m", default_band=_FRA_BAND, validity=_FRA_BAND,
        source=(f"US FRA class {k}, cycles/m form of Fryba, Dynamics of Railway Bridges (1996), "
                f"A = {_FRA_FRYBA_A[k - 1]:g}, n1 = 23.3e-3, n2 = 13.1e-2 1/m, converted S(O) = S(n)/(2 pi) "
                "[check: A is listed in m^3 but is dimensionally m, and at wavelengths < 20 m this form lies "
                "10-80x below the rad/m form although their band variances are similar]"),
        a=_FRA_FRYBA_A[k - 1])
    return out


_CHINESE = {  # suffix: (kind, breaks n [1/m], A [mm^2/(1/m) * (1/m)^k], k)
    "vertical": ("vertical", (0.0187, 0.0474, 0.1533), (1.0544e-5, 3.5588e-3, 1.9784e-2, 3.9488e-4),
                 (3.3891, 1.9271, 1.3643, 3.4516)),
    "alignment": ("alignment", (0.0450, 0.1234), (3.9513e-3, 1.1047e-2, 7.5633e-4), (1.8670, 1.5354, 2.8171)),
    "cross_level_height": ("cross_level", (0.0258, 0.1163), (3.6148e-3, 4.3685e-2, 4.5867e-3),
                           (1.7278, 1.0461, 2.0939)),
    "gauge": ("gauge", (0.1090, 0.2938), (5.4978e-2, 5.0701e-3, 1.8778e-4), (0.8282, 1.9037, 4.5948)),
}
_CHINESE_BAND = band_from_wavelengths(2.0, 200.0)
_CHINESE_SRC = ("Chinese ballastless high-speed track spectrum TB/T 3352-2014 (300-350 km/h), "
                "S(n) = A/n^k in mm^2/(1/m), converted S(O) = 1e-6 S(n)/(2 pi); coefficients from public code")


def _chinese() -> dict[str, Spectrum]:
    out: dict[str, Spectrum] = {}
    for suffix, (kind, breaks, amps, exps) in _CHINESE.items():
        note, unit, scale = "", "m", 1e-6
        if suffix == "cross_level_height":
            note = "; the standard gives cross-level as a rail height difference in mm"
        name = f"chinese_tbt3352.{suffix}"
        out[name] = PowerLawSpectrum(name=name, kind=kind, unit=unit, source=_CHINESE_SRC + note,
                                     default_band=_CHINESE_BAND, validity=_CHINESE_BAND,
                                     breaks_n=breaks, amplitudes=amps, exponents=exps, scale=scale)
    h = out["chinese_tbt3352.cross_level_height"]
    assert isinstance(h, PowerLawSpectrum)
    out["chinese_tbt3352.cross_level"] = PowerLawSpectrum(
        name="chinese_tbt3352.cross_level", kind="cross_level", unit="rad",
        source=h.source + f"; angle = height / 2b, b = {HALF_RAIL_DISTANCE} m",
        default_band=h.default_band, validity=h.validity, breaks_n=h.breaks_n, amplitudes=h.amplitudes,
        exponents=h.exponents, scale=h.scale / (2 * HALF_RAIL_DISTANCE) ** 2)
    return out


@lru_cache(maxsize=1)
def _registry() -> Mapping[str, Spectrum]:
    makers: list[Callable[[], dict[str, Spectrum]]] = [lambda: _german("low"), lambda: _german("high"), _chinese]
    makers += [lambda k=k: _fra(k) for k in range(1, 7)]
    reg: dict[str, Spectrum] = {}
    for make in makers:
        reg.update(make())
    return MappingProxyType(dict(sorted(reg.items())))


def spectrum_names() -> list[str]:
    """Sorted names of all built-in spectra."""
    return list(_registry())


@dataclass(frozen=True, eq=False)
class LevelledSpectrum(Spectrum):
    """A spectrum whose PSD is ``level`` times that of ``base`` (the scenario's
    ``track.irregularity_level``: the track's quality as a factor on the spectra's level)."""

    base: Spectrum = None  # type: ignore[assignment]
    level: float = 1.0

    def _psd(self, omega: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.level * self.base._psd(omega)

    def breakpoints(self) -> tuple[float, ...]:
        return self.base.breakpoints()

    def closed_form_variance(self, omega_min: float, omega_max: float) -> float:
        return self.level * self.base.closed_form_variance(omega_min, omega_max)


def track_spectrum(name: str, level: float = 1.0) -> Spectrum:
    """The spectrum ``name`` at the track's level (``track.irregularity_level``): the ONE place where the
    level factor is applied; at level 1 the registry's spectrum itself (bitwise as before)."""
    s = get_spectrum(name)
    if level == 1.0:
        return s
    return LevelledSpectrum(name=s.name, kind=s.kind, unit=s.unit, source=s.source + f"; PSD level x {level:g}",
                            default_band=s.default_band, validity=s.validity, base=s, level=float(level))


def get_spectrum(name: str) -> Spectrum:
    """Built-in spectrum by name; SpectrumError naming the bad name and listing the allowed ones."""
    try:
        return _registry()[name]
    except (KeyError, TypeError):
        raise SpectrumError(f"unknown spectrum {name!r}; allowed names: {', '.join(spectrum_names())}") from None
