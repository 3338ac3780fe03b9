"""Figures of results: each function takes a result and returns a :class:`matplotlib.figure.Figure`.

The figures are created with the object-oriented API (``Figure()``, not pyplot): no backend is set
and nothing is registered with pyplot, so they work on any machine and are freed with the object.
To draw into a pyplot window instead, pass ``fig=plt.figure()``. Values are drawn in engineering
units (:func:`tb_exudyn.plotting.data.display_unit`: kN, mm, m/s^2) and labelled in words
(:func:`~tb_exudyn.plotting.data.channel_label`). Time axes mark when the first and the last axle
enter and leave the bridge: those of the channel's own car for a vehicle channel, the train's for
the bridge.
"""

from __future__ import annotations

import math
import textwrap
from typing import Sequence

import numpy as np
from matplotlib import rcParams
from matplotlib.axes import Axes
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.markers import TICKUP
from matplotlib.ticker import LogFormatter, MaxNLocator, NullLocator, ScalarFormatter
from matplotlib.transforms import offset_copy

from ..results.checks import GRID_ERROR_TOLERANCE
from ..scenario import Scenario
from ..system.labels import display_unit
from . import data
from .data import RandomResponse, TimeHistory

_EVENT_STYLE = {  # key: (colour, line style)
    "first_on": ("tab:green", "--"), "first_off": ("tab:green", ":"),
    "last_on": ("tab:red", "--"), "last_off": ("tab:red", ":"),
}


#: Figure margins [inch]: room for the two-line title and the position axis above, the time axis
#: and the legend below, the axis label at the left. Fixed margins instead of a layout engine: the
#: constrained layout took more than half of the time to draw a figure.
_WIDTH, _TOP, _BOTTOM, _LEFT, _RIGHT, _GAP = 7.5, 1.05, 1.0, 0.85, 0.25, 0.45


def _figure(fig: Figure | None, nrows: int = 1, height: float = 3.0, sharex: bool = True,
            legend_below: bool = True, position_axis: bool = True) -> tuple[Figure, list[Axes]]:
    """A new figure (or ``fig``) with ``nrows`` axes of ``height`` inches each, one above the other."""
    if fig is None:
        bottom = _BOTTOM if legend_below else 0.55
        top = _TOP if position_axis else 0.6
        total = top + bottom + nrows * height + (nrows - 1) * _GAP
        fig = Figure(figsize=(_WIDTH, total))
        fig.subplots_adjust(left=_LEFT / _WIDTH, right=1 - _RIGHT / _WIDTH, top=1 - top / total,
                            bottom=bottom / total, hspace=_GAP / height)
    axes = fig.subplots(nrows, 1, sharex=sharex, squeeze=False)[:, 0]
    return fig, list(axes)


def _plain_log(axis) -> None:
    """Label a logarithmic axis as plain text (1e-05) instead of mathtext (10^-5 typeset): mathtext
    parsing took a seventh of the time to draw a figure with log axes."""
    axis.set_major_formatter(LogFormatter(labelOnlyBase=True))
    axis.set_minor_formatter(LogFormatter(labelOnlyBase=True, minor_thresholds=(0, 0)))


def _fig_legend(fig: Figure) -> None:
    """One legend for the figure, below the axes (outside them with the constrained layout)."""
    outside = type(fig.get_layout_engine()).__name__ == "ConstrainedLayoutEngine"
    fig.legend(loc="outside lower center" if outside else "lower center", ncols=4, fontsize="x-small",
               frameon=False)


def mark_crossing(ax: Axes, scenario: Scenario | None, legend: bool = True, position_axis: bool = False,
                  channel: str | None = None) -> None:
    """Shade the time the train (or the channel's car) is on the bridge and draw the four entry/exit
    times of its first and last axle (gid ``crossing.<event>``); optionally a top axis with that
    first axle's position x [m]. ``channel``: a vehicle channel marks its own car's events."""
    if scenario is None:
        return
    c = data.channel_crossing(scenario, channel) if channel is not None else data.crossing_times(scenario)
    ax.axvspan(c.first_on, c.last_off, color="0.5", alpha=0.08, lw=0, gid="crossing.span")
    for key, label, t in c.marks():
        colour, style = _EVENT_STYLE[key]
        ax.axvline(t, color=colour, ls=style, lw=1.0, label=label if legend else None, gid=f"crossing.{key}")
    if position_axis:
        whose = f"{c.who}'s first axle" if c.who else "first axle"
        _position_scale(ax, c, f"{whose}: position x [m] (bridge from 0 to {c.bridge_length:g} m)")


#: the height of the position scale's title above the axes [points]: where matplotlib's secondary axis put
#: its label with its default fonts (measured: tick labels 7-17 points above the axes, the label 18.6-28.9)
_POSITION_LABEL_RISE = 18.6

#: gid of the position scale's tick marks, labels and title above an axes (:func:`_position_scale`)
POSITION_GID = "position_axis"


def _position_scale(ax: Axes, c: data.Crossing, label: str) -> None:
    """The first axle's position x [m] as a scale along the top of ``ax``: tick marks, their labels and
    ``label``, as matplotlib's secondary axis draws them (its locator and formatter, its tick length, pad
    and fonts) but as one line and a few texts at the times of round positions over ``ax``'s time
    limits, made now and again whenever those limits change (a zoom, ``set_xlim``), not at every draw.
    A secondary axis is a second Axes whose ticks are made again at every draw: it took a sixth of the
    CPU of drawing the page's figures (docs/speed.md section 16)."""
    made: list = []

    def make(_ax: Axes | None = None) -> None:
        for artist in made:
            artist.remove()
        made.clear()
        lo, hi = sorted(ax.get_xlim())
        x_lo, x_hi = sorted((float(c.position(lo)), float(c.position(hi))))
        values = [x for x in MaxNLocator(nbins="auto", steps=[1, 2, 2.5, 5, 10]).tick_values(x_lo, x_hi)
                  if x_lo - 1e-9 * (x_hi - x_lo) <= x <= x_hi + 1e-9 * (x_hi - x_lo)]
        fmt = ScalarFormatter()
        fmt.create_dummy_axis()
        labels = fmt.format_ticks(values)
        times = c.time_at(np.asarray(values, dtype=float))
        size, width, pad = (float(rcParams[f"xtick.major.{k}"]) for k in ("size", "width", "pad"))
        colour = rcParams["xtick.color"]
        base = ax.get_xaxis_transform()  # x in data (time), y in axes fraction
        # add_artist, not plot: the marks must not take part in the autoscale (their change would call this again)
        made.append(ax.add_artist(Line2D(times, np.ones_like(times), transform=base, ls="none", marker=TICKUP, ms=size,
                                         mew=width, color=colour, clip_on=False, gid=POSITION_GID,
                                         label="_position_ticks")))
        text = offset_copy(base, fig=ax.figure, y=size + pad, units="points")
        for t, s in zip(times, labels):
            made.append(ax.text(t, 1.0, s, transform=text, ha="center", va="bottom", fontsize=rcParams["xtick.labelsize"],
                                color=rcParams["xtick.labelcolor"] if rcParams["xtick.labelcolor"] != "inherit" else colour,
                                clip_on=False, gid=POSITION_GID))
        above = offset_copy(ax.transAxes, fig=ax.figure, y=_POSITION_LABEL_RISE, units="points")
        made.append(ax.text(0.5, 1.0, label, transform=above, ha="center", va="bottom", fontsize=rcParams["axes.labelsize"],
                            color=rcParams["axes.labelcolor"], clip_on=False, gid=POSITION_GID))

    make()
    ax.callbacks.connect("xlim_changed", make)


def _time_axis(ax: Axes) -> None:
    ax.set_xlabel("time t [s]")
    ax.grid(True, alpha=0.3)


def _edges(x: np.ndarray, first: float, last: float) -> np.ndarray:
    """Cell edges around centres x: halfway between neighbours, first/2 and last/2 outside the ends."""
    x = np.asarray(x, dtype=float)
    return np.concatenate(([x[0] - first / 2], (x[:-1] + x[1:]) / 2, [x[-1] + last / 2]))


def plot_psd_map(resp: RandomResponse, channel: str, *, fig: Figure | None = None, dynamic_range: float = 1e8,
                 log_frequency: bool | None = None) -> Figure:
    """Time-frequency map of the one-sided PSD of ``channel`` (log colour scale, display unit^2/Hz),
    as the reference study's figures 3-5. Zero PSD (frequencies outside the track's wavelength band)
    stays blank; the colour scale spans at most ``dynamic_range`` below the peak.

    ``log_frequency``: a logarithmic frequency axis; None (default) chooses it where the content
    sits at low frequencies (:func:`tb_exudyn.plotting.data.low_frequency_content`, e.g. car bodies).
    """
    du = data.display_unit(resp.unit(channel))
    S = data._psd_of(resp, channel) * du.factor ** 2
    if log_frequency is None:
        log_frequency = data.low_frequency_content(resp, channel)
    fig, (ax,) = _figure(fig, height=3.4)
    vmax = float(S.max())
    exponent = 0  # a map far from 1 (e.g. 1e-300) is drawn in units of 10^exponent: log colour bars need headroom
    if vmax > 0 and not 1e-200 <= vmax <= 1e200:
        exponent = math.floor(math.log10(vmax))
        S = S / 10.0 ** exponent
        vmax = float(S.max())
    positive = S[S > 0]
    if vmax > 0:
        norm = LogNorm(vmin=max(float(positive.min()), vmax / dynamic_range), vmax=vmax)
    else:
        norm = LogNorm(vmin=1.0, vmax=10.0)
        ax.text(0.5, 0.5, "PSD is zero everywhere", transform=ax.transAxes, ha="center")
    dt = resp.scenario.analysis.output_step
    t_edges = _edges(resp.time, dt, dt)
    f_edges = _edges(resp.freq, resp.df[0], resp.df[-1])  # the PEM quadrature cells
    if log_frequency and f_edges[0] <= 0:
        f_edges[0] = resp.freq[0] / 2
    mesh = ax.pcolormesh(t_edges, f_edges, np.ma.masked_less_equal(S, 0.0), norm=norm, shading="flat",
                         cmap="viridis", rasterized=True)
    if log_frequency:
        ax.set_yscale("log")
        _plain_log(ax.yaxis)
    cb = fig.colorbar(mesh, ax=ax)
    _plain_log(cb.ax.yaxis)
    cb.ax.yaxis.set_minor_locator(NullLocator())  # up to 8 decades: minor ticks add nothing but drawing time
    cb.set_label(f"S [{f'1e{exponent} ' if exponent else ''}{data.psd_unit(du.unit)}]")
    mark_crossing(ax, resp.scenario, position_axis=True, channel=channel)
    ax.set_ylabel("frequency f [Hz]" + (" (log scale)" if log_frequency else ""))
    _time_axis(ax)
    _fig_legend(fig)
    _title(ax, channel, f"one-sided PSD, band {data.band_text(resp)}")
    return fig


#: the height of the position axis above an axes (its tick labels and its label) [points], as
#: matplotlib's automatic title position measured it with its default fonts
_POSITION_AXIS_HEIGHT = 28.9


def _title(ax: Axes, channel: str, what: str) -> None:
    """Two-line title: the readable label, then the channel name and what is shown; placed at a fixed
    distance above the axes, or above its position axis (:func:`mark_crossing`), where matplotlib's
    automatic position measured every tick label above the axes at each draw (a fifth of the time
    to draw a figure with a position axis, docs/speed.md section 13)."""
    above = any(t.get_gid() == POSITION_GID for t in ax.texts)
    pad = float(rcParams["axes.titlepad"]) + (_POSITION_AXIS_HEIGHT if above else 0.0)
    ax.set_title(f"{data.channel_label(channel)}\n{channel}: {what}", fontsize="medium", y=1.0, pad=pad)


def plot_psd_slices(resp: RandomResponse, channel: str, times: Sequence[float] | None = None, *,
                    fig: Figure | None = None, log_frequency: bool | None = None) -> Figure:
    """PSD of ``channel`` (display unit^2/Hz) against frequency at the output times nearest to
    ``times`` (default: the time of maximum sigma); each line is labelled with its time and sigma.
    ``log_frequency`` as in :func:`plot_psd_map`."""
    used, freq, S = data.psd_slices(resp, channel, times)
    du = data.display_unit(resp.unit(channel))
    if log_frequency is None:
        log_frequency = data.low_frequency_content(resp, channel)
    row = resp.index(channel)
    fig, (ax,) = _figure(fig, sharex=False, legend_below=False, position_axis=False)
    for t, s in zip(used, S * du.factor ** 2):
        sigma = resp.std[row, int(np.argmin(np.abs(resp.time - t)))] * du.factor
        ax.plot(freq, np.where(s > 0, s, np.nan), marker=".",
                label=f"t = {t:.4g} s, sigma = {data.format_number(sigma, 3)} {du.unit}")
    ax.set_yscale("log")
    _plain_log(ax.yaxis)
    ax.yaxis.set_minor_locator(NullLocator())  # many decades: minor ticks add nothing but drawing time
    if log_frequency:
        ax.set_xscale("log")
        _plain_log(ax.xaxis)
    ax.set_xlabel("frequency f [Hz]")
    ax.set_ylabel(f"S [{data.psd_unit(du.unit)}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    _title(ax, channel, f"one-sided PSD, band {data.band_text(resp)}")
    return fig


def plot_bounds(resp: RandomResponse, channel: str, k: float = 3.0, samples=None, *,
                fig: Figure | None = None) -> Figure:
    """Mean and mean +- k sigma of ``channel`` against time (the reference study's figures 6-8),
    in the channel's display unit.

    ``samples``: None (none), True (the result's stored Monte Carlo samples), an array (n, nt) or
    (n, n_channels, nt), or TimeHistory objects; drawn faintly behind.
    """
    row = resp.index(channel)
    unit = resp.unit(channel)
    f = data.display_unit(unit).factor
    mean, std = resp.mean[row] * f, resp.std[row] * f
    fig, (ax,) = _figure(fig)
    paths = data.sample_matrix(resp, channel, samples)
    if paths is not None:
        for i, p in enumerate(paths):
            ax.plot(resp.time, p * f, color="0.55", lw=0.5, alpha=0.35, zorder=1,
                    label=f"samples ({len(paths)})" if i == 0 else None)
    ax.fill_between(resp.time, mean - k * std, mean + k * std, color="tab:blue", alpha=0.2, lw=0, zorder=2,
                    label=f"mean +- {k:g} sigma")
    ax.plot(resp.time, mean + k * std, color="tab:blue", lw=0.8, zorder=3, gid="upper")
    ax.plot(resp.time, mean - k * std, color="tab:blue", lw=0.8, zorder=3, gid="lower")
    ax.plot(resp.time, mean, color="k", lw=1.2, zorder=4, label="mean", gid="mean")
    mark_crossing(ax, resp.scenario, position_axis=True, channel=channel)
    ax.set_ylabel(data.axis_label(channel, unit))
    _time_axis(ax)
    _fig_legend(fig)
    _title(ax, channel, f"{data.mc_label(resp)}, sigma over {data.band_text(resp)}")
    return fig


def plot_pem_vs_mc(pem: RandomResponse, mc: RandomResponse | Sequence[RandomResponse], channel: str, *,
                   fig: Figure | None = None) -> Figure:
    """Mean (top) and sigma (bottom) of ``channel`` by PEM and by one or more Monte Carlo runs, with
    the Monte Carlo 95 % confidence bands (``mean_ci``, ``std_ci``), as the reference study's
    figures 1-2; in the channel's display unit."""
    runs = [mc] if hasattr(mc, "std") else list(mc)  # one result, or a sequence of them
    du = data.display_unit(pem.unit(channel))
    f = du.factor
    fig, (ax_m, ax_s) = _figure(fig, nrows=2, height=2.4, legend_below=False)
    ax_m.plot(pem.time, pem.mean[pem.index(channel)] * f, color="k", lw=1.4, label="PEM mean (deterministic run)")
    ax_s.plot(pem.time, pem.std[pem.index(channel)] * f, color="k", lw=1.4, label=f"PEM ({data.band_text(pem)})")
    for r in runs:
        row, name = r.index(channel), data.mc_label(r)
        line, = ax_m.plot(r.time, r.mean[row] * f, lw=1.0, label=f"{name} mean")
        if r.mean_ci is not None:
            ax_m.fill_between(r.time, r.mean_ci[0, row] * f, r.mean_ci[1, row] * f, color=line.get_color(), alpha=0.2,
                              lw=0, label=f"{name} 95 % interval")
        line, = ax_s.plot(r.time, r.std[row] * f, lw=1.0, label=f"{name} ({data.band_text(r)})")
        if r.std_ci is not None:
            ax_s.fill_between(r.time, r.std_ci[0, row] * f, r.std_ci[1, row] * f, color=line.get_color(), alpha=0.2,
                              lw=0, label=f"{name} 95 % interval")
    for ax, what in ((ax_m, "mean"), (ax_s, "sigma")):
        mark_crossing(ax, pem.scenario, legend=ax is ax_m, position_axis=ax is ax_m, channel=channel)
        ax.set_ylabel(f"{what} [{du.unit}]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small", ncols=2 if ax is ax_s else 1, loc="upper left")
    ax_s.set_xlabel("time t [s]")
    _title(ax_m, channel, "PEM against Monte Carlo")
    return fig


def plot_time_history(th: TimeHistory, channels: str | Sequence[str], *, fig: Figure | None = None) -> Figure:
    """Deterministic histories of ``channels`` (names or glob patterns), one axes each, in display
    units, with the passage over the bridge marked (each vehicle channel: its own car's) and the
    first axle's position on a top axis."""
    names = data.select_channels(th, channels, where="plot_time_history")
    fig, axes = _figure(fig, nrows=len(names), height=2.0 if len(names) > 1 else 3.0)
    for i, (ax, name) in enumerate(zip(axes, names)):
        du = data.display_unit(th.unit(name))
        ax.plot(th.time, np.asarray(th[name]) * du.factor, color="k", lw=1.0, gid="history")
        mark_crossing(ax, th.scenario, legend=i == 0, position_axis=i == 0, channel=name)
        if len(names) == 1:
            ax.set_ylabel(data.axis_label(name, th.unit(name)))
        else:  # long labels do not fit beside short axes: label above, unit beside
            ax.set_title(data.channel_label(name), loc="left", fontsize="small")
            ax.set_ylabel(f"[{du.unit}]")
        ax.grid(True, alpha=0.3)
    _fig_legend(fig)
    axes[-1].set_xlabel("time t [s]")
    title = th.scenario.name if th.scenario is not None else "time history"
    what = f"one run, excitation {th.provenance.get('excitation', 'not recorded')}"
    if len(names) == 1:
        _title(axes[0], names[0], f"{title}, {what}")
    else:
        axes[0].set_title(f"{title}: {what}", loc="center")
    return fig


__all__ = ["mark_crossing", "plot_bounds", "plot_pem_vs_mc", "plot_psd_map", "plot_psd_slices", "plot_time_history"]


def plot_speed_sweep(sweep, *, fig: Figure | None = None, grid_tolerance: float = GRID_ERROR_TOLERANCE) -> Figure:  # noqa: ANN001 - a results.sweep.SweepResult
    """Each key quantity of a speed sweep against speed, in display units: the largest |mean| + 3
    sigma, sigma and |mean| over its channels and time, with the resonance speeds v = f_n d / i of
    the bridge's first modes marked (solid: d the car length, dotted: the bogie spacing; gid
    ``resonance.<direction>``) and the speeds where the quantity's estimated grid error exceeds
    ``grid_tolerance`` crossed out in red (gid ``grid_error``: those numbers depend on the grid)."""
    rows = sweep.rows()
    fig, axes = _figure(fig, nrows=len(sweep.quantities), height=2.4)
    v = np.array([r["speed_kmh"] for r in rows])
    colours = {"vertical": "tab:blue", "lateral": "tab:red", "torsion": "tab:green"}
    for ax, (key, pattern, what) in zip(axes, sweep.quantities):
        unit = display_unit(sweep.quantity_unit(key))
        design = np.array([r[f"{key}_max_abs_mean_plus_3sigma"] for r in rows]) * unit.factor
        ax.plot(v, design, "o-", ms=3, color="k", label="max |mean| + 3 sigma")
        ax.plot(v, np.array([r[f"{key}_max_sigma"] for r in rows]) * unit.factor, "s--", ms=3, color="0.4",
                label="max sigma")
        ax.plot(v, np.array([r[f"{key}_max_abs_mean"] for r in rows]) * unit.factor, ":", color="0.4", label="max |mean|")
        bad = np.array([r.get(f"{key}_grid_error", np.nan) for r in rows], dtype=float) > grid_tolerance
        if bad.any():
            ax.plot(v[bad], design[bad], "x", ms=8, mew=1.5, color="tab:red", gid="grid_error",
                    label=f"grid error > {100 * grid_tolerance:g} %")
            ax.legend(fontsize="x-small", loc="upper left")
        for res in sweep.resonances:
            if v.min() <= res.speed_kmh <= v.max():
                ax.axvline(res.speed_kmh, color=colours.get(res.direction, "0.5"), lw=0.8, alpha=0.7,
                           ls="-" if res.distance_name == "car length" else ":", gid=f"resonance.{res.direction}")
        ax.set_ylabel(f"{key} [{unit.unit}]" if unit.unit else key, fontsize="small")
        ax.set_title(f"{sweep.quantity_text(key)} ({pattern})", fontsize="small")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("speed [km/h]")
    axes[0].legend(fontsize="x-small", loc="upper left")
    dist = ", ".join(f"{n} {d:.4g} m ({'solid' if n == 'car length' else 'dotted'})"
                     for n, d in sorted({(r.distance_name, r.distance) for r in sweep.resonances}))
    marks = ", ".join(f"{d} {f:.3g} Hz ({colours.get(d, 'grey').replace('tab:', '')})"
                      for d, f in sorted({(r.direction, r.frequency) for r in sweep.resonances}))
    note = textwrap.fill(f"resonance speeds v = f1 d / i, i = 1, 2, 3: d = {dist}; f1 = {marks}", 110)
    fig.suptitle(f"{sweep.base.name}: speed sweep\n{note}", fontsize="x-small")
    return fig
