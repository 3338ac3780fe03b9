"""The one error type a user's scenario data can raise."""

from __future__ import annotations

from typing import Any


class ScenarioError(ValueError):
    """A scenario, vehicle or bridge description is not valid.

    The message names the file, the key path, the value found and what is allowed, so that
    the command-line tool can print it as it is (no traceback) and the user can fix the file.
    """

    def __init__(self, file: str | None, key: str, value: Any, allowed: str, reason: str = ""):
        self.file = file or "<scenario>"
        self.key = key or "<top level>"
        self.value = value
        self.allowed = allowed
        self.reason = reason
        shown = _short_repr(value)
        text = f"{self.file}: key '{self.key}' = {shown}"
        if reason:
            text += f": {reason}"
        text += f" (allowed: {allowed})"
        super().__init__(text)


def _short_repr(value: Any, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."
