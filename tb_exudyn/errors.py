"""The error types of tb_exudyn: one hierarchy, every class picklable.

    TbExudynError                 anything tb_exudyn raises on purpose
    ├── UserError                 the user can fix it: the CLI prints the one-line message, exit 2
    │   ├── ScenarioError         a scenario, vehicle, bridge or limit file (or its dataclass) is not valid
    │   ├── SpectrumError         a spectrum name, band or user spectrum table is not valid (tb_exudyn.track)
    │   ├── SettingError          an argument of a Python call or a command-line option is not allowed
    │   │   └── ArgumentTypeError an argument of a Python call is of the wrong type (also a TypeError)
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
    """An error the user can fix; its message is one line naming where (a file, or the function whose
    argument it is), the key, the value found and what is allowed.

    Construct either from a finished message (``UserError("...")``, parts given as keywords when
    known) or from its parts with :meth:`from_parts`. Every instance carries its parts as attributes
    (None when not known): ``where`` (the source: a file, a function), ``key`` (the key path or argument
    name), ``value``, ``allowed`` and ``reason``; they survive a pickle. A caller that names things
    otherwise (the command line names arguments as its flags) restates the error with
    :meth:`restated`, without parsing the message.
    """

    where: str | None = None
    key: str | None = None
    value: Any = None
    allowed: str | None = None
    reason: str | None = None

    def __init__(self, message: str, *, where: str | None = None, key: str | None = None, value: Any = None,
                 allowed: str | None = None, reason: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.where, self.key, self.value, self.allowed, self.reason = where, key, value, allowed, reason

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (type(self), self.message, dict(self.__dict__)))

    def __str__(self) -> str:
        return self.message

    @classmethod
    def from_parts(cls, where: str, key: str, value: Any, allowed: str, reason: str = "") -> "UserError":
        """The error ``WHERE: key 'KEY' = VALUE: REASON (allowed: ALLOWED)``, keeping its parts.

        Classes whose constructor takes the parts (:class:`ScenarioError`, :class:`SettingError`) are
        built through it; the others take the formatted message and the parts as keywords."""
        if issubclass(cls, (ScenarioError, SettingError)):
            return cls(where, key, value, allowed, reason)  # type: ignore[call-arg]
        return cls(format_message(where, key, value, allowed, reason), where=where, key=key, value=value,
                   allowed=allowed, reason=reason)

    @property
    def source(self) -> str | None:
        """Where the error comes from (a file, a function): the same as ``where``."""
        return self.where

    def restated(self, where: str, key: str, value: Any = None, *, text: Any = None) -> "UserError":
        """The same error (same class, same parts) told by a caller that names things otherwise: ``where``
        and ``key`` (and ``value``, when given) replace the message's ``WHERE: key 'KEY' = VALUE`` head;
        ``text`` (a function of a string, e.g. a table of names) respells ``allowed``, ``reason`` and the
        rest of the message. Without known parts the message is kept (only ``text`` applied)."""
        spell = text or (lambda t: t)
        message = self.message
        parts = {"allowed": None if self.allowed is None else spell(self.allowed),
                 "reason": None if self.reason is None else spell(self.reason)}
        head = f"{self.where}: key '{self.key}' = "
        if self.where is not None and self.key is not None and message.startswith(head):
            rest = message[len(head):]
            old = shown_value(self.key, self.value)
            if value is not None and rest.startswith(old):  # the value as the caller typed it
                rest = shown_value(key, value) + rest[len(old):]
                parts["value"] = value
            message = f"{where}: key '{key}' = " + spell(rest)
            parts.update(where=where, key=key)
        else:
            message = spell(message)
        return _rebuild(type(self), message, {**self.__dict__, **parts, "message": message})


def _rebuild(cls: type, message: str, state: dict[str, Any]) -> "UserError":
    err = cls.__new__(cls)
    Exception.__init__(err, message)
    err.__dict__.update(state)
    return err


def format_message(where: str, key: str, value: Any, allowed: str, reason: str = "") -> str:
    """``WHERE: key 'KEY' = VALUE: REASON (allowed: ALLOWED)`` on one line."""
    text = f"{where}: key '{key or '<top level>'}' = {shown_value(key, value)}"
    if reason:
        text += f": {reason}"
    return text + f" (allowed: {allowed})"


#: the key of an error about a whole file (missing, unreadable): its value is the file's name
FILE_KEY = "<file>"

#: longest value a message shows whole [characters]: a value is cut only beyond it (a hostile or
#: runaway value, not a file name or a typo someone must see to fix)
SHOWN_VALUE_LIMIT = 200


def short_repr(value: Any, limit: int = SHOWN_VALUE_LIMIT) -> str:
    """repr of a value on one line, cut to ``limit`` characters only when longer."""
    text = repr(value).replace("\n", "\\n")
    return text if len(text) <= limit else text[: limit - 3] + "..."


#: longest list, tuple, set or table a message shows whole [characters]: beyond it the first items and
#: the count (a list of 1000 spans or 200 vehicles is wrong as a whole; its items stay in the user's file)
SHOWN_CONTAINER_LIMIT = 30


def short_container(value: list | tuple | set | frozenset | dict, limit: int = SHOWN_CONTAINER_LIMIT) -> str:
    """repr of a container on one line; beyond ``limit`` characters a list, tuple or set shows its first
    items and its count (``[32.0, 32.0, ... (1000 items)]``), a table its repr cut at ``limit``."""
    text = repr(value).replace("\n", "\\n")
    if len(text) <= limit:
        return text
    if isinstance(value, dict) or len(value) < 2:
        return short_repr(value, limit=limit)
    items = list(value)
    def piece_of(item: Any) -> str:  # a path is never cut
        whole = isinstance(item, str) and _looks_like_a_path(item)
        return short_repr(item, limit=1 << 30 if whole else limit)

    shown = [piece_of(items[0])]
    for item in items[1:]:
        piece = piece_of(item)
        if sum(len(t) + 2 for t in shown) + len(piece) > limit - 20:
            break
        shown.append(piece)
    open_, close = "()" if isinstance(value, tuple) else ("[]" if isinstance(value, list) else "{}")
    return f"{open_}{', '.join(shown)}, ... ({len(items)} items){close}"


def shown_value(key: str | None, value: Any) -> str:
    """A value as a message shows it: a file's name (key :data:`FILE_KEY`) always whole, a container by
    :func:`short_container`, any other value by :func:`short_repr`."""
    if key == FILE_KEY:
        return short_repr(value, limit=1 << 30)
    if isinstance(value, (list, tuple, set, frozenset, dict)):
        return short_container(value)
    if isinstance(value, str) and not _looks_like_a_path(value):
        return short_repr(value, limit=SHOWN_TEXT_LIMIT)
    return short_repr(value)


#: longest text (not a path) a message shows whole [characters]: a typed value of that length is a
#: list pasted into one option (1001 speeds), whose start says what it was
SHOWN_TEXT_LIMIT = 60


def _looks_like_a_path(text: str) -> bool:
    """A path the user typed (never cut): holds a folder separator or ends like a model or result file."""
    return "/" in text or "\\" in text or text.endswith((".toml", ".csv", ".json", ".npz", ".nc"))


class ScenarioError(UserError, ValueError):
    """A scenario, vehicle, bridge or limit description is not valid.

    The message names the file, the key path, the value found and what is allowed, so that
    the command-line tool can print it as it is (no traceback) and the user can fix the file.
    """

    def __init__(self, file: str | None, key: str, value: Any, allowed: str, reason: str = ""):
        self.file = file or "<scenario>"
        super().__init__(format_message(self.file, key or "<top level>", value, allowed, reason), where=self.file,
                         key=key or "<top level>", value=value, allowed=allowed, reason=reason)


class SettingError(UserError, ValueError):
    """A function argument or a command-line option is not allowed.

    ``where`` is the function (``"run_pem"``) or object (``"Execution"``) whose argument ``key`` is; the
    library names its own arguments, and the command line restates the error with its flag
    (``--workers``) when it prints it.
    """

    def __init__(self, where: str, key: str, value: Any, allowed: str, reason: str = "") -> None:
        super().__init__(format_message(where, key, value, allowed, reason), where=where, key=key, value=value,
                         allowed=allowed, reason=reason)


class ArgumentTypeError(SettingError, TypeError):
    """An argument of a Python call is of a type the call cannot use (an int where a channel name is
    expected, a dict where a Scenario is); the message says what to pass. Also a TypeError, as Python
    callers expect of a wrong type."""


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
    "ArgumentTypeError", "CapabilityError", "CheckpointError", "ComparisonError", "OutputFolderError", "ResourceError", "ResultsError",
    "FILE_KEY", "SHOWN_VALUE_LIMIT", "ScenarioError", "SettingError", "SimulationIncomplete", "TbExudynError", "UserError",
    "format_message", "short_repr", "shown_value",
]


#: longest list of names an error's "allowed" shows whole [characters]
SHOWN_NAMES_LIMIT = 70


def one_of(names: Any, given: Any = None, *, tail: str = "") -> str:
    """``one of a, b, c`` for an error's allowed part; a longer list (beyond :data:`SHOWN_NAMES_LIMIT`)
    shows the names closest to ``given`` (difflib) and the count, so the line stays readable."""
    import difflib  # only when an error is being written

    names = [str(n) for n in names]
    text = ", ".join(names) or "(none)"
    if len(text) > SHOWN_NAMES_LIMIT:
        near = difflib.get_close_matches(str(given), names, n=3, cutoff=0.0) if given is not None else names[:3]
        text = ", ".join(near) + f", ... ({len(names)} in all)"
    return f"one of {text}{tail}"
