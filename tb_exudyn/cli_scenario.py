"""The scenario a command line asks for: the named scenario, its ``--set KEY=VALUE`` settings and
the run's overrides (--speed-kmh, --n-freq, --freq-spacing, --channels), each checked by the schema;
a bad one names the option (used by cli.py)."""

from __future__ import annotations

import argparse

from .errors import SettingError
from .scenario import Scenario, ScenarioError, load_scenario
from .scenario.io import parse_setting, with_settings


def load(args: argparse.Namespace) -> Scenario:
    """The scenario named on the command line with its ``--set KEY=VALUE`` settings, each checked by
    the schema as in a file (a bad key or value names --set and what is allowed)."""
    scenario = load_scenario(args.scenario)
    for text in getattr(args, "settings", None) or ():
        try:
            scenario = with_settings(scenario, [parse_setting(text)])
        except ScenarioError as exc:  # before ValueError: a ScenarioError is one
            raise SettingError("command line", "--set", text, f"{exc.key}: {exc.allowed}", exc.reason) from None
        except ValueError as exc:
            raise SettingError("command line", "--set", text, str(exc)) from None
    return scenario


def with_options(scenario: Scenario, args: argparse.Namespace) -> Scenario:
    """The scenario with the run's overrides (--speed-kmh, --n-freq, --freq-spacing, --channels); a
    bad value names the option."""
    sc = scenario
    for attr, option, section in (("speed_kmh", "--speed-kmh", None), ("n_freq", "--n-freq", "analysis"),
                                  ("freq_spacing", "--freq-spacing", "analysis"), ("channels", "--channels", "analysis")):
        value = getattr(args, attr, None)
        if value is None:
            continue
        value = tuple(value) if isinstance(value, list) else value
        try:
            sc = sc.replace(**{attr: value}) if section is None else sc.replace(analysis=sc.analysis.replace(**{attr: value}))
        except ScenarioError as exc:
            raise SettingError("command line", option, value, exc.allowed, exc.reason) from None
    return sc


__all__ = ["load", "with_options"]
