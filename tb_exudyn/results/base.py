"""What every result shares: channels by name, selection by pattern, ``checks()`` and the ``plot`` accessor.

``result.plot`` (:class:`PlotAccessor`): ``result.plot.bounds(channel)``, ``.psd_map(channel)``,
``.psd_slices(channel)``, ``.history(channels)``, or ``result.plot(channel, kind)``; each hands off to
a function of :mod:`tb_exudyn.plotting` (matplotlib). Results import no plotting (plotting imports
the result types): the package root gives the loader of the plotting package
(:func:`set_figure_loader`, in tb_exudyn/__init__.py), which runs on the first figure, so that
reading results in a worker or a script without figures never imports matplotlib.
"""

from __future__ import annotations

import fnmatch
import math
import numbers
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import ArgumentTypeError, SettingError
from .checks import cached_checks

#: kind of figure -> the plotting function drawing it for one channel
PLOTS = {"bounds": "plot_bounds", "psd_map": "plot_psd_map", "psd_slices": "plot_psd_slices",
         "history": "plot_time_history"}
_figure_loader: list[Callable[[], Any]] = []


def set_figure_loader(loader: Callable[[], Any]) -> None:
    """Say how the plotting package is loaded (the package root does, once): ``loader()`` returns
    the module whose ``plot_*`` functions the accessors call."""
    _figure_loader[:] = [loader]


def figures() -> Any:
    """The plotting package (matplotlib loaded now, on the first figure)."""
    if not _figure_loader:  # a bug: tb_exudyn/__init__.py sets it before any result exists
        raise RuntimeError("no figure loader set (tb_exudyn/__init__.py sets it)")
    return _figure_loader[0]()


def channel_name(channel: Any, result: Any) -> str:
    """``channel`` if it is a channel's name (a string), else ArgumentTypeError saying what to pass: a
    channel is named, never numbered (``result["bridge.span1.x4/8.acc_z"]``; the names in stored order
    are ``result.channel_names``)."""
    if isinstance(channel, str):
        return channel
    names = list(getattr(result, "channel_names", ()))
    example = repr(names[0]) if names else "'bridge.span1.x4/8.acc_z'"
    hint = f"; the name of row {channel} is result.channel_names[{channel}]" if isinstance(channel, int) else ""
    raise ArgumentTypeError(type(result).__name__, "channel", channel,
                            f"a channel's name (a str), e.g. {example}; the names: result.channel_names",
                            f"a channel is named by a string, not by a value of type {type(channel).__name__}{hint}")


class PlotAccessor:
    """``result.plot``: the figures of one result (each a :class:`matplotlib.figure.Figure`, made by
    :mod:`tb_exudyn.plotting`; ``options`` go to the plotting function)."""

    def __init__(self, result: "ChannelResult") -> None:
        self._result = result

    def __call__(self, channel: str, kind: str | None = None, **options: Any) -> Any:
        """A figure of one channel: ``kind`` "bounds" (mean +- k sigma, the default of a random
        response), "psd_map", "psd_slices" or "history" (a time history's default)."""
        kind = kind or self._result.default_plot
        if kind not in PLOTS:
            raise SettingError("plot", "kind", kind, " or ".join(map(repr, PLOTS)))
        self._result.index(channel)
        return getattr(figures(), PLOTS[kind])(self._result, channel, **options)

    def bounds(self, channel: str, k: float = 3.0, **options: Any) -> Any:
        """mean +- k sigma of ``channel`` over time (:func:`tb_exudyn.plotting.plot_bounds`)."""
        return self(channel, "bounds", k=k, **options)

    def psd_map(self, channel: str, **options: Any) -> Any:
        """The time-dependent PSD map of ``channel`` (:func:`tb_exudyn.plotting.plot_psd_map`)."""
        return self(channel, "psd_map", **options)

    def psd_slices(self, channel: str, **options: Any) -> Any:
        """The PSD of ``channel`` at a few times (:func:`tb_exudyn.plotting.plot_psd_slices`)."""
        return self(channel, "psd_slices", **options)

    def history(self, channels: str | Sequence[str], **options: Any) -> Any:
        """The values of one channel or several over time (:func:`tb_exudyn.plotting.plot_time_history`)."""
        for channel in [channels] if isinstance(channels, str) else channels:
            self._result.index(channel)
        return figures().plot_time_history(self._result, channels, **options)


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
        """Row of a channel; KeyError listing close names if unknown (ArgumentTypeError, a TypeError, if
        ``channel`` is no string)."""
        channel = channel_name(channel, self)
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

    def checks(self, limits: Any = None, **options: Any) -> Any:
        """The code checks of this result, a :class:`~tb_exudyn.results.checks_table.ChecksTable`
        (:func:`tb_exudyn.results.checks.checks` for ``limits`` and the options: probability,
        method, confidence), computed once per result and arguments and cached
        (:func:`~tb_exudyn.results.checks.cached_checks`)."""
        return cached_checks(self, limits, **options)

    @property
    def plot(self) -> PlotAccessor:
        """The figures of this result: ``result.plot.bounds(channel)``, ``.psd_map``, ``.psd_slices``,
        ``.history``, or ``result.plot(channel, kind)`` (:class:`PlotAccessor`)."""
        return PlotAccessor(self)


__all__ = ["ChannelResult", "ChannelStatistics", "PLOTS", "PlotAccessor", "channel_name", "figures", "set_figure_loader"]
