"""RandomResponse: the statistics of every output channel over time.

Mean (the deterministic response to gravity), standard deviation sigma(t), and for PEM the
time-dependent one-sided PSD S(f, t) per Hz on the analysed band, with
sigma^2(t) = sum_k S(f_k, t) df_k. For Monte Carlo: sample mean and standard deviation with their
confidence intervals. Saved as ``arrays.npz`` + ``meta.json`` in a folder, written whole or not at
all and read defensively (:mod:`tb_exudyn.storage`).

Exceedance (format 2): a PEM result also holds, per channel and time, the mean's rate, the standard
deviation of the time derivative and the correlation of the channel with its derivative (from the
pseudo-responses of both, tb_exudyn.methods.reduction) and Vanmarcke's bandwidth; a Monte Carlo
result holds every sample's minimum and maximum of every channel over the record.
:meth:`RandomResponse.exceedance_probability` and :meth:`RandomResponse.exceedance_level` answer from
them (PEM: Rice's rate, tb_exudyn.system.statistics; Monte Carlo: empirically, with a Clopper-Pearson
interval), :meth:`RandomResponse.checks` (:class:`.base.ChannelResult`) compares the channels with the code limits.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Mapping

import numpy as np

from ..errors import ResultsError, SettingError
from ..scenario import Scenario, scenario_to_toml
from ..system.channels import is_channel_name
from . import empirical
from ..system import statistics as st
from .base import ChannelResult, ChannelStatistics, check_k
from .metadata import (meta_band, meta_channels, meta_int, meta_provenance, meta_scenario, meta_str, meta_str_list,
                       open_result_folder)
from ..storage import (ArraysInMemory, NpzFile, check_increasing, check_members, check_output_times, check_values, freeze,
                       load_json, save_result_folder)
from .kinds import RANDOM_KINDS, ResultKind
from .schema import RANDOM_RESPONSE, members, optional_names, to_xarray

FORMAT = "tb_exudyn.random_response/2"
#: formats this version reads (1: before the exceedance arrays)
READABLE_FORMATS = ("tb_exudyn.random_response/1", FORMAT)
METHODS = tuple(RANDOM_KINDS)
#: the optional arrays, in file order (the schema's arrays a result may lack)
OPTIONAL_ARRAYS = optional_names(RANDOM_RESPONSE)
#: channel kinds without exceedance statistics (windowed indices, not Gaussian processes)
INDEX_SUFFIXES = (".sperling_z", ".sperling_y")
#: the members of arrays.npz, from the schema (:data:`.schema.RANDOM_RESPONSE`: dims, >= 0, finite,
#: magnitudes); nc channels and ntypes spectra come from meta.json, ns = its n_samples
ARRAYS = members(RANDOM_RESPONSE)
_MEANING = {"nt": "the length of 'time'", "nc": "the number of channels in meta.json", "nf": "the length of 'freq'",
            "npsd": "the number of psd_channels in meta.json (or of channels)",
            "ntypes": "the number of types in meta.json", "ns": "n_samples in meta.json"}
#: relative round-off allowed on the band's upper limit and on the frequencies inside the band
BAND_RTOL = 1e-9


def band_limit(scenario: Scenario) -> tuple[float, str]:
    """The highest upper band edge [Hz] an analysis of ``scenario`` can give a result, and where it comes from.

    PEM (and Monte Carlo on the PEM grid) covers the grid's band, inside [freq_min, freq_max], and the
    scenario keeps freq_max <= 0.1 / analysis.time_step (ten steps per period, Analysis' rule); Monte
    Carlo with its own sampling covers the track's wavelength band, whose upper edge is
    speed / track.wavelength_min (tb_exudyn.methods.sampling, the temporal frequency of the shortest
    wavelength, as tb_exudyn.track.bands converts spatial to temporal frequency). A stored band above
    the larger of the two (plus round-off, :data:`BAND_RTOL`) was made by no analysis of the result's
    scenario: e.g. [0.6, 1e308] for the quick scenario, whose bound is 100 Hz."""
    pem = 0.1 / scenario.analysis.time_step
    mc = scenario.speed / scenario.track.wavelength_min
    return max(pem, mc) * (1 + BAND_RTOL), (f"max(0.1/time_step = {pem:.4g} Hz, "
                                            f"v/wavelength_min = {mc:.4g} Hz)")


@dataclass(frozen=True, eq=False)
class RandomResponse(ChannelResult):
    """Random response of every channel.

    Attributes
    ----------
    method : 'pem' or 'monte_carlo' (or 'monte_carlo_linear' for the batched linear model)
    time : (nt,) output times [s]; t = 0 when the first axle is at x = -lead_in
    channels, units : channel names (docs/channels.md naming) and their units
    mean : (nc, nt) mean response (PEM: the deterministic run with gravity, no irregularity)
    std : (nc, nt) standard deviation over the band ``band``
    band : (f_low, f_high) [Hz] the band sigma covers
    freq, df : (nf,) PEM frequencies and quadrature widths [Hz] (empty for Monte Carlo)
    psd : (nc, nf, nt) one-sided PSD per Hz [unit^2/Hz], or None when not kept
    var_by_type : (ntypes, nc, nt) variance contributed by each irregularity type (PEM), or None
    types : the irregularity spectra, in the order of var_by_type
    std_ci, mean_ci : (2, nc, nt) 95 % confidence intervals (Monte Carlo), or None
    n_samples : Monte Carlo sample count (0 for PEM)
    min_wheel_force : (n_samples,) minimum vertical wheel-rail force per sample [N] (Monte Carlo), or None
    samples : (n_samples, nc, nt) the Monte Carlo samples themselves when kept, or None
    mean_rate, std_rate : (nc, nt) PEM: the mean's time derivative and sigma of the channel's time
        derivative [unit/s], or None
    rho : (nc, nt) PEM: correlation of the channel and its time derivative at the same time, or None
    bandwidth : (nc, nt) PEM: Vanmarcke's delta of the time-dependent PSD, or None
    sample_min, sample_max : (n_samples, nc) Monte Carlo: every sample's minimum and maximum over the
        record, or None
    psd_channels : the channels whose PSD map is kept, in ``psd``'s row order (None: every channel,
        rows as ``channels``)
    scenario : the scenario it was computed for
    provenance : versions, run time, tasks, workers, seed, engine
    """

    method: str
    time: np.ndarray
    channels: tuple[str, ...]
    units: tuple[str, ...]
    mean: np.ndarray
    std: np.ndarray
    band: tuple[float, float]
    scenario: Scenario
    freq: np.ndarray = field(default_factory=lambda: np.zeros(0))
    df: np.ndarray = field(default_factory=lambda: np.zeros(0))
    psd: np.ndarray | None = None
    var_by_type: np.ndarray | None = None
    types: tuple[str, ...] = ()
    std_ci: np.ndarray | None = None
    mean_ci: np.ndarray | None = None
    n_samples: int = 0
    min_wheel_force: np.ndarray | None = None
    samples: np.ndarray | None = None
    provenance: dict[str, Any] = field(default_factory=dict)
    mean_rate: np.ndarray | None = None
    std_rate: np.ndarray | None = None
    rho: np.ndarray | None = None
    bandwidth: np.ndarray | None = None
    sample_min: np.ndarray | None = None
    sample_max: np.ndarray | None = None
    psd_channels: tuple[str, ...] | None = None
    #: every array this type holds, declared once (:mod:`.schema`): npz, NetCDF and checks
    schema: ClassVar = RANDOM_RESPONSE

    # ---------------------------------------------------------------- access
    def arrays(self) -> dict[str, np.ndarray]:
        """Every array of the result by its schema name (:data:`.schema.RANDOM_RESPONSE`), those it
        holds (an optional one that is None is left out): what ``arrays.npz`` stores."""
        return {v.name: getattr(self, v.name) for v in self.schema if getattr(self, v.name) is not None}

    def to_xarray(self) -> Any:
        """The result as an :class:`xarray.Dataset`: every array under its schema, channel names,
        units and labels as coordinates, provenance as attributes (:func:`.schema.to_xarray`)."""
        return to_xarray(self)

    @property
    def channel_names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    def unit(self, channel: str) -> str:
        return self.units[self.index(channel)]

    def psd_row(self, channel: str) -> int | None:
        """Row of ``channel`` in ``psd`` (None: its PSD map is not kept)."""
        if self.psd is None:
            return None
        if self.psd_channels is None:
            return self.index(channel)
        return self.psd_channels.index(channel) if channel in self.psd_channels else None

    def __getitem__(self, channel: str) -> ChannelStatistics:
        """One channel's statistics by name, e.g. ``pem["car1.body.acc_y"].std`` (``psd``: None when
        its map is not kept)."""
        i = self.index(channel)
        row = self.psd_row(channel)
        return ChannelStatistics(name=channel, unit=self.units[i], time=self.time, mean=self.mean[i],
                                 std=self.std[i], freq=self.freq, psd=None if row is None else self.psd[row])

    def bounds(self, k: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
        """mean - k sigma and mean + k sigma, each (nc, nt) (k finite and > 0, else SettingError)."""
        k = check_k(k, "RandomResponse.bounds")
        return self.mean - k * self.std, self.mean + k * self.std

    def summary_rows(self, k: float = 3.0) -> list[tuple[str, str, float, float, float]]:
        """Per channel: name, unit, max |mean|, max sigma, max |mean| + k sigma (over time; NaN samples,
        e.g. after a windowed index's last whole window, are left out); k finite and > 0."""
        k = check_k(k, "RandomResponse.summary_rows")
        with np.errstate(invalid="ignore"):
            peak = np.nanmax(np.abs(self.mean) + k * self.std, axis=1, initial=-np.inf)
            mm = np.nanmax(np.abs(self.mean), axis=1, initial=-np.inf)
            ms = np.nanmax(self.std, axis=1, initial=-np.inf)
        return [(c, u, float(m), float(s), float(p)) for c, u, m, s, p in zip(self.channels, self.units, mm, ms, peak)]

    # ---------------------------------------------------------------- exceedance
    @property
    def kind(self) -> ResultKind:
        """What the result is (:mod:`.kinds`: Gaussian (PEM) or sampled (Monte Carlo), ...), by its method."""
        return RANDOM_KINDS[self.method]

    def _exceedance_channel(self, channel: str, where: str) -> int:
        i = self.index(channel)
        if channel.endswith(INDEX_SUFFIXES):
            raise SettingError(where, "channel", channel, "a channel that is a random process (not a windowed index)",
                               "a Sperling index is evaluated per window: compare its values, not an exceedance")
        return i

    def gaussian(self, channel: str) -> st.GaussianResponse:
        """The per-time Gaussian statistics of a PEM channel and its derivative (:class:`~.statistics.GaussianResponse`)."""
        where = "RandomResponse.gaussian"
        i = self._exceedance_channel(channel, where)
        if not self.kind.gaussian or self.std_rate is None or self.rho is None or self.mean_rate is None:
            raise ResultsError(f"{where}: {self.method} result without the derivative statistics (a PEM result "
                               "of format 2 has them)")
        bw = None if self.bandwidth is None else np.clip(self.bandwidth[i], 0.0, 1.0)
        return st.GaussianResponse(self.time, self.mean[i], self.mean_rate[i], self.std[i], self.std_rate[i],
                                   self.rho[i], bw)

    def _extremes(self, channel: str, where: str, window: tuple[float, float] | None
                  ) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
        i = self._exceedance_channel(channel, where)
        if self.sample_min is None or self.sample_max is None:
            raise ResultsError(f"{where}: Monte Carlo result without per-sample extremes (format 2 results have them)")
        span = (float(self.time[0]), float(self.time[-1]))
        if window is not None and (float(window[0]) > span[0] or float(window[1]) < span[1]):
            raise SettingError(where, "window", window, f"None (a Monte Carlo result keeps each sample's extremes over "
                               f"its whole record {span[0]:g}-{span[1]:g} s)")
        lo, hi = self.sample_min[:, i], self.sample_max[:, i]
        keep = np.isfinite(lo) & np.isfinite(hi)
        return lo[keep], hi[keep], span

    def exceedance_probability(self, channel: str, upper: float | None = None, lower: float | None = None,
                               method: str = "poisson", *, window: tuple[float, float] | None = None,
                               confidence: float = 0.99, initial: bool = True) -> st.Exceedance:
        """The probability that ``channel`` leaves [lower, upper] at least once in the result's time window
        (or ``window``, PEM only); either bound may be None, not both.

        PEM: Rice's non-stationary up-crossing rate from the channel's and its derivative's statistics,
        first passage by ``method`` 'poisson' (out-crossings independent: errs high, on the safe side, for
        narrow-band responses) or 'vanmarcke' (tb_exudyn.system.statistics gives the formulas and the
        measured errors). Monte Carlo: the fraction of samples that left the bounds, with its
        Clopper-Pearson interval at ``confidence`` (``method`` is ignored: 'empirical')."""
        if self.kind.gaussian:
            return st.first_passage_probability(self.gaussian(channel), lower=lower, upper=upper, method=method,  # type: ignore[arg-type]
                                                window=window, initial=initial, channel=channel)
        lo, hi, span = self._extremes(channel, "RandomResponse.exceedance_probability", window)
        return empirical.empirical_exceedance_from_extremes(lo, hi, span, lower=lower, upper=upper, confidence=confidence,
                                                     channel=channel)

    def exceedance_level(self, channel: str, probability: float, kind: str = "symmetric", method: str = "poisson", *,
                         window: tuple[float, float] | None = None, confidence: float = 0.99,
                         initial: bool = True) -> st.ExceedanceLevel:
        """The level ``channel`` exceeds at least once in the window with ``probability``: kind 'symmetric'
        (|y| > level), 'upper' (y > level) or 'lower' (y < level); PEM by ``method``, Monte Carlo from the
        per-sample extremes (quantile with an order-statistic interval at ``confidence``)."""
        if self.kind.gaussian:
            return st.exceedance_level(self.gaussian(channel), probability, kind=kind, method=method,  # type: ignore[arg-type]
                                       window=window, initial=initial, channel=channel)
        lo, hi, span = self._extremes(channel, "RandomResponse.exceedance_level", window)
        return empirical.empirical_level_from_extremes(lo, hi, span, probability, kind=kind, confidence=confidence,  # type: ignore[arg-type]
                                                channel=channel)

    # ---------------------------------------------------------------- files
    def save(self, folder: str | Path) -> Path:
        """Write ``arrays.npz`` and ``meta.json`` as the folder ``folder``, whole or not at all
        (an older result there is replaced; see :func:`tb_exudyn.storage.save_result_folder`).

        What :func:`load_random_response` would refuse is refused first, nothing written: a
        ResultsError naming the file and the key (e.g. a negative ``std`` set in Python)."""
        arrays = self.arrays()
        meta = {
            "format": FORMAT,
            "method": self.method,
            "channels": list(self.channels),
            "units": list(self.units),
            "band_hz": list(self.band),
            "types": list(self.types),
            "n_samples": self.n_samples,
            "provenance": self.provenance,
            "scenario_toml": scenario_to_toml(self.scenario),
        }
        if self.psd_channels is not None:
            meta["psd_channels"] = list(self.psd_channels)
        return save_result_folder(folder, arrays, meta, check=check_folder)


def _read_meta(meta: dict[str, Any], path: Path) -> dict[str, Any]:
    """The fields of a random response's meta.json, each checked (ResultsError naming ``path`` and the key)."""
    meta_str(meta, "format", path, choices=READABLE_FORMATS)
    method = meta_str(meta, "method", path, choices=METHODS)
    channels, units = meta_channels(meta, path)
    types = meta_str_list(meta, "types", path, check=is_channel_name, rule="spectrum names (e.g. german_low.vertical)",
                          unique=True)
    n_samples = meta_int(meta, "n_samples", path, 0)
    psd_channels = None
    if "psd_channels" in meta:
        psd_channels = meta_str_list(meta, "psd_channels", path, check=lambda c: c in channels,
                                     rule="names from 'channels'", unique=True)
    provenance = meta_provenance(meta, path)
    scenario = meta_scenario(meta, path)
    band = meta_band(meta, "band_hz", path, *band_limit(scenario))
    return {"method": str(method), "channels": tuple(channels), "units": tuple(units), "band": band,
            "types": tuple(types), "n_samples": n_samples, "provenance": provenance, "scenario": scenario,
            "psd_channels": None if psd_channels is None else tuple(psd_channels)}


def _sizes(fields: dict[str, Any]) -> dict[str, int]:
    channels, psd_channels = fields["channels"], fields["psd_channels"]
    return {"nc": len(channels), "ntypes": len(fields["types"]), "ns": fields["n_samples"],
            "npsd": len(channels) if psd_channels is None else len(psd_channels)}


def _check_arrays(path: Path, arrays: Mapping[str, np.ndarray], fields: dict[str, Any]) -> None:
    """The values of the arrays (their shapes already checked): finite and >= 0 where :data:`ARRAYS` says,
    at least two output times, time and freq increasing, a PEM result's frequencies inside its band."""
    check_values(path, arrays, ARRAYS)
    check_output_times(path, arrays["time"])
    check_increasing(path, arrays, ("time", "freq"))
    freq, (lo, hi) = arrays["freq"], fields["band"]
    if "psd" in arrays and freq.size == 0:
        raise ResultsError(f"{path}: array 'psd' is a map over no frequency ('freq' is empty) (allowed: a PSD map "
                           "with at least one frequency, or no 'psd')")
    tol = BAND_RTOL * hi
    if freq.size and (freq[0] < lo - tol or freq[-1] > hi + tol):
        raise ResultsError(f"{path}: array 'freq' spans {float(freq[0])!r} to {float(freq[-1])!r} Hz, outside the "
                           f"band_hz [{lo!r}, {hi!r}] of meta.json (allowed: frequencies inside the band)")


def check_folder(folder: Path, arrays: Mapping[str, np.ndarray], meta: dict[str, Any]) -> None:
    """What :func:`load_random_response` checks, on a result about to be saved to ``folder``
    (``meta`` as meta.json will give it back): the check :meth:`RandomResponse.save` runs first."""
    fields = _read_meta(meta, folder / "meta.json")
    check_members(ArraysInMemory(folder / "arrays.npz", arrays), ARRAYS, _sizes(fields), _MEANING)
    _check_arrays(folder / "arrays.npz", arrays, fields)


def load_random_response(folder: str | Path) -> RandomResponse:
    """Read a RandomResponse written by :meth:`RandomResponse.save`, checking everything before use.

    Raises ResultsError (one line, naming the file) for a missing, foreign, damaged or hostile
    folder: see :mod:`tb_exudyn.storage`; channel names must follow the naming rule, the arrays' shapes match
    the channels, types and n_samples of meta.json and each other (:data:`ARRAYS`), checked before
    any array is read; time increasing and values finite; standard deviations, PSDs, variances,
    frequencies and widths >= 0; the band 0 <= f_low < f_high <= :func:`band_limit` of the result's
    scenario, a PEM result's frequencies inside it; the provenance fields the code reads of the types
    it writes (:data:`.metadata.PROVENANCE_FIELDS`). The arrays are read-only.
    """
    folder = open_result_folder(folder)
    path = folder / "meta.json"
    fields = _read_meta(load_json(path), path)
    with NpzFile(folder / "arrays.npz") as npz:
        check_members(npz, ARRAYS, _sizes(fields), _MEANING)
        arrays = npz.read_all()
    _check_arrays(npz.path, arrays, fields)
    freeze(arrays)
    return RandomResponse(**fields, **{v.name: arrays.get(v.name) for v in RANDOM_RESPONSE})
