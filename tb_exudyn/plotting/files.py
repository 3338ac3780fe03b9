"""Figures of saved result folders, drawn in parallel and written atomically inside the folder.

:func:`plot_folder` (``tb-exudyn plot``) draws the standard figures of every result in a folder:
per channel the k-sigma bounds, the PSD map and the PSD at maximum sigma (PEM), or the history
(one run), and PEM against Monte Carlo where the folder holds both. By default only the channels
that matter are drawn (:func:`tb_exudyn.plotting.data.default_channels`); ``channels=PATTERN``
draws others.

Parallel: the figures are independent, so they are drawn by a pool of spawned processes (the
project's start method: a forked copy of a process with threads can deadlock), each with
matplotlib's Agg backend and one BLAS thread. The calling process draws too (it takes figures from
the end of the queue while the workers start), so ``workers=N`` means N drawing processes in all
and ``workers=1`` draws everything here with no pool. Each worker receives only the channel it
draws (:func:`tb_exudyn.plotting.data.channel_subset`, about 1 MB for a 200 x 557 PSD map).

Paths: every file is written inside the folder given; a channel name that would leave it (from a
foreign or hostile ``meta.json``: ``a/../../x``) or a figures folder that is a symbolic link is
refused with a :class:`~tb_exudyn.errors.ResultsError` naming the file, before anything is drawn.
"""

from __future__ import annotations

import io
import multiprocessing
import os
import warnings
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from matplotlib.figure import Figure

from ..atomic import write_atomic
from ..errors import ResultsError, SettingError
from ..results import RandomResponse, find_results
from . import data
from .figures import plot_bounds, plot_pem_vs_mc, plot_psd_map, plot_psd_slices, plot_time_history

#: figure resolution [dots per inch] of the PNG files (and of the report's images): 750 px wide
DPI = 100
#: figure kinds, in the order they are drawn and shown
KINDS = ("bounds", "psd_map", "psd_slices", "history", "pem_vs_mc")
#: below this many figures, drawing here beats starting a worker (a spawned process needs about
#: 1-2 s to import matplotlib and tb_exudyn, the time of 5-10 figures)
MIN_JOBS_FOR_POOL = 8
_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")


def save_figure(fig: Figure, path: str | Path, dpi: int = DPI) -> Path:
    """Write ``fig`` to ``path`` atomically; the format is the file's suffix (png, pdf, svg, ...)."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in fig.canvas.get_supported_filetypes():
        raise ValueError(f"cannot write figures as {fmt!r}; formats: {sorted(fig.canvas.get_supported_filetypes())}")
    write_atomic(path, lambda fh: fig.savefig(fh, format=fmt, dpi=dpi))
    return path


#: colours of a figure's palette in the page (a PNG palette holds at most 256)
PALETTE_COLOURS = 256


def compact_png(png: bytes) -> bytes:
    """A figure's PNG as the page embeds it: re-encoded with a palette of :data:`PALETTE_COLOURS`
    colours (median cut) when that is smaller. A matplotlib figure has few colours (a colour map
    holds 256), so the picture barely changes (the reference study's 69 figures: mean difference
    at most 0.5 of 255 per channel) and takes about a third of the bytes (4.76 MB of PNG files
    gave 1.81 MB). The bytes as they are when they are not an opaque PNG (a transparent one would
    lose its alpha), or when Pillow (matplotlib's image library) cannot read them. The figure files
    on disk are not changed."""
    try:
        from PIL import Image
        with Image.open(io.BytesIO(png)) as im:
            if im.format != "PNG" or im.mode not in ("RGB", "RGBA"):
                return png
            small = _palette_png(im)
    except (ImportError, OSError, ValueError, SyntaxError):  # not an image Pillow reads (SyntaxError: a broken PNG)
        return png
    return small if small is not None and len(small) < len(png) else png


def _palette_png(im) -> bytes | None:  # noqa: ANN001 - a PIL image
    """The PNG of an RGB(A) image with a palette of :data:`PALETTE_COLOURS` colours (median cut); None
    when it has transparent pixels (a palette would lose them)."""
    from PIL import Image
    if im.mode == "RGBA" and im.getchannel("A").getextrema()[0] < 255:
        return None
    out = io.BytesIO()
    im.convert("RGB").quantize(PALETTE_COLOURS, method=Image.Quantize.MEDIANCUT).save(out, "PNG")
    return out.getvalue()


#: zlib level of the figure files drawn for a page: level 1 writes them 3 % larger than matplotlib's
#: default (6) in a third less time (the reference study's figures)
FILE_PNG_LEVEL = 1


def figure_pngs(fig: Figure, dpi: int = DPI) -> tuple[bytes, bytes]:
    """(the figure's PNG file, the PNG the page embeds), from one drawing on Agg: the file has the
    pixels ``fig.savefig(format="png", dpi=dpi)`` writes (RGBA, or RGB when every pixel is opaque,
    with matplotlib's Software and dpi fields), the page's copy is :func:`compact_png` of it, made from
    the pixels in memory instead of decoding the file (when the palette is not smaller, the file's bytes)."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image, PngImagePlugin
    original, original_dpi = fig.canvas, fig.dpi
    try:
        canvas = FigureCanvasAgg(fig)
        fig.set_dpi(dpi)
        canvas.draw()
        rgba = Image.frombuffer("RGBA", canvas.get_width_height(physical=True), canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
        rgba.load()
    finally:
        fig.set_dpi(original_dpi)
        fig.set_canvas(original)
    opaque = rgba.getchannel("A").getextrema()[0] == 255
    image = rgba.convert("RGB") if opaque else rgba
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/")
    buf = io.BytesIO()
    image.save(buf, "PNG", pnginfo=info, dpi=(dpi, dpi), compress_level=FILE_PNG_LEVEL)
    png = buf.getvalue()
    small = _palette_png(image) if opaque else None
    return png, small if small is not None and len(small) < len(png) else png


# ============================================================================================ paths
def confined_path(root: Path, folder: Path, stem: str, suffix: str, source: Path) -> Path:
    """``folder/<stem>.<suffix>``, checked to lie inside ``root``.

    ``stem`` comes from a channel name read from ``source`` (a ``meta.json``); it must be one
    file name (no path separator, not '.' or '..'), ``folder`` must not be a symbolic link, and
    the resolved path must lie inside the resolved ``root``. Raises ResultsError naming ``source``
    (or the folder) otherwise.
    """
    name = f"{stem}.{suffix}"
    if "/" in stem or "\\" in stem or "\x00" in stem or stem in (".", "..") or name.startswith("."):
        raise ResultsError(f"{source}: channel {stem.rsplit('.', 1)[0]!r} is not a plain name (it holds a path "
                           f"separator or '..'); refusing to write a figure outside {root}")
    if folder.is_symlink():
        raise ResultsError(f"{folder}: the figures folder is a symbolic link (to {os.readlink(folder)}); "
                           f"refusing to write figures through it (remove it, then plot again)")
    path = folder / name
    real_root = root.resolve()
    if not path.resolve().is_relative_to(real_root):
        raise ResultsError(f"{source}: figure {path} would be written outside the output folder {real_root} "
                           "(through a symbolic link); refusing")
    return path


# ============================================================================================ jobs
@dataclass(frozen=True)
class FigureJob:
    """One figure: its kind (:data:`KINDS`), the channel, the files to write (one per format) and
    the data it needs (one-channel results, picklable)."""

    kind: str
    channel: str
    paths: tuple[Path, ...]
    payload: tuple[Any, ...]


def figure_file(folder: Path, channel: str, kind: str, fmt: str = "png") -> Path:
    """Where a figure goes: ``<folder>/figures/<channel>.<kind>.<fmt>`` (no checks)."""
    return folder / "figures" / f"{channel}.{kind}.{fmt}"


def _jobs_of(root: Path, path: Path, result, channels, formats: Sequence[str], where: str,
             shown: Callable[[str], bool] | None) -> list[FigureJob]:
    source = path / "meta.json"
    out = []
    for ch in data.select_channels(result, channels, where=where, source=str(path)):
        if shown is not None and not shown(ch):
            continue
        kinds = ("bounds",) if isinstance(result, RandomResponse) else ("history",)
        if data.has_psd(result, ch):
            kinds += ("psd_map", "psd_slices")
        one = (data.channel_subset(result, [ch]),)
        for kind in kinds:
            paths = tuple(confined_path(root, path / "figures", f"{ch}.{kind}", fmt, source) for fmt in formats)
            out.append(FigureJob(kind, ch, paths, one))
    return out


def figure_jobs(folder: str | Path, found: Sequence[tuple[Path, Any]], channels: str | Sequence[str] | None = None,
                formats: Sequence[str] = ("png",), where: str = "figure_jobs",
                shown: Callable[[str], bool] | None = None) -> list[FigureJob]:
    """Every standard figure of the results ``found`` in ``folder`` (see :func:`plot_folder`),
    with its paths checked (:func:`confined_path`). ``shown``: which of the selected channels get
    figures (None: all; a page's default: :func:`data.page_channel`)."""
    root = Path(folder)
    jobs: list[FigureJob] = []
    for path, result in found:
        jobs += _jobs_of(root, path, result, channels, formats, where, shown)
    pems = [r for _, r in found if r.kind.gaussian]
    mcs = [(p, r) for p, r in found if r.kind.sampled]
    if pems and mcs:
        for ch in data.select_channels(pems[0], channels, where=where):
            if all(ch in r.channels for _, r in mcs):
                paths = tuple(confined_path(root, root / "figures", f"{ch}.pem_vs_mc", fmt, mcs[0][0] / "meta.json")
                              for fmt in formats)
                payload = (data.channel_subset(pems[0], [ch]), [data.channel_subset(r, [ch]) for _, r in mcs])
                jobs.append(FigureJob("pem_vs_mc", ch, paths, payload))
    return jobs


def make_figure(kind: str, channel: str, payload: tuple[Any, ...]) -> Figure:
    """The figure of one job (what a worker draws)."""
    if kind == "pem_vs_mc":
        return plot_pem_vs_mc(payload[0], payload[1], channel)
    (result,) = payload
    if kind == "history":
        return plot_time_history(result, [channel])
    if kind == "bounds":
        return plot_bounds(result, channel, samples=True if result.samples is not None else None)
    if kind == "psd_map":
        return plot_psd_map(result, channel)
    if kind == "psd_slices":
        return plot_psd_slices(result, channel)
    raise ValueError(f"unknown figure kind {kind!r}; kinds: {KINDS}")


def draw_job(job: FigureJob, dpi: int = DPI) -> tuple[Path, ...]:
    """Draw one job and write its files (runs in a worker or here)."""
    fig = make_figure(job.kind, job.channel, job.payload)
    return tuple(save_figure(fig, p, dpi=dpi) for p in job.paths)


def draw_job_for_page(job: FigureJob, dpi: int = DPI) -> tuple[tuple[Path, ...], bytes]:
    """Draw one job, write its files and return, with their paths, the PNG as a page embeds it
    (:func:`compact_png`): the palette re-encoding is done where the figure is drawn, in parallel,
    not one figure after another in the process writing the page, and from the pixels in memory
    (:func:`figure_pngs`). The job's first file must be a PNG."""
    fig = make_figure(job.kind, job.channel, job.payload)
    png, page = figure_pngs(fig, dpi)
    paths = []
    for p in job.paths:
        if p.suffix.lower() == ".png":
            write_atomic(p, lambda fh: fh.write(png))
            paths.append(p)
        else:
            paths.append(save_figure(fig, p, dpi=dpi))
    return tuple(paths), page


def _init_worker() -> None:
    for name in _THREAD_VARIABLES:
        os.environ[name] = "1"
    import matplotlib

    matplotlib.use("Agg")


def default_workers() -> int:
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def draw_jobs(jobs: Sequence[FigureJob], workers: int | None = None, progress: bool = False,
              dpi: int = DPI) -> list[Path]:
    """Draw ``jobs`` with ``workers`` drawing processes in all (this one included; default: the
    cores this process may use; fewer than :data:`MIN_JOBS_FOR_POOL` jobs are drawn here), with a tqdm
    progress bar over figures when ``progress``; returns the files written, in the order of ``jobs``."""
    done = run_jobs(draw_job, jobs, workers, progress, dpi)
    return [p for paths in done for p in paths]


def draw_jobs_for_page(jobs: Sequence[FigureJob], workers: int | None = None, progress: bool = False,
                       dpi: int = DPI) -> list[bytes]:
    """As :func:`draw_jobs`, returning each job's PNG as a page embeds it (:func:`draw_job_for_page`)."""
    return [png for _, png in run_jobs(draw_job_for_page, jobs, workers, progress, dpi)]


def run_jobs(draw, jobs: Sequence[FigureJob], workers: int | None = None, progress: bool = False,
             dpi: int = DPI) -> list[Any]:
    """``draw(job, dpi)`` for each of ``jobs`` (see :func:`draw_jobs`); returns what it returned, in
    the order of ``jobs``."""
    from tqdm.auto import tqdm

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise SettingError("plot_folder", "workers", workers, "a whole number >= 1 or None (all cores)")
    n = min(workers or default_workers(), len(jobs))
    if len(jobs) < MIN_JOBS_FOR_POOL:
        n = 1
    with tqdm(total=len(jobs), unit="figure", desc="figures", disable=None if progress else True, leave=False) as bar:
        if n <= 1:
            done = []
            for job in jobs:
                done.append(draw(job, dpi))
                bar.update()
            return done
        with ProcessPoolExecutor(max_workers=n - 1, mp_context=multiprocessing.get_context("spawn"),
                                 initializer=_init_worker) as pool:
            futures = [pool.submit(draw, job, dpi) for job in jobs]
            return _collect(draw, jobs, futures, list(range(len(jobs))), dpi, bar)


def _collect(draw, jobs: Sequence[FigureJob], futures: Sequence[Future], order: Sequence[int], dpi: int,
             bar) -> list[Any]:  # noqa: ANN001
    """What ``futures[i]`` (``draw(jobs[i], dpi)`` in a pool) returned, for each i. This process draws
    too: it takes the jobs from the end of the pool's queue (``order``: the indices as submitted), those
    not yet started, while the workers take them from the front; a pool that cannot start draws here."""
    for fut in futures:
        fut.add_done_callback(lambda f: None if f.cancelled() else bar.update())
    done: dict[int, Any] = {}
    for i in reversed(order):
        if not futures[i].cancel():
            break
        done[i] = draw(jobs[i], dpi)
        bar.update()
    broken = False
    for i, fut in enumerate(futures):
        if i in done:
            continue
        if not broken:
            try:
                done[i] = fut.result()
                continue
            except BrokenProcessPool:  # e.g. a script without `if __name__ == "__main__":`
                broken = True
                warnings.warn("the figure workers could not start; drawing the figures in this "
                              "process (guard a script's main code with `if __name__ == "
                              "\"__main__\":`)", RuntimeWarning, stacklevel=3)
        done[i] = draw(jobs[i], dpi)
        bar.update()
    return [done[i] for i in range(len(jobs))]


class PageDrawing:
    """A page's figures drawn on a pool started beforehand (``executor``: e.g.
    :func:`tb_exudyn.execution.standby.standby_pool`, whose processes imported this module while a
    run computed): :meth:`submit` hands jobs to it as soon as their result exists, :meth:`pictures`
    returns the page's PNGs of jobs (:func:`draw_job_for_page`), submitting those not yet submitted
    and drawing in this process too (see :func:`run_jobs`). A job is drawn once, by its files."""

    def __init__(self, executor: Any, dpi: int = DPI) -> None:
        self.executor, self.dpi = executor, dpi
        self._futures: dict[tuple[str, ...], tuple[int, Future]] = {}

    @staticmethod
    def _key(job: FigureJob) -> tuple[str, ...]:
        return tuple(os.path.realpath(p) for p in job.paths)

    def submit(self, jobs: Sequence[FigureJob]) -> None:
        for job in jobs:
            if self._key(job) not in self._futures:
                self._futures[self._key(job)] = (len(self._futures), self.executor.submit(draw_job_for_page, job, self.dpi))

    def has(self, job: FigureJob) -> bool:
        return self._key(job) in self._futures

    def pictures(self, jobs: Sequence[FigureJob], progress: bool = False) -> list[bytes]:
        from tqdm.auto import tqdm

        self.submit(jobs)
        seq_futures = [self._futures[self._key(j)] for j in jobs]
        order = sorted(range(len(jobs)), key=lambda i: seq_futures[i][0])
        with tqdm(total=len(jobs), unit="figure", desc="figures", disable=None if progress else True, leave=False) as bar:
            done = _collect(draw_job_for_page, jobs, [f for _, f in seq_futures], order, self.dpi, bar)
        return [png for _, png in done]


def plot_folder(folder: str | Path, channels: str | Sequence[str] | None = None,
                formats: Sequence[str] = ("png",), *, workers: int | None = None, progress: bool = False,
                found: Sequence[tuple[Path, Any]] | None = None, where: str = "plot_folder") -> list[Path]:
    """Write the standard figures of a saved result folder and return their paths.

    ``folder`` is one result folder (``meta.json`` + ``arrays.npz``) or a folder holding several
    (e.g. the ``--out`` folder with ``pem/`` and ``mc/``). Each result's figures go to
    ``<result>/figures/<channel>.<kind>.<format>``; when the folder holds a PEM and Monte Carlo
    results, ``<folder>/figures/<channel>.pem_vs_mc.<format>`` compares them. ``channels``: names or
    glob patterns (default: the channels that matter, :func:`tb_exudyn.plotting.data.default_channels`).
    ``workers``: drawing processes (default: all cores); ``progress``: a progress bar over figures.
    ``found``: the results already loaded (``find_results(folder)``), to avoid reading them again.

    Raises ResultsError, before drawing anything, when a figure would be written outside ``folder``,
    and SettingError when a pattern of ``channels`` matches no channel of a result (naming ``where``,
    the caller, and the argument ``channels``).
    """
    folder = Path(folder)
    found = find_results(folder) if found is None else found
    return draw_jobs(figure_jobs(folder, found, channels, formats, where), workers=workers, progress=progress)


__all__ = ["DPI", "FigureJob", "KINDS", "PALETTE_COLOURS", "compact_png", "confined_path", "default_workers", "draw_job",
           "draw_job_for_page", "draw_jobs", "figure_pngs", "PageDrawing", "draw_jobs_for_page", "figure_file", "run_jobs",
           "figure_jobs", "make_figure", "plot_folder", "save_figure"]
