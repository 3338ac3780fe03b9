"""A self-contained HTML report of saved results, read top-down by an engineer.

Sections, in order: the verdicts and the warnings (each result's provenance ``warnings``); for a
scenario that reproduces a study, the study's stated findings beside ours (data:
``models/studies/*.toml``, :func:`load_study`); the figures, each next to the numbers it explains,
grouped by bridge / car / wheelsets; the full channel table, grouped the same way, collapsible and
filterable; the modes (:class:`ModeEntry` rows); the scenario; the provenance.

The verdicts (:class:`Verdicts`, from the checks of the first random result, or given): a one-line
count per verdict (how many conditional: a caveat could change the verdict); one sentence each on
what the target probability and the estimate are; one row per criterion, its deciding location
(readable label, the channel name beside it, linked to the channel's figure when the report has
one), the bridge's limit sets first (deck acceleration, twist), then the vehicle's (ride comfort,
running safety), each under a heading with its counts; a NOT EVALUATED row gives its reason in the
row; each distinct caveat once, numbered under the table (the rows carry the numbers), folded unless
one could change a verdict; the full per-location table folded below. Probabilities, estimates and limits as the
terminal shows them (:func:`tb_exudyn.results.checks_table.format_probability`, ``format_value``:
"< 1e-09" below SMALLEST_SHOWN, kN, mm, m/s^2).

Inputs that other layers compute arrive as documented data objects; a section whose input is
absent says "not computed":

- ``checks``: a checks table (``result.checks()``, :class:`tb_exudyn.results.checks_table.ChecksTable`)
  or a sequence of :class:`CheckEntry` (or objects with the same attribute names), one per
  criterion and location;
- ``modes``: a sequence of :class:`ModeEntry` (or objects with the same attribute names), the
  damped modes of the linearised system.

One page, no external resources: figures are embedded as base64 PNG (re-encoded with a 256-colour
palette, :func:`~tb_exudyn.plotting.files.compact_png`: the reference study's page 6.92 MB before,
2.83 MB after; the figure files keep their colours), the style and the few lines of script (links
open folded sections, the channel filter; the page reads the same without it) are inline, and every
piece of text is escaped. The full channel table, the provenance's per-channel entries (one table
each), the vehicle's figure groups and a long modes table are folded (the reference study's page:
about 11 screens at 1400 px, 36 before). Values are shown in engineering units (:func:`tb_exudyn.plotting.data.display_unit`).
When the checks cannot be computed, the verdict section shows a screening of max |mean| + 3 sigma
against the limits of :func:`code_limit` (all [check]), clearly labelled as not being a verdict.
Importing this package imports matplotlib (:mod:`tb_exudyn.plotting.files`, whose figures the page
embeds): the command line loads it only for the commands that draw figures or write a page, and
reading results (:mod:`tb_exudyn.results`) never imports it. The checks are the result's own cached
table (``result.checks()``), the one the terminal's verdict lines read.
"""

from __future__ import annotations

import datetime as _dt
import functools
import html
import os
from pathlib import Path
from typing import Any, Iterable, Sequence

from .._version import __version__
from ..files import output_targets, write_output
from ..plotting import data as pdata
from ..plotting.data import pattern_channels
from ..plotting.files import PageDrawing, compact_png, draw_jobs_for_page, figure_jobs, plot_folder, save_figure
from ..errors import UserError
from ..results import RandomResponse, find_results
from ..results.checks import default_limits
from ..scenario.show import run_label
from ..scenario.studies import Study, StudyFinding, StudyQuantity, load_study, studies_for
from .entries import (CheckEntry, CodeLimit, FindingRow, ModeEntry, Result, SummaryRow, Verdicts, as_check_entries,
                      as_mode_entries, check_entries, code_limit, compare_findings, screening, static_axle_load, summary,
                      verdicts_of)
from .sections import (FILTER_SCRIPT, STYLE, anchor, channels_section, figures_section, findings_section, link, modes_section,
                   provenance_section, result_name, scenario_section, warnings_section)
from .check import CHECK_REPORT, check_files, render_check_report, write_check_report
from .sweep import SWEEP_REPORT, render_sweep_report, write_sweep_report
from .uq import UQ_REPORT, render_uq_report, write_uq_report
from .verdicts import verdicts_section

esc = html.escape


def ordered(found: Sequence[tuple[Path, Result]]) -> list[tuple[Path, Result]]:
    """The results in reading order: PEM first, then Monte Carlo, then single runs (stable)."""
    def rank(item):
        r = item[1]
        return 0 if r.kind.gaussian else 1 if r.kind.random else 2
    return sorted(found, key=rank)


def _first_random(found: Sequence[tuple[Path, Result]]) -> Result | None:
    for _, r in found:
        if r.kind.gaussian:
            return r
    return found[0][1] if found else None


def render_report(found: Sequence[tuple[Path, Result]], k: float = 3.0,
                  channels: str | Sequence[str] | None = None, title: str | None = None, *,
                  checks: Iterable[Any] | None = None, modes: Iterable[Any] | None = None,
                  pictures: dict[tuple[str, str, str], bytes] | None = None,
                  names: dict[str, list[str]] | None = None, comparison: Sequence[str] = (),
                  warnings: Sequence[str] = (), left_out: Sequence[str] = ()) -> str:
    """The HTML text of a report on ``found`` results (see :func:`write_report`).

    ``pictures``: PNG bytes by (result folder name, channel, kind) ("" as folder for pem_vs_mc);
    ``names``: the channels with figures per result folder name (default: ``channels`` selected);
    ``comparison``: channels with a PEM against Monte Carlo figure; ``warnings``: the report's own;
    ``left_out``: channels whose figures the page leaves out (it says so, and how to draw them).
    """
    found = ordered(found)
    report_warnings = list(warnings)
    if checks is None:  # the checks of the first random response (the verdicts at the top)
        first = _first_random(found)
        limits = default_limits() if first is not None else None  # a broken limit file: its error, not "not computed"
        try:
            checks = first.checks(limits) if first is not None else None
        except UserError as exc:  # e.g. a result saved before the exceedance statistics existed
            report_warnings.append(f"code checks not computed: {exc}")
    if modes is None:  # the modal table a random result carries (its analysis set-up)
        carried = [r.provenance["damped_modes"] for _, r in found if r.provenance.get("damped_modes")]
        modes = [ModeEntry(**m) for m in carried[0]] if carried else None
    mode_rows = as_mode_entries(modes)
    pictures = pictures or {}
    if names is None:
        names = {p.name: pdata.select_channels(r, channels) for p, r in found}
    figure_ids = {anchor("fig", ch) for ch in names.get(found[0][0].name, [])} if found else set()
    scenarios = [r.scenario for _, r in found if r.scenario is not None]
    sc = scenarios[0] if scenarios else None
    first = _first_random(found)
    verdicts = verdicts_of(checks, sc)
    title = title or f"tb_exudyn report: {sc.name if sc else found[0][0].name}" + (f" at {sc.speed_kmh:g} km/h" if sc else "")
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    what = []
    for path, r in found:
        w = result_name(path, r)
        if isinstance(r, RandomResponse):
            w += f", sigma over {pdata.band_text(r)}" + (f", {r.n_samples} samples" if r.n_samples else
                                                         f", {len(r.freq)} frequencies")
        what.append(w)
    pem = next((r for _, r in found if r.kind.gaussian and r.psd is not None), None)
    studies = studies_for(sc)
    nav = [("verdicts", "Verdicts"), ("warnings", "Warnings")] + ([("findings", "Study findings")] if studies else []) + [
        ("figures", "Figures"), ("channels", "All channels"), ("modes", "Modes"), ("scenario", "Scenario"),
        ("provenance", "Provenance")]
    body = [f"<h1>{esc(title)}</h1>",
            f'<p class="meta">{esc(run_label(sc) if sc else "")}</p>',
            f'<p class="meta">{esc("; ".join(what))}. Generated {esc(now)} by tb_exudyn {esc(__version__)}.</p>',
            "<nav>" + " | ".join(link(a, t) for a, t in nav) + "</nav>",
            verdicts_section(verdicts, first, k, figure_ids),
            warnings_section(found, report_warnings),
            findings_section(studies, pem, figure_ids),
            figures_section(found, pictures, names, k, list(comparison), list(left_out)),
            channels_section(found, k, figure_ids),
            modes_section(mode_rows),
            scenario_section(scenarios),
            provenance_section(found)]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(b for b in body if b)
            + f"\n<script>{FILTER_SCRIPT}</script>\n</body></html>\n")


def _fresh(png: Path, newest_input: float) -> bool:
    try:
        return png.stat().st_mtime >= newest_input
    except OSError:
        return False


def page_jobs(folder: Path, found: Sequence[tuple[Path, Result]], channels=None, *,  # noqa: ANN001
              all_figures: bool = False) -> tuple[list[Any], list[str]]:
    """The figures a report page shows (:func:`tb_exudyn.plotting.files.figure_jobs`, PNG) and the
    channels whose figures it leaves out: for the default channels (``channels`` None) without
    ``all_figures``, those of :func:`tb_exudyn.plotting.data.page_channel` only (the bridge, the
    leading car and the checks' deciding channels)."""
    if channels is not None or all_figures:
        return figure_jobs(folder, found, channels, ("png",)), []
    deciding = [c for _, r in found for c in pdata.deciding_channels(r)]
    shown = functools.partial(pdata.page_channel, deciding=deciding)
    left_out = list(dict.fromkeys(c for _, r in found for c in pdata.select_channels(r) if not shown(c)))
    return figure_jobs(folder, found, channels, ("png",), shown=shown), left_out


def report_pictures(folder: Path, found: Sequence[tuple[Path, Result]], channels, *, workers: int | None = None,
                    progress: bool = False, drawing: PageDrawing | None = None, all_figures: bool = False,
                    ) -> tuple[dict[tuple[str, str, str], bytes], dict[str, list[str]], list[str], list[str]]:
    """The report's figures as PNG bytes, as the page embeds them (:func:`compact_png`): the files
    ``plot_folder`` wrote when they are newer than the results, the others drawn now (in parallel,
    into the same files; each worker also re-encodes the figures it draws; with ``drawing``, on its
    pool, which may have drawn some already). The default channels (``channels`` None) without
    ``all_figures``: the channels of :func:`tb_exudyn.plotting.data.page_channel` only.
    Returns (pictures, channels with figures per result folder name, channels with a PEM against
    Monte Carlo figure, channels whose figures were left out)."""
    jobs, left_out = page_jobs(folder, found, channels, all_figures=all_figures)
    newest = max((p / n).stat().st_mtime for p, _ in found for n in ("arrays.npz", "meta.json") if (p / n).exists())
    if drawing is not None:
        missing = [j for j in jobs if drawing.has(j) or not _fresh(j.paths[0], newest)]
        pngs = drawing.pictures(missing, progress=progress)
    else:
        missing = [j for j in jobs if not _fresh(j.paths[0], newest)]
        pngs = draw_jobs_for_page(missing, workers=workers, progress=progress)
    drawn = dict(zip((j.paths[0] for j in missing), pngs))
    def page_png(path: Path) -> bytes:  # noqa: E306 (drawn now: already compact; else the file, compacted here)
        return drawn[path] if path in drawn else compact_png(path.read_bytes())
    pictures: dict[tuple[str, str, str], bytes] = {}
    names: dict[str, list[str]] = {p.name: [] for p, _ in found}
    comparison: list[str] = []
    for job in jobs:
        if job.kind == "pem_vs_mc":
            pictures[("", job.channel, job.kind)] = page_png(job.paths[0])
            comparison.append(job.channel)
            continue
        result_dir = job.paths[0].parent.parent.name
        pictures[(result_dir, job.channel, job.kind)] = page_png(job.paths[0])
        if job.channel not in names[result_dir]:
            names[result_dir].append(job.channel)
    return pictures, names, comparison, left_out


def report_target(folder: str | Path, out_html: str | Path | None = None, *, overwrite: bool = False,
                  where: str = "write_report", key: str = "out_html") -> tuple[Path, Path, bool]:
    """Where :func:`write_report` writes: (the page as named, the file to write, whether it is the
    folder's own default page); OutputFolderError if the target is refused (see write_report)."""
    folder = Path(folder)
    default = folder / "report.html"
    out = Path(out_html) if out_html is not None else default
    derived = out_html is None or os.path.realpath(out) == os.path.realpath(default)
    (target,) = output_targets(out, overwrite=overwrite or derived, derived=derived, where=where, key=key)
    return out, target, derived


def write_report(folder: str | Path, out_html: str | Path | None = None, *, k: float = 3.0,
                 channels: str | Sequence[str] | None = None, checks: Iterable[Any] | None = None,
                 modes: Iterable[Any] | None = None, workers: int | None = None, progress: bool = False,
                 found: Sequence[tuple[Path, Result]] | None = None, overwrite: bool = False,
                 where: str = "write_report", key: str = "out_html", drawing: PageDrawing | None = None,
                 all_figures: bool = False) -> Path:
    """Write one self-contained HTML page on the results in ``folder`` (one result folder, or a
    folder of result folders) to ``out_html`` (default ``<folder>/report.html``), atomically.

    ``channels``: names or glob patterns of the channels to draw (default: the channels that
    matter, :func:`tb_exudyn.plotting.data.default_channels`); the channel table lists every
    channel. Figures that ``plot_folder`` already wrote (newer than the results) are embedded as
    they are; missing ones are drawn (``workers`` processes, a progress bar with ``progress``) into
    ``<result>/figures``. ``checks``: a checks table or the verdict rows (:func:`verdicts_of`; None:
    the checks of the first random result); ``modes``: the modes (:class:`ModeEntry`; None: "not computed"). ``found``: the results already
    loaded (``find_results(folder)``). ``drawing``: a :class:`~tb_exudyn.plotting.files.PageDrawing`
    whose pool draws the figures (``tb-exudyn run`` starts it before the analysis and gives it the
    result's figures as soon as the result is saved); ``workers`` is then unused. ``all_figures``:
    the default channels' every figure; without it the figures of the cars behind the leading one
    are left out unless a verdict names the channel (:func:`tb_exudyn.plotting.data.page_channel`),
    and the page says so.

    The default page is the folder's own and is rewritten each time; a named ``out_html`` is
    checked before anything is drawn (:func:`tb_exudyn.files.output_targets`): refused inside a
    result or checkpoint folder, when it is not a regular file, and when it exists unless
    ``overwrite``. Either way a FIFO, device or folder at the target is refused, and a full disk
    leaves the old page (OutputFolderError naming the file and ``where``/``key``, e.g.
    ``command line``, ``--html``).
    """
    folder = Path(folder)
    found = find_results(folder) if found is None else found
    out, target, derived = report_target(folder, out_html, overwrite=overwrite, where=where, key=key)
    pictures, names, comparison, left_out = report_pictures(folder, found, channels, workers=workers,
                                                            progress=progress, drawing=drawing, all_figures=all_figures)
    text = render_report(found, k=k, channels=channels, checks=checks, modes=modes, pictures=pictures,
                         names=names, comparison=comparison, left_out=left_out)
    write_output([(target, text.encode("utf-8"))], named=out, overwrite=overwrite or derived, where=where, key=key)
    return out



__all__ = ["CheckEntry", "CodeLimit", "FindingRow", "ModeEntry", "Study", "StudyFinding", "StudyQuantity",
           "SummaryRow", "Verdicts", "as_check_entries", "check_entries", "as_mode_entries", "code_limit", "compare_findings", "find_results",
           "figure_jobs", "PageDrawing", "page_jobs", "pattern_channels", "load_study", "plot_folder", "render_report", "report_pictures", "report_target", "save_figure", "scenario_sections", "screening",
           "static_axle_load", "studies_for", "summary", "verdicts_of", "write_report",
           "SWEEP_REPORT", "render_sweep_report", "write_sweep_report", "UQ_REPORT", "render_uq_report", "write_uq_report",
           "CHECK_REPORT", "check_files", "render_check_report", "write_check_report"]
