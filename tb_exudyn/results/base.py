"""What every result shares: channels by name, selection by pattern, and ``plot()``.

``plot()`` hands off to :mod:`tb_exudyn.plotting` (matplotlib), which is loaded on first use by
name (``importlib``), so that reading results in a worker or a script without figures never imports
matplotlib; plotting imports the result types, not the other way round.
"""

from __future__ import annotations

import fnmatch
import importlib
import math
import numbers
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..errors import SettingError

#: kind of figure -> the plotting function drawing it for one channel
PLOTS = {"bounds": "plot_bounds", "psd_map": "plot_psd_map", "psd_slices": "plot_psd_slices",
         "history": "plot_time_history"}


def check_k(k: Any, where: str) -> float:
    """The factor k of mean +- k sigma as a float: a real number (not a bool), finite and > 0 (k <= 0
    would swap or merge the bounds, NaN or inf give no bounds); SettingError naming ``k`` otherwise."""
    if isinstance(k, bool) or not isinstance(k, numbers.Real) or not math.isfinite(float(k)) or not float(k) > 0.0:
        raise SettingError(where, "k", k, "a finite number > 0 (mean +- k sigma, e.g. 3)")
    return float(k)


@dataclass(frozen=True)
class ChannelStatistics:
    """One channel of a random response: its unit, mean and sigma over time (and PSD map when kept)."""

    name: str
    unit: str
    time: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    freq: np.ndarray
    psd: np.ndarray | None

    def bounds(self, k: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
        """mean - k sigma and mean + k sigma over time (k finite and > 0, else SettingError)."""
        k = check_k(k, "ChannelStatistics.bounds")
        return self.mean - k * self.std, self.mean + k * self.std


class ChannelResult:
    """Channel access shared by :class:`~.time_history.TimeHistory` and
    :class:`~.random_response.RandomResponse` (subclasses give ``channel_names`` and ``unit``)."""

    default_plot = "bounds"

    @property
    def channel_names(self) -> tuple[str, ...]:  # pragma: no cover - overridden
        raise NotImplementedError

    def index(self, channel: str) -> int:
        """Row of a channel; KeyError listing close names if unknown."""
        names = self.channel_names
        try:
            return names.index(channel)
        except ValueError:
            head = channel.split(".")[0]
            close = [c for c in names if c.startswith(head)][:8] or list(names[:8])
            raise KeyError(f"no channel {channel!r}; e.g. {close}") from None

    def select(self, patterns: str | Sequence[str]) -> list[str]:
        """Channel names matching glob pattern(s), in stored order."""
        pats = [patterns] if isinstance(patterns, str) else list(patterns)
        return [c for c in self.channel_names if any(fnmatch.fnmatchcase(c, p) for p in pats)]

    def plot(self, channel: str, kind: str | None = None, **options: Any) -> Any:
        """A figure of one channel (a :class:`matplotlib.figure.Figure`): ``kind`` "bounds" (mean
        +- k sigma, the default of a random response), "psd_map", "psd_slices" or "history" (a time
        history's default); ``options`` go to the plotting function (:mod:`tb_exudyn.plotting`)."""
        kind = kind or self.default_plot
        if kind not in PLOTS:
            raise SettingError("plot", "kind", kind, " or ".join(map(repr, PLOTS)))
        self.index(channel)
        plotting = importlib.import_module("tb_exudyn.plotting.figures")  # matplotlib on first use
        return getattr(plotting, PLOTS[kind])(self, channel, **options)


__all__ = ["ChannelResult", "ChannelStatistics", "PLOTS"]
