"""Exceedance of Monte Carlo samples, counted: the fraction of samples that leave [lower, upper] in a
window, its Clopper-Pearson interval, and the empirical level for a probability (the counterparts of
:mod:`.statistics` for Monte Carlo results)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import SettingError
from ..system.statistics import LEVEL_KINDS, Exceedance, ExceedanceLevel, LevelKind, _check_bounds, _check_probability, _shape, _window_mask


def binomial_interval(k: int, n: int, confidence: float = 0.99) -> tuple[float, float]:
    """Clopper-Pearson ("exact") two-sided interval of a binomial proportion k/n.

    Chosen over Wilson because its coverage is at least ``confidence`` for every true probability and
    every n (Wilson's is only close to it on average and falls below it for p near 0, where
    exceedance probabilities of code limits live); the price is a slightly wider interval.
    """
    from scipy import stats

    if n <= 0 or not 0 <= k <= n:
        raise SettingError("binomial_interval", "k", k, f"0 <= k <= n with n = {n} > 0")
    if not 0.0 < confidence < 1.0:
        raise SettingError("binomial_interval", "confidence", confidence, "a level strictly between 0 and 1")
    alpha = 1.0 - confidence
    low = 0.0 if k == 0 else float(stats.beta.ppf(alpha / 2, k, n - k + 1))
    high = 1.0 if k == n else float(stats.beta.ppf(1 - alpha / 2, k + 1, n - k))
    return low, high


def _samples(where: str, samples: ArrayLike, time: ArrayLike, window: tuple[float, float] | None
             ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    y = np.asarray(samples, dtype=float)
    t = np.asarray(time, dtype=float)
    if y.ndim != 2 or t.ndim != 1 or y.shape[1] != t.size or y.shape[0] < 1:
        raise SettingError(where, "samples", _shape(y), f"an array (n_samples, n_t = {t.size}) matching time")
    mask = _window_mask(t, window, where)
    return y[:, mask], t[mask]


def sample_extremes(samples: ArrayLike, time: ArrayLike, window: tuple[float, float] | None = None
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[float, float]]:
    """(per-sample minimum, per-sample maximum, (t_start, t_end)) of Monte Carlo samples (n_samples, n_t)
    over the window: all that the empirical statistics need, so an engine can keep these (2 numbers per
    sample and channel) instead of the samples."""
    y, t = _samples("sample_extremes", samples, time, window)
    return y.min(axis=1), y.max(axis=1), (float(t[0]), float(t[-1]))


def _extremes(where: str, sample_min: ArrayLike, sample_max: ArrayLike) -> tuple[NDArray, NDArray]:
    lo, hi = np.asarray(sample_min, dtype=float), np.asarray(sample_max, dtype=float)
    if lo.ndim != 1 or lo.shape != hi.shape or lo.size < 1 or np.any(lo > hi):
        raise SettingError(where, "sample_min", _shape(lo), "per-sample minima and maxima of equal shape (n_samples,), min <= max")
    return lo, hi


def empirical_exceedance_from_extremes(sample_min: ArrayLike, sample_max: ArrayLike, window: tuple[float, float], *,
                                       lower: float | None = None, upper: float | None = None,
                                       confidence: float = 0.99, channel: str = "") -> Exceedance:
    """:func:`empirical_exceedance` from per-sample extremes over ``window`` (:func:`sample_extremes`)."""
    where = "empirical_exceedance"
    lo, hi = _check_bounds(where, lower, upper)
    y_min, y_max = _extremes(where, sample_min, sample_max)
    out = (y_min < lo) | (y_max > hi)
    k, n = int(out.sum()), int(out.size)
    return Exceedance(k / n, "empirical", (float(window[0]), float(window[1])), lower, upper, channel,
                      binomial_interval(k, n, confidence), confidence, n, k)


def empirical_exceedance(samples: ArrayLike, time: ArrayLike, *, lower: float | None = None,
                         upper: float | None = None, confidence: float = 0.99,
                         window: tuple[float, float] | None = None, channel: str = "") -> Exceedance:
    """The fraction of Monte Carlo samples (n_samples, n_t) that leave [lower, upper] at least once in the
    window, with its Clopper-Pearson interval (:func:`binomial_interval`). A sample counts as leaving
    when one of its time samples is outside (strictly below lower or above upper)."""
    _check_bounds("empirical_exceedance", lower, upper)
    y_min, y_max, span = sample_extremes(samples, time, window)
    return empirical_exceedance_from_extremes(y_min, y_max, span, lower=lower, upper=upper, confidence=confidence,
                                              channel=channel)


def empirical_level_from_extremes(sample_min: ArrayLike, sample_max: ArrayLike, window: tuple[float, float],
                                  probability: float, *, kind: LevelKind = "symmetric", confidence: float = 0.99,
                                  channel: str = "") -> ExceedanceLevel:
    """:func:`empirical_level` from per-sample extremes over ``window`` (:func:`sample_extremes`)."""
    from scipy import stats

    where = "empirical_level"
    p = _check_probability(where, probability)
    if kind not in LEVEL_KINDS:
        raise SettingError(where, "kind", kind, " | ".join(LEVEL_KINDS))
    if not 0.0 < confidence < 1.0:
        raise SettingError(where, "confidence", confidence, "a level strictly between 0 and 1")
    y_min, y_max = _extremes(where, sample_min, sample_max)
    extreme = {"symmetric": np.maximum(np.abs(y_min), np.abs(y_max)), "upper": y_max, "lower": y_min}[kind]
    q = p if kind == "lower" else 1.0 - p
    n = extreme.size
    ordered = np.sort(extreme)
    alpha = 1.0 - confidence
    r = int(stats.binom.ppf(alpha / 2, n, q))
    s = int(stats.binom.ppf(1 - alpha / 2, n, q)) + 1
    low = ordered[max(r, 1) - 1]
    high = ordered[min(s, n) - 1]
    return ExceedanceLevel(kind, float(np.quantile(extreme, q)), p, "empirical", (float(window[0]), float(window[1])),
                           channel, (float(low), float(high)), confidence, n)


def empirical_level(samples: ArrayLike, time: ArrayLike, probability: float, *, kind: LevelKind = "symmetric",
                    confidence: float = 0.99, window: tuple[float, float] | None = None,
                    channel: str = "") -> ExceedanceLevel:
    """The level exceeded with the given probability by Monte Carlo samples (n_samples, n_t).

    The per-sample extreme e_i (max |y|, max y or min y over the window) is found; the level is its
    (1 - p) quantile (p for 'lower'; numpy's linear interpolation), and the interval the
    distribution-free order-statistic interval [e_(r), e_(s)] with r, s from the binomial
    distribution of the number of e_i below the true quantile (coverage >= ``confidence``).
    """
    y_min, y_max, span = sample_extremes(samples, time, window)
    return empirical_level_from_extremes(y_min, y_max, span, probability, kind=kind, confidence=confidence,
                                         channel=channel)


__all__ = ["binomial_interval", "sample_extremes", "empirical_exceedance_from_extremes", "empirical_exceedance", "empirical_level_from_extremes", "empirical_level"]
