"""PEM's checks before any run (the irregularities, the PSD channels), the PSD rows a result keeps
and the grid error's warning."""

from __future__ import annotations

import fnmatch
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ...errors import ScenarioError, SettingError
from ...results.checks import GRID_ERROR_TOLERANCE  # grid errors above it are warned about and reported
from ...scenario import Scenario
from ...system.labels import default_patterns
from ...track import get_spectrum
from ..grid_error import GridError
from ..reduction import ReductionPlan
from .columns import kind_and_unit

IntArray = NDArray[np.int64]


class GridErrorWarning(UserWarning):
    """The frequency grid changes a channel's max sigma by more than GRID_ERROR_TOLERANCE."""


GridErrorWarning.__module__ = "tb_exudyn.methods.pem"  # its public name (a sweep stores warnings' kinds by it)


def grid_error_messages(error: GridError, tolerance: float = GRID_ERROR_TOLERANCE) -> list[str]:
    """One line on the channels whose estimated grid error exceeds ``tolerance`` (empty if none)."""
    bad = error.exceeding(tolerance)
    if not bad:
        return []
    i = int(np.argmax(np.abs(error.rel_error_max_sigma)))
    return [f"the frequency grid is too coarse for {len(bad)} of {len(error.channels)} channels: their max sigma "
            f"changes by more than {100 * tolerance:g} % when the grid is refined (largest "
            f"{100 * error.rel_error_max_sigma[i]:+.2g} % on {error.channels[i]}; e.g. {', '.join(bad[:3])}); "
            "use analysis.freq_spacing = 'adaptive' or more frequencies (analysis.n_freq)"]


def prepare_sweep(scenario: Scenario) -> dict[str, Any]:
    """Checks before any run: irregularities present and modelled. Returns the spectra."""
    if not scenario.track.irregularities:
        raise ScenarioError(scenario.where, "track.irregularities", [], "at least one spectrum name", "no irregularity to analyse")
    spectra = {n: get_spectrum(n) for n in scenario.track.irregularities}
    for n in spectra:
        kind_and_unit(n, scenario.where)
    return spectra


def psd_rows(names: Sequence[str], psd_channels: str | Sequence[str]) -> list[int]:
    """Rows of ``names`` whose PSD map a result keeps: "key" (the key channels,
    :func:`tb_exudyn.system.labels.default_patterns`: those with checks and those of the reference
    study's figures), "all", or glob patterns."""
    if psd_channels == "all":
        return list(range(len(names)))
    pats = [p for _, group in default_patterns(names) for p in group] if psd_channels == "key" else (
        [psd_channels] if isinstance(psd_channels, str) else list(psd_channels))
    return [i for i, n in enumerate(names) if any(fnmatch.fnmatchcase(n, p) for p in pats)]


def psd_z_rows(plan: ReductionPlan, psd_rows: Sequence[int] | None) -> IntArray | None:
    """The z rows a task must keep PSD maps of for the result rows ``psd_rows`` (None: all rows, all
    z): a linear row's own z, a ratio's numerator and denominator (its cross term is kept for every
    ratio); Sperling rows have none. What :func:`~tb_exudyn.methods.reduction.finish_pem_task` reads, so a worker builds and
    sends only these maps."""
    if psd_rows is None:
        return None
    ratio_at = {int(r[0]): (int(r[1]), int(r[2])) for r in plan.ratios}
    z: set[int] = set()
    for r in psd_rows:
        if plan.result_z[int(r)] >= 0:
            z.add(int(plan.result_z[int(r)]))
        elif int(r) in ratio_at:
            z.update(ratio_at[int(r)])
    return np.array(sorted(z), dtype=np.int64)


def check_psd_channels(names: Sequence[str] | None, psd_channels: Any, where: str) -> None:
    """SettingError (``where``: the caller; key ``psd_channels``) for a ``psd_channels`` that is not
    "key", "all" or glob patterns each matching one of the result channels ``names`` (None: the form
    only)."""
    key = "psd_channels"
    allowed = "'key', 'all', or glob patterns of result channels (e.g. 'car1.body.*'; channels.txt lists them)"
    if psd_channels in ("key", "all"):
        return
    pats = [psd_channels] if isinstance(psd_channels, str) else psd_channels
    if not isinstance(pats, (list, tuple)) or not pats or not all(isinstance(p, str) and p.strip() for p in pats):
        raise SettingError(where, key, psd_channels, allowed)
    for p in pats if names is not None else ():
        if not any(fnmatch.fnmatchcase(n, p) for n in names):
            raise SettingError(where, key, p, allowed, "matches no channel")


__all__ = ["GridErrorWarning", "check_psd_channels", "grid_error_messages", "prepare_sweep", "psd_rows", "psd_z_rows"]
