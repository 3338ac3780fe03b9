"""The mode tables do not depend on the BLAS kernel (issue 27).

Exact problem: the shipped scenario ``quick`` (one ICE motor car, car15, on one 32 m span: its
decoupled weak springs are critically damped, double roots that round-off splits either into two
reals or into a conjugate pair; its bogie yaw/lateral modes are almost undamped) and the same
scenario with the ICE motor creep car (two identical wheelsets' slow spin roots, -7e-4 1/s, a
double root on a matrix of norm 2e6). Each table is computed in a child process under each
OPENBLAS_CORETYPE this test names (numpy's OpenBLAS picks its kernel from it), at rest and with the
train standing on the bridge.

Reference: the table of the machine's default kernel, computed the same way. The rows must be the
same, in number, kind and label (exact), and each row's undamped frequency and damping ratio
must agree within 1e-6 (relative, and absolute for zeta): the kernels differ by round-off, 1e-13
relative on a simple root; a critically damped double root lambda (1 +- d) carries d of order
sqrt(eps) = 1.5e-8 (times the root's conditioning), which 1e-6 covers with margin while a wrong
pairing of rows (different modes, 1e-2 apart or more) still fails.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("exudyn")

pytestmark = pytest.mark.exudyn

ROOT = Path(__file__).resolve().parents[2]
KERNELS = ("Haswell", "SkylakeX", "Prescott", "Zen")
#: the instructions each kernel's code uses (Linux /proc/cpuinfo flag names; pni is SSE3): a kernel
#: this CPU lacks dies of SIGILL in OpenBLAS, whatever our code does, so it cannot be tested here
#: (the same rule as .ci/run's cpu_can_run)
NEEDS = {"Haswell": ("avx2", "fma"), "Zen": ("avx2", "fma"), "Prescott": ("pni",),
         "SkylakeX": ("avx512f", "avx512dq", "avx512bw", "avx512vl")}


def cpu_lacks(kernel: str) -> tuple[str, ...]:
    """The instructions of ``kernel`` this CPU does not have (empty where /proc/cpuinfo is not there:
    then every kernel is tried)."""
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return ()
    line = next((ln for ln in text.splitlines() if ln.startswith("flags")), "")
    flags = set(line.partition(":")[2].split())
    return tuple(f for f in NEEDS[kernel] if f not in flags) if flags else ()

CHILD = r"""
import json, sys
import numpy as np
from tb_exudyn.builder.system_modes import system_modes
from tb_exudyn.scenario import Train, load_scenario, load_vehicle
out = {}
base = load_scenario("quick")
for name, sc in (("car15", base),
                 ("creep", base.replace(train=Train(vehicles=(load_vehicle("ice_motor_creep"),))))):
    for where, pos in (("rest", None), ("on bridge", 10.0)):
        t = system_modes(sc, pos)
        z = np.nan_to_num(t.damping_ratio, nan=-1.0)
        out[f"{name} {where}"] = {"kind": list(t.kind), "label": list(t.label),
                                  "frequency": t.frequency.tolist(), "zeta": z.tolist()}
json.dump(out, sys.stdout)
"""


def tables(kernel: str | None) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")}
    env.update(PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    if kernel is not None:
        env["OPENBLAS_CORETYPE"] = kernel
    proc = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, env=env, cwd=ROOT,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout)


@pytest.fixture(scope="module")
def reference() -> dict:
    return tables(None)


@pytest.mark.parametrize("kernel", KERNELS)
def test_mode_tables_are_the_same_on_every_blas_kernel(kernel, reference):
    missing = cpu_lacks(kernel)
    if missing:
        pytest.skip(f"this CPU cannot run OpenBLAS's {kernel} kernel (no {', '.join(missing)})")
    got = tables(kernel)
    assert got.keys() == reference.keys()
    for key, ref in reference.items():
        g = got[key]
        assert len(g["kind"]) == len(ref["kind"]), (key, len(g["kind"]), len(ref["kind"]))
        assert g["kind"] == ref["kind"], key
        assert g["label"] == ref["label"], key
        f, f_ref = np.array(g["frequency"]), np.array(ref["frequency"])
        assert np.allclose(f, f_ref, rtol=1e-6, atol=0.0), (key, np.abs(f / np.where(f_ref > 0, f_ref, 1) - 1).max())
        assert np.abs(np.array(g["zeta"]) - np.array(ref["zeta"])).max() < 1e-6, key
