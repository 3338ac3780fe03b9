"""Result types and their files: TimeHistory (one run), RandomResponse (PEM, Monte Carlo).

Every result is a folder with ``arrays.npz`` (never unpickled) and ``meta.json`` (whose ``format``
names the type), written whole or not at all and read defensively (:mod:`tb_exudyn.storage`);
:func:`load_results` reads any of them. Each type's arrays are declared once (:mod:`.schema`: the npz
members, ``result.to_xarray()`` and the NetCDF export); a speed sweep is :class:`.sweep.SweepResult`.
:mod:`.compare` compares a PEM result with a Monte Carlo one.
"""

from __future__ import annotations

from .folders import Result, find_results, load_results
from .random_response import RandomResponse, load_random_response
from .time_history import TimeHistory, load_time_history

__all__ = ["RandomResponse", "Result", "TimeHistory", "find_results", "load_random_response", "load_results",
           "load_time_history"]
