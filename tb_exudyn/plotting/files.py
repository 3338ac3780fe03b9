"""Figures of saved result folders, written atomically next to the results (for ``tb-exudyn plot``)."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from matplotlib.figure import Figure

from ..results import RandomResponse, find_results
from ..atomic import write_atomic
from . import data
from .figures import plot_bounds, plot_pem_vs_mc, plot_psd_map, plot_psd_slices, plot_time_history


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Write ``fig`` to ``path`` atomically; the format is the file's suffix (png, pdf, svg, ...)."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in fig.canvas.get_supported_filetypes():
        raise ValueError(f"cannot write figures as {fmt!r}; formats: {sorted(fig.canvas.get_supported_filetypes())}")
    write_atomic(path, lambda fh: fig.savefig(fh, format=fmt, dpi=dpi))
    return path


def figures_of(result, channels: str | Sequence[str] | None = None):
    """(file stem, figure factory) of every standard figure of one result: per selected channel the
    k-sigma bounds (with stored samples), PSD map and PSD at maximum sigma, or the history."""
    for ch in data.select_channels(result, channels):
        if isinstance(result, RandomResponse):
            yield f"{ch}.bounds", lambda ch=ch: plot_bounds(result, ch, samples=True if result.samples is not None else None)
            if result.psd is not None:
                yield f"{ch}.psd_map", lambda ch=ch: plot_psd_map(result, ch)
                yield f"{ch}.psd_slices", lambda ch=ch: plot_psd_slices(result, ch)
        else:
            yield f"{ch}.history", lambda ch=ch: plot_time_history(result, [ch])


def plot_folder(folder: str | Path, channels: str | Sequence[str] | None = None,
                formats: Sequence[str] = ("png",)) -> list[Path]:
    """Write the standard figures of a saved result folder and return their paths.

    ``folder`` is one result folder (``meta.json`` + ``arrays.npz``) or a folder holding several
    (e.g. the ``--out`` folder with ``pem/`` and ``mc/``). Each result's figures go to
    ``<result>/figures/<channel>.<kind>.<format>``; when the folder holds a PEM and Monte Carlo
    results, ``<folder>/figures/<channel>.pem_vs_mc.<format>`` compares them. ``channels``: names or
    glob patterns (default: the key channels, see :data:`tb_exudyn.plotting.data.KEY_CHANNELS`).
    """
    folder = Path(folder)
    found = find_results(folder)
    written: list[Path] = []

    def write(make, out: Path, stem: str) -> None:
        fig = make()
        written.extend(save_figure(fig, out / f"{stem}.{fmt}") for fmt in formats)

    for path, result in found:
        for stem, make in figures_of(result, channels):
            write(make, path / "figures", stem)
    pems = [r for _, r in found if isinstance(r, RandomResponse) and r.method == "pem"]
    mcs = [r for _, r in found if isinstance(r, RandomResponse) and r.method.startswith("monte_carlo")]
    if pems and mcs:
        common = [c for c in data.select_channels(pems[0], channels) if all(c in m.channels for m in mcs)]
        for ch in common:
            write(lambda ch=ch: plot_pem_vs_mc(pems[0], mcs, ch), folder / "figures", f"{ch}.pem_vs_mc")
    return written


__all__ = ["figures_of", "plot_folder", "save_figure"]
