"""Figures of results (matplotlib is imported only in this package).

Compute and plot stay apart: the solvers return results, :mod:`.data` turns them into what a figure
shows (no matplotlib: display units, readable labels, crossing events, PSD statistics), and each
``plot_*`` function takes a result and returns a new :class:`matplotlib.figure.Figure`
(object-oriented API: no backend is set, nothing goes to pyplot). :func:`plot_folder` writes the
standard figures of saved results, in parallel.
"""

from .check_figure import plot_check
from .data import (
    KEY_CHANNELS, Crossing, axis_label, channel_label, crossing_times, default_channels, display_unit, psd_slices,
    select_channels,
)
from .figures import (mark_crossing, plot_bounds, plot_pem_vs_mc, plot_psd_map, plot_psd_slices, plot_speed_sweep,
                      plot_time_history)
from .files import draw_jobs, figure_jobs, plot_folder, save_figure
from .uq_figure import plot_uq_band, plot_uq_sobol

__all__ = ["plot_check", 
    "Crossing", "KEY_CHANNELS", "axis_label", "channel_label", "crossing_times", "default_channels", "display_unit",
    "draw_jobs", "figure_jobs", "mark_crossing", "plot_bounds", "plot_folder", "plot_pem_vs_mc", "plot_psd_map",
    "plot_psd_slices", "plot_speed_sweep", "plot_time_history", "plot_uq_band", "plot_uq_sobol", "psd_slices", "save_figure", "select_channels",
]
