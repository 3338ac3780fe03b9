"""Every plot function returns a Figure with the expected axes, labels and data (synthetic results)."""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.collections import PolyCollection, QuadMesh
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from tb_exudyn.errors import SettingError
from tb_exudyn.plotting import (
    crossing_times, plot_bounds, plot_pem_vs_mc, plot_psd_map, plot_psd_slices, plot_time_history, select_channels,
)

CH = "car1.body.acc_y"
# quick scenario: lead-in 30 m, one 32 m span, one ICE car (last axle 19.875 m behind the first), 250 km/h
V = 250 / 3.6
EVENTS = {"first_on": 30 / V, "first_off": 62 / V, "last_on": 49.875 / V, "last_off": 81.875 / V}


def _crossing_lines(ax):
    return {ln.get_gid().split(".")[1]: ln.get_xdata()[0] for ln in ax.lines if (ln.get_gid() or "").startswith("crossing.")}


def _line(ax, gid):
    (line,) = [ln for ln in ax.lines if ln.get_gid() == gid]
    return line


def test_crossing_times_follow_the_axle_positions(pem):
    c = crossing_times(pem.scenario)
    for key, t in EVENTS.items():
        assert getattr(c, key) == pytest.approx(t, rel=1e-12)
    assert c.position(c.first_on) == pytest.approx(0.0, abs=1e-12)
    assert c.position(c.first_off) == pytest.approx(32.0)
    assert c.time_at(-30.0) == pytest.approx(0.0, abs=1e-12)


def test_psd_map(pem):
    fig = plot_psd_map(pem, CH)
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    S = pem.psd[pem.index(CH)]
    shown = np.ma.asarray(mesh.get_array()).reshape(S.shape)
    assert np.array_equal(shown.compressed(), S[S > 0])
    assert shown.mask[-1].all() and not shown.mask[:-1].any()  # zero PSD (outside the band) left blank
    assert isinstance(mesh.norm, LogNorm) and mesh.norm.vmax == S.max()
    assert ax.get_ylim() == pytest.approx(pem.band)  # cells are the PEM quadrature cells
    assert ax.get_xlabel() == "time t [s]" and ax.get_ylabel() == "frequency f [Hz]"
    assert ax.get_yscale() == "linear"  # the synthetic map's content is spread over the band
    assert "car 1, body, lateral acceleration" in ax.get_title() and CH in ax.get_title() and "0-12 Hz" in ax.get_title()
    assert fig.axes[1].get_ylabel() == "S [(m/s^2)^2/Hz]"  # the colour bar
    assert _crossing_lines(ax) == pytest.approx(EVENTS)


def test_psd_map_in_display_units_and_log_frequency(pem):
    """A force channel is drawn in kN^2/Hz (S times 1e-6); log_frequency=True gives a log axis whose
    lowest edge stays positive (the first cell's edge, 0 Hz, becomes half the first frequency)."""
    ch = "car1.axle1.force_y"
    fig = plot_psd_map(pem, ch, log_frequency=True)
    ax = fig.axes[0]
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    S = pem.psd[pem.index(ch)]
    shown = np.ma.asarray(mesh.get_array()).reshape(S.shape)
    assert np.allclose(shown.compressed(), 1e-6 * S[S > 0], rtol=1e-15, atol=0)
    assert fig.axes[1].get_ylabel() == "S [kN^2/Hz]" and ax.get_yscale() == "log"
    assert ax.get_ylim()[0] == pytest.approx(pem.freq[0] / 2)
    assert plot_psd_slices(pem, ch, log_frequency=True).axes[0].get_xscale() == "log"


def test_psd_map_needs_a_psd(mc):
    with pytest.raises(ValueError, match="no PSD map"):
        plot_psd_map(mc, CH)


def test_psd_slices_default_is_the_time_of_max_sigma(pem):
    row = pem.index(CH)
    i = int(np.argmax(pem.std[row]))
    ax = plot_psd_slices(pem, CH).axes[0]
    (line,) = ax.lines
    expected = pem.psd[row, :, i]
    assert np.array_equal(line.get_xdata(), pem.freq)
    assert np.array_equal(line.get_ydata()[:-1], expected[:-1]) and np.isnan(line.get_ydata()[-1])
    assert f"t = {pem.time[i]:.4g} s" in line.get_label() and f"{pem.std[row, i]:.3g} m/s^2" in line.get_label()
    # the label's sigma is formatted by format_number: 3 significant digits, no exponent
    assert ax.get_yscale() == "log" and ax.get_xlabel() == "frequency f [Hz]"


def test_psd_slices_at_given_times_take_the_nearest_output_time(pem):
    ax = plot_psd_slices(pem, CH, times=[0.2, 0.504]).axes[0]
    assert len(ax.lines) == 2
    i = int(np.argmin(np.abs(pem.time - 0.504)))
    assert pem.time[i] == pytest.approx(0.5)
    assert np.array_equal(ax.lines[1].get_ydata()[:-1], pem.psd[pem.index(CH), :-1, i])


def test_bounds(pem):
    """A force is drawn in kN: the lines are 1e-3 times the stored N (to rounding: rtol 1e-15)."""
    fig = plot_bounds(pem, "car1.axle1.force_y", k=2.5)
    ax = fig.axes[0]
    r = pem.index("car1.axle1.force_y")
    assert np.allclose(_line(ax, "mean").get_ydata(), 1e-3 * pem.mean[r], rtol=1e-15, atol=0)
    assert np.allclose(_line(ax, "upper").get_ydata(), 1e-3 * (pem.mean[r] + 2.5 * pem.std[r]), rtol=1e-14, atol=1e-12)
    assert np.allclose(_line(ax, "lower").get_ydata(), 1e-3 * (pem.mean[r] - 2.5 * pem.std[r]), rtol=1e-14, atol=1e-12)
    assert ax.get_ylabel() == "lateral wheel-rail force [kN]"
    assert "car 1, axle 1, lateral wheel-rail force" in ax.get_title()
    assert "PEM" in ax.get_title() and "0-12 Hz" in ax.get_title()
    assert _crossing_lines(ax) == pytest.approx(EVENTS)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "mean +- 2.5 sigma" in labels and "car 1: first axle enters" in labels and "car 1: last axle leaves" in labels


def test_vehicle_channels_mark_their_own_cars_crossing(pem):
    """Two cars: car 2's channel marks car 2's first and last axle, the bridge's the train's."""
    sc = pem.scenario
    car = sc.train.vehicles[0]
    two = sc.replace(train=sc.train.replace(vehicles=(car, car)))
    r = type(pem)(**{**pem.__dict__, "scenario": two, "channels": ("bridge.span1.mid.acc_z", "car2.body.acc_y",
                                                                   "car2.axle1.force_y", "car2.axle1.left.force_z")})
    v = 250 / 3.6
    a_first, a_last = car.length + car.axle_offsets[0], car.length + car.axle_offsets[-1]
    car2 = {"first_on": (30 + a_first) / v, "first_off": (62 + a_first) / v, "last_on": (30 + a_last) / v,
            "last_off": (62 + a_last) / v}
    assert _crossing_lines(plot_bounds(r, "car2.axle1.force_y").axes[0]) == pytest.approx(car2)
    train = {"first_on": 30 / v, "first_off": 62 / v, "last_on": (30 + a_last) / v, "last_off": (62 + a_last) / v}
    assert _crossing_lines(plot_bounds(r, "bridge.span1.mid.acc_z").axes[0]) == pytest.approx(train)


def test_bounds_with_samples(mc):
    ax = plot_bounds(mc, CH, samples=True).axes[0]
    grey = [ln for ln in ax.lines if ln.get_gid() is None]
    assert len(grey) == mc.n_samples
    assert np.array_equal(grey[2].get_ydata(), mc.samples[2, mc.index(CH)])
    own = np.zeros((3, mc.time.size))  # an explicit (n, nt) array
    assert len([ln for ln in plot_bounds(mc, CH, samples=own).axes[0].lines if ln.get_gid() is None]) == 3
    with pytest.raises(ValueError, match="samples must be"):
        plot_bounds(mc, CH, samples=np.zeros((3, 7)))


def test_pem_vs_mc(pem, mc):
    fig = plot_pem_vs_mc(pem, mc, CH)
    ax_m, ax_s = fig.axes[:2]
    r = pem.index(CH)
    labels = [ln.get_label() for ln in ax_s.lines]
    assert "MC5 (0-12 Hz)" in labels and "PEM (0-12 Hz)" in labels
    assert np.array_equal(ax_s.lines[0].get_ydata(), pem.std[r])
    assert np.array_equal(ax_m.lines[0].get_ydata(), pem.mean[r])
    (band,) = [c for c in ax_s.collections if isinstance(c, PolyCollection)]
    y = band.get_paths()[0].vertices[:, 1]
    assert y.min() == pytest.approx(mc.std_ci[0, r].min()) and y.max() == pytest.approx(mc.std_ci[1, r].max())
    assert ax_m.get_ylabel() == "mean [m/s^2]" and ax_s.get_ylabel() == "sigma [m/s^2]"
    assert ax_s.get_xlabel() == "time t [s]"
    # several Monte Carlo runs (MC500 and MC2500 in the reference study)
    two = plot_pem_vs_mc(pem, [mc, mc], CH)
    assert len(two.axes[1].lines) - len(_crossing_lines(two.axes[1])) == 3


def test_time_history(th):
    fig = plot_time_history(th, ["bridge.*", "car1.axle1.force_y"])
    axes = [ax for ax in fig.axes if ax.get_ylabel()]
    assert len(axes) == 2
    assert [ax.get_title(loc="left") for ax in axes] == ["span 1, mid-span, vertical acceleration",
                                                         "car 1, axle 1, lateral wheel-rail force"]
    assert [ax.get_ylabel() for ax in axes] == ["[m/s^2]", "[kN]"]
    assert np.allclose(_line(axes[1], "history").get_ydata(), 1e-3 * th["car1.axle1.force_y"], rtol=1e-15, atol=0)
    assert _crossing_lines(axes[0]) == pytest.approx(EVENTS)
    single = plot_time_history(th, "car1.body.acc_y").axes[0]
    assert single.get_ylabel() == "lateral acceleration [m/s^2]"
    with pytest.raises(SettingError, match=r"plot_time_history: key 'channels' = 'car9\.\*': matches no channel"):
        plot_time_history(th, "car9.*")


def test_figures_stay_out_of_pyplot_and_accept_a_given_figure(pem):
    before = plt.get_fignums()
    plot_bounds(pem, CH)
    assert plt.get_fignums() == before
    fig = plt.figure()
    try:
        assert plot_bounds(pem, CH, fig=fig) is fig
    finally:
        plt.close(fig)


def test_default_channels_are_the_channels_that_matter(pem):
    assert select_channels(pem) == ["bridge.span1.mid.acc_z", "car1.body.acc_y", "car1.axle1.force_y",
                                    "car1.axle1.left.force_z"]
    assert select_channels(pem, "car1.axle1.*") == ["car1.axle1.force_y", "car1.axle1.left.force_z"]


def test_matplotlib_is_imported_only_in_the_plotting_package():
    root = Path(__file__).resolve().parents[2] / "tb_exudyn"
    imports = re.compile(r"^\s*(import|from)\s+matplotlib\b", re.MULTILINE)
    offenders = [str(p.relative_to(root)) for p in root.rglob("*.py")
                 if p.relative_to(root).parts[0] != "plotting" and imports.search(p.read_text())]
    assert not offenders, offenders


@pytest.mark.parametrize("kind", ["bounds", "psd_map", "psd_slices"])
def test_title_sits_where_matplotlibs_automatic_position_puts_it(pem, kind):
    """The title is placed at a fixed pad (docs/speed.md section 13) instead of matplotlib's automatic
    position above the position scale; the reference is that automatic position, drawn in this test on
    the same figure with the scale as matplotlib's secondary axis (section 16: the figure draws it as
    texts, which the automatic position does not see). Within 1 px: text extents round to whole pixels."""
    from matplotlib import rcParams
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from tb_exudyn.plotting.figures import POSITION_GID

    fig = {"bounds": plot_bounds, "psd_map": plot_psd_map, "psd_slices": plot_psd_slices}[kind](pem, CH)
    ax = fig.axes[0]
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    fixed = ax.title.get_window_extent(canvas.get_renderer())
    scale = [a for a in (*ax.texts, *ax.lines) if a.get_gid() == POSITION_GID]
    assert bool(scale) == (kind != "psd_slices")
    for artist in scale:
        artist.set_visible(False)
    if scale:
        ref = ax.secondary_xaxis("top", functions=(lambda t: V * t - 30.0, lambda x: (x + 30.0) / V))
        ref.set_xlabel([a for a in scale if isinstance(a, type(ax.title))][-1].get_text())
    ax.set_title(ax.get_title(), fontsize="medium", pad=rcParams["axes.titlepad"])
    ax._autotitlepos = True  # matplotlib's own placement (what set_title without y gives a new axes)
    canvas.draw()
    auto = ax.title.get_window_extent(canvas.get_renderer())
    assert abs(fixed.y0 - auto.y0) <= 1.0 and abs(fixed.x0 - auto.x0) <= 1.0
    assert auto.y0 > ax.get_window_extent().y1  # above the axes (and its position scale, where it has one)


@pytest.mark.parametrize("kind", ["bounds", "psd_map"])
def test_the_position_scale_shows_what_matplotlibs_secondary_axis_showed(pem, kind):
    """The first axle's position along the top (docs/speed.md section 16): the same round positions
    and labels as matplotlib's secondary axis with the crossing's functions, drawn in this test on the
    same figure (the reference), each tick at the time the closed form gives (x = v t - lead_in, the
    quick scenario's 30 m lead-in at 250 km/h; 1e-12 s: round-off), and its marks and texts drawn
    at the same heights (within 1 px: text extents round to whole pixels)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from tb_exudyn.plotting.figures import POSITION_GID

    fig = {"bounds": plot_bounds, "psd_map": plot_psd_map}[kind](pem, CH)
    ax = fig.axes[0]
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    (ticks,) = [ln for ln in ax.lines if ln.get_gid() == POSITION_GID]
    texts = [t for t in ax.texts if t.get_gid() == POSITION_GID]
    labels, title = texts[:-1], texts[-1]
    assert title.get_text().startswith("car 1's first axle: position x [m]")
    times = np.asarray(ticks.get_xdata(), dtype=float)
    values = [float(t.get_text().replace("\u2212", "-")) for t in labels]
    assert times == pytest.approx((np.asarray(values) + 30.0) / V, abs=1e-12)
    ref = ax.secondary_xaxis("top", functions=(lambda t: V * t - 30.0, lambda x: (x + 30.0) / V))
    ref.set_xlabel(title.get_text())
    canvas.draw()
    lo, hi = sorted(ref.get_xlim())
    shown = [(t.get_text(), t.get_window_extent(renderer)) for tick, t in
             zip(ref.xaxis.get_major_ticks(), ref.xaxis.get_ticklabels())
             if t.get_visible() and t.get_text() and lo - 1e-9 <= tick.get_loc() <= hi + 1e-9]
    assert [t.get_text() for t in labels] == [text for text, _ in shown]
    for t, (_, box) in zip(labels, shown):
        mine = t.get_window_extent(renderer)
        assert abs(mine.y0 - box.y0) <= 1.0 and abs(mine.x0 - box.x0) <= 1.0
    assert abs(title.get_window_extent(renderer).y0 - ref.xaxis.label.get_window_extent(renderer).y0) <= 1.0


def test_the_position_scale_follows_a_zoom(pem):
    """The scale is made when the figure is made and again when its time limits change (a user's zoom or
    set_xlim): after set_xlim every tick lies in the new limits, the positions are round numbers of the
    new range (the reference: matplotlib's locator on the closed-form positions x = v t - 30 m of the
    limits), and the scale's title is there once."""
    from matplotlib.ticker import MaxNLocator

    from tb_exudyn.plotting.figures import POSITION_GID

    fig = plot_bounds(pem, CH)
    ax = fig.axes[0]
    ax.set_xlim(0.5, 0.9)
    (ticks,) = [ln for ln in ax.lines if ln.get_gid() == POSITION_GID]
    texts = [t for t in ax.texts if t.get_gid() == POSITION_GID]
    times = np.asarray(ticks.get_xdata(), dtype=float)
    assert len(times) >= 2 and np.all((times >= 0.5 - 1e-12) & (times <= 0.9 + 1e-12))
    lo, hi = V * 0.5 - 30.0, V * 0.9 - 30.0
    expected = [x for x in MaxNLocator(nbins="auto", steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi) if lo <= x <= hi]
    assert times == pytest.approx((np.asarray(expected) + 30.0) / V, abs=1e-12)
    assert len(texts) == len(times) + 1 and sum("position x [m]" in t.get_text() for t in texts) == 1
