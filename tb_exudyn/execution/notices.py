"""Notices: one-line messages about how a run goes (not errors; the run goes on).

A notice is a :class:`RunNotice` warning, so that a program can filter, record or raise it like any
warning; the command line prints every warning as one line (``tb-exudyn: warning: ...``).
"""

from __future__ import annotations

import warnings


class RunNotice(UserWarning):
    """How a run goes: a checkpoint file not used (and why), workers capped at the cores, a lock not
    available on this file system. One line, naming the file or the setting."""


def notice(message: str, stacklevel: int = 3) -> None:
    """Issue ``message`` (one line) as a :class:`RunNotice`."""
    warnings.warn(" ".join(message.split()), RunNotice, stacklevel=stacklevel)


__all__ = ["RunNotice", "notice"]
