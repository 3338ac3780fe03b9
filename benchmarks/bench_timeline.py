"""Benchmark: where the time of the reference study's PEM goes, part by part (docs/speed.md, issue 28).

    python benchmarks/bench_timeline.py [--repeat 3] [--step compiled|numpy]

One process (``workers=1``) runs ``run_pem(li_zhu_2011)`` as shipped (batched engine, its local
grid-error estimate) ``--repeat`` times after a warm-up run (imports, the compiled code's cache);
each run under cProfile, whose cumulative times of the functions below split the run into its parts:
the compiled step (or, with ``--step numpy``, the numpy step's solve and update), the outputs, the
per-block operators, the time-only block data, the PEM reducer, the linear mean and the rest (set-up,
the task loop, the PSD reduction). cProfile adds a little to every Python call, so the parts are
read as shares; the run's own wall time is measured without the profiler, before. Prints medians.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import statistics
import time
import warnings

#: the parts of a run: label -> (file suffix, function name) whose cumulative time is the part's
PARTS = {
    "compiled step (run_steps)": ("batched/compiled.py", "run_steps"),
    "numpy step: solve": ("batched/run.py", "solve"),
    "numpy step: update": ("batched/run.py", "update"),
    "outputs (compiled)": ("batched/compiled.py", "write_outputs"),
    "outputs (numpy)": ("batched/outputs.py", "write"),
    "per-block operators (prepare)": ("batched/run.py", "prepare"),
    "time-only block data (step_block)": ("batched/steps.py", "step_block"),
    "PEM reducer (record)": ("methods/pseudo_reduction.py", "record"),
    "linear mean": ("batched/mean.py", "linear_mean"),
}


def _parts(stats: pstats.Stats) -> dict[str, float]:
    out = {k: 0.0 for k in PARTS}
    for (path, _, name), (_, _, _, cum, _) in stats.stats.items():  # type: ignore[attr-defined]
        for label, (suffix, fn) in PARTS.items():
            if name == fn and path.replace(os.sep, "/").endswith(suffix):
                out[label] += cum
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--step", default="compiled", choices=("compiled", "numpy"))
    a = parser.parse_args()
    warnings.simplefilter("ignore")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import tb_exudyn as tbx
    from tb_exudyn.engines.batched import BatchedOptions
    from tb_exudyn.methods import run_pem

    sc = tbx.load_scenario("li_zhu_2011")
    opts = BatchedOptions(step=a.step)
    run_pem(sc, workers=1, progress=False, options=opts)  # warm-up
    walls, totals, parts = [], [], {k: [] for k in PARTS}
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        run_pem(sc, workers=1, progress=False, options=opts)
        walls.append(time.perf_counter() - t0)
        prof = cProfile.Profile()
        t0 = time.perf_counter()
        prof.enable()
        run_pem(sc, workers=1, progress=False, options=opts)
        prof.disable()
        totals.append(time.perf_counter() - t0)
        for k, v in _parts(pstats.Stats(prof)).items():
            parts[k].append(v)
    wall, total = statistics.median(walls), statistics.median(totals)
    print(f"li_zhu_2011, run_pem(workers=1), step {a.step}: wall {wall:.2f} s (median of {a.repeat}; "
          f"{total:.2f} s under cProfile); load {os.getloadavg()[0]:.2f}")
    named = 0.0
    for k, v in parts.items():
        m = statistics.median(v)
        if m > 0:
            named += m if k != "linear mean" else 0.0  # the mean's integration is inside the parts above
            print(f"  {k:36s} {m:6.2f} s  {m / total:5.1%}")
    print(f"  {'the rest (set-up, tasks, PSD reduction)':36s} {total - named:6.2f} s  {(total - named) / total:5.1%}")


if __name__ == "__main__":
    main()
