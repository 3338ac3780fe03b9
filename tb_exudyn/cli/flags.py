"""How the command line names what the library names: ONE table of library keys (function arguments,
method and execution options) and the command-line flags that set them.

The library raises errors with its own keys (``workers``, ``n_samples``, ``psd_channels``) and the
caller's name as ``where``; the ``tb-exudyn`` command passes ``where="command line"`` (:data:`WHERE`)
to what it calls, and when it prints an error of such a call it restates it with the flag as the key
(:func:`as_flags`): ``command line: key '--samples' = 1 ...``. Mentions of other arguments in the
message (``overwrite=True``, ``another out folder``) are respelled as the flags the user can type
(:data:`MENTIONS`), in errors and warnings alike.
"""

from __future__ import annotations

import re
from pathlib import Path

from ..errors import SettingError, UserError
from ..scenario.registry import models_dir

#: the caller's name the command passes to the library (``where``)
WHERE = "command line"

#: library key -> command-line flag (the one table; every key a library call raises with for an
#: argument the command line sets)
FLAGS: dict[str, str] = {
    # methods (run_pem, run_monte_carlo, simulate, the sweep)
    "engine": "--engine",
    "linearization": "--linearization",
    "psd_channels": "--psd-channels",
    "n_samples": "--samples",
    "seed": "--seed",
    "keep_samples": "--keep-samples",
    "speeds_kmh": "--speeds-kmh",
    "line_speed_kmh": "--line-speed-kmh",
    "step_kmh": "--speed-step-kmh",
    "n_freq": "--n-freq",
    "freq_spacing": "--freq-spacing",
    "precision": "--precision",
    # execution (Execution's fields)
    "workers": "--workers",
    "max_memory": "--max-memory",
    "out": "--out",
    "resume": "--resume",
    "overwrite": "--overwrite",
    "keep_checkpoint": "--keep-checkpoint",
    # results, figures, exports
    "format": "--format",
    "channels": "--channels",
    "formats": "--formats",
    # structure.imported.export_modes
    "max_frequency": "--max-frequency",
    "max_modes": "--max-modes",
    # codes.check (the check's arguments)
    "trains": "--trains",
    "track": "--track",
    "construction": "--construction",
    "bridge": "BRIDGE",
    "stochastic": "--stochastic",
    "stochastic_speeds": "--stochastic-speeds",
    "stochastic_scenario": "--stochastic-scenario",
    "interaction": "--interaction",
    "alpha": "--alpha",
}

#: how a library message mentions an argument -> what the command line says instead
MENTIONS: dict[str, str] = {
    "overwrite=True": FLAGS["overwrite"],
    "resume=True": FLAGS["resume"],
    "keep_checkpoint=True": FLAGS["keep_checkpoint"],
    "another out folder": f"another {FLAGS['out']}",
    "the max_memory of": f"the {FLAGS['max_memory']} of",
    "with stochastic=True only": f"with {FLAGS['stochastic']} only",
    "fewer samples (n_samples or": f"fewer samples ({FLAGS['n_samples']}, n_samples or",
    "not keeping them (keep_samples=False)": f"not keeping them (no {FLAGS['keep_samples']})",
    "fewer PSD maps (psd_channels), or keep_psd=False": f"fewer PSD maps ({FLAGS['psd_channels']} key)",
    "an uncertain file (uncertain_file)": "an uncertain file (--uncertain-file)",
    "run_pem of the scenario at that speed": "run --speed-kmh",
}
_MENTION = re.compile("|".join(re.escape(m) for m in sorted(MENTIONS, key=len, reverse=True)))
#: the head of a library notice about one of its arguments, ``command line: workers = 8 ...``
_NOTICE_HEAD = re.compile(rf"^{re.escape(WHERE)}: (\w+) = ")


def flag(key: str) -> str:
    """The flag of a library key (the key itself when no flag sets it)."""
    return FLAGS.get(key, key)


def respelled(text: str) -> str:
    """``text`` with the library's mentions of its arguments spelled as flags (:data:`MENTIONS`)."""
    return _MENTION.sub(lambda m: MENTIONS[m.group(0)], text)


def as_flags(exc: UserError) -> UserError:
    """The error as the command line prints it: an error of a call the command made (``where`` is
    :data:`WHERE`) about a key of :data:`FLAGS` restated with the flag as the key; mentions of
    arguments respelled as flags. Other errors (a file's) are kept."""
    if exc.where == WHERE and exc.key in FLAGS:
        return exc.restated(WHERE, FLAGS[exc.key], text=respelled)
    shipped = shipped_name(exc.where)
    if shipped is not None and exc.key is not None:  # a shipped model by its name: the line stays within 200
        exc = exc.restated(shipped, exc.key)  # characters (an installed package's path is 60-90 of them)
    return exc.restated(exc.where or "", exc.key or "", text=respelled) if _MENTION.search(str(exc)) else exc


def shipped_name(where: str | None) -> str | None:
    """``shipped scenario quick.toml`` for the file of a model shipped with the package (the user names it
    by its name; its path says nothing they can edit), else None."""
    if not where or not where.endswith(".toml"):
        return None
    try:
        rel = Path(where).resolve().relative_to(models_dir().resolve())
    except (ValueError, OSError):
        return None
    if len(rel.parts) != 2:
        return None
    kind = {"scenarios": "scenario", "bridges": "bridge", "vehicles": "vehicle", "trains": "train"}.get(rel.parts[0])
    return f"shipped {kind} {rel.name}" if kind else None


def notice_as_flags(text: str) -> str:
    """A warning's text as the command line prints it: ``command line: KEY = ...`` with the flag, and
    mentions respelled."""
    m = _NOTICE_HEAD.match(text)
    if m and m.group(1) in FLAGS:
        text = f"{WHERE}: {FLAGS[m.group(1)]} = " + text[m.end():]
    return respelled(text)



def int_option(text: str | None, option: str, low: int, high: int | None = None, why: str = "") -> int | None:
    """The whole number given to ``option`` (None if not given); SettingError naming the option."""
    if text is None:
        return None
    allowed = f"a whole number >= {low}" + (f" and <= {high}" if high is not None else "") + (f" ({why})" if why else "")
    try:
        value = int(text)
    except ValueError:
        raise SettingError("command line", option, text, allowed, "not a whole number") from None
    if value < low or (high is not None and value > high):
        raise SettingError("command line", option, value, allowed, "out of range")
    return value

__all__ = ["FLAGS", "MENTIONS", "WHERE", "as_flags", "flag", "int_option", "notice_as_flags", "respelled"]
