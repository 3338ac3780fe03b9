"""The EN 1990 Annex A2 (A2.4.4) deformation and comfort criteria as data, and the record of a verdict.

The criteria live in ``models/criteria/en1990_a2.toml`` (one ``[[criteria]]`` table each: clause, source, load
model, loaded tracks, quantity, where it is read, ``bound`` upper or lower, unit, and the limit); this module
reads and checks that file (:func:`load_criteria`, a ScenarioError naming the file and key for anything
invalid). A criterion is the one :class:`tb_exudyn.scenario.limits.Criterion` of every limit file, here a
structural one (a ``bound``, a ``unit``, the load model and where it is read; no statistic of a result),
with the limit kinds of :mod:`tb_exudyn.scenario.limits` (a ratio of the span, ``span_ratio``: L/600; the
comfort figure, ``comfort_figure``: Figure A2.3 by speed and span). No limit lives in Python code. The deck acceleration's criterion has one source too: models/limits/
en1990_deck.toml (:func:`deck_acceleration_limit`), read by the moving-force rows and the stochastic column.

A :class:`CriterionVerdict` is one line of the check's verdict per criterion: value, limit, utilisation
(value / limit for an upper bound, limit / value for a lower one), the deciding case and location, the
verdict and its caveats.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..errors import SettingError
from ..results.checks import default_limits
from ..results.checks_table import format_value
from ..scenario.limits import ComfortFigureLimit, Criterion, LimitSet, SpanRatioLimit, limits_from_dict
from ..scenario.registry import models_dir
from ..scenario.schema import set_source_file
from ..scenario.toml_io import read_toml

#: the criteria file's stem in models/criteria/
CRITERIA_FILE = "en1990_a2"
#: the deck limits' file and, per track form, its criterion (models/limits/en1990_deck.toml)
DECK_LIMIT_SET = "en1990_deck"
DECK_ACCELERATION_CRITERIA: dict[str, str] = {"ballasted": "deck_acc_ballasted", "direct": "deck_acc_direct_fastened"}



def deck_criterion(track: str) -> str:
    """The deck acceleration criterion of a track form as the records name it: 'en1990_deck/deck_acc_ballasted'."""
    return f"{DECK_LIMIT_SET}/{DECK_ACCELERATION_CRITERIA[track]}"


def moving_force_load_model(train: str) -> str:
    """The load model of a moving-force row of ``train``: HSLM-A or HSLM-B (EN 1991-2 6.4.6.1.1, Annex E), or a
    real train's axle loads."""
    for name in ("HSLM-A", "HSLM-B"):
        if train.startswith(name):
            return f"{name} as moving forces (EN 1991-2 6.4.6.1.1)"
    return "real train as moving forces (its axle loads)"


VERDICT_OK, VERDICT_EXCEEDS, VERDICT_NOT_EVALUATED, VERDICT_INFO = "ok", "exceeds", "not evaluated", "comparison"


def criteria_path() -> Path:
    """models/criteria/en1990_a2.toml of the model library (``$TB_EXUDYN_MODELS``), or the package's own
    when that library has no criteria/ folder."""
    own = models_dir() / "criteria" / f"{CRITERIA_FILE}.toml"
    if own.exists():
        return own
    return Path(__file__).resolve().parent.parent.parent / "models" / "criteria" / f"{CRITERIA_FILE}.toml"


def load_criteria(path: str | Path | None = None) -> LimitSet:
    """Read and check the criteria file (default :func:`criteria_path`): a LimitSet of structural criteria
    (:class:`~tb_exudyn.scenario.limits.Criterion` with a ``bound`` and no ``statistic``, computed by the check
    on the bridge, not on a result); ScenarioError names file and key."""
    p = Path(path) if path is not None else criteria_path()
    return set_source_file(limits_from_dict(read_toml(p), str(p), structural=True), str(p))


def deck_acceleration_limit(track: str) -> float:
    """The peak deck acceleration limit [m/s^2] of a track form, read from its one source: the criterion
    :data:`DECK_ACCELERATION_CRITERIA` of the limit file ``en1990_deck`` (EN 1990 A2.4.4.2.1(4)P: 3.5
    ballasted, 5.0 direct fastening, recommended values)."""
    if track not in DECK_ACCELERATION_CRITERIA:
        raise SettingError("deck_acceleration_limit", "track", track, " or ".join(DECK_ACCELERATION_CRITERIA))
    sets = {ls.name: ls for ls in default_limits()}
    found = sets.get(DECK_LIMIT_SET)
    crit = None if found is None else next((c for c in found.criteria if c.id == DECK_ACCELERATION_CRITERIA[track]), None)
    if crit is None or crit.limit.kind != "fixed":
        raise SettingError("check", "limits", sorted(sets), f"a limit file {DECK_LIMIT_SET!r} with a fixed criterion "
                           f"{DECK_ACCELERATION_CRITERIA[track]!r} (models/limits/en1990_deck.toml)",
                           "the deck acceleration criterion is missing")
    return float(crit.limit_value())


@dataclass(frozen=True)
class CriterionVerdict:
    """The verdict of one criterion: ``value`` against ``limit`` (both in ``unit``), ``utilisation`` (value /
    limit for an upper bound, limit / value for a lower one; NaN when not evaluated), the deciding case and
    location, and why it could not be evaluated or what it leaves out (``caveats``). ``bound`` 'compare': a
    ratio that is no limit (its verdict is 'comparison', never 'exceeds')."""

    criterion: str
    title: str
    clause: str
    load_model: str
    value: float
    limit: float
    unit: str
    bound: str
    case: str
    location: str
    caveats: str = ""
    check: bool = False

    @property
    def utilisation(self) -> float:
        if not (math.isfinite(self.value) and math.isfinite(self.limit)):
            return math.nan
        if self.bound == "lower":
            return self.limit / self.value if self.value > 0 else math.inf
        return self.value / self.limit if self.limit > 0 else math.inf

    @property
    def verdict(self) -> str:
        u = self.utilisation
        if math.isnan(u):
            return VERDICT_NOT_EVALUATED
        if self.bound == "compare":
            return VERDICT_INFO
        return VERDICT_OK if u <= 1.0 else VERDICT_EXCEEDS

    @property
    def short_clause(self) -> str:
        """The clause as the terminal names it: 'EN 1990 Annex A2, A2.4.4.2.3(2) (limits left ...)' -> 'A2.4.4.2.3(2)'
        (the terminal's block is headed EN 1990 A2.4.4; the full clause is in the report)."""
        text = self.clause.replace("EN 1990 Annex A2, ", "").replace(":2003", "")
        return text.split(";")[0].split(" (")[0]

    def shown(self, x: float) -> str:
        """A value or limit in the project's display units (:func:`tb_exudyn.results.checks_table.format_value`:
        mm for deflections and twists, mrad for rotations); a radius (a lower bound in m) in whole metres."""
        if self.unit == "m" and self.bound == "lower" and math.isfinite(x):
            return f"{x:.0f} m"
        return format_value(x, self.unit)

    def line(self) -> str:
        """One line: criterion, verdict, utilisation, value against limit, deciding case, clause. The caveats,
        the full load and the full clause are in the report (tb_exudyn.report.check)."""
        name = self.criterion.split(" (")[0]
        if self.verdict == VERDICT_NOT_EVALUATED:
            return f"{name}: not evaluated ({self.caveats.split('; ')[0]}) [{self.short_clause}]"
        if self.verdict == VERDICT_INFO:
            return (f"{name}: ratio {self.value:.2f}, a comparison: {self.caveats.split('; ')[0]}; {self.case} "
                    f"[{self.short_clause}]"
                    + (" [check]" if self.check else ""))
        sign = ">=" if self.bound == "lower" else "<="
        state = "EXCEEDED" if self.verdict == VERDICT_EXCEEDS else "met"
        return (f"{name}: {state}, utilisation {self.utilisation:.2f} ({self.shown(self.value)} {sign} "
                f"{self.shown(self.limit)}), {self.case}, {self.location} [{self.short_clause}]"
                + (" [check]" if self.check else ""))


__all__ = ["ComfortFigureLimit", "Criterion", "CriterionVerdict", "DECK_ACCELERATION_CRITERIA", "DECK_LIMIT_SET",
           "SpanRatioLimit", "criteria_path", "deck_acceleration_limit", "deck_criterion", "load_criteria",
           "moving_force_load_model"]
