"""The scenario a command line asks for: the named scenario, its ``--set KEY=VALUE`` settings and
the run's overrides (--speed-kmh, --n-freq, --freq-spacing, --channels, --linearization, --samples,
--seed), each set through ``Scenario.replace`` and checked by the schema; a bad one names the option
(used by the commands)."""

from __future__ import annotations

import argparse

from .flags import flag
from ..errors import FILE_KEY, SettingError
from ..scenario import Scenario, ScenarioError, load_scenario
from ..scenario.io import parse_setting, with_settings
from ..scenario.speed_rule import at_speed, statement


#: the help of ``--set`` on every command that takes it
SET_HELP = ("set a scenario key, checked as in a file (repeatable), e.g. --set track.lead_in=150; a file "
            "(--set bridge=my/x.toml) is found from the working folder")


def load(args: argparse.Namespace) -> Scenario:
    """The scenario named on the command line with its ``--set KEY=VALUE`` settings, each checked by
    the schema as in a file (a bad key or value names --set and what is allowed; an error in or about
    another file names that file). A file named in a value is found from the working folder."""
    scenario = load_scenario(args.scenario)
    for text in getattr(args, "settings", None) or ():
        try:
            scenario = with_settings(scenario, [parse_setting(text)])
        except ScenarioError as exc:  # before ValueError: a ScenarioError is one
            raise set_error(text, exc, scenario) from None
        except ValueError as exc:
            raise SettingError("command line", "--set", text, str(exc)) from None
    return scenario


def set_error(text: str, exc: ScenarioError, scenario: Scenario) -> SettingError:
    """A --set setting's error as the command line tells it: the key and what is allowed, and the file
    when it is not the scenario's (a missing file: the path tried; a bad key in a bridge file: that
    file)."""
    if exc.key == FILE_KEY:
        return SettingError("command line", "--set", text, exc.allowed, f"{exc.reason}: {exc.where}")
    elsewhere = exc.where not in (None, "<scenario>", scenario.source_file)
    return SettingError("command line", "--set", text, f"{exc.key}: {exc.allowed}",
                        f"{exc.reason} (in {exc.where})" if elsewhere else exc.reason)


def with_options(scenario: Scenario, args: argparse.Namespace) -> Scenario:
    """The scenario with the run's overrides: --speed-kmh by the one rule for a run at a speed
    (:func:`tb_exudyn.scenario.speed_rule.at_speed`: the band and the approach scaled by v / v0, as
    every speed of a sweep), then the analysis keys of :data:`ANALYSIS_OPTIONS` (--n-freq, --freq-spacing,
    --channels; --linearization for PEM and Monte Carlo; --samples and --seed for Monte Carlo), each
    through ``Scenario.replace``; a bad value names the option."""
    sc = scenario
    speed = getattr(args, "speed_kmh", None)
    if speed is not None:
        try:
            sc = at_speed(sc, speed)
        except ScenarioError as exc:
            raise SettingError("command line", "--speed-kmh", speed, exc.allowed,
                               exc.reason if exc.key == "speed_kmh" else f"{exc.key} = {_shown(exc.value)}: {exc.reason}"
                               ) from None
    method = getattr(args, "method", None)
    for attr, key, methods in ANALYSIS_OPTIONS:
        value = getattr(args, attr, None)
        if value is None or (methods and method not in methods):
            continue
        value = tuple(value) if isinstance(value, list) else value
        try:
            sc = sc.replace(analysis=sc.analysis.replace(**{key: value}))
        except ScenarioError as exc:
            raise SettingError("command line", flag(key), value, exc.allowed, exc.reason) from None
    return sc


#: (argument of the command line, analysis key, the methods it applies to (empty: every one)): the run's
#: options that override a scenario key (the key's one home is the scenario; the flag is named by
#: tb_exudyn.cli_flags.FLAGS)
ANALYSIS_OPTIONS = (
    ("n_freq", "n_freq", ()), ("freq_spacing", "freq_spacing", ()), ("channels", "channels", ()),
    ("linearization", "linearization", ("pem", "mc")), ("samples", "n_samples", ("mc",)), ("seed", "seed", ("mc",)),
)


def _shown(value: object) -> str:
    return f"{value:.4g}" if isinstance(value, float) else repr(value)


def _set_keys(args: argparse.Namespace) -> dict[str, object]:
    """The keys the command line's ``--set`` settings give, with their values (the last one wins)."""
    out: dict[str, object] = {}
    for text in getattr(args, "settings", None) or ():
        try:
            key, value = parse_setting(text)
        except ValueError:
            continue
        out[key] = value
    return out


def adaptive_count_free(args: argparse.Namespace) -> bool:
    """Whether the command line asks for the adaptive grid (``--freq-spacing adaptive`` or ``--set
    analysis.freq_spacing=adaptive``) and leaves its count free (no ``--n-freq``, no ``--set
    analysis.n_freq``). Then the run takes at least the count the grid's rules need (the scenario's
    n_freq was chosen for the grid it had; a railway engineer asking for the adaptive grid expects it to
    place what it needs), and says so (:func:`least_count_line`); a count chosen on the command line
    below that need stays an error naming the count."""
    sets = _set_keys(args)
    asked = getattr(args, "freq_spacing", None) == "adaptive" or sets.get("analysis.freq_spacing") == "adaptive"
    chosen = getattr(args, "n_freq", None) is not None or "analysis.n_freq" in sets
    return asked and not chosen


def least_count_line(before: Scenario, after: Scenario) -> str | None:
    """The terminal's line on an adaptive grid's count raised to what its rules need (None: not raised)."""
    if after.analysis.n_freq == before.analysis.n_freq:
        return None
    return (f"adaptive grid: {after.analysis.n_freq} frequencies, the least its rules need here (the scenario's "
            f"n_freq is {before.analysis.n_freq}; --n-freq N to choose more)")


def speed_rule_line(base: Scenario, scenario: Scenario) -> str | None:
    """The terminal's line on a run at another speed than the scenario's (None when there is none)."""
    if scenario.speed_kmh == base.speed_kmh:
        return None
    return "speed rule: " + statement(base, scenario)


__all__ = ["SET_HELP", "adaptive_count_free", "least_count_line", "load", "set_error", "speed_rule_line",
           "with_options"]
