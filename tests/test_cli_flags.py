"""Errors carry their parts, and the command line's one table of flags (issue 30, item 2).

The library raises with its own keys (``max_memory``, ``workers``, ``channels``) and the caller's name
as ``where``; ``tb-exudyn`` passes ``where="command line"`` and, when it prints such an error, names the
key by its flag (tb_exudyn/cli/flags.py: FLAGS) and the library's mentions of other arguments
(``overwrite=True``, ``another out folder``) as flags. The messages a user of the command sees are
those of before the change (the reliability cases check them; the texts below are the same lines).
"""

from __future__ import annotations

import pickle
import re
from pathlib import Path

import pytest

from tb_exudyn.cli import flags as cli_flags
from tb_exudyn.cli import build_parser, main
from tb_exudyn.errors import (CapabilityError, CheckpointError, OutputFolderError, ResourceError, ResultsError,
                              ScenarioError, SettingError, UserError)
from tb_exudyn.execution import Execution
from tb_exudyn.track.spectra import SpectrumError

PARTS = ("where", "key", "value", "allowed", "reason")


@pytest.mark.parametrize("cls", [UserError, ScenarioError, SettingError, CapabilityError, CheckpointError,
                                 ResultsError, OutputFolderError, ResourceError, SpectrumError])
def test_every_user_error_keeps_its_parts_through_a_pickle(cls):
    """from_parts on every class: the message is the one format_message writes, the parts are
    attributes, and a pickle (a worker's error reaching the parent) keeps class, message and parts."""
    err = cls.from_parts("run_pem", "workers", 0, "a whole number >= 1", "too few")
    assert str(err) == "run_pem: key 'workers' = 0: too few (allowed: a whole number >= 1)"
    again = pickle.loads(pickle.dumps(err))
    assert type(again) is cls and str(again) == str(err)
    assert [getattr(again, p) for p in PARTS] == ["run_pem", "workers", 0, "a whole number >= 1", "too few"]
    assert again.source == "run_pem"


def test_an_error_from_a_message_has_no_parts_but_the_attributes():
    err = pickle.loads(pickle.dumps(CheckpointError("checkpoint 'x' is damaged")))
    assert str(err) == "checkpoint 'x' is damaged" and [getattr(err, p) for p in PARTS] == [None] * 5


def test_a_scenario_error_names_its_file_as_where():
    err = ScenarioError("sc.toml", "analysis.n_freq", 0, ">= 1", "too small")
    assert (err.file, err.where, err.key) == ("sc.toml", "sc.toml", "analysis.n_freq")
    assert ScenarioError(None, "", 1, "x").key == "<top level>"


def test_restated_replaces_the_head_and_keeps_the_class_and_the_rest():
    err = ResourceError.from_parts("command line", "max_memory", "1 kB", "at least 1 GB",
                                   "more than the max_memory of 1 kB")
    told = cli_flags.as_flags(err)
    assert type(told) is ResourceError
    assert str(told) == ("command line: key '--max-memory' = '1 kB': more than the --max-memory of 1 kB "
                         "(allowed: at least 1 GB)")
    assert (told.key, told.reason) == ("--max-memory", "more than the --max-memory of 1 kB")
    typed = SettingError("run_sweep", "speeds_kmh", [0.0], "speeds > 0", "no speed").restated(
        "command line", "--speeds-kmh", "0:0:1")
    assert str(typed) == "command line: key '--speeds-kmh' = '0:0:1': no speed (allowed: speeds > 0)"


def test_only_the_command_lines_own_calls_are_told_as_flags():
    """An error of a Python caller (where: the function) or of a file keeps its key; mentions of
    arguments are respelled in every line the command prints."""
    python = SettingError("run_pem", "workers", 0, "a whole number >= 1")
    assert cli_flags.as_flags(python) is python
    file = ScenarioError("sc.toml", "seed", -1, ">= 0")
    assert str(cli_flags.as_flags(file)) == str(file)
    checkpoint = CheckpointError("checkpoint 'c' holds another computation: use overwrite=True to replace it, "
                                 "another out folder, or the computation it holds")
    assert str(cli_flags.as_flags(checkpoint)).endswith("use --overwrite to replace it, another --out, or the "
                                                        "computation it holds")


def test_the_table_covers_the_library_keys_and_names_real_flags():
    """Every flag of the table is an option of some command (or BRIDGE, check's argument), and the keys
    the methods raise with (issue 30: psd_channels, linearization, n_samples, seed, speeds_kmh) and
    those of execution, plotting and export are in it."""
    needed = {"psd_channels", "linearization", "n_samples", "seed", "speeds_kmh", "workers", "max_memory", "out",
              "overwrite", "format", "channels", "resume"}
    assert needed <= set(cli_flags.FLAGS)
    parser = build_parser()
    flags = {"BRIDGE"}
    for action in parser._subparsers._group_actions:  # noqa: SLF001 - argparse's sub-commands
        for sub in action.choices.values():
            for a in sub._actions:  # noqa: SLF001
                flags.update(a.option_strings)
    assert set(cli_flags.FLAGS.values()) <= flags, set(cli_flags.FLAGS.values()) - flags


def test_execution_raises_with_its_own_keys():
    """Execution names its fields, whoever calls it (no branching on the caller)."""
    for kwargs, key in [({"workers": 0}, "workers"), ({"out": " "}, "out"), ({"resume": True}, "resume"),
                        ({"max_memory": "abc"}, "max_memory"), ({"out": "o", "resume": True, "overwrite": True},
                                                                 "overwrite")]:
        with pytest.raises(SettingError) as info:
            Execution(where="command line", **kwargs)
        assert info.value.key == key and info.value.where == "command line"
        assert cli_flags.as_flags(info.value).key == cli_flags.FLAGS[key]
    with pytest.raises(SettingError) as info:
        Execution(out="o", resume=True, overwrite=True)
    assert "either --resume or --overwrite" in str(cli_flags.as_flags(
        info.value.restated("command line", "overwrite")))


def test_notices_are_told_as_flags():
    assert cli_flags.notice_as_flags("command line: workers = 9 is more than 2 cores") == \
        "command line: --workers = 9 is more than 2 cores"
    assert cli_flags.notice_as_flags("run_pem: workers = 9 is more") == "run_pem: workers = 9 is more"


# ------------------------------------------------------------------ the command, end to end
def _error_line(capsys) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    lines = [ln for ln in err.splitlines() if ln.startswith("tb-exudyn: error: ")]
    assert len(lines) == 1, err
    return lines[0]


def _tiny(tmp_path: Path) -> str:
    from .reliability.execution_helpers import write_scenario

    return str(write_scenario(tmp_path / "tiny.toml"))


@pytest.mark.exudyn
@pytest.mark.parametrize("argv, texts", [
    (["--max-memory", "abc"], ["command line: key '--max-memory' = 'abc' (allowed: a positive size"]),
    (["--max-memory", "1KB"], ["command line: key '--max-memory' = '1 kB': the run needs about",
                               "more than the --max-memory of 1 kB (allowed: at least"]),
])
def test_run_prints_a_library_refusal_with_the_flag(tmp_path, capsys, argv, texts):
    """``run`` refused by Execution or the memory check: one error line, the flag as the key, nothing
    left in the scratch folder (the new --out is removed again)."""
    pytest.importorskip("exudyn")
    out = tmp_path / "o"
    assert main(["run", _tiny(tmp_path), "--out", str(out), "--no-figures", "--no-progress", *argv]) == 2
    line = _error_line(capsys)
    for text in texts:
        assert text in line, line
    assert not out.exists()


@pytest.mark.exudyn
def test_run_into_an_earlier_result_names_the_flags(tmp_path, capsys):
    pytest.importorskip("exudyn")
    from .reliability.cases import rr_arrays, rr_meta, write_result

    write_result(tmp_path / "o" / "pem", rr_arrays(), rr_meta())
    assert main(["run", _tiny(tmp_path), "--out", str(tmp_path / "o"), "--no-figures", "--no-progress"]) == 2
    line = _error_line(capsys)
    assert re.search(r"command line: output folder '.*' holds the result pem/ of an earlier run: use --overwrite "
                     r"to replace it, or another --out$", line), line


def test_run_overrides_go_through_the_scenario():
    """--samples, --seed and --linearization set analysis.n_samples, seed and linearization by
    Scenario.replace (their one home), for the methods they concern; a value the schema refuses names
    the flag (the table's)."""
    import argparse

    from tb_exudyn.cli import scenario as cli_scenario
    from tb_exudyn.scenario import load_scenario

    base = load_scenario("quick")
    args = argparse.Namespace(method="mc", samples=7, seed=11, linearization="static", n_freq=None,
                              freq_spacing=None, channels=None, speed_kmh=None)
    sc = cli_scenario.with_options(base, args)
    assert (sc.analysis.n_samples, sc.analysis.seed, sc.analysis.linearization) == (7, 11, "static")
    pem = cli_scenario.with_options(base, argparse.Namespace(**{**vars(args), "method": "pem"}))
    assert (pem.analysis.n_samples, pem.analysis.seed) == (base.analysis.n_samples, base.analysis.seed)
    assert pem.analysis.linearization == "static"
    with pytest.raises(SettingError, match=r"^command line: key '--samples' = 0\b"):
        cli_scenario.with_options(base, argparse.Namespace(**{**vars(args), "samples": 0}))


def test_check_alpha_is_refused_with_its_flag_before_any_work(tmp_path, capsys):
    """Exact problem: ``tb-exudyn check single_span_32m --alpha 2``: EN 1991-2 6.3.2(3) allows only
    0.75 ... 1.46 for the classified-load factor. Reference: the code's list (codes.a2_verdicts.ALPHA_VALUES);
    the refusal is one line naming --alpha and the allowed values, exit 2, and --out is never made."""
    out = tmp_path / "o"
    assert main(["check", "single_span_32m", "--line-speed-kmh", "200", "--alpha", "2", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'--alpha' = 2.0" in err[0] and "1.21" in err[0] and "6.3.2(3)" in err[0], err
    assert not out.exists()
