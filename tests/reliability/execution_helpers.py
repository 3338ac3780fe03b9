"""Shared pieces of the execution-layer reliability tests (issue 15): tiny scenarios, the command
run in a subprocess, folder snapshots, process trees.

The scenarios: the damped VBI-2D sprung mass (5750 kg) over the VBI-2D 25 m beam at 300 km/h, German
low-interference vertical profile, two output channels. TINY (10 m approach, 6 frequencies 2-20 Hz,
2 ms step) runs in a fraction of a second on the batched engine (4 tasks: the mean and 3 slices);
SLOW (150 m approach, 16 frequencies) on the Exudyn engine is 17 tasks of about 0.2 s each, long
enough to be interrupted or killed part-way.
"""

from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[2]

_SCENARIO = """\
name = "{name}"
description = "execution reliability test"
speed_kmh = {speed}
bridge = "vbi2d_beam"

[train]
vehicles = ["vbi2d_damped"]

[track]
irregularities = ["german_low.vertical"]
wavelength_min = 1.0
wavelength_max = 120.0
lead_in = {lead_in}
taper_length = 5.0
run_out = 5.0

[analysis]
time_step = {time_step}
output_step = {output_step}
freq_min = 2.0
freq_max = 20.0
n_freq = {n_freq}
n_samples = 4
seed = 1
mode_max_frequency = 80.0
channels = {channels}
"""


def write_scenario(path: Path, *, name: str = "tiny", speed: float = 300.0, lead_in: float = 10.0,
                   time_step: float = 0.002, output_step: float = 0.01, n_freq: int = 6,
                   channels: str = '["bridge.span1.mid.acc_z", "car1.body.acc_z"]') -> Path:
    """A scenario file (see the module docstring); the arguments change one value each."""
    path.write_text(_SCENARIO.format(name=name, speed=speed, lead_in=lead_in, time_step=time_step,
                                     output_step=output_step, n_freq=n_freq, channels=channels), encoding="utf-8")
    return path


def slow_scenario(path: Path, n_freq: int = 16) -> Path:
    return write_scenario(path, name="slow", lead_in=150.0, n_freq=n_freq)


def env() -> dict[str, str]:
    """The environment of a child process: this worktree's tb_exudyn first, one BLAS thread."""
    out = dict(os.environ)
    out["PYTHONPATH"] = str(ROOT) + (os.pathsep + out["PYTHONPATH"] if out.get("PYTHONPATH") else "")
    out.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
    return out


def cli(*args: object, cwd: Path | None = None, timeout: float = 120) -> subprocess.CompletedProcess:
    """``tb-exudyn ARGS`` in a child process (text output captured)."""
    return subprocess.run([sys.executable, "-m", "tb_exudyn", *map(str, args)], capture_output=True, text=True,
                          env=env(), cwd=cwd or ROOT, timeout=timeout)


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start_cli(*args: object, new_session: bool = False) -> subprocess.Popen:
    """The command in a child process, with SIGINT's default disposition as at a terminal (a suite run
    in the background of a non-interactive shell inherits SIGINT ignored, and Python then installs
    no KeyboardInterrupt handler: the Ctrl-C tests would test nothing)."""
    return subprocess.Popen([sys.executable, "-m", "tb_exudyn", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env(), cwd=ROOT, start_new_session=new_session,
                            preexec_fn=_default_sigint)


def run_args(scenario: Path, out: Path, *extra: object, engine: str = "batched", workers: int = 1) -> list[object]:
    return ["run", scenario, "--engine", engine, "--workers", workers, "--out", out, "--no-figures", "--no-progress",
            *extra]


def error_lines(stderr: str) -> list[str]:
    """The lines of stderr that are not warnings (the scenario's own advice about its short approach):
    a warning is a line "tb-exudyn: warning: ..." and its continuation, indented by two spaces."""
    out, in_warning = [], False
    for line in stderr.splitlines():
        if line.startswith("tb-exudyn: warning:"):
            in_warning = True
        elif not (in_warning and line.startswith("  ")):
            in_warning = False
            if line.strip():
                out.append(line)
    return out


def assert_one_line_error(proc: subprocess.CompletedProcess, *named: str, code: int = 2) -> str:
    """Exit ``code``, no traceback, one error line naming everything in ``named``; returns the line."""
    assert proc.returncode == code, (proc.returncode, proc.stderr[-2000:])
    assert "Traceback" not in proc.stderr, proc.stderr[-2000:]
    lines = error_lines(proc.stderr)
    assert len(lines) == 1, lines
    for text in named:
        assert text in lines[0], (text, lines[0])
    return lines[0]


def snapshot(folder: Path, ignore: tuple[str, ...] = (".tb_exudyn.lock",)) -> dict[str, str]:
    """Every entry below ``folder`` with the hash of its content (files) or its kind: what 'nothing
    changed' compares. The lock file is left out: a run that finds a killed run's lock file removes it."""
    out = {}
    for p in sorted(folder.rglob("*")):
        if p.name in ignore:
            continue
        rel = str(p.relative_to(folder))
        if p.is_symlink():
            out[rel] = "link -> " + os.readlink(p)
        elif p.is_file():
            out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
        else:
            out[rel] = "dir"
    return out


def wait_for(condition: Callable[[], bool], timeout: float = 90.0) -> bool:
    end = time.time() + timeout
    while time.time() < end:
        if condition():
            return True
        time.sleep(0.05)
    return False


def finished_tasks(out: Path, name: str = "checkpoint") -> int:
    tasks = out / name / "tasks"
    return len(list(tasks.glob("*.npz"))) if tasks.is_dir() else 0


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` now (from /proc)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
        except (OSError, IndexError, ValueError):
            continue
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def alive(pids: list[int]) -> list[int]:
    """The processes of ``pids`` that still run (not zombies)."""
    out = []
    for pid in pids:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state not in ("Z", "X"):
            out.append(pid)
    return out


def std_of(folder: Path):  # noqa: ANN201 - numpy array or None
    """sigma of the result saved in ``folder`` (None when it does not load)."""
    from tb_exudyn.errors import UserError
    from tb_exudyn.results import load_results

    try:
        return load_results(folder).std
    except (UserError, OSError, ValueError, KeyError):
        return None
