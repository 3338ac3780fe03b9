"""Broken limit files (issue 27) as data, in the form of tests/reliability/cases.py: each case copies the
model library into its scratch folder, breaks one limit file there and points ``TB_EXUDYN_MODELS`` at
the copy (the way a user gives the command line their own limit files), or names the file in a Python
call (``load_limits(path)``, ``result.checks(limits=path)``).

Before issue 27 a negative, zero, NaN or inf limit, a window_max on a random process and similar files
loaded; the run then ended in exit 0 with "Verdicts: not computed" in the report (``--method det``), or
the error came after the run had written its results. Every case here must end in exit status 2 with
one line naming the limit file (or TB_EXUDYN_MODELS), the key and what is allowed, before any work:
the snapshot of tests/reliability/test_limits_files.py shows that no --out folder is made.
Group "limits"; the list is CASES_LIMITS.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import Callable

import numpy as np

from .cases import Case, Run, report, rr_arrays, rr_meta, write_result

#: the repository's model library (copied, never changed)
MODELS = Path(__file__).resolve().parents[2] / "models"


def _library(d: Path) -> Path:
    """A copy of the model library in the scratch folder ``d``; returns its limits/ folder."""
    shutil.copytree(MODELS, d / "models")
    return d / "models" / "limits"


def _env(d: Path) -> dict[str, str]:
    return {"TB_EXUDYN_MODELS": str(d / "models")}


def _run_quick(d: Path) -> tuple[str, ...]:
    return ("run", "quick", "--out", str(d / "out"), "--no-figures", "--no-progress")


def _edit(name: str, old: str, new: str) -> Callable[[Path], Path]:
    """Replace ``old`` (which must be there once) by ``new`` in limits/<name>.toml of the copy."""
    def change(limits: Path) -> Path:
        p = limits / f"{name}.toml"
        text = p.read_text()
        assert text.count(old) == 1, (name, old)
        p.write_text(text.replace(old, new))
        return p
    return change


def _run_case(change: Callable[[Path], Path], *expect: str, argv: Callable[[Path], tuple[str, ...]] = _run_quick
              ) -> Callable[[Path], Run]:
    """A case: the library copy with ``change`` applied, ``argv`` run against it; the line must name the
    changed file and ``expect``."""
    def build(d: Path) -> Run:
        p = change(_library(d))
        return Run(argv=argv(d), env=_env(d), expect=(str(p), *expect))
    return build


# the first criterion of en1990_deck (deck_acc_ballasted, max_abs) has "value = 3.5"; its third
# (deck_twist_3m) the speed bands "values = [4.5e-3, 3.0e-3, 1.5e-3]"
_DECK_VALUE = "value = 3.5\n"
_value = lambda text: _edit("en1990_deck", _DECK_VALUE, f"value = {text}\n")  # noqa: E731


def _drop_criteria(limits: Path) -> Path:
    p = limits / "ride_comfort.toml"
    head = p.read_text().split("[[criteria]]")[0]
    p.write_text(head)
    return p


def _empty_criteria(limits: Path) -> Path:
    p = limits / "ride_comfort.toml"
    p.write_text(p.read_text().split("[[criteria]]")[0] + "criteria = []\n")
    return p


def _binary(limits: Path) -> Path:
    p = limits / "zz_binary.toml"
    p.write_bytes(bytes(np.random.default_rng(27).integers(0, 256, 4096, dtype=np.uint8)))
    return p


def _not_utf8(limits: Path) -> Path:
    p = limits / "ride_comfort.toml"
    p.write_bytes(p.read_bytes().replace(b"Ride comfort", b"Ride c\xf6mfort"))
    return p


def _fifo(limits: Path) -> Path:
    p = limits / "zz_fifo.toml"
    os.mkfifo(p)
    return p


def _dev_zero(limits: Path) -> Path:
    p = limits / "zz_zero.toml"
    os.symlink("/dev/zero", p)
    return p


def _directory(limits: Path) -> Path:
    p = limits / "zz_folder.toml"
    p.mkdir()
    return p


def _huge(limits: Path) -> Path:
    p = limits / "zz_huge.toml"
    with open(p, "wb") as fh:  # sparse: 64 MiB of zeros without writing them
        fh.truncate(64 * 1024 * 1024)
    return p


def _same_name(limits: Path) -> Path:
    p = limits / "zz_copy.toml"  # read after ride_comfort.toml (the files are read in name order)
    shutil.copyfile(limits / "ride_comfort.toml", p)
    return p


def _no_limit_files(d: Path) -> Run:
    limits = _library(d)
    for p in limits.glob("*.toml"):
        p.unlink()
    return Run(argv=_run_quick(d), env=_env(d), expect=("TB_EXUDYN_MODELS", str(d / "models"), "no limit file"))


def _sweep(d: Path) -> tuple[str, ...]:
    return ("sweep", "quick", "--speeds-kmh", "200:250:50", "--out", str(d / "out"), "--no-figures", "--no-progress")


def _det_with_report(d: Path) -> tuple[str, ...]:
    """The deterministic run with its report: the path that said "Verdicts: not computed" with exit 0."""
    return ("run", "quick", "--method", "det", "--out", str(d / "out"), "--no-progress")


def _report_of_results(d: Path) -> Run:
    """`tb-exudyn report` on a results folder: the broken file refuses it before the report is written."""
    folder = write_result(d / "res" / "pem", rr_arrays(), rr_meta()).parent
    p = _value("nan")(_library(d))
    return Run(argv=report(folder), env=_env(d), expect=(str(p), "criteria[0].limit.value", "nan"))


def _python_load(d: Path) -> Run:
    """A user's own file named in Python (no library): the same checks."""
    p = d / "my_limits.toml"
    p.write_text((MODELS / "limits" / "en1990_deck.toml").read_text().replace(_DECK_VALUE, "value = inf\n"))
    return Run(code=f"from tb_exudyn.scenario.limits import load_limits; load_limits({str(p)!r})",
               expect=(str(p), "criteria[0].limit.value", "inf"))


def _python_checks(d: Path) -> Run:
    """``result.checks(limits=path)`` with a user's own file (limit 0 on a max_abs criterion)."""
    folder = write_result(d / "pem", rr_arrays(), rr_meta())
    p = d / "my_limits.toml"
    p.write_text((MODELS / "limits" / "en1990_deck.toml").read_text().replace(_DECK_VALUE, "value = 0.0\n"))
    code = (f"from tb_exudyn.results import load_results; load_results({str(folder)!r}).checks(limits={str(p)!r})")
    return Run(code=code, expect=(str(p), "criteria[0].limit.value", "> 0"))


def _isolated(build: Callable[[Path], Run]) -> Callable[[Path], Run]:
    def run(d: Path) -> Run:
        r = build(d)
        return Run(argv=r.argv, code=r.code, expect=r.expect, env=r.env, isolate=True)
    return run


CASES_LIMITS: list[Case] = [
    Case("limit negative", "limits", _run_case(_value("-3.5"), "criteria[0].limit.value", "> 0")),
    Case("limit zero", "limits", _run_case(_value("0.0"), "criteria[0].limit.value", "> 0")),
    Case("limit text", "limits", _run_case(_value('"3.5"'), "criteria[0].limit.value", "wrong type")),
    Case("limit NaN", "limits", _run_case(_value("nan"), "criteria[0].limit.value", "nan")),
    Case("limit inf", "limits", _run_case(_value("inf"), "criteria[0].limit.value", "inf")),
    Case("limit missing", "limits", _run_case(_edit("en1990_deck", _DECK_VALUE, ""), "criteria[0].limit.value",
                                              "missing key")),
    Case("speed band inf", "limits", _run_case(
        _edit("en1990_deck", "values = [4.5e-3, 3.0e-3, 1.5e-3]", "values = [4.5e-3, 3.0e-3, inf]"),
        "criteria[2].limit.values[2]", "finite")),
    Case("grade negative", "limits", _run_case(
        _edit("running_safety", "values = [1.0, 1.2]", "values = [-1.2, -1.0]"), "criteria[1].limit.values[0]", "> 0")),
    Case("static load limit 0", "limits", _run_case(
        _edit("running_safety", "constant = 10000.0\ncoefficient = 0.3333333333333333",
              "constant = 0.0\ncoefficient = 0.0"), "criteria[4].limit.coefficient", "the limit is 0")),
    Case("unknown quantity", "limits", _run_case(
        _edit("ride_comfort", 'quantity = "body_acc_y"', 'quantity = "body_acc_lateral"'), "criteria[1].quantity",
        "unknown quantity")),
    Case("window_max on a random process", "limits", _run_case(
        _edit("ride_comfort", 'quantity = "body_acc_y"\nstatistic = "max_abs"',
              'quantity = "body_acc_y"\nstatistic = "window_max"\nwindow = 5.0'), "criteria[1].statistic",
        "window_max")),
    Case("window on max_abs (ignored)", "limits", _run_case(
        _edit("ride_comfort", 'quantity = "body_acc_y"\nstatistic = "max_abs"',
              'quantity = "body_acc_y"\nstatistic = "max_abs"\nwindow = 5.0'), "criteria[1].window", "ignored")),
    Case("duplicate id", "limits", _run_case(
        _edit("ride_comfort", 'id = "body_acc_y_tb10621"', 'id = "body_acc_z_tb10621"'), "criteria[1].id",
        "duplicate id")),
    Case("no criteria", "limits", _run_case(_drop_criteria, "'criteria'", "missing key")),
    Case("criteria = []", "limits", _run_case(_empty_criteria, "'criteria'", "at least one")),
    Case("two files of one name", "limits", _run_case(_same_name, "'name'", "duplicate", "ride_comfort.toml")),
    Case("limit file binary", "limits", _run_case(_binary)),
    Case("limit file not UTF-8", "limits", _run_case(_not_utf8, "UTF-8")),
    Case("limit file is a directory", "limits", _run_case(_directory, "directory")),
    Case("limit file is a FIFO", "limits", _isolated(_run_case(_fifo, "FIFO"))),
    Case("limit file -> /dev/zero", "limits", _isolated(_run_case(_dev_zero, "device"))),
    Case("limit file 64 MiB", "limits", _isolated(_run_case(_huge, "MiB"))),
    Case("no limit file", "limits", _no_limit_files),
    Case("broken limit (sweep)", "limits", _run_case(_value("-3.5"), "criteria[0].limit.value", argv=_sweep)),
    Case("broken limit (det run, report)", "limits", _run_case(_value("nan"), "criteria[0].limit.value",
                                                                argv=_det_with_report)),
    Case("broken limit (report)", "limits", _report_of_results),
    Case("own limit file inf (load_limits)", "limits", _python_load),
    Case("own limit file 0 (result.checks)", "limits", _python_checks),
]
