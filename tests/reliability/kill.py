"""A process SIGKILLed while it saves a large result over an older one (shared by the tests and by
measure.py): afterwards the folder must load as the old result or as the new one, never a mix.

The child saves a TimeHistory of 40 channels x 250 000 steps (80 MB) whose values are all equal to
``value`` and whose provenance says ``tag`` (and carries 300 000 numbers, so that writing meta.json
takes a while too). ``outcome`` reads a folder back: "old" (tag old, every value 1), "new" (tag
new, every value 2), "mix" (anything else that loads), or the error line when it does not load.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

CHILD = """
import signal, sys
import numpy as np
from tb_exudyn.results import TimeHistory
folder, tag, value, kill = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
nc, nt = 40, 250_000
names = [f"bridge.c{i}.disp_z" for i in range(nc)]
th = TimeHistory(time=np.arange(nt) * 1e-3, channels={n: np.full(nt, value) for n in names},
                 units={n: "m" for n in names}, provenance={"tag": tag, "pad": list(range(300_000))})
print("ready", flush=True)
if kill != "none":  # SIGPROF's default action ends the process at once, as SIGKILL, after that much CPU time
    signal.setitimer(signal.ITIMER_PROF, max(float(kill), 1e-6))
th.save(folder)
print("saved", flush=True)
"""

READ = """
import sys
import numpy as np
from tb_exudyn.results import load_results
try:
    th = load_results(sys.argv[1])
except Exception as exc:
    print("error:", str(exc).splitlines()[0][:200])
    sys.exit(0)
values = set(np.unique(np.array([th[n] for n in th.names])).tolist())
tag = th.provenance.get("tag")
print("old" if (tag, values) == ("old", {1.0}) else "new" if (tag, values) == ("new", {2.0}) else f"mix: {tag} {values}")
"""


def child_env(root: Path) -> dict[str, str]:
    """Environment of a child that imports tb_exudyn from ``root`` (run it in a folder holding no
    tb_exudyn: ``python -c`` puts the current folder first on the path)."""
    return {**os.environ, "PYTHONPATH": str(root), "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def save_in_child(root: Path, folder: Path, tag: str, value: float, kill_after: float | None) -> bool:
    """Run the child saving ``folder``; end it at once (no clean-up, as SIGKILL) after ``kill_after``
    seconds of its own CPU time into the save (None: let it finish): counted by the child's CPU clock,
    so the point of the kill does not depend on how loaded the machine is. Returns whether the save
    finished."""
    kill = "none" if kill_after is None else repr(float(kill_after))
    proc = subprocess.Popen([sys.executable, "-c", CHILD, str(folder), tag, str(value), kill], stdout=subprocess.PIPE,
                            text=True, env=child_env(root), cwd=Path(folder).parent)
    assert proc.stdout is not None
    try:
        assert proc.stdout.readline().strip() == "ready"
        out = proc.communicate(timeout=600)[0]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return "saved" in out


def outcome(root: Path, folder: Path) -> str:
    """How ``folder`` reads back with the checkout at ``root`` (in a fresh process)."""
    proc = subprocess.run([sys.executable, "-c", READ, str(folder)], capture_output=True, text=True,
                          env=child_env(root), timeout=120, cwd=Path(folder).parent)
    return (proc.stdout.strip() or proc.stderr.strip().splitlines()[-1])[:300]


__all__ = ["CHILD", "READ", "outcome", "save_in_child"]
