"""Values of derived channels from real time histories (a deterministic run, the mean, one sample).

The definitions are in :mod:`tb_exudyn.system.derived`; this module evaluates them on real signals
sampled at fs [Hz] from t = 0: linear combinations, EN 12299 weightings filtered in time from rest
(:func:`tb_exudyn.system.comfort.apply_weighting`), exact ratios, and Sperling indices per window
(:func:`tb_exudyn.system.comfort.sperling_window_energy`), which become a piecewise-constant series
(:func:`window_series`: each window's value at its samples, the last window's after it).
"""

from __future__ import annotations

import dataclasses
from typing import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from .derived import DerivedChannel
from .comfort import apply_weighting, sperling_index, sperling_window_energy, window_slices

FloatArray = NDArray[np.float64]


def combine(terms: Sequence[tuple[str, float]], values: Mapping[str, np.ndarray]) -> np.ndarray:
    """sum_j c_j values[name_j] (any shape, real or complex)."""
    out = None
    for name, c in terms:
        part = c * np.asarray(values[name])
        out = part if out is None else out + part
    assert out is not None, "a derived channel has at least one term"
    return out


def window_series(values: np.ndarray, n_t: int, fs: float, window: float) -> FloatArray:
    """A per-window index (..., n_w) as a series (..., n_t): window w's value at its samples (the
    windows of :func:`~tb_exudyn.system.comfort.window_slices`); the samples after the last whole
    window (shorter than a window, so without an index of their own) hold the last window's value, so
    the series is finite and its maximum is the largest window value."""
    slices, _ = window_slices(n_t, fs, window, "window_series")
    v = np.asarray(values, dtype=float)
    out = np.empty(v.shape[:-1] + (n_t,))
    for w, s in enumerate(slices):
        out[..., s] = v[..., w : w + 1]
    out[..., slices[-1].stop:] = v[..., -1:]
    return out


def sperling_series(acc: np.ndarray, fs: float, channel: DerivedChannel) -> FloatArray:
    """Sperling Wz of acceleration histories (..., n_t) per window of ``channel.window``, as a series."""
    _, _, energy = sperling_window_energy(acc, fs, channel.weighting, window=channel.window)  # type: ignore[arg-type]
    return window_series(sperling_index(energy), np.shape(acc)[-1], fs, channel.window)


def derived_value(channel: DerivedChannel, values: Mapping[str, np.ndarray], fs: float) -> FloatArray:
    """The values of one derived channel from real histories ``values`` (name -> (..., n_t)) at fs [Hz]."""
    if channel.kind == "linear":
        return combine(channel.terms, values)
    if channel.kind == "weighted":
        return apply_weighting(combine(channel.terms, values), fs, channel.weighting)  # type: ignore[arg-type]
    if channel.kind == "ratio":  # NaN where the denominator is 0 (e.g. a run without gravity: no wheel load)
        with np.errstate(divide="ignore", invalid="ignore"):
            return combine(channel.terms, values) / combine(channel.denominator, values)
    if channel.kind == "sperling":
        return sperling_series(combine(channel.terms, values), fs, channel)
    raise ValueError(f"unknown derived kind {channel.kind!r}")  # pragma: no cover - DerivedChannel's Literal


def derived_values(channels: Sequence[DerivedChannel], values: Mapping[str, np.ndarray], fs: float
                   ) -> dict[str, FloatArray]:
    """Name -> values of every derived channel (:func:`derived_value`). A Sperling window longer than
    these histories (a run shorter than the crossing, ``run_model(duration=...)``) is the whole record,
    as the channel catalogue makes it for a crossing shorter than the window."""
    n_t = max((np.shape(v)[-1] for v in values.values()), default=0)
    record = n_t / fs
    return {d.name: derived_value(dataclasses.replace(d, window=record)
                                  if d.kind == "sperling" and d.window > record else d,
                                  values, fs) for d in channels}


__all__ = ["combine", "derived_value", "derived_values", "sperling_series", "window_series"]
