"""Benchmark: the reference study's PEM, this checkout against another (today's main), side by side.

    python benchmarks/bench_speed.py [--base PATH] [--repeat 3] [--workers 2] [--no-grid-error] [--skip-dense] [--skip-exudyn]

Everything runs in fresh child processes (``python this_file --child ...`` with PYTHONPATH set to
the checkout, so each side imports its own tb_exudyn), alternating this checkout and ``--base``
(e.g. a worktree of main: ``git -C /work/main worktree add /tmp/speed/base 608e341``) run after run,
so both see the same load. Printed:

1. the full study (scenario ``li_zhu_2011``: 4 cars, 3 spans, 200 frequencies x 3 irregularity
   types, all 471 channels) with ``run_pem(engine="batched")`` on ``--workers`` processes (as
   shipped, with its grid-error sweep on the cells' midpoints; ``--no-grid-error``: without it, the
   work of a base that has none; a base from before the solver restructure runs
   ``tb_exudyn.solvers.pem.run_pem``): wall time
   and CPU time of the whole process tree (this child and its workers), the peak resident memory
   of the process tree (sampled every 20 ms; shared libraries count once per process: an upper
   bound), the load average before and after; medians over ``--repeat`` runs of each side and their
   ratios (base / this);
2. the integration's floating-point rate: the flops of every BLAS product of the batched engine's
   step (counted by wrapping the gemm kernels in a separate run; the per-block set-up and the output
   products are not counted) over the time of one integration of all 600 columns in one process
   (no reducer), with the numpy step and the compiled one, against a plain gemm of the same shapes
   (each distinct shape timed on its own with the engine's own call, weighted by its flops): the
   fraction of the machine's limit;
3. the compile time of the compiled step: a small run in a fresh process with an empty cache
   of compiled code, then with it warm (the difference: what the first run after an install pays);
4. the dense engine (naive baseline, :mod:`tb_exudyn.engines.dense`) and the Exudyn engine
   extrapolated from reduced grids (2 and 6 frequencies: time = a + b x columns, fitted) to the
   full study, in one process.

The machine may be shared (the 2-core machine of the measurements in docs/speed.md had 6 other
agents): medians, CPU times and the load are printed for that reason.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve()
THIS = HERE.parents[1]


# ====================================================================================== children
class PeakMemory:
    """Peak resident memory of this process and its children, sampled in a thread (psutil)."""

    def __init__(self, interval: float = 0.02) -> None:
        import psutil

        self.interval, self.peak, self._stop = interval, 0, threading.Event()
        self._proc = psutil.Process()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self._stop.is_set():
            total = self._proc.memory_info().rss
            for p in self._proc.children(recursive=True):
                try:
                    total += p.memory_info().rss
                except Exception:  # noqa: BLE001 - a child may just have exited
                    pass
            self.peak = max(self.peak, total)
            self._stop.wait(self.interval)

    def __enter__(self) -> "PeakMemory":
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


def _cpu_seconds() -> float:
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def child_full(workers: int, grid_error: str = "default") -> dict:
    """One full-study run; wall, CPU, peak memory, load. ``grid_error`` "off": without the grid-error
    sweep (the same work as a checkout that has none); checkouts from before the solver restructure
    (tb_exudyn.solvers) are run as they were."""
    import tb_exudyn as tbx

    try:
        from tb_exudyn.methods import run_pem
        kwargs = {"grid_error": False} if grid_error == "off" else {}
    except ImportError:  # a checkout from before issue 13 (e.g. b901919)
        from tb_exudyn.solvers.pem import run_pem
        kwargs = {}

    sc = tbx.load_scenario("li_zhu_2011")
    load0 = os.getloadavg()[0]
    with PeakMemory() as mem:
        c0, t0 = _cpu_seconds(), time.perf_counter()
        r = run_pem(sc, workers=workers, progress=False, engine="batched", **kwargs)
        wall, cpu = time.perf_counter() - t0, _cpu_seconds() - c0
    return {"wall": wall, "cpu": cpu, "peak_mib": mem.peak / 2**20, "load_before": load0, "load_after": os.getloadavg()[0],
            "mean_s": float(r.provenance.get("mean_seconds", float("nan"))), "psd_mib": r.psd.nbytes / 2**20}


class _Null:
    def record(self, i, Y, ext) -> None:  # noqa: ANN001
        pass

    def result(self) -> dict:
        return {}


def _all_columns(sc):  # noqa: ANN001, ANN202
    from tb_exudyn.methods.common import analysis_setup
    from tb_exudyn.methods.pem import harmonic_columns, pem_tasks

    return harmonic_columns(pem_tasks(sc, analysis_setup(sc).grid), sc)


def child_flops(precision: str) -> dict:
    """Flops of the batched step (counted on the numpy step, whose gemm calls the compiled step makes
    in the same order), the time of one integration of all columns with each step, and the time
    plain gemms of the same shapes take (the machine's limit for this work)."""
    import numpy as np

    import tb_exudyn as tbx
    from tb_exudyn.engines.batched import BatchedEngine, BatchedOptions, kernels

    sc = tbx.load_scenario("li_zhu_2011")
    steps = ("numpy", "compiled") if "step" in BatchedOptions.__dataclass_fields__ else (None,)
    engines = {s: BatchedEngine(sc, BatchedOptions(precision=precision, **({"step": s} if s else {}))) for s in steps}
    engine = engines[steps[0]]
    cols = _all_columns(sc)
    shapes: dict[tuple, int] = {}
    originals = dict(kernels._GEMM)

    def counting(f):  # noqa: ANN001, ANN202
        def g(alpha, a, b, beta, c, ta, tb, ow):  # noqa: ANN001, ANN202
            key = (c.shape[0], c.shape[1], a.shape[1], tb, a.dtype.str)
            shapes[key] = shapes.get(key, 0) + 1
            return f(alpha, a, b, beta, c, ta, tb, ow)
        return g

    kernels._GEMM.update({k: counting(f) for k, f in originals.items()})
    try:
        engine.integrate(cols, _Null())
    finally:
        kernels._GEMM.update(originals)
    flops = sum(2 * m * n * k * count for (m, n, k, _, _), count in shapes.items())
    t_steps = {}
    for s, eng in engines.items():
        eng.integrate(cols, _Null()) if s == "compiled" else None  # loads (or compiles) the compiled code
        times = []
        for _ in range(2):
            t0 = time.process_time()
            eng.integrate(cols, _Null())
            times.append(time.process_time() - t0)
        t_steps[str(s)] = min(times)
    t_int = t_steps[str(steps[-1])]
    # plain gemm of the same shapes: each shape on its own, the engine's own positional call
    rng = np.random.default_rng(0)
    t_gemm = 0.0
    for (m, n, k, tb, dt), count in shapes.items():
        dtype = np.dtype(dt)
        A = np.asfortranarray(rng.random((m, k)), dtype=dtype)
        B = np.asfortranarray(rng.random((n, k) if tb else (k, n)), dtype=dtype)
        C = np.asfortranarray(np.zeros((m, n)), dtype=dtype)
        f = originals[dtype]
        reps = max(20, min(2000, int(2e8 / (2 * m * n * k + 1))))
        best = float("inf")
        for _ in range(3):
            t0 = time.perf_counter()
            for _ in range(reps):
                f(1.0, A, B, 1.0, C, 0, tb, 1)
            best = min(best, (time.perf_counter() - t0) / reps)
        t_gemm += best * count
    return {"flops": flops, "integration_s": t_int, "gemm_s": t_gemm, "calls": sum(shapes.values()),
            "shapes": len(shapes), "load": os.getloadavg()[0], "by_step": t_steps}


def child_compile(cache: str) -> dict:
    """Wall time of a small PEM run (quick, 2 frequencies, no grid error) in this fresh process with
    the compiled code's cache at ``cache``: with an empty cache it includes compiling (float64 and
    float32), with a warm one loading it."""
    os.environ["NUMBA_CACHE_DIR"] = cache
    import tb_exudyn as tbx
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    sc = tbx.load_scenario("quick")
    sc = sc.replace(analysis=sc.analysis.replace(n_freq=2, freq_spacing="linear"))
    t0 = time.perf_counter()
    for precision in ("float64", "float32"):
        run_pem(sc, workers=1, progress=False, grid_error=False, options=BatchedOptions(precision=precision))
    return {"wall": time.perf_counter() - t0}


def child_reduced(engine_name: str) -> dict:
    """Run time of PEM on reduced grids (2 and 6 frequencies, same band, 3 types), one process."""
    import tb_exudyn as tbx
    from tb_exudyn.methods import run_pem

    sc = tbx.load_scenario("li_zhu_2011")
    out = {}
    for n in (2, 6):
        red = sc.replace(analysis=sc.analysis.replace(n_freq=n))
        t0 = time.perf_counter()
        r = run_pem(red, workers=1, progress=False, engine=engine_name)
        out[n] = {"wall": time.perf_counter() - t0, "columns": int(r.provenance["columns"])}
    out["full_columns"] = int(sc.analysis.n_freq) * len(sc.track.irregularities)
    out["load"] = os.getloadavg()[0]
    return out


# ======================================================================================== parent
def run_child(repo: Path, what: str, *args: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(repo), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    proc = subprocess.run([sys.executable, str(HERE), "--child", what, *args], env=env, cwd=str(repo),
                          capture_output=True, text=True, check=False)
    if proc.returncode:
        raise RuntimeError(f"child {what} in {repo} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _med(runs: list[dict], key: str) -> float:
    return statistics.median(r[key] for r in runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, default=None, help="checkout to compare with (e.g. a worktree of main)")
    parser.add_argument("--repeat", type=int, default=3, help="full-study runs of each side (medians)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--precision", default="float64", help="precision of the flop-rate measurement")
    parser.add_argument("--no-grid-error", action="store_true",
                        help="this checkout without its grid-error sweep (the same work as a base that has none)")
    parser.add_argument("--skip-dense", action="store_true")
    parser.add_argument("--skip-exudyn", action="store_true")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("args", nargs="*", help=argparse.SUPPRESS)
    a = parser.parse_args()
    warnings.simplefilter("ignore")
    if a.child:
        fn = {"full": lambda: child_full(int(a.args[0]), *a.args[1:]), "flops": lambda: child_flops(a.args[0]),
              "reduced": lambda: child_reduced(a.args[0]), "compile": lambda: child_compile(a.args[0])}[a.child]
        print(json.dumps(fn()))
        return

    sides = [("this", THIS)] + ([("base", a.base.resolve())] if a.base else [])
    print(f"{os.cpu_count()} cores; load average {os.getloadavg()}; workers {a.workers}; "
          f"grid-error sweep on this side: {'off' if a.no_grid_error else 'as shipped'}; sides: "
          + ", ".join(f"{n} = {p}" for n, p in sides))
    # 1. full study, alternating
    runs: dict[str, list[dict]] = {n: [] for n, _ in sides}
    for i in range(a.repeat):
        for name, repo in sides:
            r = run_child(repo, "full", str(a.workers), "off" if a.no_grid_error and name == "this" else "default")
            runs[name].append(r)
            print(f"  run {i + 1} {name}: wall {r['wall']:.2f} s, CPU {r['cpu']:.2f} s, peak {r['peak_mib']:.0f} MiB, "
                  f"mean task {r['mean_s']:.2f} s, load {r['load_before']:.2f} -> {r['load_after']:.2f}", flush=True)
    print("full study (li_zhu_2011, 600 columns, 471 channels), medians:")
    for name, _ in sides:
        rs = runs[name]
        print(f"  {name:5s}: wall {_med(rs, 'wall'):6.2f} s (min {min(r['wall'] for r in rs):.2f}), CPU {_med(rs, 'cpu'):6.2f} s, "
              f"peak memory {max(r['peak_mib'] for r in rs):.0f} MiB (PSD map {rs[0]['psd_mib']:.0f} MiB)")
    if a.base:
        b, t = runs["base"], runs["this"]
        print(f"  ratio base / this: wall {_med(b, 'wall') / _med(t, 'wall'):.2f} (median), "
              f"{min(r['wall'] for r in b) / min(r['wall'] for r in t):.2f} (min); CPU {_med(b, 'cpu') / _med(t, 'cpu'):.2f}")
    # 2. compile time of the compiled step (an empty cache, then the same cache warm, then again)
    import tempfile

    with tempfile.TemporaryDirectory() as cache:
        cold, warm, warm2 = (run_child(THIS, "compile", cache)["wall"] for _ in range(3))
    print(f"compiled step: a small PEM run (float64 and float32) in a fresh process {cold:.1f} s with an empty "
          f"cache, {min(warm, warm2):.1f} s with the cache warm: compiling costs about {cold - min(warm, warm2):.1f} s, "
          "once per install (the cache is the user's, tb_exudyn.jit.cache_dir; the step and the PEM reducer)")
    # 3. flop rate
    f = run_child(THIS, "flops", a.precision)
    print(f"integration ({a.precision}, all 600 columns in one process, no reducer): {f['flops'] / 1e9:.1f} GFlop in "
          f"{f['calls']} gemm calls of {f['shapes']} shapes; {f['integration_s']:.2f} s CPU = "
          f"{f['flops'] / f['integration_s'] / 1e9:.1f} GFlop/s; plain gemm of the same shapes {f['gemm_s']:.2f} s = "
          f"{f['flops'] / f['gemm_s'] / 1e9:.1f} GFlop/s; fraction {f['gemm_s'] / f['integration_s']:.0%} (load {f['load']:.2f})")
    for step, t in f.get("by_step", {}).items():
        print(f"  step {step}: {t:.2f} s CPU = {f['flops'] / t / 1e9:.1f} GFlop/s, {f['gemm_s'] / t:.0%} of plain gemm")
    # 4. dense and Exudyn, extrapolated
    t_this = _med(runs["this"], "wall")
    for eng, skip in (("dense", a.skip_dense), ("exudyn", a.skip_exudyn)):
        if skip:
            continue
        r = run_child(THIS, "reduced", eng)
        (w2, c2), (w6, c6) = (r["2"]["wall"], r["2"]["columns"]), (r["6"]["wall"], r["6"]["columns"])
        slope = (w6 - w2) / (c6 - c2)
        full = w2 + slope * (r["full_columns"] - c2)
        print(f"{eng} engine, one process: {c2} columns {w2:.1f} s, {c6} columns {w6:.1f} s -> full study "
              f"({r['full_columns']} columns) about {full:.0f} s = {full / 60:.1f} min on one core; "
              f"{full / t_this:.0f}x this checkout's batched wall time (load {r['load']:.2f})")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
