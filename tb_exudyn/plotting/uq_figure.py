"""The figures of an uncertainty study (:class:`tb_exudyn.results.uq.UqResult`; ``result.plot_sobol()``
and ``result.plot_band(channel)`` hand off to them): the Sobol indices of its key quantities as bars,
and a channel's sigma(t) over the crossing with its band over the uncertain keys."""

from __future__ import annotations

import numpy as np


def plot_uq_sobol(result, quantities=None):  # noqa: ANN001, ANN201
    """A matplotlib Figure: per quantity (default those with a finite variance, at most 12) the
    first-order (filled) and total (outlined) Sobol index of each uncertain key."""
    from matplotlib.figure import Figure

    names = list(quantities) if quantities is not None else [
        q for i, q in enumerate(result.quantities) if np.isfinite(result.quantity_std[i]) and result.quantity_std[i] > 0
    ][:12]
    keys = result.key_names
    fig = Figure(figsize=(max(6.0, 1.2 * len(names) + 2.0), 4.5))
    ax = fig.add_subplot()
    width = 0.8 / max(len(keys), 1)
    x = np.arange(len(names))
    for j, key in enumerate(keys):
        first = [result.quantity(q)["sobol_first"][key] for q in names]
        total = [result.quantity(q)["sobol_total"][key] for q in names]
        pos = x - 0.4 + width * (j + 0.5)
        bars = ax.bar(pos, first, width, label=key)
        ax.bar(pos, total, width, fill=False, edgecolor=bars.patches[0].get_facecolor() if bars.patches else None)
    labels = [f"{n.split(':', 1)[0]}\n{n.split(':', 1)[-1].split('/')[-1]}" for n in names]
    ax.set_xticks(x, labels, fontsize=7, rotation=20)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("Sobol index (filled: first order, outline: total)")
    ax.legend(fontsize=8)
    ax.set_title(f"{result.scenario.name}: what the uncertain keys explain")
    fig.tight_layout()
    return fig


def plot_uq_band(result, channel: str):  # noqa: ANN001, ANN201
    """A matplotlib Figure: ``channel``'s sigma(t), its mean over the keys and its 5-95 % band."""
    from matplotlib.figure import Figure

    i = result.index(channel)
    fig = Figure(figsize=(8.0, 4.0))
    ax = fig.add_subplot()
    band = result.sigma_band[:, i]
    ax.fill_between(result.time, band[0], band[2], alpha=0.3, label="5-95 % over the keys")
    ax.plot(result.time, band[1], lw=0.8, label="median")
    ax.plot(result.time, result.mean_sigma[i], lw=1.2, label="mean")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"sigma of {channel} [{result.units[i]}]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


__all__ = ["plot_uq_band", "plot_uq_sobol"]
