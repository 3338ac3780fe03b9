"""The error a user's scenario data can raise (part of the hierarchy in :mod:`tb_exudyn.errors`)."""

from __future__ import annotations

from typing import Any

from ..errors import UserError, format_message, short_repr


class ScenarioError(UserError, ValueError):
    """A scenario, vehicle or bridge description is not valid.

    The message names the file, the key path, the value found and what is allowed, so that
    the command-line tool can print it as it is (no traceback) and the user can fix the file.
    Picklable (a worker's ScenarioError reaches the parent intact).
    """

    def __init__(self, file: str | None, key: str, value: Any, allowed: str, reason: str = ""):
        self.file = file or "<scenario>"
        self.key = key or "<top level>"
        self.value = value
        self.allowed = allowed
        self.reason = reason
        super().__init__(format_message(self.file, self.key, value, allowed, reason))


_short_repr = short_repr
