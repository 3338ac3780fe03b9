"""The figure of an EN 1991-2 check: peak deck acceleration against speed, one line per train, with
the limit and the resonant speeds v_i = n0 D / i inside the speed range (``CheckResult.plot()`` hands off
to it, as ``result.plot()`` does for results)."""

from __future__ import annotations

import numpy as np


def plot_check(result, resonant_orders: int = 4):  # noqa: ANN001, ANN201
    """A matplotlib Figure of ``result`` (a :class:`~tb_exudyn.codes.check.CheckResult`): max_deck_acc_z
    [m/s^2] against speed [km/h] per train; the limit (3.5 m/s^2 ballasted, 5 direct) as a red line; each
    train's resonant speeds (first ``resonant_orders`` orders) inside the range as dotted lines of its
    colour."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 5.0))
    ax = fig.add_subplot()
    speeds = np.array(result.column("speed_kmh"))
    lo, hi = float(speeds.min()), float(speeds.max())
    names = result.trains()
    cmap = __import__("matplotlib").colormaps["tab10" if len(names) <= 10 else "tab20"]
    for i, name in enumerate(names):
        rows = [r for r in result.rows if r["train"] == name]
        color = cmap(i % cmap.N)
        ax.plot([r["speed_kmh"] for r in rows], [r["max_deck_acc_z"] for r in rows], color=color, lw=1.2,
                label=name)
        for v in result.resonant_speeds_kmh.get(name, ())[:resonant_orders]:
            if lo <= v <= hi:
                ax.axvline(v, color=color, lw=0.6, ls=":", alpha=0.8)
    ax.axhline(result.limit, color="red", lw=1.5, label=f"limit {result.limit:g} m/s$^2$ ({result.track})")
    ax.set_xlim(lo, hi)
    ax.set_ylim(0.0, max(1.1 * result.limit, 1.05 * max(result.column("max_deck_acc_z"))))
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("peak vertical deck acceleration [m/s$^2$]")
    ax.set_title(f"{result.bridge}: EN 1991-2 check, line speed {result.line_speed_kmh:g} km/h, "
                 f"damping {100 * result.damping_ratio:.3g} % (dotted: v = n0 D / i)", fontsize=9)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, ncol=2 if len(names) > 6 else 1, loc="best")
    fig.tight_layout()
    return fig


__all__ = ["plot_check"]
