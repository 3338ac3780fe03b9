"""Measure the hostile-input table (issues 15 and 27) on any checkout: ``python -m tests.reliability.measure ROOT [--kills N]``.

Runs every case of cases.py in its own process against the tb_exudyn at ROOT (2 GB of address
space, 20 s), and N SIGKILLs of a large save (kill.py) plus one save that raises between the two
files, and prints one row per group: cases tried, clear errors (exit 2, one line, naming the file
or key), unclear errors (exit 2 without naming it), tracebacks (or hangs), wrong results (exit 0
on a hostile input, or old metadata over new arrays), data lost (neither the old nor the new result
loads), and runs that wrote, moved or deleted files.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

from .all_cases import ALL_CASES as CASES
from .cases import snapshot, subprocess_command
from .kill import child_env, outcome, save_in_child

RAISE_BETWEEN = """
import sys
import numpy as np
from tb_exudyn.results import TimeHistory
import tb_exudyn.storage as storage
names = ["bridge.a.disp_z", "bridge.b.disp_z"]
def th(tag, value):
    return TimeHistory(time=np.arange(51) * 0.01, channels={n: np.full(51, value) for n in names},
                       units={n: "m" for n in names}, provenance={"tag": tag})
folder = sys.argv[1]
th("old", 1.0).save(folder)
def boom(*args, **kwargs):
    raise OSError(28, "No space left on device")
if hasattr(storage, "save_result_folder"):          # this branch: the meta.json write of the new folder
    write_file = storage._write_file
    storage._write_file = lambda p, w: boom() if p.name == "meta.json" else write_file(p, w)
else:                                               # base: the second of the two file replacements
    import tb_exudyn.results.time_history as m
    m.save_json_atomic = boom
try:
    th("new", 2.0).save(folder)
except OSError:
    pass
"""


def classify(code: int | None, err: str, expect: tuple[str, ...]) -> str:
    if code is None:
        return "traceback"  # hung (or blew the time limit)
    if "Traceback" in err or code not in (0, 2):
        return "traceback"
    if code == 0:
        return "wrong"
    one_line = len(err.strip().splitlines()) == 1
    return "clear" if one_line and all(e in err for e in expect) else "unclear"


def run_cases(root: Path, scratch: Path) -> list[tuple[str, str, str, bool, str]]:
    rows = []
    for case in CASES:
        d = Path(tempfile.mkdtemp(dir=scratch))
        (d / "work").mkdir()
        (d / "cwd").mkdir()
        run = case.build(d / "work")
        before = snapshot(d)
        env = {**child_env(root), **run.env, "MPLBACKEND": "Agg"}
        try:
            proc = subprocess.run(subprocess_command(run, sys.executable), capture_output=True, text=True,
                                  timeout=20, env=env, cwd=d / "cwd")
            code, err = proc.returncode, proc.stderr
        except subprocess.TimeoutExpired:
            code, err = None, "timeout after 20 s"
        kind = classify(code, err, run.expect)
        wrote = snapshot(d) != before
        last = (err.strip().splitlines() or [""])[-1][:160]
        rows.append((case.group, case.id, kind, wrote, last))
        shutil.rmtree(d, ignore_errors=True)
    return rows


def run_saves(root: Path, scratch: Path, kills: int) -> list[tuple[str, str, str, bool, str]]:
    rows = []
    d = Path(tempfile.mkdtemp(dir=scratch))
    subprocess.run([sys.executable, "-c", RAISE_BETWEEN, str(d / "det")], env=child_env(root), check=True, cwd=d)
    got = outcome(root, d / "det")
    left = [p.name for p in list(d.iterdir()) + list((d / "det").iterdir()) if p.name.startswith(".")]
    rows.append(("save", "write raising between the two files", _save_kind(got), bool(left), f"{got}; leftovers {left}"))
    shutil.rmtree(d, ignore_errors=True)
    for i in range(kills):
        delay = 0.6 * i / max(kills - 1, 1)
        d = Path(tempfile.mkdtemp(dir=scratch))
        save_in_child(root, d / "det", "old", 1.0, None)
        finished = save_in_child(root, d / "det", "new", 2.0, delay)
        got = outcome(root, d / "det")
        left = [p.name for p in list(d.iterdir()) + (list((d / "det").iterdir()) if (d / "det").is_dir() else [])
                if p.name.startswith(".")]
        rows.append(("save", f"SIGKILL {delay:.2f} s into a large save", _save_kind(got), bool(left),
                     f"{got}{' (finished)' if finished else ''}; leftovers after loading {left}"))
        shutil.rmtree(d, ignore_errors=True)
    return rows


def _save_kind(got: str) -> str:
    return "clear" if got in ("old", "new") else "wrong" if got.startswith("mix") else "lost"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=Path, help="checkout whose tb_exudyn is measured")
    parser.add_argument("--kills", type=int, default=21, help="SIGKILL trials (spread over 0-0.6 s)")
    parser.add_argument("--details", action="store_true", help="print every case")
    args = parser.parse_args(argv)
    scratch = Path(tempfile.mkdtemp(prefix="tb-measure-"))
    try:
        rows = run_cases(args.root.resolve(), scratch) + run_saves(args.root.resolve(), scratch, args.kills)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if args.details:
        for group, cid, kind, wrote, last in rows:
            print(f"{group:13} {cid:42} {kind:9} {'WROTE ' if wrote else ''}{last}")
    print(f"{'group':13} {'tried':>5} {'clear':>5} {'unclear':>7} {'traceback/hang':>14} {'wrong':>5} {'lost':>4} "
          f"{'wrote/left files':>16}")
    groups = list(dict.fromkeys(r[0] for r in rows)) + ["all"]
    for g in groups:
        sel = [r for r in rows if g == "all" or r[0] == g]
        c = Counter(r[2] for r in sel)
        print(f"{g:13} {len(sel):5} {c['clear']:5} {c['unclear']:7} {c['traceback']:14} {c['wrong']:5} {c['lost']:4} "
              f"{sum(r[3] for r in sel):16}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
