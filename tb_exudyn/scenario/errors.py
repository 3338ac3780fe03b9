"""The error a user's scenario data can raise (defined with the whole hierarchy in :mod:`tb_exudyn.errors`)."""

from __future__ import annotations

from ..errors import ScenarioError, short_repr

_short_repr = short_repr

__all__ = ["ScenarioError"]
