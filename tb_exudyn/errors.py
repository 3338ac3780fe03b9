"""The error types of tb_exudyn: one hierarchy, every class picklable.

    TbExudynError                 anything tb_exudyn raises on purpose
    ├── UserError                 the user can fix it: the CLI prints the one-line message, exit 2
    │   ├── ScenarioError         a scenario, vehicle, bridge or limit file (or its dataclass) is not valid
    │   ├── SpectrumError         a spectrum name, band or user spectrum table is not valid (tb_exudyn.track)
    │   ├── SettingError          an argument of a Python call or a command-line option is not allowed
    │   ├── CapabilityError       the chosen engine or method cannot do what was asked
    │   ├── CheckpointError       a checkpoint folder belongs to another computation or is damaged
    │   ├── ResultsError          a results folder cannot be read (missing, foreign, damaged, hostile)
    │   ├── ComparisonError       two results cannot be compared
    │   ├── OutputFolderError     the output folder cannot be created or written (also an OSError)
    │   └── ResourceError         the request does not fit this machine (memory, steps, workers)
    └── SimulationIncomplete      an integration stopped before its end time (also a RuntimeError)

User errors cross process boundaries intact: a worker's error is pickled and raised again in the
parent with the same message, so the CLI prints the same line and exits 2 whatever the number of
workers. Exceptions pickle as ``cls(*self.args)``; classes whose constructor takes other arguments
define ``__reduce__`` (see :class:`UserError`).
"""

from __future__ import annotations

from typing import Any


class TbExudynError(Exception):
    """Base of every error tb_exudyn raises on purpose."""


class UserError(TbExudynError):
    """An error the user can fix; its message is one line naming where (a file, ``command line``
    with the option, or a function argument), the key, the value found and what is allowed.

    Construct either from a finished message (``UserError("...")``) or from its parts with
    :meth:`from_parts`.
    """

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (type(self), self.message, dict(self.__dict__)))

    def __str__(self) -> str:
        return self.message

    @classmethod
    def from_parts(cls, where: str, key: str, value: Any, allowed: str, reason: str = "") -> "UserError":
        return cls(format_message(where, key, value, allowed, reason))


def _rebuild(cls: type, message: str, state: dict[str, Any]) -> "UserError":
    err = cls.__new__(cls)
    Exception.__init__(err, message)
    err.__dict__.update(state)
    return err


def format_message(where: str, key: str, value: Any, allowed: str, reason: str = "") -> str:
    """``WHERE: key 'KEY' = VALUE: REASON (allowed: ALLOWED)`` on one line."""
    text = f"{where}: key '{key or '<top level>'}' = {short_repr(value)}"
    if reason:
        text += f": {reason}"
    return text + f" (allowed: {allowed})"


def short_repr(value: Any, limit: int = 80) -> str:
    """repr of a value, cut to ``limit`` characters and to one line."""
    text = repr(value).replace("\n", "\\n")
    return text if len(text) <= limit else text[: limit - 3] + "..."


class ScenarioError(UserError, ValueError):
    """A scenario, vehicle, bridge or limit description is not valid.

    The message names the file, the key path, the value found and what is allowed, so that
    the command-line tool can print it as it is (no traceback) and the user can fix the file.
    """

    def __init__(self, file: str | None, key: str, value: Any, allowed: str, reason: str = ""):
        self.file = file or "<scenario>"
        self.key = key or "<top level>"
        self.value = value
        self.allowed = allowed
        self.reason = reason
        super().__init__(format_message(self.file, self.key, value, allowed, reason))


class SettingError(UserError, ValueError):
    """A function argument or a command-line option is not allowed.

    ``where`` is e.g. ``"command line"`` (key: the option, ``--workers``) or ``"run_pem"`` (key: the
    argument name).
    """

    def __init__(self, where: str, key: str, value: Any, allowed: str, reason: str = "") -> None:
        super().__init__(format_message(where, key, value, allowed, reason))
        self.where, self.key, self.value, self.allowed, self.reason = where, key, value, allowed, reason


class CapabilityError(SettingError):
    """The chosen engine (or method) cannot do what was asked, e.g. a static linearisation on an
    engine that runs the pseudo-excitations from rest."""


class CheckpointError(UserError, ValueError):
    """A checkpoint folder belongs to another computation, or one of its files is damaged."""


class ResultsError(UserError, ValueError):
    """A results folder cannot be read: missing, of another format, damaged or hostile."""


class ComparisonError(UserError, ValueError):
    """Two results cannot be compared."""


class OutputFolderError(UserError, OSError):
    """The output folder cannot be created or written, or holds another run's files."""


class ResourceError(UserError, ValueError):
    """The request does not fit this machine: the message gives the estimate and the key to change."""


class SimulationIncomplete(TbExudynError, RuntimeError):
    """An integration stopped before its end time (Newton failed, or the solver gave up)."""

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), self.args)


__all__ = [
    "CapabilityError", "CheckpointError", "ComparisonError", "OutputFolderError", "ResourceError", "ResultsError",
    "ScenarioError", "SettingError", "SimulationIncomplete", "TbExudynError", "UserError", "format_message", "short_repr",
]
