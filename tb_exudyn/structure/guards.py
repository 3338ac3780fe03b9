"""A scenario's sizes checked before any work: the run's length, the bridge's model, the train-bridge
system (each refused with one line naming the file and the key to change).

:func:`check_scenario_size` is what the command line runs first (``run``, ``modes``), before the output
folder is made or anything is built; the library checks the same again where it builds
(:func:`~.fe.bridge_modes`, ``build_model``), with the exact number of bridge modes.
"""

from __future__ import annotations

from typing import Any

from ..execution.resources import check_run_length, check_system_size
from .assembly import StructureError, located, validate_bridge
from .fe import bridge_modes, solve_modes
from .imported import imported_modal_bridge
from ..scenario.model import ModalTable
from ..scenario.track_structure import refuse_unbuilt_track
from .size import check_bridge_size


def check_scenario_size(scenario: Any) -> None:
    """Refuse a scenario too large to run or to hold on this machine, before anything is built: its
    bridge's data (:func:`~.assembly.validate_bridge`), its crossing's steps
    (:func:`~tb_exudyn.execution.resources.check_run_length`), its bridge's model
    (:func:`~.size.check_bridge_size`; bridge errors located in the scenario's or the bridge's file), its
    linearised system with the bridge's estimated modes
    (:func:`~tb_exudyn.execution.resources.check_system_size`). A small bridge (no count needed) is
    solved at once, so that a degenerate one (:class:`~.assembly.StructureError`) is refused here."""
    refuse_unbuilt_track(scenario)
    an = scenario.analysis
    if isinstance(scenario.bridge, ModalTable):  # its tables read and checked now (their size is the model's)
        try:
            n_modes = imported_modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes).n_modes
        except StructureError as exc:
            raise located(exc, scenario) from None
        check_run_length(scenario)
        check_system_size(scenario, n_modes)
        return
    try:
        validate_bridge(scenario.bridge)  # its data first (a span of 1e9 m is no bridge, not a long run)
    except StructureError as exc:
        raise located(exc, scenario) from None
    check_run_length(scenario)
    try:
        size = check_bridge_size(scenario.bridge, an.mode_max_frequency, an.max_modes, solve_modes)
        # a small bridge (no count made) is solved now, at most milliseconds: a degenerate one is refused
        # here too, and the system's check has its exact modes
        n_modes = bridge_modes(scenario.bridge, an.mode_max_frequency, an.max_modes).n_modes if size.upper \
            else size.n_modes
    except StructureError as exc:
        raise located(exc, scenario) from None
    check_system_size(scenario, n_modes)


__all__ = ["check_scenario_size"]
