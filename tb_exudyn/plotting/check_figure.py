"""The figure of an EN 1991-2 check: peak deck acceleration against speed, one line per train, with
the limit and the resonant speeds v_i = n0 D / i inside the speed range (``CheckResult.plot()`` hands off
to it, as ``result.plot()`` does for results)."""

from __future__ import annotations

import numpy as np

#: the line style of each mass case
CASE_STYLES = {"nominal": "-", "lower": "--", "upper": "-."}


def plot_check(result, resonant_orders: int = 4):  # noqa: ANN001, ANN201
    """A matplotlib Figure of ``result`` (a :class:`~tb_exudyn.codes.check.CheckResult`): its records' values
    (max_deck_acc_z) [m/s^2] against speed [km/h] per train, one line per mass case (nominal solid, lower dashed, upper
    dash-dotted); the limit (3.5 m/s^2 ballasted, 5 direct) as a red line; each
    train's resonant speeds (first ``resonant_orders`` orders) inside the range as dotted lines of its
    colour; where the stochastic rows were computed, their level_at_target (the level exceeded with the
    target probability per passage, PEM of the track irregularity) as crosses of the train's colour."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 5.0))
    ax = fig.add_subplot()
    speeds = np.array([r.speed_kmh for r in result.rows])
    lo, hi = float(speeds.min()), float(speeds.max())
    names = result.trains()
    cmap = __import__("matplotlib").colormaps["tab10" if len(names) <= 10 else "tab20"]
    for i, name in enumerate(names):
        rows = [r for r in result.rows if r.train == name]
        color = cmap(i % cmap.N)
        cases = list(dict.fromkeys(r.case for r in rows))
        for case in cases:
            line = [r for r in rows if r.case == case]
            ax.plot([r.speed_kmh for r in line], [r.value for r in line], color=color, lw=1.2,
                    ls=CASE_STYLES.get(case, "-"), marker="o" if len(line) == 1 else None,  # one speed: a point
                    label=name if len(cases) == 1 else f"{name} ({case})")
        stoch = [r for r in rows if r.stochastic is not None and np.isfinite(r.stochastic.level_at_target)]
        if stoch:
            ax.plot([r.speed_kmh for r in stoch], [r.stochastic.level_at_target for r in stoch], ls="none", marker="x",
                    color=color, ms=6, label=f"{name}: level at P = {result.target_probability:.3g} per passage (PEM)")
        for v in result.resonant_speeds_kmh.get(name, ())[:resonant_orders]:
            if lo <= v <= hi:
                ax.axvline(v, color=color, lw=0.6, ls=":", alpha=0.8)
    ax.axhline(result.limit, color="red", lw=1.5, label=f"limit {result.limit:g} m/s$^2$ ({result.track})")
    pad = 5.0 if hi - lo < 1e-6 else 0.0  # a series of one speed (1.2 x the line speed below 144 km/h): +- a step
    ax.set_xlim(lo - pad, hi + pad)
    levels = [r.stochastic.level_at_target for r in result.rows if r.stochastic is not None
              and np.isfinite(r.stochastic.level_at_target)]
    ax.set_ylim(0.0, max(1.1 * result.limit, 1.05 * max(r.value for r in result.rows), *(1.05 * x for x in levels)))
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("peak vertical deck acceleration [m/s$^2$]")
    ax.set_title(f"{result.bridge}: EN 1991-2 check, line speed {result.line_speed_kmh:g} km/h, "
                 f"damping {100 * result.damping_ratio:.3g} % (dotted: v = n0 D / i)", fontsize=9)
    ax.grid(True, lw=0.3)
    n_labels = len(ax.get_legend_handles_labels()[1])
    ax.legend(fontsize=7 if n_labels <= 16 else 6, ncol=1 if n_labels <= 6 else 2 if n_labels <= 16 else 3, loc="best")
    fig.tight_layout()
    return fig


__all__ = ["plot_check"]
