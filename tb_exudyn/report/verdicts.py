"""The report's verdict section: what an engineer reads first.

A one-line count per verdict (and how many are conditional); one sentence each on the target
probability and the estimate (:func:`terms_html`); one row per criterion (the location that decides
it) under a heading per part and limit set, the bridge's first (:func:`first_screen_groups`); a NOT
EVALUATED row with its reason in the row (:func:`reason_of`); each distinct caveat once as a numbered
note under the table (the rows carry the numbers), folded unless one could change a verdict
(:func:`notes_fold`); the table's own notes, and the full per-location table folded below. Numbers are shown by
the one display rule of the checks (:func:`tb_exudyn.results.checks_table.format_probability`,
:func:`~tb_exudyn.results.checks_table.format_value`: "< 1e-09" below SMALLEST_SHOWN, kN, mm,
m/s^2), the same as the terminal's. Without checks: the interim screening, labelled as not a verdict.
"""

from __future__ import annotations

import html
import math
from typing import Sequence

from ..plotting.data import channel_label
from ..results.checks import DEFAULT_TARGET_PROBABILITY, SET_ORDER
from ..results.checks_table import VERDICTS, Caveat, format_probability, format_value
from .entries import CheckEntry, Result, Verdicts, part_of, screening
from .sections import Raw, anchor, html_table, link, verdict_class

esc = html.escape

#: reading order of the rows: exceeding first, then undetermined, not evaluated, OK (other words after EXCEEDS)
_ORDER = {"EXCEEDS": 0, "UNDETERMINED": 2, "NOT EVALUATED": 3, "OK": 4}

#: what "conditional" means, said once (the verdict cells link here)
CONDITIONAL = ("a caveat that could change the verdict applies to the row (its note is marked "
               "\u201ccould change the verdict\u201d): the verdict holds only as far as that caveat allows")


class _Notes:
    """The distinct caveats, numbered in order of first use (1, 2, ...): a caveat's number is the
    same in every row and table of the section."""

    def __init__(self) -> None:
        self.items: list[Caveat] = []
        self._number: dict[tuple[str, bool, str], int] = {}

    def number(self, c: Caveat) -> int:
        key = (c.kind, c.changes_verdict, c.text)
        if key not in self._number:
            self.items.append(c)
            self._number[key] = len(self.items)
        return self._number[key]

    def html(self, start: int, list_id: str) -> str:
        """The notes from number ``start`` on, as an ordered list ("" if none)."""
        items = []
        for i, c in enumerate(self.items[start - 1:], start):
            flag = '<b class="conditional">could change the verdict</b> \u00b7 ' if c.changes_verdict else ""
            kind = f" <small><code>{esc(c.kind)}</code></small>" if c.kind else ""
            items.append(f'<li id="note-{i}">{flag}{esc(c.text)}{kind}</li>')
        return f'<ol class="notes" id="{list_id}" start="{start}">' + "".join(items) + "</ol>" if items else ""


def _where(channel: str, label: str, figure_ids: set[str]) -> str:
    """The readable label (linked to the channel's figure when the report has one), the name beside it."""
    target = anchor("fig", channel)
    text = link(target, label) if channel and target in figure_ids else esc(label)
    return text + (f" <small><code>{esc(channel)}</code></small>" if channel and channel != label else "")


def _cells(c: CheckEntry, notes: _Notes, figure_ids: set[str], mark_worst: bool = False,
           skip: Caveat | None = None) -> tuple:
    """location, estimate, limit, probability, verdict (conditional, grade) and the caveats' numbers
    (``skip``: a caveat the row shows itself); ``mark_worst``: say "worst" at the location that
    decides its criterion."""
    marks = []
    for cav in c.caveats:
        if cav == skip:
            continue
        n = notes.number(cav)
        cls = ' class="conditional"' if cav.changes_verdict else ""
        marks.append(f'<a href="#note-{n}"{cls}>{n}</a>')
    verdict = f'<span class="{verdict_class(c.verdict)}">{esc(c.verdict)}</span>'
    if c.conditional:
        verdict += ' <a class="conditional" href="#conditional">conditional</a>'
    if c.grade:
        verdict += f" <small>{esc(c.grade)}</small>"
    where = _where(c.channel, c.location, figure_ids) + (" <b>(worst)</b>" if mark_worst and c.decisive else "")
    return (Raw(where), format_value(c.estimate, c.unit), format_value(c.limit, c.unit), _utilisation_text(c),
            format_probability(c), Raw(verdict), Raw(",".join(marks)))


def count_text(rows: Sequence[CheckEntry]) -> str:
    """'68 OK, 112 EXCEEDS, 16 NOT EVALUATED; 180 conditional' (the verdicts in the order of
    VERDICTS, then any other word; the terminal summary's first line counts the same way)."""
    words = list(VERDICTS) + sorted({r.verdict for r in rows} - set(VERDICTS))
    counts = {w: sum(r.verdict == w for r in rows) for w in words}
    n_cond = sum(r.conditional for r in rows)
    return ", ".join(f"{counts[w]} {w}" for w in words if counts[w]) + (f"; {n_cond} conditional" if n_cond else "")


_HEAD = ["location", "estimate", "limit", "est. / limit", "P(exceed) per passage", "verdict", "notes"]
_CLASSES = ("", "num", "num", "num", "num", "", "notes")


def utilisation(c: CheckEntry) -> float | None:
    """|estimate| / |limit| of a row with both numbers finite and the limit not 0 (None otherwise)."""
    if not (math.isfinite(c.estimate) and math.isfinite(c.limit)) or c.limit == 0:
        return None
    return abs(c.estimate) / abs(c.limit)


def _utilisation_text(c: CheckEntry) -> str:
    u = utilisation(c)
    return "-" if u is None else f"{u:.2f}"

#: the first screen's parts, in reading order, and the words for the shipped limit sets
PARTS = {"bridge": "Bridge", "vehicle": "Vehicle"}
SET_WORDS = {"en1990_deck": "deck acceleration and twist", "ride_comfort": "ride comfort",
             "running_safety": "running safety"}


def first_screen_groups(top: Sequence[CheckEntry]) -> list[tuple[str, str, list[CheckEntry]]]:
    """The first table's rows as (part, limit set, rows): the bridge's first (deck acceleration,
    twist), then the vehicle's (ride comfort, running safety; the order of
    :data:`tb_exudyn.results.checks.SET_ORDER`, other sets after them by name); in a set, exceeding
    first, then undetermined, not evaluated, OK, each in the table's order."""
    groups: dict[tuple[str, str], list[CheckEntry]] = {}
    for r in top:
        groups.setdefault((part_of(r), r.limit_set), []).append(r)
    rank = {p: i for i, p in enumerate(PARTS)}
    keys = sorted(groups, key=lambda k: (rank[k[0]], SET_ORDER.index(k[1]) if k[1] in SET_ORDER else len(SET_ORDER), k[1]))
    return [(p, n, sorted(groups[(p, n)], key=lambda r: _ORDER.get(r.verdict, 1))) for p, n in keys]


def reason_of(c: CheckEntry) -> Caveat | None:
    """Why a NOT EVALUATED row is not evaluated: the model's reason (what the vehicle model cannot give
    and what to run instead), else the last statistic caveat (no such channel, no limit value)."""
    model = [cav for cav in c.caveats if cav.kind == "model"]
    stat = [cav for cav in c.caveats if cav.kind == "statistic"]
    return model[0] if model else stat[-1] if stat else None


def _part_verdict(rows: Sequence[CheckEntry]) -> str:
    """The verdict of a part: EXCEEDS if a row exceeds, else UNDETERMINED, else OK if a row is OK, else NOT
    EVALUATED; "conditional" when a row of that verdict is."""
    for word in ("EXCEEDS", "UNDETERMINED", "OK", "NOT EVALUATED"):
        same = [r for r in rows if r.verdict == word]
        if same:
            return word + (" (conditional)" if any(r.conditional for r in same) else "")
    return rows[0].verdict if rows else ""


def decision_html(verdicts: Verdicts, top: Sequence[CheckEntry]) -> str:
    """One line per part of the first screen: each limit set's verdict with its largest estimate / limit
    (the table's first row of the set shows where); the bridge's with the scope its verdict holds for (this train at this speed over the
    random irregularities; the code's speed series and trains are ``tb-exudyn check``'s)."""
    lines = []
    groups = first_screen_groups(top)
    for part in dict.fromkeys(p for p, _, _ in groups):
        sets = []
        for _, set_name, rows in (g for g in groups if g[0] == part):
            words = SET_WORDS.get(set_name, set_name.replace("_", " ")) or "criteria"
            worst = max((r for r in rows if utilisation(r) is not None), key=utilisation, default=None)
            text = f"{esc(words)} <b>{esc(_part_verdict(rows))}</b>"
            if worst is not None:
                text += f" (up to {utilisation(worst):.2f} of its limit)"
            elif rows and all(r.verdict == "NOT EVALUATED" for r in rows):
                text += f" ({len(rows)} criteria)"
            sets.append(text)
        line = f"<b>{esc(PARTS[part])}</b>: " + "; ".join(sets)
        if part == "bridge" and not verdicts.deterministic:
            speed = f" at {verdicts.speed_kmh:g} km/h" if verdicts.speed_kmh else ""
            check = f"tb-exudyn check {verdicts.bridge or 'BRIDGE'} --line-speed-kmh V"
            line += (f"; this train{speed} over random track irregularities only (code trains and speeds, EN 1991-2: "
                     f"<code>{esc(check)}</code>)")
        lines.append(line)
    return '<p class="counts" id="verdict-decision">' + "<br>".join(lines) + "</p>"


def terms_html(verdicts: Verdicts) -> str:
    """What the target probability and the estimate are, one sentence each."""
    t = verdicts.target
    if verdicts.deterministic:
        return ('<p class="terms" id="verdict-terms"><b>Estimate</b>: one deterministic run, so the estimate is the '
                "run's own statistic (its largest value) against the limit, with no probability of exceedance.</p>")
    why = ("once a year at 100 passages a day; not a code value"
           if t is not None and abs(t - DEFAULT_TARGET_PROBABILITY) <= 1e-12 else "a choice, not a code value")
    target = (f"<b>Target probability</b>{'' if t is None else f' {t:.3g}'} per passage ({esc(why)}): a criterion "
              "is met (OK) when the probability that its limit is exceeded at least once while the train passes is "
              "at most this.")
    estimate = ("<b>Estimate</b>: the level exceeded with the target probability in one passage (&le; limit exactly "
                "when OK), not max |mean| + 3 sigma; a Sperling index: its largest window value.")
    return f'<p class="terms" id="verdict-terms">{target}<br>{estimate}</p>'


def notes_fold(notes: _Notes, n_top: int) -> str:
    """The first table's numbered notes in a <details>: open when one of them could change a verdict,
    else folded under a line that counts them by kind (the first screen then ends with the table)."""
    if not n_top:
        return ""
    items = notes.items[:n_top]
    n_turn = sum(c.changes_verdict for c in items)
    kinds: dict[str, int] = {}
    for c in items:
        kinds[c.kind or "other"] = kinds.get(c.kind or "other", 0) + 1
    what = ", ".join(f"{k.replace('_', ' ')} {n}" for k, n in kinds.items())
    turn = (f'<b class="conditional">{n_turn} could change the verdict</b>' if n_turn else "none can change a verdict")
    return (f'<details id="verdict-notes-fold"{" open" if n_turn else ""}><summary>Notes 1-{n_top} on the rows: '
            f"{turn} <small>({esc(what)})</small></summary>{notes.html(1, 'verdict-notes')}</details>")


def _criterion(c: CheckEntry) -> str:
    return f'<span title="{esc(c.clause)}">{esc(c.criterion)}</span>' if c.clause else esc(c.criterion)


def _td(cell, cls: str) -> str:
    text = cell.html if isinstance(cell, Raw) else esc(str(cell))
    return f'<td class="{cls}">{text}</td>' if cls else f"<td>{text}</td>"


def _top_table(groups: list[tuple[str, str, list[CheckEntry]]], notes: _Notes, figure_ids: set[str],
               folded: bool) -> str:
    """The first table: a heading row per part and limit set with its counts, one row per criterion;
    a NOT EVALUATED row shows its reason in one line in place of location, estimate, limit and
    probability (one cell for the neighbouring rows with the same reason)."""
    head = ["criterion", "worst location" if folded else "location"] + _HEAD[1:]
    # the location rule, once in the header: with probabilities, a row's location is the criterion's most
    # probable exceedance (not always its largest estimate)
    if any(c.probability is not None for _, _, rows in groups for c in rows):
        head[1] += " (most likely to exceed)"
    out = ['<table id="verdicts-table"><thead><tr>' + "".join(f"<th>{esc(h)}</th>" for h in head) + "</tr></thead>"]
    for part, set_name, rows in groups:
        words = SET_WORDS.get(set_name, set_name.replace("_", " "))
        title = f"{PARTS[part]}: {words}" if words else PARTS[part]
        named = f" <small><code>{esc(set_name)}</code></small>" if set_name else ""
        out.append(f'<tbody><tr class="part"><th colspan="{len(head)}">{esc(title)}{named} '
                   f"<small>\u00b7 {esc(count_text(rows))}</small></th></tr>")
        i = 0
        while i < len(rows):
            c = rows[i]
            criterion = _criterion(c)
            reason = reason_of(c) if c.verdict == "NOT EVALUATED" else None
            if reason is None:
                cells = _cells(c, notes, figure_ids)
                out.append(f"<tr><td>{criterion}</td>" + "".join(_td(cell, cls) for cell, cls in zip(cells, _CLASSES)) + "</tr>")
                i += 1
                continue
            same = 1
            while (i + same < len(rows) and rows[i + same].verdict == "NOT EVALUATED"
                   and reason_of(rows[i + same]) == reason):
                same += 1
            for j, r in enumerate(rows[i:i + same]):
                crit = _criterion(r)
                cells = _cells(r, notes, figure_ids, skip=reason)
                span = f' rowspan="{same}"' if same > 1 else ""
                why = (f'<td class="reason" colspan="5"{span}>not evaluated: {esc(reason.text)}</td>' if j == 0 else "")
                out.append(f"<tr><td>{crit}</td>{why}{_td(cells[5], '')}{_td(cells[6], 'notes')}</tr>")
            i += same
        out.append("</tbody>")
    return "".join(out) + "</table>"


def checks_html(verdicts: Verdicts, figure_ids: set[str]) -> list[str]:
    """The verdict section's body from the checks (module docstring)."""
    rows = list(verdicts.rows)
    if not rows:
        return ['<p id="verdicts-table">No criterion of the limit files applies to the channels of this result.</p>'] + [
            f'<p class="meta">note: {esc(n)}</p>' for n in verdicts.notes]
    top = verdicts.decisive
    folded = len(top) < len(rows)  # some locations do not decide their criterion: the per-location tables
    counts = f"{len(rows)} checks of {len({r.criterion for r in rows})} criteria: {esc(count_text(rows))}"
    # the decision lines first; the counts of every location with the folded per-location tables
    out = [decision_html(verdicts, top)] if folded else [
        f'<p class="counts" id="verdict-counts"><b>{counts}</b></p>', decision_html(verdicts, top)]
    notes = _Notes()
    out.append(terms_html(verdicts))
    out.append(_top_table(first_screen_groups(top), notes, figure_ids, folded))
    if any(c.conditional for c in rows):
        out.append(f'<p class="meta" id="conditional"><span class="conditional">conditional</span>: {esc(CONDITIONAL)}.</p>')
    n_top = len(notes.items)
    out.append(notes_fold(notes, n_top))
    out += [f'<p class="meta">note: {esc(n)}</p>' for n in verdicts.notes]
    if folded:
        by_criterion: dict[str, list[CheckEntry]] = {c.criterion: [] for c in top}  # the table's order
        for r in rows:
            by_criterion.setdefault(r.criterion, []).append(r)
        parts = []
        for i, (criterion, group) in enumerate(by_criterion.items()):
            clause = f" <small>{esc(group[0].clause)}</small>" if group[0].clause else ""
            parts.append(f"<h4>{esc(criterion)}{clause}</h4>" + html_table(
                f"verdicts-locations-{i + 1}", _HEAD,
                [_cells(c, notes, figure_ids, mark_worst=True) for c in group], _CLASSES))
        out.append(f'<details id="verdicts-all"><summary id="verdict-counts">Every location: {counts}; the worst '
                   f"location per criterion (the table): {esc(count_text(top))}</summary>"
                   + "".join(parts) + notes.html(n_top + 1, "verdict-notes-more") + "</details>")
    return out


def screening_html(first: Result | None, k: float, figure_ids: set[str]) -> list[str]:
    """The interim screening of max |mean| + k sigma against the limits of :func:`code_limit`."""
    out = ['<p class="placeholder"><b>Verdicts: not computed.</b> The code checks (exceedance '
           "probabilities of the limits in models/limits) were not given to this report. Below: a "
           f"screening of max |mean| + {k:g} sigma against the interim limits, all "
           '<span class="check">[check]</span>, which is not a verdict (a Gaussian response exceeds '
           f"its {k:g}-sigma level in a sizeable share of passages).</p>"]
    if first is None:
        return out
    rows = []
    for s in screening(first, k):
        w = s.worst
        rows.append((s.criterion, Raw(_where(w.channel, channel_label(w.channel), figure_ids)),
                     format_value(w.peak, w.unit), Raw(f'{esc(format_value(w.limit.value, w.unit))} '
                                                      f'<span class="check">[check]</span>'),
                     Raw(f'<span class="{verdict_class(w.status)}">{esc(w.status)}</span>'),
                     f"{s.n_exceeding} of {s.n_locations}", Raw(f"<small>{esc(w.limit.source)}"
                                                                 f"{'; ' + esc(w.limit.note) if w.limit.note else ''}</small>")))
    head = ["criterion", "worst location", f"max |mean| + {k:g} sigma", "limit", "screening",
            "locations exceeding", "source"]
    out.append(html_table("verdicts-table", head, rows, ("", "", "num", "num", "", "num", "")) if rows
               else '<p id="verdicts-table">No channel of this result has a screening limit.</p>')
    return out


def verdicts_section(verdicts: Verdicts | None, first: Result | None, k: float, figure_ids: set[str]) -> str:
    """The verdicts from the checks, or "not computed" with the interim screening."""
    body = checks_html(verdicts, figure_ids) if verdicts is not None else screening_html(first, k, figure_ids)
    what = f" <small>({esc(verdicts.heading)})</small>" if verdicts is not None and verdicts.heading else ""
    return "\n".join([f'<section id="verdicts"><h2>Verdicts{what}</h2>', *body, "</section>"])


__all__ = ["CONDITIONAL", "PARTS", "SET_WORDS", "checks_html", "count_text", "decision_html", "first_screen_groups",
           "notes_fold", "reason_of", "screening_html", "terms_html", "utilisation", "verdicts_section"]
