"""The library takes Python names; only the command line knows its flags (issue 48).

A library function names its arguments in its errors and messages (``n_samples``, ``keep_samples=False``,
``stochastic_speeds``) and the command line respells them as its flags when it prints them
(``tb_exudyn/cli/flags.py``: ``FLAGS`` for keys, ``MENTIONS`` for phrases). So no module outside
``tb_exudyn/cli/`` has a flag of the ``tb-exudyn`` command in a string of its code (docstrings and comments
may say what the command does). The flags are read from the command's own parser (every sub-command's
option strings), so a new flag is covered without a list to keep.

Known exceptions, each a page or a text the command line shows without restating it (the report's HTML
pages say which command line made a figure or a table; the uncertainty study's notes are printed by
cli/uq.py as they are): :data:`ALLOWED`. Each must still hold a flag (a stale entry fails).
"""

from __future__ import annotations

import argparse
import re

from tb_exudyn.cli import build_parser

from .import_graph import ROOT, modules
from .test_layout import code_strings

#: module -> why it may name flags (the remaining places; removing one means its text says the library's names)
ALLOWED = {
    "tb_exudyn.report.check": "check.html: 'tb-exudyn check --stochastic', 'Not drawn (--no-figures)'",
    "tb_exudyn.report.sections": "report.html: an override 'such as --speed-kmh or --set'; the figures left out: "
                                 "'tb-exudyn run ... --figures all'",
    "tb_exudyn.report.sweep": "speed_sweep.html: 'tb-exudyn run --speed-kmh', '--freq-spacing adaptive', '--no-figures'",
    "tb_exudyn.report.uq": "uq.html: '--order', '--no-figures'",
    "tb_exudyn.report.verdicts": "the verdicts' hint 'tb-exudyn check BRIDGE --line-speed-kmh V'",
    "tb_exudyn.methods.uq.summary": "the surrogate's leave-one-out warning: 'raise --order'",
    "tb_exudyn.results.uq": "loo_notes: 'use --design sobol --nodes N', printed by cli/uq.py as it is",
}


def command_flags(parser: argparse.ArgumentParser) -> set[str]:
    """Every long option string of ``parser`` and its sub-commands' parsers (``--help`` left out)."""
    out: set[str] = set()
    for action in parser._actions:
        out |= {o for o in action.option_strings if o.startswith("--") and o != "--help"}
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                out |= command_flags(sub)
    return out


def flags_in_code(source: str, flags: set[str]) -> list[tuple[int, str]]:
    """(line, flag) of each flag in a string literal of ``source`` (f-strings' literal parts included),
    docstrings excepted; a flag is matched whole (``--out`` is not in ``--output``)."""
    pattern = re.compile(r"(?<![\w-])(" + "|".join(re.escape(f) for f in sorted(flags, key=len, reverse=True))
                         + r")(?![\w-])")
    return sorted({(node.lineno, m) for node in code_strings(source) for m in pattern.findall(node.value)})


def test_the_finder_finds_flags_in_code_not_in_docstrings():
    code = ('"""Run `tb-exudyn run --samples 5`."""\n'
            'def f(n):\n    """--samples in a docstring."""\n'
            '    # "--samples" in a comment\n'
            '    raise ValueError(f"use --samples {n} or --output x")\n')
    assert flags_in_code(code, {"--samples", "--out"}) == [(5, "--samples")]


def test_the_parser_has_the_flags_everyone_knows():
    flags = command_flags(build_parser())
    assert {"--out", "--workers", "--resume", "--samples", "--line-speed-kmh", "--stochastic-speeds"} <= flags


def test_no_flag_name_outside_the_command_line():
    flags = command_flags(build_parser())
    found, stale = [], []
    for name, path in modules().items():
        if name == "tb_exudyn.cli" or name.startswith("tb_exudyn.cli."):
            continue
        hits = flags_in_code(path.read_text(encoding="utf-8"), flags)
        if name in ALLOWED:
            stale += [] if hits else [name]
        else:
            found += [f"{path.relative_to(ROOT)}:{line}: {flag}" for line, flag in hits]
    assert not found, "flag names outside tb_exudyn/cli/ (name the argument; cli/flags.py respells it): " + ", ".join(found)
    assert not stale, f"no flag left in {stale}: remove them from ALLOWED"
