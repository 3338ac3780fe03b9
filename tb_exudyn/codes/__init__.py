"""Design codes: the EN 1991-2 dynamic analysis of railway bridges under trains of moving forces.

- :mod:`.en1991`: the code's tables and formulas as functions with their clause numbers (Table 6.6,
  eq. 6.13, Figures 6.9 / 6.10, Annex C, the speed series, the mode cut-off, the deck limits);
- :mod:`.trains`: HSLM-A1 ... A10 (Annex E) and real trains as axle loads (models/trains);
- :mod:`.moving_force`: the modal response to moving forces at all speeds in one integration;
- :mod:`.check`: :func:`check` -> :class:`CheckResult` (the table, ``to_csv``, the verdict);
- :mod:`.stochastic`: the stochastic column (``check(..., stochastic=True)``): the PEM of the track
  irregularity for trains given as vehicle models (the methods, so Exudyn, imported on use);
- the figure: :func:`tb_exudyn.plotting.plot_check` (``CheckResult.plot()``, matplotlib loaded on use).

Pure numpy/scipy, no Exudyn. What the check does clause by clause: docs/en1991.md.
"""

from . import en1991, stochastic
from .check import CHECK_CSV, CHECK_FIGURE, CHECK_PAGE, CheckResult, check
from .moving_force import MovingForceResponse, deck_stations, moving_force_response
from .trains import ForceTrain, hslm_a, list_trains, load_train, resolve_trains, train_names

__all__ = [
    "CHECK_CSV", "CHECK_FIGURE", "CHECK_PAGE", "CheckResult", "ForceTrain", "MovingForceResponse", "check", "deck_stations", "en1991",
    "hslm_a", "list_trains", "load_train", "moving_force_response", "resolve_trains", "stochastic", "train_names",
]
