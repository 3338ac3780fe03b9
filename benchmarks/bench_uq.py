"""Benchmark: an uncertainty study's time, node by node (issue 46; docs/uq.md, "Speed").

    python benchmarks/bench_uq.py [--scenario quick] [--order 3] [--workers 2] [--repeat 3] [--phases 3]
                                  [--out DIR]

Three uncertain keys (girder E lognormal cov 5 %, damping +-30 %, girder mass +-5 %) at ``--order``
on a tensor Gauss grid ((order + 1)^3 nodes: 64 at order 3), ``tbx.run_uq`` with ``--workers``
process workers, ``--repeat`` times. Per study: the wall time, the CPU seconds of this process and
of its workers (``resource``: the pool's processes are reaped at its end), the load average, and the
per-node timeline from the result's provenance (``node_timeline``): which worker ran each node,
when it started, its PEM and its summary (the checks); the first node of each worker carries the
worker's start (imports, the compiled code's load). Then the medians.

``--phases N``: where a node's time goes, on the first N nodes' scenarios, in this process, on the
study's own code path (:class:`~tb_exudyn.methods.pem.method.PemMethod` as a node runs it: its plan,
the worker's set-up, its tasks, its finish; then the node's summary): the set-up (the model build,
the modes, the grid, the damping guard, the linear model: cProfile's cumulative times inside the
plan), the engine's set-up, the mean, the column slice, the grid error's midpoint sweep, the
reduction and the checks. A node run first in this process (imports, compiled code) is left out.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import resource
import statistics
import sys
import time
import warnings
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout: the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

KEYS = {
    "bridge.girder.E": {"distribution": "lognormal", "cov": 0.05},
    "bridge.damping_ratio": {"distribution": "uniform", "relative_bounds": [-0.3, 0.3]},
    "bridge.girder.mass_per_length": {"distribution": "uniform", "relative_bounds": [-0.05, 0.05]},
}

#: the plan's parts: label -> (file suffix, function) whose cumulative time is the part's
PLAN_PARTS = {
    "model build": ("builder/model.py", "build_model"),
    "modes": ("builder/system_modes.py", "system_modes"),
    "damping guard": ("builder/system_modes.py", "damping_guard"),
    "linear model": ("engines/exudyn_runs.py", "linear_model"),
}


def cpu_seconds() -> tuple[float, float]:
    """(this process, its reaped children) user + system CPU seconds."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, kids.ru_utime + kids.ru_stime


def study(scenario: str, order: int, workers: int, out: Path) -> dict:
    """One study: wall, CPU, load and the result's node timeline."""
    import tb_exudyn as tbx

    load0 = os.getloadavg()[0]
    c0, t0 = cpu_seconds(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = tbx.run_uq(scenario, KEYS, order=order, workers=workers, progress=False, out=out, overwrite=True)
    wall, c1 = time.perf_counter() - t0, cpu_seconds()
    return {"wall": wall, "cpu_parent": c1[0] - c0[0], "cpu_workers": c1[1] - c0[1], "load": (load0, os.getloadavg()[0]),
            "timeline": r.provenance["node_timeline"], "nodes": r.provenance["n_nodes"], "result": r}


def print_timeline(tl: dict, wall: float) -> None:
    print("  node  worker  start [s]   PEM [s]  summary [s]")
    for n, (s, w, p, q) in enumerate(zip(tl["start"], tl["worker"], tl["pem"], tl["summary"])):
        print(f"  {n:4d}  {w:6d}  {s:9.2f}  {p:8.3f}  {q:10.3f}")
    busy = {w: 0.0 for w in tl["worker"]}
    for w, p, q in zip(tl["worker"], tl["pem"], tl["summary"]):
        busy[w] += p + q
    firsts = {w: tl["start"][tl["worker"].index(w)] for w in busy}
    rest = [p + q for n, (w, p, q) in enumerate(zip(tl["worker"], tl["pem"], tl["summary"]))
            if tl["worker"].index(w) != n]
    first_nodes = [tl["pem"][tl["worker"].index(w)] + tl["summary"][tl["worker"].index(w)] for w in busy]
    print(f"  workers' first node starts at {', '.join(f'{v:.2f}' for v in firsts.values())} s; their first node "
          f"takes {', '.join(f'{v:.2f}' for v in first_nodes)} s (start-up, compiled code), the others a median "
          f"{statistics.median(rest):.3f} s (PEM {statistics.median(tl['pem'][1:]):.3f} + summary "
          f"{statistics.median(tl['summary'][1:]):.3f})")
    print(f"  busy per worker {', '.join(f'{v:.1f}' for v in busy.values())} s of {wall:.1f} s wall; "
          f"after the last node: {wall - max(s + p + q for s, p, q in zip(tl['start'], tl['pem'], tl['summary'])):.2f} s "
          "(the expansion, the bands, the save)")


def _plan_parts(stats: pstats.Stats) -> dict[str, float]:
    out = {k: 0.0 for k in PLAN_PARTS}
    for (path, _, name), (_, _, _, cum, _) in stats.stats.items():  # type: ignore[attr-defined]
        for label, (suffix, fn) in PLAN_PARTS.items():
            if name == fn and path.replace(os.sep, "/").endswith(suffix):
                out[label] = max(out[label], cum)
    return out


def node_phases(scenario) -> dict[str, float]:  # noqa: ANN001
    """One node's PEM on the study's code path, timed part by part (the module docstring)."""
    from tb_exudyn.execution import Execution
    from tb_exudyn.methods.common import MeanTask
    from tb_exudyn.methods.driver import worker_task
    from tb_exudyn.methods.pem.method import PemMethod
    from tb_exudyn.methods.sweep import check_values
    from tb_exudyn.methods.uq.method import NODE_SLICES
    from tb_exudyn.methods.uq.summary import node_summary

    method = PemMethod(scenario, "batched", None, keep_psd=False)
    execution = Execution(workers=1, progress=False, slices=NODE_SLICES, where="bench_uq")
    t: dict[str, float] = {}
    prof = cProfile.Profile()
    c = time.perf_counter()
    prof.enable()
    plan = method.plan(execution)
    prof.disable()
    t["set-up (plan)"] = time.perf_counter() - c
    t.update(_plan_parts(pstats.Stats(prof)))
    c = time.perf_counter()
    built = plan.worker.setup()
    t["engine set-up"] = time.perf_counter() - c
    t.update({"mean": 0.0, "columns": 0.0, "grid error": 0.0, "reduce": 0.0})
    for i, task in enumerate(plan.tasks):
        c = time.perf_counter()
        r = worker_task((plan.worker, built), task)
        part = ("mean" if isinstance(task.data, MeanTask) else "grid error" if task.data.midpoints else "columns")
        t[part] += time.perf_counter() - c
        c = time.perf_counter()
        method.reduce(plan.state, i, task, r)
        t["reduce"] += time.perf_counter() - c
    c = time.perf_counter()
    result = method.finish(plan.state, {})
    t["finish"] = time.perf_counter() - c
    c = time.perf_counter()
    node_summary(result, check_values)
    t["summary (checks)"] = time.perf_counter() - c
    return t


def phases(scenario_name: str, order: int, n: int) -> None:
    import tb_exudyn as tbx
    from tb_exudyn.methods.uq.method import UqMethod
    from tb_exudyn.scenario.uncertain import check_uncertain

    sc = tbx.load_scenario(scenario_name)
    keys = check_uncertain(sc, KEYS, "bench_uq")
    scenarios = UqMethod(sc, keys, order).design()[-1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        node_phases(scenarios[-1])  # imports, compiled code: left out
        rows = [node_phases(s) for s in scenarios[:n]]
    print(f"where a node's time goes ({scenario_name}, median of {n} nodes, one process; the plan's parts "
          "are inside its set-up):")
    total = statistics.median(sum(v for k, v in r.items() if k not in PLAN_PARTS) for r in rows)
    for k in rows[0]:
        med = statistics.median(r[k] for r in rows)
        inside = "    " if k in PLAN_PARTS else ""
        print(f"  {inside}{k:<24} {med:8.3f} s  {100 * med / total:5.1f} %")
    print(f"  {'node':<24} {total:8.3f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", default="quick")
    parser.add_argument("--order", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--phases", type=int, default=0, help="time the parts of the first N nodes (0: not)")
    parser.add_argument("--out", default="/tmp/bench_uq")
    a = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    if a.phases:
        phases(a.scenario, a.order, a.phases)
    runs = []
    for k in range(a.repeat):
        r = study(a.scenario, a.order, a.workers, Path(a.out))
        runs.append(r)
        print(f"run {k + 1}: {a.scenario}, 3 keys, order {a.order}, {r['nodes']} nodes, {a.workers} workers: "
              f"wall {r['wall']:.1f} s, CPU {r['cpu_parent']:.1f} s (parent) + {r['cpu_workers']:.1f} s (workers); "
              f"load average {r['load'][0]:.2f} before, {r['load'][1]:.2f} after")
        print_timeline(r["timeline"], r["wall"])
    if runs:
        walls = [r["wall"] for r in runs]
        print(f"median wall {statistics.median(walls):.1f} s of {len(walls)} runs ({', '.join(f'{w:.1f}' for w in walls)}); "
              f"median CPU {statistics.median(r['cpu_parent'] + r['cpu_workers'] for r in runs):.1f} s")


if __name__ == "__main__":
    main()
