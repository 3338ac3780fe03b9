"""RandomResponse: the statistics of every output channel over time.

Mean (the deterministic response to gravity), standard deviation sigma(t), and for PEM the
time-dependent one-sided PSD S(f, t) per Hz on the analysed band, with
sigma^2(t) = sum_k S(f_k, t) df_k. For Monte Carlo: sample mean and standard deviation with their
confidence intervals. Saved as ``arrays.npz`` + ``meta.json`` in a folder, written whole or not at
all and read defensively (:mod:`.storage`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..scenario import Scenario, scenario_to_toml
from ..system.channels import is_channel_name
from .base import ChannelResult, ChannelStatistics
from .metadata import (meta_band, meta_channels, meta_dict, meta_int, meta_scenario, meta_str, meta_str_list,
                       open_result_folder)
from .storage import Member, NpzFile, check_increasing, check_members, check_values, load_json, save_result_folder

FORMAT = "tb_exudyn.random_response/1"
METHODS = ("pem", "monte_carlo", "monte_carlo_linear")
#: the arrays of arrays.npz; nc channels and ntypes spectra come from meta.json, ns = its n_samples
ARRAYS = {
    "time": Member(("nt",)), "mean": Member(("nc", "nt")), "std": Member(("nc", "nt")),
    "freq": Member(("nf",)), "df": Member(("nf",)),
    "psd": Member(("nc", "nf", "nt"), required=False), "var_by_type": Member(("ntypes", "nc", "nt"), required=False),
    "std_ci": Member((2, "nc", "nt"), required=False), "mean_ci": Member((2, "nc", "nt"), required=False),
    "min_wheel_force": Member(("ns",), required=False, finite=False),  # NaN: a sample without wheel forces
    "samples": Member(("ns", "nc", "nt"), required=False, finite=False),
}
_MEANING = {"nt": "the length of 'time'", "nc": "the number of channels in meta.json", "nf": "the length of 'freq'",
            "ntypes": "the number of types in meta.json", "ns": "n_samples in meta.json"}


@dataclass(frozen=True, eq=False)
class RandomResponse(ChannelResult):
    """Random response of every channel.

    Attributes
    ----------
    method : 'pem' or 'monte_carlo' (or 'monte_carlo_linear' for the batched linear model)
    time : (nt,) output times [s]; t = 0 when the first axle is at x = -lead_in
    channels, units : channel names (DESIGN.md naming) and their units
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

    # ---------------------------------------------------------------- access
    @property
    def channel_names(self) -> tuple[str, ...]:
        return tuple(self.channels)

    def unit(self, channel: str) -> str:
        return self.units[self.index(channel)]

    def __getitem__(self, channel: str) -> ChannelStatistics:
        """One channel's statistics by name, e.g. ``pem["car1.body.acc_y"].std``."""
        i = self.index(channel)
        return ChannelStatistics(name=channel, unit=self.units[i], time=self.time, mean=self.mean[i],
                                 std=self.std[i], freq=self.freq, psd=None if self.psd is None else self.psd[i])

    def bounds(self, k: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
        """mean - k sigma and mean + k sigma, each (nc, nt)."""
        return self.mean - k * self.std, self.mean + k * self.std

    def summary_rows(self, k: float = 3.0) -> list[tuple[str, str, float, float, float]]:
        """Per channel: name, unit, max |mean|, max sigma, max |mean| + k sigma (over time)."""
        peak = np.max(np.abs(self.mean) + k * self.std, axis=1)
        return [
            (c, u, float(np.max(np.abs(m))), float(np.max(s)), float(p))
            for c, u, m, s, p in zip(self.channels, self.units, self.mean, self.std, peak)
        ]

    # ---------------------------------------------------------------- files
    def save(self, folder: str | Path) -> Path:
        """Write ``arrays.npz`` and ``meta.json`` as the folder ``folder``, whole or not at all
        (an older result there is replaced; see :func:`.storage.save_result_folder`)."""
        arrays = {"time": self.time, "mean": self.mean, "std": self.std, "freq": self.freq, "df": self.df}
        for name in ("psd", "var_by_type", "std_ci", "mean_ci", "min_wheel_force", "samples"):
            value = getattr(self, name)
            if value is not None:
                arrays[name] = value
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
        return save_result_folder(folder, arrays, meta)


def load_random_response(folder: str | Path) -> RandomResponse:
    """Read a RandomResponse written by :meth:`RandomResponse.save`, checking everything before use.

    Raises ResultsError (one line, naming the file) for a missing, foreign, damaged or hostile
    folder: see :mod:`.storage`; channel names must follow the naming rule, the arrays' shapes match
    the channels, types and n_samples of meta.json and each other (:data:`ARRAYS`), checked before
    any array is read; time increasing and values finite.
    """
    folder = open_result_folder(folder)
    path = folder / "meta.json"
    meta = load_json(path)
    meta_str(meta, "format", path, choices=(FORMAT,))
    method = meta_str(meta, "method", path, choices=METHODS)
    channels, units = meta_channels(meta, path)
    band = meta_band(meta, "band_hz", path)
    types = meta_str_list(meta, "types", path, check=is_channel_name, rule="spectrum names (e.g. german_low.vertical)",
                          unique=True)
    n_samples = meta_int(meta, "n_samples", path, 0)
    provenance = meta_dict(meta, "provenance", path)
    scenario = meta_scenario(meta, path)
    with NpzFile(folder / "arrays.npz") as npz:
        check_members(npz, ARRAYS, {"nc": len(channels), "ntypes": len(types), "ns": n_samples}, _MEANING)
        arrays = npz.read_all()
    check_values(npz.path, arrays, ARRAYS)
    check_increasing(npz.path, arrays, ("time", "freq"))
    return RandomResponse(
        method=str(method),
        time=arrays["time"],
        channels=tuple(channels),
        units=tuple(units),
        mean=arrays["mean"],
        std=arrays["std"],
        band=band,
        scenario=scenario,
        freq=arrays["freq"],
        df=arrays["df"],
        psd=arrays.get("psd"),
        var_by_type=arrays.get("var_by_type"),
        types=tuple(types),
        std_ci=arrays.get("std_ci"),
        mean_ci=arrays.get("mean_ci"),
        n_samples=n_samples,
        min_wheel_force=arrays.get("min_wheel_force"),
        samples=arrays.get("samples"),
        provenance=provenance,
    )
