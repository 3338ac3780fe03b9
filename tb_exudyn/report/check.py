"""The HTML page of an EN 1991-2 check (``tb-exudyn check``): one self-contained page beside check.csv.

Read top-down:

- the verdict: the deck acceleration limit met or exceeded, and what decides it: the train, speed, mass
  case and location of the largest peak deck acceleration, its value, the limit and the margin;
- what the check did: the bridge's construction type and damping, the mass cases, the modes up to the
  cut-off, the mesh, whether Figure 6.9 requires a dynamic analysis;
- per train: its speeds, its largest peak deck acceleration (at which speed and case), its largest
  phi'_dyn and its resonant speeds v_i = n0 D / i;
- the stochastic rows, where computed: per row the deterministic value, that value x (1 + k phi''), the
  vehicle model's mean, the level exceeded with the target probability and the probability of exceeding
  the limit in one passage, the deciding channel, the verdict and its caveats; then the PEM runs'
  warnings, each once;
- with interaction (``check(..., interaction=True)``): per train of vehicle models the largest mid-span peak
  as moving forces, with vehicle-bridge interaction and at zeta + Delta zeta (eq. 6.13), and the difference;
- the figure (peak deck acceleration against speed, the limit, the resonant speeds), when drawn;
- the whole table, folded.

The check is taken as a :class:`tb_exudyn.codes.check.CheckResult` (its records, read by attribute, the
table from their schema: :mod:`tb_exudyn.results.check_records`; and its settings); no
module of :mod:`tb_exudyn.methods` is imported. Every piece of text is escaped; the figure is embedded as
base64 PNG.
"""

from __future__ import annotations

import datetime as _dt
import html
import io
import math
from pathlib import Path
from typing import Any

from .._version import __version__
from ..atomic import write_text_atomic
from ..plotting.files import DPI
from ..results.check_records import table_cells
from ..results.checks_table import SMALLEST_SHOWN
from ..system.labels import format_number
from .sections import STYLE, _img, html_table, link

esc = html.escape

#: the check's page in its output folder, beside check.csv (the same names as tb_exudyn.codes.CHECK_PAGE,
#: CHECK_CSV and CHECK_FIGURE)
CHECK_REPORT = "check.html"
CHECK_TABLE = "check.csv"
CHECK_FIGURE = "check.png"


def _num(x: Any) -> str:
    return "" if x is None else format_number(float(x)) if isinstance(x, (int, float)) else str(x)


def _probability(p: Any) -> str:
    if p is None or not isinstance(p, (int, float)) or math.isnan(p):
        return "" if p is None else "not evaluated"
    return f"< {SMALLEST_SHOWN:g}" if p < SMALLEST_SHOWN else f"{p:.3g}"


def verdict_section(result: Any) -> str:
    """The verdict and what decides it (the row with the largest peak deck acceleration)."""
    r = result.deciding_row()
    margin = result.limit - r.value
    exceeded = result.verdict == "exceeds"
    word = "EXCEEDED" if exceeded else "met"
    rows = [["deciding train", r.train], ["speed", f"{_num(r.speed_kmh)} km/h"], ["mass case", r.case],
            ["location", r.location],
            ["peak deck acceleration", f"{r.value:.3f} m/s^2"],
            ["limit", f"{result.limit:g} m/s^2 ({result.track} track, EN 1990 A2.4.4.2.1)"],
            ["margin", f"{margin:+.3f} m/s^2 ({100 * margin / result.limit:+.1f} %)"]]
    n_exc = sum(x.verdict == "exceeds" for x in result.rows)
    return ('<section id="verdict"><h2>Verdict</h2>'
            f'<p class="{"warn" if exceeded else ""}"><b>Deck acceleration limit {esc(word)}</b>: '
            f"{esc(result.verdict_line())}" + (f" ({n_exc} of {len(result.rows)} rows exceed)" if n_exc else "")
            + "</p>" + html_table("check-verdict", ["", ""], rows) + "</section>")


def criteria_section(result: Any) -> str:
    """One line per EN 1990 A2.4.4 criterion (``result.criteria``): verdict, utilisation, value and limit, the
    deciding case, clause and caveats."""
    items = getattr(result, "criteria", ())
    if not items:
        return ""
    body = []
    for c in items:
        u = c.utilisation
        sign = ">=" if c.bound == "lower" else "<=" if c.bound == "upper" else "vs"
        body.append([c.criterion, c.verdict, "" if math.isnan(u) else f"{u:.2f}",
                     "" if math.isnan(c.value) else f"{c.value:.4g} {c.unit}",
                     "" if math.isnan(c.limit) else f"{sign} {c.limit:.4g} {c.unit}", c.case, c.location,
                     c.clause + (" [check]" if c.check else ""), c.caveats or "-"])
    exceeded = [c.criterion for c in items if c.verdict == "exceeds"]
    head = (f'<p class="warn"><b>Exceeded</b>: {esc(", ".join(exceeded))}</p>' if exceeded else
            "<p><b>Every evaluated criterion is met.</b></p>")
    return ('<section id="criteria"><h2>Criteria (EN 1990 A2.4.4)</h2>' + head
            + html_table("check-criteria", ["criterion", "verdict", "utilisation", "value", "limit", "deciding case",
                                            "location", "clause", "caveats"], body,
                         ["", "", "num", "num", "num", "", "", "", ""])
            + '<p class="meta">Static criteria: tb_exudyn/codes/deformation.py on the bridge\'s finite elements; '
              "limits and their sources: models/criteria/en1990_a2.toml; docs/en1991.md.</p></section>")


def settings_section(result: Any) -> str:
    req, why = result.dynamic_analysis
    bridge = result.bridge + (f" ({result.bridge_file})" if getattr(result, "bridge_file", "") else "")
    rows = [["bridge", bridge], ["line speed", f"{_num(result.line_speed_kmh)} km/h (speeds up to 1.2 x)"],
            ["construction", f"{result.construction.replace('_', ' ')} ({result.construction_basis})"],
            ["damping", result.damping_basis], ["mass cases", ", ".join(result.cases)],
            ["modes", f"{len(result.mode_frequencies)} up to {result.cutoff_hz:.3g} Hz ({result.cutoff_basis}), at the "
                      "track line (torsion included)"],
            ["mesh", result.mesh_basis],
            ["Figure 6.9", f"dynamic analysis {'required' if req else 'not required'}: {why}"],
            ["run time", f"{result.seconds:.1f} s"]]
    return '<section id="settings"><h2>What the check did</h2>' + html_table("check-settings", ["", ""], rows) + \
        '<p class="meta">Clause by clause, with what was not read in the code text marked [check]: docs/en1991.md.</p>' \
        "</section>"


def trains_section(result: Any) -> str:
    body = []
    for name in result.trains():
        rows = [r for r in result.rows if r.train == name]
        top = max(rows, key=lambda r: r.value)
        body.append([name, str(len(rows)), f"{top.value:.3f}", _num(top.speed_kmh), top.case,
                     top.location, f"{max(r.phi_dyn for r in rows):.3f}",
                     ", ".join(f"{v:.0f}" for v in result.resonant_speeds_kmh.get(name, ()))])
    return ('<section id="trains"><h2>Trains</h2>'
            + html_table("check-trains", ["train", "rows", "max deck acc [m/s^2]", "at [km/h]", "case", "location",
                                          "max phi'_dyn", "v_i = n0 D / i [km/h]"], body,
                         ["", "num", "num", "num", "", "", "num", ""]) + "</section>")


def stochastic_section(result: Any) -> str:
    rows = [r for r in result.rows if r.stochastic is not None]
    out = ['<section id="stochastic"><h2>Stochastic rows</h2>']
    if not rows:
        out.append("<p>Not computed (tb-exudyn check --stochastic: the PEM of the track irregularity for the trains "
                   "given as vehicle models).</p></section>")
        return "\n".join(out)
    out.append(f'<p class="meta">{esc(result.stochastic_basis)}. The check\'s verdict above is the code\'s '
               "deterministic one; these rows add the probability of exceeding the limit in one passage with the "
               "random track irregularity on top of the vehicle model's mean.</p>")
    body = [[r.train, _num(r.speed_kmh), f"{r.value:.3f}", f"{r.value_with_phi2:.3f}",
             f"{s.mean_acc:.3f}", f"{s.level_at_target:.3f}", _probability(s.p_exceed),
             s.location, s.verdict, s.caveats or "-"] for r in rows if (s := r.stochastic) is not None]
    target = result.target_probability
    out.append(html_table("check-stochastic", [
        "train", "speed [km/h]", "det. max [m/s^2]", "det. x (1 + k phi'') [m/s^2]", "mean (vehicle model) [m/s^2]",
        f"level at P = {target:.3g} [m/s^2]" if target else "level at target [m/s^2]",
        f"P(|a| > {result.limit:g}) per passage", "location", "verdict", "caveats"], body,
        ["", "num", "num", "num", "num", "num", "num", "", "", ""]))
    if result.warnings:
        out.append(f"<h3>Warnings of the PEM runs ({len(result.warnings)})</h3>")
        out += [f'<p class="warn">{esc(w)}</p>' for w in result.warnings]
    out.append("</section>")
    return "\n".join(out)


def interaction_section(result: Any) -> str:
    """The interaction rows (tb_exudyn.codes.interaction.InteractionComparison), '' where not computed."""
    rows = getattr(result, "interaction", ())
    if not rows:
        return ""
    body = [[c.train, _num(c.speed_kmh), c.case, f"{100 * c.damping_ratio:.3g}", f"{c.max_moving_force:.3f}",
             f"{c.max_interaction:.3f}", f"{c.difference:+.3f}", f"{-100 * c.reduction:+.1f}",
             f"{c.max_moving_force_dz:.3f}", f"{100 * c.additional_damping:.3g}"] for c in rows]
    return ('<section id="interaction"><h2>Interaction</h2><p class="meta">Per train given as vehicle models, at the '
            "speed of its largest mid-span peak: that peak as moving forces, with vehicle-bridge interaction (the "
            "deterministic run of the vehicle models, smooth track: the mean response) and as moving forces at zeta "
            "+ Delta zeta (EN 1991-2 eq. 6.13), on the same modes. The check's verdict above is the moving forces'."
            "</p>" + html_table("check-interaction", [
                "train", "speed [km/h]", "case", "zeta [%]", "moving forces [m/s^2]", "interaction [m/s^2]",
                "difference [m/s^2]", "difference [%]", "zeta + Delta zeta [m/s^2]", "Delta zeta [%]"], body,
                ["", "num", "", "num", "num", "num", "num", "num", "num", "num"]) + "</section>")


def table_section(result: Any) -> str:
    columns, cells = table_cells(result.rows)
    body = [[_num(x) if isinstance(x, float) else ("" if x is None else str(x)) for x in row] for row in cells]
    return ('<section id="table"><h2>The table</h2>'
            f"<details><summary>All {len(result.rows)} rows ({len(columns)} columns, as check.csv)</summary>"
            + html_table("check-table", columns, body) + "</details></section>")


def render_check_report(result: Any, figure_png: bytes | None = None) -> str:
    """The HTML text of the page on ``result`` (a CheckResult; see the module docstring); ``figure_png``:
    the check's figure as PNG bytes, or None (not drawn)."""
    title = f"tb_exudyn EN 1991-2 check: {result.bridge}, line speed {_num(result.line_speed_kmh)} km/h"
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    nav = [("criteria", "Criteria"), ("verdict", "Verdict"), ("settings", "What the check did"), ("trains", "Trains"),
           ("stochastic", "Stochastic rows"), ("figure", "Figure"), ("table", "The table")]
    if getattr(result, "interaction", ()):
        nav.insert(5, ("interaction", "Interaction"))
    figure = ('<section id="figure"><h2>Figure</h2>'
              + (_img(figure_png, "peak deck acceleration against speed") if figure_png else
                 "<p>Not drawn (--no-figures).</p>") + "</section>")
    body = [f"<h1>{esc(title)}</h1>",
            f'<p class="meta">{esc(", ".join(result.trains()))}; {len(result.rows)} rows. Generated {esc(now)} by '
            f"tb_exudyn {esc(__version__)}.</p>",
            "<nav>" + " | ".join(link(a, t) for a, t in nav) + "</nav>",
            criteria_section(result), verdict_section(result), settings_section(result), trains_section(result), stochastic_section(result),
            interaction_section(result), figure, table_section(result)]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"viewport\" content=\"width=device-width\"><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def check_files(result: Any, figure: Any = None) -> dict[str, bytes]:
    """Every file of a check, rendered in memory (nothing is written): ``check.csv`` (the table),
    ``check.png`` (``figure``, a matplotlib figure, when given) and ``check.html`` (this page, the figure
    embedded), by name in that order; the command writes them as one (tb_exudyn.files.write_output)."""
    out = {CHECK_TABLE: result.csv_text().encode("utf-8")}
    png = None
    if figure is not None:
        buf = io.BytesIO()
        figure.savefig(buf, format="png", dpi=DPI)
        png = out[CHECK_FIGURE] = buf.getvalue()
    out[CHECK_REPORT] = render_check_report(result, png).encode("utf-8")
    return out


def write_check_report(result: Any, folder: str | Path, figure_png: bytes | None = None) -> Path:
    """Write :func:`render_check_report` to ``folder/check.html``, atomically."""
    out = Path(folder) / CHECK_REPORT
    write_text_atomic(out, render_check_report(result, figure_png))
    return out


__all__ = ["CHECK_FIGURE", "CHECK_REPORT", "CHECK_TABLE", "check_files", "criteria_section", "render_check_report",
           "write_check_report"]
