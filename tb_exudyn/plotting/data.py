"""What the figures show, computed without matplotlib (the compute half of compute-then-plot).

Everything here takes a result (:class:`~tb_exudyn.results.RandomResponse` or
:class:`~tb_exudyn.results.TimeHistory`) or a scenario and returns plain numbers and arrays, so the
report, the exports and other plotting libraries can use it too.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from typing import Sequence, Union

import numpy as np

from ..results import RandomResponse, TimeHistory
from ..scenario import Scenario

Result = Union[RandomResponse, TimeHistory]

#: Channels plotted when none are asked for (glob patterns; those of the reference study's
#: figures 3-8: bridge mid-span, car bodies, the first motor car's leading bogie and first wheelset).
KEY_CHANNELS: tuple[str, ...] = (
    "bridge.*.mid.disp_[yz]", "bridge.*.mid.acc_[yz]", "car*.body.acc_[yz]",
    "car1.bogie1.acc_[yz]", "car1.axle1.*force_[yz]",
)


@dataclass(frozen=True)
class Crossing:
    """When the train is on the bridge. t = 0 when the first axle is at x = -lead_in; axle j, a_j
    behind the first, is on the bridge from (lead_in + a_j) / v to (lead_in + a_j + L) / v."""

    first_on: float   # first axle enters the bridge [s]
    first_off: float  # first axle leaves [s]
    last_on: float    # last axle enters [s]
    last_off: float   # last axle leaves [s]
    speed: float      # [m/s]
    lead_in: float    # [m]
    bridge_length: float  # [m]

    def position(self, t):
        """Position x [m] of the first axle at time t (x = 0 at the bridge start)."""
        return self.speed * np.asarray(t, dtype=float) - self.lead_in

    def time_at(self, x):
        """Time [s] at which the first axle is at x [m]."""
        return (np.asarray(x, dtype=float) + self.lead_in) / self.speed

    def marks(self) -> tuple[tuple[str, str, float], ...]:
        """(key, label, time) of the four events, in the order of time of first and last axle."""
        return (
            ("first_on", "first axle enters", self.first_on),
            ("first_off", "first axle leaves", self.first_off),
            ("last_on", "last axle enters", self.last_on),
            ("last_off", "last axle leaves", self.last_off),
        )


def crossing_times(scenario: Scenario) -> Crossing:
    """The four crossing events of a scenario (see :class:`Crossing`)."""
    v, lead, L = scenario.speed, scenario.track.lead_in, scenario.bridge.length
    a_last = scenario.train.axle_positions[-1]
    return Crossing(
        first_on=lead / v, first_off=(lead + L) / v, last_on=(lead + a_last) / v,
        last_off=(lead + a_last + L) / v, speed=v, lead_in=lead, bridge_length=L,
    )


def channel_names(result: Result) -> tuple[str, ...]:
    return tuple(result.channels) if isinstance(result, RandomResponse) else result.names


def select_channels(result: Result, channels: str | Sequence[str] | None = None) -> list[str]:
    """Channel names matching ``channels`` (names or glob patterns), in stored order.

    None: the key channels (:data:`KEY_CHANNELS`) that exist, or every channel when none does.
    Raises KeyError naming a pattern that matches nothing.
    """
    names = channel_names(result)
    if channels is None:
        keep = [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in KEY_CHANNELS)]
        return keep or list(names)
    pats = [channels] if isinstance(channels, str) else list(channels)
    for p in pats:
        if not any(fnmatch.fnmatchcase(n, p) for n in names):
            raise KeyError(f"channel {p!r} matches no channel; e.g. {list(names[:6])}")
    return [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in pats)]


def channel_label(name: str, unit: str) -> str:
    return f"{name} [{unit}]"


def psd_unit(unit: str) -> str:
    """Unit of a one-sided PSD per Hz of a channel in ``unit``."""
    return f"({unit})^2/Hz" if "/" in unit or " " in unit else f"{unit}^2/Hz"


def band_text(resp: RandomResponse) -> str:
    return f"{resp.band[0]:.3g}-{resp.band[1]:.3g} Hz"


def max_sigma_time(resp: RandomResponse, channel: str) -> float:
    """Output time [s] at which sigma of ``channel`` is largest."""
    return float(resp.time[int(np.argmax(resp.std[resp.index(channel)]))])


def psd_slices(
    resp: RandomResponse, channel: str, times: Sequence[float] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """PSD of ``channel`` against frequency at the output times nearest to ``times``.

    Default: the time of maximum sigma. Returns (times used (n,), freq (nf,), S (n, nf)) with S in
    unit^2/Hz. Raises ValueError when the result holds no PSD map.
    """
    if resp.psd is None:
        raise ValueError("this result holds no PSD map (Monte Carlo, or PEM run with keep_psd=False)")
    row = resp.index(channel)
    wanted = [max_sigma_time(resp, channel)] if times is None else [float(t) for t in np.atleast_1d(times)]
    idx = np.array([int(np.argmin(np.abs(resp.time - t))) for t in wanted], dtype=int)
    return resp.time[idx], resp.freq, resp.psd[row][:, idx].T


def mc_label(resp: RandomResponse) -> str:
    """'PEM', or 'MC500' as the reference study names a Monte Carlo run of 500 samples ('MC500 (linear)'
    for the batched engine's Monte Carlo of the linear model)."""
    if resp.method == "pem":
        return "PEM"
    if resp.method == "monte_carlo_linear":
        return f"MC{resp.n_samples} (linear)"
    if resp.method.startswith("monte_carlo"):
        return f"MC{resp.n_samples}"
    return resp.method


def sample_matrix(resp: RandomResponse, channel: str, samples) -> np.ndarray | None:
    """Sample histories (n, nt) of ``channel``: samples = None/False (none), True (``resp.samples``,
    stored as (n, nc, nt)), an array (n, nt) of this channel or (n, nc, nt), or TimeHistory objects."""
    if samples is None or samples is False:
        return None
    if samples is True:
        if resp.samples is None:
            raise ValueError("this result stores no samples")
        samples = resp.samples
    if not isinstance(samples, np.ndarray) and len(samples) and isinstance(samples[0], TimeHistory):
        arr = np.array([np.asarray(th[channel], dtype=float) for th in samples])
    else:
        arr = np.asarray(samples, dtype=float)
        if arr.ndim == 3:
            arr = arr[:, resp.index(channel)]
    if arr.ndim != 2 or arr.shape[1] != resp.time.size:
        raise ValueError(f"samples must be (n, {resp.time.size}) or (n, n_channels, {resp.time.size}), got {arr.shape}")
    return arr


__all__ = [
    "Crossing", "KEY_CHANNELS", "band_text", "channel_label", "channel_names", "crossing_times",
    "max_sigma_time", "mc_label", "psd_slices", "psd_unit", "sample_matrix", "select_channels",
]
