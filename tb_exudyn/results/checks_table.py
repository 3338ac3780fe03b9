"""The rows of a code check and their table (what :func:`tb_exudyn.results.checks.checks` returns):
per criterion and location the estimate, the limit, the exceedance probability, the verdict and the
caveats that apply."""

from __future__ import annotations

import math
import textwrap
from dataclasses import asdict, dataclass, field
from typing import Any

from ..system.labels import display_unit, format_number
from .kinds import ResultKind

#: the verdicts a row can have
VERDICTS = ("OK", "EXCEEDS", "UNDETERMINED", "NOT EVALUATED")


@dataclass(frozen=True)
class Caveat:
    """Something that qualifies a verdict.

    kind : 'lightly_damped_mode', 'grid_error', 'loss_of_contact', 'linear_model', 'first_passage',
        'window', 'frequency_range', 'limit_unverified', 'limit_note' (the limits file's note), 'statistic', 'model'
    text : one line
    changes_verdict : True when it could turn the verdict (the row is then conditional)
    """

    kind: str
    text: str
    changes_verdict: bool


@dataclass(frozen=True)
class CheckRow:
    """One criterion at one location (channel).

    criterion : 'limit set/criterion id'; title, clause : the criterion's; channel, unit
    statistic : the criterion's statistic
    limit : the limit value for this scenario (speed band, static load), in the channel's unit (nan if
        it cannot be evaluated); limit_text : where it comes from
    estimate : the level exceeded with the target probability (random processes) or the index's largest
        window value (Sperling); estimate_text : what it is
    peak_3sigma : max over time of |mean| + 3 sigma (the 3-sigma rule, for comparison)
    probability : the probability of exceeding the limit in one passage (None: not a random process)
    interval : its confidence interval (Monte Carlo), or None
    probability_vanmarcke : PEM: the same by Vanmarcke's first passage, or None
    target : the target probability per passage
    verdict : 'OK', 'EXCEEDS', 'UNDETERMINED' or 'NOT EVALUATED'
    grade : for graded limits, the grade of the estimate ('' if none, 'beyond the last grade')
    caveats : what qualifies the verdict
    """

    criterion: str
    title: str
    clause: str
    channel: str
    unit: str
    statistic: str
    limit: float
    limit_text: str
    estimate: float
    estimate_text: str
    peak_3sigma: float
    probability: float | None
    interval: tuple[float, float] | None
    probability_vanmarcke: float | None
    target: float
    verdict: str
    grade: str = ""
    caveats: tuple[Caveat, ...] = ()

    @property
    def conditional(self) -> bool:
        """A verdict (OK or EXCEEDS, not NOT EVALUATED) that a caveat could turn."""
        return self.verdict != "NOT EVALUATED" and any(c.changes_verdict for c in self.caveats)

    @property
    def verdict_text(self) -> str:
        """The verdict, with 'conditional' when a caveat could turn it."""
        return f"{self.verdict} (conditional)" if self.conditional else self.verdict

    def as_dict(self) -> dict[str, Any]:
        """Plain data (JSON-ready)."""
        d = asdict(self)
        d["conditional"] = self.conditional
        d["verdict_text"] = self.verdict_text
        d["interval"] = None if self.interval is None else list(self.interval)
        return d


@dataclass(frozen=True)
class ChecksTable:
    """The checks of one result (module docstring).

    kind : what the result is (:class:`~tb_exudyn.results.kinds.ResultKind`; ``method`` its name); scenario : its
    name; speed_kmh : the train speed
    target : the target probability per passage; first_passage : the PEM first-passage method
    window : (t_start, t_end) [s] of the passage
    rows : per criterion and location
    notes : remarks on the whole table (target, criteria without channels, global caveats)
    """

    kind: ResultKind
    scenario: str
    speed_kmh: float
    target: float
    first_passage: str
    window: tuple[float, float]
    rows: tuple[CheckRow, ...]
    notes: tuple[str, ...] = field(default=())

    @property
    def method(self) -> str:
        """The name of the result's method ("pem", "monte_carlo", ..., "deterministic"), for display."""
        return self.kind.method

    def by_criterion(self) -> dict[str, list[CheckRow]]:
        out: dict[str, list[CheckRow]] = {}
        for r in self.rows:
            out.setdefault(r.criterion, []).append(r)
        return out

    def worst(self) -> list[CheckRow]:
        """Per criterion the location that decides it (highest probability, else the largest estimate /
        limit), in table order."""
        return [max(rows, key=_severity) for rows in self.by_criterion().values()]

    def counts(self) -> dict[str, int]:
        """Number of rows per verdict."""
        return {v: sum(r.verdict == v for r in self.rows) for v in VERDICTS}

    def as_dicts(self) -> list[dict[str, Any]]:
        """One plain dict per row (JSON-ready: the report's table data)."""
        return [r.as_dict() for r in self.rows]

    def to_dict(self) -> dict[str, Any]:
        """The whole table as plain data."""
        return {"method": self.method, "scenario": self.scenario, "speed_kmh": self.speed_kmh, "target": self.target,
                "first_passage": self.first_passage, "window": list(self.window), "notes": list(self.notes),
                "rows": self.as_dicts()}

    def text(self, worst_only: bool = False) -> str:
        """A plain-text table (``worst_only``: one row per criterion); caveats numbered below it."""
        rows = self.worst() if worst_only else list(self.rows)
        head = ["criterion", "location", "estimate", "limit", "P(exceed)/passage", "verdict"]
        caveats: list[str] = []
        table = []
        for r in rows:
            marks = []
            for c in r.caveats:
                line = f"[{c.kind}{', could change the verdict' if c.changes_verdict else ''}] {c.text}"
                if line not in caveats:
                    caveats.append(line)
                marks.append(str(caveats.index(line) + 1))
            p = format_probability(r)
            limit = format_value(r.limit, r.unit)
            est = format_value(r.estimate, r.unit, with_unit=False)
            verdict = r.verdict_text + (f" {r.grade}" if r.grade else "")
            table.append([r.criterion, r.channel, est, limit, p, verdict + (f" [{','.join(marks)}]" if marks else "")])
        widths = [max(len(h), *(len(row[i]) for row in table)) if table else len(h) for i, h in enumerate(head)]
        fmt = "  ".join(f"{{:<{w}}}" for w in widths)
        lines = [f"checks of {self.scenario} ({self.method}, {self.speed_kmh:g} km/h, passage "
                 f"{self.window[0]:.3g}-{self.window[1]:.4g} s, target P <= {self.target:.3g} per passage"
                 + (f", first passage: {self.first_passage}" if self.kind.gaussian else "") + ")",
                 fmt.format(*head)]
        lines += [fmt.format(*row) for row in table]
        lines += [f"  [{i + 1}] {c}" for i, c in enumerate(caveats)]
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)


def _severity(r: CheckRow) -> tuple[int, float, float]:
    """Which row decides a criterion: the verdict, then the probability as shown (3 digits: rows whose
    probabilities read the same, e.g. both 1, are not told apart by round-off), then estimate / limit."""
    rank = {"EXCEEDS": 3, "UNDETERMINED": 2, "OK": 1, "NOT EVALUATED": 0}[r.verdict]
    ratio = r.estimate / r.limit if math.isfinite(r.estimate) and r.limit and math.isfinite(r.limit) else -math.inf
    if r.probability is not None and math.isfinite(r.probability):
        return rank, float(f"{r.probability:.3g}"), ratio
    return rank, -math.inf, ratio


#: below this a displayed probability reads "< 1e-09": the Gaussian tail that far out says more about
#: the model than about the bridge (the value itself stays in the table's data)
SMALLEST_SHOWN = 1e-9


def format_value(x: float, si_unit: str, with_unit: bool = True) -> str:
    """An estimate or a limit in the channel's engineering display unit (kN, mm, m/s^2:
    :func:`tb_exudyn.system.labels.display_unit`), 4 significant digits; "-" when not finite."""
    if not math.isfinite(x):
        return "-"
    du = display_unit(si_unit)
    text = format_number(x * du.factor)
    return f"{text} {du.unit}".rstrip() if with_unit and du.unit not in ("", "-") else text


def format_probability(r: CheckRow) -> str:
    """The probability as the report and the terminal show it (3 digits, "< 1e-09" below
    SMALLEST_SHOWN, the interval when there is one)."""
    if r.probability is None:
        return "-"
    text = f"< {SMALLEST_SHOWN:.0e}" if r.probability < SMALLEST_SHOWN else f"{r.probability:.3g}"
    if r.interval is not None:
        text += f" [{r.interval[0]:.2g}, {r.interval[1]:.2g}]"
    return text


def wrapped_line(line: str, width: int) -> list[str]:
    """A terminal line wrapped at ``width``: the criteria not evaluated under their heading, any other line
    indented two more than it (a long location or note stays readable on an engineer's screen)."""
    if len(line) <= width:
        return [line]
    lead = len(line) - len(line.lstrip(" "))
    indent = 17 if line.startswith("  NOT EVALUATED  ") else lead + 2
    return textwrap.wrap(line, width, subsequent_indent=" " * indent, break_on_hyphens=False, break_long_words=False)


__all__ = ["SMALLEST_SHOWN", "Caveat", "CheckRow", "ChecksTable", "VERDICTS", "format_probability", "format_value",
           "wrapped_line"]
