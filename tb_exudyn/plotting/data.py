"""What the figures show, computed without matplotlib (the compute half of compute-then-plot).

Everything here takes a result (:class:`~tb_exudyn.results.RandomResponse` or
:class:`~tb_exudyn.results.TimeHistory`) or a scenario and returns plain numbers, strings and
arrays, so the report, the exports and other plotting libraries can use it too:

- engineering display units (:func:`display_unit`: one place that maps an SI unit to the unit an
  engineer reads, kN, mm, m/s^2, and its factor);
- readable channel labels (:func:`channel_label`: "car 1, leading bogie, lateral acceleration");
- the crossing events of the train or of one car (:func:`crossing_times`);
- the channels drawn by default (:func:`default_channels`);
- the statistics a PSD map is read by (:func:`psd_peak`, :func:`psd_band`, :func:`low_frequency_content`).
"""

from __future__ import annotations

import fnmatch
import re
from dataclasses import dataclass, replace
from typing import Any, Sequence, Union

import numpy as np
from numpy.typing import NDArray

from ..errors import SettingError, UserError
from ..scenario import Scenario
from ..system.labels import (DISPLAY_UNITS, DisplayUnit, channel_label, default_patterns, display_unit, format_number,
                             psd_unit)

#: the result types (tb_exudyn.results.RandomResponse and TimeHistory), known here by what plotting reads
#: of them (:func:`is_time_history`): plotting imports nothing of results, whose ``result.plot()``
#: loads plotting.figures by name (no import cycle, tests/architecture)
RandomResponse = Any
TimeHistory = Any
Result = Union[RandomResponse, TimeHistory]


def is_time_history(result: Any) -> bool:
    """A time history (channels by name, ``names``, no statistics) rather than a random response."""
    return hasattr(result, "names") and not hasattr(result, "std")


# ============================================================================================ display units
# ============================================================================================ labels
def quantity_label(name: str) -> str:
    """The part of :func:`channel_label` after the last comma (what is measured, for an axis
    label: "lateral acceleration"), or the name itself."""
    label = channel_label(name)
    return label.rsplit(", ", 1)[-1] if label != name else name


def axis_label(name: str, si_unit: str) -> str:
    """Axis label of a channel in its display unit: "lateral acceleration [m/s^2]"."""
    return f"{quantity_label(name)} [{display_unit(si_unit).unit}]"


def channel_car(name: str) -> int | None:
    """The car number of a vehicle channel (``car3.axle1.force_y`` -> 3), None for the bridge."""
    m = re.match(r"car(\d+)\.", name)
    return int(m.group(1)) if m else None


def channel_group(name: str) -> tuple[str, str]:
    """(key, heading) of the table group a channel belongs to: the bridge, a car's body and
    bogies, or a car's wheelsets and wheel-rail forces."""
    car = channel_car(name)
    if car is None:
        return ("bridge", "Bridge") if name.startswith("bridge.") else ("other", "Other channels")
    if re.match(rf"car{car}\.axle\d+\.", name):
        return (f"car{car}.axles", f"Car {car}: wheelsets and wheel-rail forces")
    return (f"car{car}", f"Car {car}: body and bogies")


# ============================================================================================ crossing
@dataclass(frozen=True)
class Crossing:
    """When the train, or one car of it, is on the bridge. t = 0 when the train's first axle is
    at x = -lead_in; an axle a behind the train's first is on the bridge from (lead_in + a) / v
    to (lead_in + a + L) / v. ``who`` is "" for the whole train or "car k"; ``offset`` is the
    distance of its first axle behind the train's first axle [m]."""

    first_on: float   # the first axle (of the train or of the car) enters the bridge [s]
    first_off: float  # it leaves [s]
    last_on: float    # the last axle enters [s]
    last_off: float   # it leaves [s]
    speed: float      # [m/s]
    lead_in: float    # [m]
    bridge_length: float  # [m]
    who: str = ""
    offset: float = 0.0  # [m]

    def position(self, t):
        """Position x [m] of the (train's or car's) first axle at time t (x = 0 at the bridge start)."""
        return self.speed * np.asarray(t, dtype=float) - self.lead_in - self.offset

    def time_at(self, x):
        """Time [s] at which the (train's or car's) first axle is at x [m]."""
        return (np.asarray(x, dtype=float) + self.lead_in + self.offset) / self.speed

    def marks(self) -> tuple[tuple[str, str, float], ...]:
        """(key, label, time) of the four events, in the order of time of first and last axle."""
        who = f"{self.who}: " if self.who else ""
        return (
            ("first_on", f"{who}first axle enters", self.first_on),
            ("first_off", f"{who}first axle leaves", self.first_off),
            ("last_on", f"{who}last axle enters", self.last_on),
            ("last_off", f"{who}last axle leaves", self.last_off),
        )


def crossing_times(scenario: Scenario, car: int | None = None) -> Crossing:
    """The four crossing events of the whole train (``car=None``) or of car number ``car``
    (1-based, running order): when THAT car's first and last axle enter and leave the bridge."""
    v, lead, L = scenario.speed, scenario.track.lead_in, scenario.bridge.length
    positions = scenario.train.axle_positions
    who = ""
    if car is None:
        a_first, a_last = positions[0], positions[-1]
    else:
        vehicles = scenario.train.vehicles
        if not 1 <= car <= len(vehicles):
            raise ValueError(f"car {car}: the train has cars 1-{len(vehicles)}")
        first = sum(len(x.axle_offsets) for x in vehicles[: car - 1])
        a_first, a_last = positions[first], positions[first + len(vehicles[car - 1].axle_offsets) - 1]
        who = f"car {car}"
    return Crossing(
        first_on=(lead + a_first) / v, first_off=(lead + a_first + L) / v, last_on=(lead + a_last) / v,
        last_off=(lead + a_last + L) / v, speed=v, lead_in=lead, bridge_length=L, who=who, offset=a_first,
    )


def channel_crossing(scenario: Scenario, channel: str) -> Crossing:
    """The events that matter for a channel: its car's for a vehicle channel, the train's for the bridge."""
    car = channel_car(channel)
    if car is not None and car <= len(scenario.train.vehicles):
        return crossing_times(scenario, car)
    return crossing_times(scenario)


# ============================================================================================ channels
def channel_names(result: Result) -> tuple[str, ...]:
    return result.names if is_time_history(result) else tuple(result.channels)


def deciding_channels(result: Result) -> list[str]:
    """The channels that decide a criterion of the result's code checks (its worst locations, e.g.
    ``bridge.span1.q1.acc_z_en1990``, ``car3.body.acc_z``), those the verdicts name; none for a result
    without checks or whose limits cannot be read (the run reports that)."""
    if not hasattr(result, "checks"):
        return []
    try:
        rows = result.checks().worst()
    except UserError:
        return []
    return list(dict.fromkeys(r.channel for r in rows if r.verdict != "NOT EVALUATED"))


def deciding_bridge_channels(result: Result) -> list[str]:
    """The bridge channels of :func:`deciding_channels`, so that the report's verdict rows link to their figures."""
    return [c for c in deciding_channels(result) if c.startswith("bridge.")]


#: the car whose figures a page shows (the leading car: the others' are left out, drawn on request)
PAGE_CAR = 1


def page_channel(channel: str, deciding: Sequence[str] = ()) -> bool:
    """Whether a report page draws the figures of ``channel`` by default: the bridge's channels, the
    leading car's (:data:`PAGE_CAR`) and those the checks' verdicts name (``deciding``); the other
    cars' are left out (their sigma, PSD maps and slices: about 30 % of the main job's drawing,
    docs/speed.md section 15; their numbers stay in the channel table), and the page says so and
    how to draw them."""
    car = channel_car(channel)
    return car is None or car == PAGE_CAR or channel in deciding


def default_channels(result: Result) -> list[str]:
    """The channels drawn when none are asked for (:func:`default_patterns` and
    :func:`deciding_bridge_channels`), in stored order; every channel when none of them exists."""
    names = channel_names(result)
    pats = [p for _, group in default_patterns(names) for p in group] + deciding_bridge_channels(result)
    keep = [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in pats)]
    return keep or list(names)


def pattern_channels(result: Result) -> list[str]:
    """The channels of :func:`default_channels` known without the result's code checks (those of
    :func:`default_patterns`), in stored order: a run draws their figures while it computes the checks."""
    names = channel_names(result)
    pats = [p for _, group in default_patterns(names) for p in group]
    return [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in pats)]


#: The default figure channels of the reference study's layout (kept for callers of the old name;
#: :func:`default_patterns` adapts the bridge's middle span to the bridge at hand).
KEY_CHANNELS: tuple[str, ...] = tuple(p for _, g in default_patterns(["bridge.span2.mid.acc_z", "bridge.span1.mid.acc_z",
                                                                      "bridge.span3.mid.acc_z"]) for p in g)


def select_channels(result: Result, channels: str | Sequence[str] | None = None, *, where: str = "select_channels",
                    source: str = "") -> list[str]:
    """Channel names matching ``channels`` (names or glob patterns), in stored order.

    None: :func:`default_channels`. A pattern that matches nothing is a SettingError naming ``where``
    (the caller) and its argument ``channels``, the pattern, the result (``source``, e.g.
    its folder) and a few of its channels.
    """
    names = channel_names(result)
    if channels is None:
        return default_channels(result)
    pats = [channels] if isinstance(channels, str) else list(channels)
    for p in pats:
        if not any(fnmatch.fnmatchcase(n, p) for n in names):
            head = str(p).split(".")[0]
            close = [n for n in names if n.startswith(head)][:5] or list(names[:5])
            more = f" ({len(names)} in all)" if len(names) > len(close) else ""
            raise SettingError(where, "channels", p,
                               f"channel names or glob patterns, e.g. {', '.join(close)}{more}" if names else
                               "none: the result has no channel",
                               f"matches no channel of {source}" if source else "matches no channel")
    return [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in pats)]


def channel_subset(result: Result, channels: Sequence[str]) -> Result:
    """The same result restricted to ``channels`` (arrays sliced, scenario and provenance kept):
    what a figure worker needs, small enough to send to another process."""
    if is_time_history(result):
        return type(result)(time=result.time, channels={c: result[c] for c in channels},
                           units={c: result.unit(c) for c in channels}, scenario=result.scenario,
                           provenance=result.provenance)
    rows = [result.index(c) for c in channels]

    def cut(a, axis):
        return None if a is None else np.take(a, rows, axis=axis)

    psd = None
    if result.psd is not None and all(has_psd(result, c) for c in channels):
        psd = np.take(result.psd, [psd_row(result, c) for c in channels], axis=0)
    by_channel = {v.name: cut(getattr(result, v.name), v.dims.index("channel"))  # every array over channels (schema)
                  for v in result.schema if "channel" in v.dims}
    out = replace(result, channels=tuple(channels), units=tuple(result.units[i] for i in rows), psd=psd, **by_channel)
    if getattr(out, "psd_channels", None) is not None:
        out = replace(out, psd_channels=None if psd is None else tuple(channels))
    return out


# ============================================================================================ PSD statistics
def band_text(resp: RandomResponse) -> str:
    return f"{resp.band[0]:.3g}-{resp.band[1]:.3g} Hz"


def max_sigma_time(resp: RandomResponse, channel: str) -> float:
    """Output time [s] at which sigma of ``channel`` is largest."""
    return float(resp.time[int(np.argmax(resp.std[resp.index(channel)]))])


def psd_row(resp: RandomResponse, channel: str) -> int | None:
    """Row of ``channel`` in ``resp.psd``, or None when the result holds no PSD map for it
    (:meth:`~tb_exudyn.results.RandomResponse.psd_row`)."""
    return resp.psd_row(channel)


def has_psd(resp: Result, channel: str) -> bool:
    """True when ``resp`` holds a PSD map of ``channel``."""
    return not is_time_history(resp) and psd_row(resp, channel) is not None


def _psd_of(resp: RandomResponse, channel: str) -> np.ndarray:
    row = psd_row(resp, channel)
    if row is None:
        raise ValueError(f"this result holds no PSD map of {channel} (Monte Carlo, a PEM run with keep_psd=False, "
                         "or a channel whose map was not kept)")
    return np.asarray(resp.psd[row], dtype=float)


def psd_slices(
    resp: RandomResponse, channel: str, times: Sequence[float] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """PSD of ``channel`` against frequency at the output times nearest to ``times``.

    Default: the time of maximum sigma. Returns (times used (n,), freq (nf,), S (n, nf)) with S in
    unit^2/Hz (SI). Raises ValueError when the result holds no PSD map.
    """
    S = _psd_of(resp, channel)
    wanted = [max_sigma_time(resp, channel)] if times is None else [float(t) for t in np.atleast_1d(times)]
    idx = np.array([int(np.argmin(np.abs(resp.time - t))) for t in wanted], dtype=int)
    return resp.time[idx], resp.freq, S[:, idx].T


def crossing_columns(resp: RandomResponse, channel: str) -> NDArray[np.bool_]:
    """The output times of the crossing that matters for ``channel`` (:func:`channel_crossing`: its
    car's first axle on the bridge until its last axle off; the train's for a bridge channel), where
    a PSD map is read: before it the response is the start-up from rest on the approach, not the
    crossing. Every time when the result has no scenario or the window holds no output time."""
    t = np.asarray(resp.time)
    sc = resp.scenario
    if sc is None:
        return np.ones(t.size, dtype=bool)
    c = channel_crossing(sc, channel)
    keep = (t >= c.first_on - 1e-9) & (t <= c.last_off + 1e-9)
    return keep if keep.any() else np.ones(t.size, dtype=bool)


def psd_peak(resp: RandomResponse, channel: str) -> tuple[float, float]:
    """(frequency [Hz], time [s]) of the largest cell of the PSD map S(f, t) of ``channel`` over the
    crossing (:func:`crossing_columns`): the "frequency of the peak value" the reference study reads
    off its figures 3-5 (its maps span the crossing)."""
    S = _psd_of(resp, channel)
    cols = np.flatnonzero(crossing_columns(resp, channel))
    i, j = np.unravel_index(int(np.argmax(S[:, cols])), (S.shape[0], cols.size))
    return float(resp.freq[i]), float(resp.time[cols[j]])


def psd_band(resp: RandomResponse, channel: str, share: float = 0.99) -> tuple[float, float]:
    """(lowest, highest) frequency [Hz] of the smallest set of grid cells that holds ``share`` of
    sigma^2 at the time of maximum sigma over the crossing (:func:`crossing_columns`; cells taken
    largest S df first): a reproducible stand-in for the "frequency distribution range" the study
    reads off its maps (docs/findings.md)."""
    S = _psd_of(resp, channel)
    cols = np.flatnonzero(crossing_columns(resp, channel))
    j = int(cols[np.argmax(resp.std[resp.index(channel)][cols])])
    var = S[:, j] * resp.df
    order = np.argsort(var)[::-1]
    total = var.sum()
    if total <= 0:
        return (float("nan"), float("nan"))
    n = int(np.searchsorted(np.cumsum(var[order]) / total, share) + 1)
    kept = resp.freq[order[: min(n, order.size)]]
    return float(kept.min()), float(kept.max())


def low_frequency_content(resp: RandomResponse, channel: str) -> bool:
    """True when the channel's content sits at low frequencies, so that its PSD map reads better
    on a logarithmic frequency axis: half of its variance (integrated over the run) lies below a
    tenth of the band's upper edge (e.g. car bodies: 0.3-2 Hz in a 0.3-60 Hz band)."""
    S = _psd_of(resp, channel)
    var = S.sum(axis=1) * resp.df
    if var.sum() <= 0 or resp.freq.size < 2 or resp.freq[0] <= 0:
        return False
    median = float(resp.freq[int(np.searchsorted(np.cumsum(var) / var.sum(), 0.5))])
    return median < 0.1 * float(resp.band[1])


def band_across_zero_share(resp: RandomResponse, channel: str, k: float = 3.0) -> float:
    """Share of the crossing (the train's first axle on until its last axle off) during which the
    band mean +- k sigma contains zero (the study's "upper and lower boundary curves above and
    below the x axis")."""
    row = resp.index(channel)
    c = crossing_times(resp.scenario)
    on = (resp.time >= c.first_on) & (resp.time <= c.last_off)
    if not on.any():
        return float("nan")
    m, s = resp.mean[row, on], resp.std[row, on]
    return float(np.mean((m - k * s <= 0) & (m + k * s >= 0)))


def sigma_to_mean_ratio(resp: RandomResponse, channel: str, k: float = 3.0) -> float:
    """k max sigma / max |mean| of a channel (inf when the mean is zero): how wide the k-sigma
    band is against the deterministic response (docs/findings.md, finding 2)."""
    row = resp.index(channel)
    m = float(np.max(np.abs(resp.mean[row])))
    s = float(np.max(resp.std[row]))
    return float("inf") if m == 0 else k * s / m


# ============================================================================================ misc
def mc_label(resp: RandomResponse) -> str:
    """'PEM', or 'MC500' as the reference study names a Monte Carlo run of 500 samples ('MC500 (linear)'
    for the batched engine's Monte Carlo of the linear model)."""
    kind = resp.kind
    if kind.sampled:
        return f"MC{resp.n_samples}" + (" (linear)" if kind.linear_samples else "")
    return kind.label


def sample_matrix(resp: RandomResponse, channel: str, samples) -> np.ndarray | None:
    """Sample histories (n, nt) of ``channel``: samples = None/False (none), True (``resp.samples``,
    stored as (n, nc, nt)), an array (n, nt) of this channel or (n, nc, nt), or TimeHistory objects."""
    if samples is None or samples is False:
        return None
    if samples is True:
        if resp.samples is None:
            raise ValueError("this result stores no samples")
        samples = resp.samples
    if not isinstance(samples, np.ndarray) and len(samples) and is_time_history(samples[0]):
        arr = np.array([np.asarray(th[channel], dtype=float) for th in samples])
    else:
        arr = np.asarray(samples, dtype=float)
        if arr.ndim == 3:
            arr = arr[:, resp.index(channel)]
    if arr.ndim != 2 or arr.shape[1] != resp.time.size:
        raise ValueError(f"samples must be (n, {resp.time.size}) or (n, n_channels, {resp.time.size}), got {arr.shape}")
    return arr


__all__ = [
    "Crossing", "DISPLAY_UNITS", "DisplayUnit", "KEY_CHANNELS", "axis_label", "band_across_zero_share", "band_text",
    "channel_car", "channel_crossing", "channel_group", "channel_label", "channel_names", "channel_subset",
    "crossing_times", "deciding_bridge_channels", "deciding_channels", "page_channel", "PAGE_CAR", "default_channels", "default_patterns", "display_unit", "format_number", "has_psd", "psd_row",
    "low_frequency_content", "max_sigma_time", "mc_label", "psd_band", "psd_peak", "psd_slices", "psd_unit",
    "quantity_label", "sample_matrix", "select_channels", "sigma_to_mean_ratio",
]
