"""Every hint a message gives works as given (issue 49).

The hints are collected from the package's own source: every string a message is built from (string
constants and f-strings, without docstrings and argparse help), searched for hint-like text: a
``--set KEY=`` example, ``use KEY >= VALUE`` (the command line turns it into ``--set KEY=VALUE``:
cli.text.with_set_hint), ``run again with --FLAG``, ``use|fewer|or|with --FLAG``, the library's
``overwrite=True`` / ``resume=True`` / ``keep_checkpoint=True`` and ``another out folder`` (the command
line respells them as flags: cli.flags.MENTIONS). Each hint found must have a case here (a new hint
without one fails :func:`test_every_hint_in_the_package_has_a_case`), and each case provokes its message
on a small scenario (quick, one car over one 32 m span), takes the hint from the printed text where
it can, and runs the command again with it, as given: it must succeed (exit 0) and, for a warning,
the warning must be gone.

The commands run as subprocesses, as a user runs them (a fresh process per command: warnings are not
deduplicated across commands as they would be in one process).
"""

from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Callable, Iterator

import pytest

import tb_exudyn
from tb_exudyn.scenario import load_scenario, save_scenario
from tb_exudyn.scenario.registry import model_files

PACKAGE = Path(tb_exudyn.__file__).resolve().parent
ROOT = PACKAGE.parent
SCENARIO_KEY = r"(?:track|analysis|bridge|train)"

#: (pattern over a message's text, the hint it gives) -- the hint's identity: the flag or the --set key
HINT_PATTERNS: tuple[tuple[re.Pattern[str], Callable[[re.Match[str]], str]], ...] = (
    (re.compile(rf"--set ({SCENARIO_KEY}[A-Za-z0-9_.]*)="), lambda m: f"--set {m[1]}"),
    (re.compile(rf"\b(?i:use) ({SCENARIO_KEY}\.[A-Za-z0-9_.]+) (?:>=|<=|=) "), lambda m: f"--set {m[1]}"),
    (re.compile(r"(?i:run again with) (--[a-z-]+|resume)\b"), lambda m: "--resume" if m[1] == "resume" else m[1]),
    (re.compile(r"\b(overwrite|resume|keep_checkpoint)=True"), lambda m: "--" + m[1].replace("_", "-")),
    (re.compile(r"\banother (?:out folder|--out|output folder)"), lambda m: "--out"),
    (re.compile(r"\b(?i:use|fewer|or|with) (--[a-z][a-z-]+)"), lambda m: m[1]),
)


def _message_texts(tree: ast.AST) -> Iterator[str]:
    """The strings of a module that messages are made of: constants and f-strings (a formatted field as
    "{}"), without docstrings and the command line's help texts."""
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                skip.add(id(first.value))
        if isinstance(node, ast.keyword) and node.arg in ("help", "description", "epilog", "usage"):
            skip.update(id(sub) for sub in ast.walk(node.value))
        if isinstance(node, ast.JoinedStr):
            skip.update(id(v) for v in node.values)
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.JoinedStr):
            yield "".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.values)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            yield node.value


def collect_hints() -> dict[str, list[str]]:
    """hint -> the modules whose messages give it."""
    found: dict[str, list[str]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        for text in _message_texts(ast.parse(path.read_text(encoding="utf-8"))):
            for pattern, hint in HINT_PATTERNS:
                for m in pattern.finditer(text):
                    name = hint(m)
                    if name != "--set":  # "--set" alone names the option, it asks for nothing
                        found.setdefault(name, []).append(str(path.relative_to(PACKAGE)))
    return found


# ------------------------------------------------------------------------------------------ running
def tb(*argv: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
           "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-m", "tb_exudyn", *argv], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def given(text: str, pattern: str) -> list[str]:
    """The hint as the message printed it: the words matched by ``pattern`` in ``text`` (whitespace
    of a wrapped line joined)."""
    joined = " ".join(text.split())
    m = re.search(pattern, joined)
    assert m, f"no {pattern!r} in: {joined}"
    return m.group(0).split()


def _fast_run(d: Path, out: str, *extra: str) -> list[str]:
    return ["run", "quick", "--method", "det", "--out", str(d / out), "--no-figures", *extra]


def case_set_track_lead_in(d: Path) -> None:
    """The warning on a lead-in too short to settle: 'use track.lead_in >= X m' (--set track.lead_in=X)."""
    short = _fast_run(d, "a", "--set", "track.lead_in=10", "--set", "track.taper_length=0")
    first = tb(*short, cwd=d)
    assert first.returncode == 0, first.stderr
    hint = given(first.stderr, r"--set track\.lead_in=[0-9.e+-]+")
    again = tb(*short, "--overwrite", *hint, cwd=d)
    assert again.returncode == 0 and "track.lead_in = " not in again.stderr, again.stderr


def case_set_analysis_time_step(d: Path) -> None:
    """The warning on a time step that does not resolve the contact mode (--set analysis.time_step=X)."""
    coarse = _fast_run(d, "b", "--set", "analysis.time_step=0.002")
    first = tb(*coarse, cwd=d)
    assert first.returncode == 0, first.stderr
    hint = given(first.stderr, r"--set analysis\.time_step=[0-9.e+-]+")
    again = tb(*coarse, "--overwrite", *hint, cwd=d)
    assert again.returncode == 0 and "contact mode" not in again.stderr, again.stderr


def case_set_analysis_freq_spacing(d: Path) -> None:
    """The grid warning of a coarse linear grid: 'use analysis.freq_spacing = adaptive' (--set
    analysis.freq_spacing=adaptive), given with the scenario's n_freq of 40, below what the adaptive
    grid needs: the run takes what it needs and says so (the issue's failure)."""
    sc = load_scenario("quick")
    path = save_scenario(sc.replace(analysis=sc.analysis.replace(freq_spacing="linear", n_freq=40)), d / "q40.toml")
    argv = ["run", str(path), "--out", str(d / "c"), "--no-figures", "--workers", "1"]
    first = tb(*argv, cwd=d)
    assert first.returncode == 0 and "frequency grid is too coarse" in first.stderr, first.stderr
    hint = given(first.stderr, r"--set analysis\.freq_spacing=\w+")
    again = tb(*argv, "--overwrite", *hint, cwd=d)
    assert again.returncode == 0, again.stderr
    assert "frequency grid is too coarse" not in again.stderr and "adaptive grid:" in again.stdout, again.stdout


def case_set_bridge(d: Path) -> None:
    """--set's help: 'a file (--set bridge=my/x.toml) is found from the working folder'."""
    (d / "my").mkdir()
    (d / "my" / "x.toml").write_text(model_files("bridges")["continuous_3x32m"].read_text())
    done = tb("show", "quick", "--set", "bridge=my/x.toml", cwd=d)
    assert done.returncode == 0 and "continuous_3x32m" in done.stdout, done.stderr


def case_overwrite_out_resume_keep_checkpoint(d: Path) -> None:
    """A second run into the folder of an earlier one is refused: 'use --resume to continue it,
    --overwrite to replace it, or another --out'; each works as given. A run interrupted (its checkpoint
    kept, its result not written) is told 'run again with --resume'; that works as given too."""
    argv = ["run", "quick", "--out", str(d / "e"), "--no-figures", "--workers", "1", "--keep-checkpoint"]
    assert tb(*argv, cwd=d).returncode == 0
    refused = tb(*argv, cwd=d)
    assert refused.returncode == 2
    for flag in ("--resume", "--overwrite", "--out"):
        assert flag in " ".join(refused.stderr.split()), refused.stderr
    assert tb(*argv, "--resume", cwd=d).returncode == 0
    assert tb(*argv, "--overwrite", cwd=d).returncode == 0
    assert tb(*argv[:3], str(d / "other"), *argv[4:], cwd=d).returncode == 0
    # as after Ctrl-C: the checkpoint kept, no result
    import shutil

    shutil.rmtree(d / "e" / "pem")
    resumed = tb(*argv, "--resume", cwd=d)
    assert resumed.returncode == 0 and "from the checkpoint" in resumed.stdout, resumed.stdout + resumed.stderr


def case_engine(d: Path) -> None:
    """'--linearization with --engine batched (the Exudyn engine: ...)': the refused command with
    --engine batched added runs."""
    argv = ["run", "quick", "--engine", "exudyn", "--linearization", "static", "--out", str(d / "g"),
            "--no-figures", "--workers", "1"]
    refused = tb(*argv, cwd=d)
    assert refused.returncode == 2 and "--engine batched" in refused.stderr
    assert tb(*argv, "--engine", "batched", cwd=d).returncode == 0


def case_memory_flags(d: Path) -> None:
    """The out-of-memory message: 'fewer --workers, ..., or --psd-channels key': the flags as given."""
    done = tb("run", "quick", "--out", str(d / "h"), "--no-figures", "--workers", "1", "--psd-channels", "key", cwd=d)
    assert done.returncode == 0, done.stderr


def case_sweep_freq_spacing(d: Path) -> None:
    """The sweep report on a grid not converged: 'Use --freq-spacing adaptive or more frequencies
    (--n-freq)': a sweep of a scenario with 40 linear frequencies, with --freq-spacing adaptive added,
    runs (each speed takes the count its adaptive grid needs)."""
    sc = load_scenario("quick")
    path = save_scenario(sc.replace(analysis=sc.analysis.replace(freq_spacing="linear", n_freq=40)), d / "q40.toml")
    argv = ["sweep", str(path), "--speeds-kmh", "200,250", "--out", str(d / "s"), "--no-figures", "--workers", "1"]
    done = tb(*argv, "--freq-spacing", "adaptive", cwd=d)
    assert done.returncode == 0, done.stderr
    more = tb(*argv, "--n-freq", "80", "--out", str(d / "s2"), cwd=d)
    assert more.returncode == 0, more.stderr


def case_uq_design(d: Path) -> None:
    """A study of one key on the default tensor design has as many nodes as basis terms, so no
    leave-one-out error: 'use --design sobol --nodes N' (the sprung mass of
    tests/methods/test_uq_sprung_mass.py, damping uniform +-20 %, order 2): run as given, the note is gone."""
    sys.path.insert(0, str(ROOT / "tests" / "methods"))
    from test_uq_sprung_mass import scenario

    path = save_scenario(scenario(), d / "s.toml")
    path.write_text(path.read_text() + '\n[uncertain."train.vehicles.0.damping"]\ndistribution = "uniform"\n'
                    'relative_bounds = [-0.2, 0.2]\n')
    argv = ["uq", str(path), "--order", "2", "--workers", "1", "--no-progress", "--no-figures",
            "--channels", "car1.body.acc_z"]
    first = tb(*argv, "--out", str(d / "u1"), cwd=d)
    assert first.returncode == 0 and "error is unknown" in first.stdout + first.stderr, first.stdout + first.stderr
    hint = given(first.stdout + first.stderr, r"--design sobol --nodes [0-9]+")
    again = tb(*argv, *hint, "--out", str(d / "u2"), cwd=d)
    assert again.returncode == 0 and "error is unknown" not in again.stdout + again.stderr, again.stdout + again.stderr


#: hint -> the cases that run it as given
CASES: dict[str, tuple[Callable[[Path], None], ...]] = {
    "--set track.lead_in": (case_set_track_lead_in,),
    "--set analysis.time_step": (case_set_analysis_time_step,),
    "--set analysis.freq_spacing": (case_set_analysis_freq_spacing,),
    "--set bridge": (case_set_bridge,),
    # (Ctrl-C tells --resume only to commands that have it; check's own hints after Ctrl-C, "run the same
    # command again" and --overwrite, are run as given in tests/reliability/test_check_outputs.py)
    "--resume": (case_overwrite_out_resume_keep_checkpoint,),
    "--overwrite": (case_overwrite_out_resume_keep_checkpoint,),
    "--out": (case_overwrite_out_resume_keep_checkpoint,),
    "--keep-checkpoint": (case_overwrite_out_resume_keep_checkpoint,),
    "--engine": (case_engine,),
    "--workers": (case_memory_flags,),
    "--psd-channels": (case_memory_flags,),
    "--freq-spacing": (case_sweep_freq_spacing,),
    "--design": (case_uq_design,),
}


def test_every_hint_in_the_package_has_a_case():
    found = collect_hints()
    assert "--set analysis.freq_spacing" in found and "--resume" in found  # the collector sees the known ones
    missing = {h: found[h] for h in found if h not in CASES}
    assert not missing, f"hints without a case here (add one that runs it as given): {missing}"
    stale = set(CASES) - set(found)
    assert not stale, f"cases of hints no message gives any more: {stale}"


_ALL = sorted({case for cases in CASES.values() for case in cases}, key=lambda c: c.__name__)


@pytest.mark.slow
@pytest.mark.exudyn
@pytest.mark.parametrize("case", _ALL, ids=[c.__name__ for c in _ALL])
def test_each_hint_works_as_given(case, tmp_path):
    case(tmp_path)
