"""What a worker process imports before its first task.

Every PEM worker (spawned) imports tb_exudyn.methods.pem and the batched engine before it can take a
task, and so does every command. scipy's fft, interpolate, optimize, special, stats and signal
packages cost about 0.7 s at import on the project's machine (measured with ``python -X importtime``:
1.35 s -> 0.62 s for these two imports) and are needed only by some runs (Monte Carlo profiles, creep
cars, exceedance statistics, comfort filters), which import them on first use. Numba (about 0.25 s)
is imported by the first integration with the compiled step or the compiled PEM reducer
(tb_exudyn/jit.py), not before.
"""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("scipy.fft", "scipy.interpolate", "scipy.optimize", "scipy.special", "scipy.stats", "scipy.signal",
         "matplotlib", "numba")


def test_a_pem_worker_imports_no_heavy_scipy_package():
    """Problem: a fresh interpreter imports what a PEM worker of the batched engine imports.
    Reference: the list above, none of which may be loaded (exact: a module is loaded or not)."""
    code = ("import sys, json; import tb_exudyn.methods.pem, tb_exudyn.engines.batched; "
            f"print(json.dumps([m for m in {list(HEAVY)!r} if m in sys.modules]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd="/")
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []
