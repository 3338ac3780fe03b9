"""Published studies a scenario reproduces, with their stated findings, as data
(models/studies/NAME.toml): the report puts them beside our results."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from .model import Scenario
from .registry import models_dir
from .schema import Context, Validated, from_dict, param
from .toml_io import read_toml

Measure = Literal["psd_peak_frequency", "psd_band_99", "sigma_to_mean_ratio", "band_across_zero_share"]
MEASURES: dict[str, tuple[str, str]] = {  # measure -> (unit, description)
    "psd_peak_frequency": ("Hz", "frequency of the PSD map's peak"),
    "psd_band_99": ("Hz", "band holding 99 % of sigma^2 at max sigma"),
    "sigma_to_mean_ratio": ("", "3 max sigma / max |mean|"),
    "band_across_zero_share": ("", "share of the crossing with the 3-sigma band across zero"),
}


@dataclass(frozen=True, kw_only=True)
class StudyQuantity(Validated):
    """A quantity a finding is read by: what the study says and how we judge agreement."""

    channel: str = param(doc="the channel (tb_exudyn naming)")
    measure: Measure = param(doc="how the quantity is computed from a result (see MEASURES)")
    study: float = param(math.nan, doc="the value the study states, in the measure's unit (nan: none)")
    study_range: tuple[float, ...] = param((), doc="the range the study states [low, high]")
    study_text: str = param("", doc="the study's words, for a qualitative statement")
    tolerance: float = param(math.nan, doc="agreement if |ours - study| <= tolerance (nan: no such rule)")
    agree_below: float = param(math.nan, doc="agreement if ours < agree_below")
    agree_above: float = param(math.nan, doc="agreement if ours > agree_above")
    basis: str = param("", doc="where the agreement rule comes from ([check]: our reading)")

    def _validate(self, ctx: Context) -> None:
        if self.study_range and len(self.study_range) != 2:
            raise ctx.child("study_range").error(list(self.study_range), "[low, high]", "not two numbers")
        rules = [n for n in ("tolerance", "agree_below", "agree_above") if not math.isnan(getattr(self, n))]
        if len(rules) > 1:
            raise ctx.child(rules[1]).error(getattr(self, rules[1]), f"at most one rule (already {rules[0]})",
                                            "two agreement rules")
        if "tolerance" in rules and math.isnan(self.study):
            raise ctx.child("study").error("<missing>", "a number (tolerance needs the study's value)", "missing key")


@dataclass(frozen=True, kw_only=True)
class StudyFinding(Validated):
    """One finding the study states, with the quantities it is read by."""

    id: str = param(doc="short name (conclusion or figure)")
    claim: str = param(doc="the study's statement")
    where: str = param("", doc="section or figure of the study")
    quantities: tuple[StudyQuantity, ...] = param((), doc="the quantities compared")
    explained: str = param("", doc="where our own findings explain the comparison, e.g. 'docs/findings.md section 1' "
                                   "(the report links a row not matched to it)")


@dataclass(frozen=True, kw_only=True)
class Study(Validated):
    """A published study a scenario reproduces, with its stated findings (models/studies/NAME.toml)."""

    name: str = param(doc="identifier")
    title: str = param(doc="author and title")
    source: str = param("", doc="citation")
    scenarios: tuple[str, ...] = param((), doc="the scenarios that reproduce it")
    findings: tuple[StudyFinding, ...] = param((), doc="the stated findings")


def studies_dir() -> Path:
    """models/studies (beside vehicles/, bridges/, scenarios/)."""
    return models_dir() / "studies"


def load_study(path: str | Path) -> Study:
    """Read a study file; a bad file gets a one-line ScenarioError naming the file and the key."""
    path = Path(path)
    return from_dict(Study, read_toml(path), Context(str(path)))


def studies_for(scenario: Scenario | None) -> list[Study]:
    """The studies whose ``scenarios`` list the scenario's name."""
    if scenario is None:
        return []
    folder = studies_dir()
    files = sorted(folder.glob("*.toml")) if folder.is_dir() else []
    return [s for s in map(load_study, files) if scenario.name in s.scenarios]


__all__ = ["MEASURES", "Measure", "Study", "StudyFinding", "StudyQuantity", "load_study", "studies_dir", "studies_for"]
