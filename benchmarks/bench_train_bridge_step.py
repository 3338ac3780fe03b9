"""Benchmark: cost per time step of the Exudyn train-bridge model, the reference study's case.

The reference study's train (ICE motor + 2 trailers + motor, 220 km/h; scenario ``li_zhu_2011``)
on its bridge: three 32 m spans on 15 m piers from the finite-element model (modes up to 100 Hz)
when ``tb_exudyn.structure.modal_bridge`` is available, else (or with ``--closed-form``) three
simply supported 32 m spans from the closed form (``single_span_32m`` girder), modes up to
100 Hz. A whole crossing at 1 ms steps, deterministic (gravity, static start) and with a harmonic
pseudo-excitation (no gravity, from rest: the PEM run), repeated; prints medians.

    python benchmarks/bench_train_bridge_step.py [--repeat 5] [--closed-form]

Target (issue 5): no slower than 1.2 ms per step on a 2-core machine.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import numpy as np

from tb_exudyn.builder import HarmonicExcitation, build_model
from tb_exudyn.builder.model import bridge_modes, closed_form_modes
from tb_exudyn.scenario import load_bridge, load_scenario
from tb_exudyn.engines.exudyn_runs import run_model



def closed_form_bridge(scenario):
    """Three simply supported 32 m spans with the single_span_32m girder (closed-form modes)."""
    single = load_bridge("single_span_32m")
    three = single.replace(name="three_spans_closed_form", spans=scenario.bridge.spans)
    return closed_form_modes(three, scenario.analysis.mode_max_frequency, scenario.analysis.max_modes)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (median reported)")
    parser.add_argument("--closed-form", action="store_true", help="closed-form 3 x 32 m spans instead of the FE bridge")
    args = parser.parse_args()

    sc = load_scenario("li_zhu_2011")
    t0 = time.perf_counter()
    if args.closed_form:
        modes, label = closed_form_bridge(sc), "closed-form 3 x 32 m simply supported spans"
    else:
        try:
            modes, label = bridge_modes(sc), f"finite-element model of {sc.bridge.name!r}"
        except NotImplementedError:
            modes, label = closed_form_bridge(sc), "closed-form 3 x 32 m simply supported spans (no FE model)"
    t_modes = time.perf_counter() - t0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        model = build_model(sc, modal_bridge=modes)
        t_build = time.perf_counter() - t0
    n_bodies = sum(1 for b in model.parts.bodies)
    print(f"scenario {sc.name}: {len(sc.train.vehicles)} cars, {n_bodies} rigid bodies, {sc.speed_kmh:g} km/h, "
          f"crossing {sc.duration:.3f} s")
    print(f"bridge: {label}, {modes.n_modes} modes <= {sc.analysis.mode_max_frequency:g} Hz "
          f"({t_modes:.2f} s to compute)")
    print(f"system: {model.n_ode2} ODE2 coordinates, coupling object over {model.coupling.n} coordinates, "
          f"{model.coupling.n_contacts} contact forces; built in {t_build * 1e3:.0f} ms")

    harmonic = HarmonicExcitation("vertical", 2 * np.pi / 10.0, sc.analysis.pem_amplitude)
    cases = {
        "deterministic (gravity, static start)": dict(excitation=None, gravity=True, initial="static"),
        "PEM run (harmonic, no gravity, rest)": dict(excitation=harmonic, gravity=False, initial="rest"),
    }
    for name, kw in cases.items():
        per_step, wall, overhead, iters = [], [], [], []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            th, info = run_model(model, kw["excitation"], gravity=kw["gravity"], initial=kw["initial"])
            total = time.perf_counter() - t0
            per_step.append(info.wall_time / info.n_steps * 1e6)
            wall.append(info.wall_time)
            overhead.append(total - info.wall_time)
            iters.append(info.newton_iterations / info.n_steps)
        print(f"{name}: median {statistics.median(per_step):.0f} us/step "
              f"(min {min(per_step):.0f}, max {max(per_step):.0f}, {args.repeat} runs), "
              f"crossing {info.n_steps} steps in {statistics.median(wall):.2f} s, "
              f"re-run set-up and outputs {statistics.median(overhead) * 1e3:.0f} ms (no rebuild), "
              f"{statistics.median(iters):.2f} Newton iterations/step")


if __name__ == "__main__":
    main()
