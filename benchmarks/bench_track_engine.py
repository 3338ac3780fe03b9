"""Benchmark: the batched engine with the track (a coupled bridge block) against the same wheels without it.

Problem (tests/engines/test_batched_track.py's case): three free wheels of 1000 kg on the linearised Hertz
spring at 120 km/h, 0.5 s, h = 0.6 m / v / 96, pseudo-excitation columns of a vertical irregularity
spread over 2-100 Hz, the outputs of the test (three contact forces, a wheel, the deck at mid-span):

- ``deck``: the wheels on a 12 m simply supported deck (8 Hz, its modes up to 130 Hz): today's model;
- ``track, modal damping``: ballasted_uic60 (40 supports) on that deck, the track and the deck as one
  modal body of 103 modes up to 3 kHz, damping Phi^T C Phi cut to its diagonal (the compiled step);
- ``track, full damping``: the same with the full damping, a coupled bridge block (the numpy step, the
  block in the basis where A0_b^-1 K0_b is diagonal, the contacts by Woodbury: engines/batched/coupled.py);
- ``track, full, two products``: the same block as given (A0_b inverted once, two dense products a step);
- ``dense``: the full-damping system on the dense engine (one LU of the whole system per step).

Usage::

    python benchmarks/bench_track_engine.py [--repeat 3] [--columns 8 64] [--supports 40 80 160]
    python benchmarks/bench_track_engine.py --fe-supports 160 640
    python benchmarks/bench_track_engine.py --scenario [--repeat 3]

The second form compares, per step, the coupled block's two dense products over the track's modes with the
track in its finite-element coordinates (K q~ + C v~ and the solve by A0's sparse LU, factorised once), 128
real columns, median of 5 (docs/track.md, section 3d). The third runs PEM of a scenario (the Yang & Yau
sprung mass at 180 km/h over a 10 m span, 6 m of approach: tests/engines/test_batched_track.py's) with and
without track.structure on the batched engine, with 2 and 8 frequencies, one worker: the time per
frequency is the difference over the 6 frequencies (the set-up, the modes and Exudyn's mean cancel).

Prints, per number of supports (a longer track: more modes, the deck and the wheels as before), number
of columns and case, the median wall and CPU time over ``repeat`` runs, the CPU time per column and the
ratio to the deck's in the same run.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

try:
    import tb_exudyn  # noqa: F401  (installed, or run from the repository root with PYTHONPATH=.)
except ImportError:  # a plain checkout: use the package next to this folder
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tb_exudyn.engines.batched import BatchedEngine, coupled  # noqa: E402
from tb_exudyn.engines.dense import DenseEngine  # noqa: E402
from tb_exudyn.execution.threads import single_threaded_blas  # noqa: E402
from tb_exudyn.scenario.track_structure import load_track_structure  # noqa: E402
from tb_exudyn.structure import simply_supported_modes  # noqa: E402
from tb_exudyn.system.channels import Channel, output_map  # noqa: E402
from tb_exudyn.system.columns import HarmonicColumns  # noqa: E402
from tb_exudyn.system.conventions import run_steps  # noqa: E402
from tb_exudyn.system.track_model import ModalTrack, modal_track, track_model, track_on_deck  # noqa: E402
from tb_exudyn.system.track_wheel import wheel_on_modal_track  # noqa: E402

M_W, K_H, V, STARTS, DECK_START = 1000.0, 1.4e9, 120.0 / 3.6, np.array([3.0, 0.5, -2.0]), 6.0


class _Sum:
    """A reducer that keeps sigma^2(t) of every output (what PEM's keeps, without its weights)."""

    def __init__(self, n_t: int) -> None:
        self.n_t, self.var = n_t, None

    def record(self, i: int, Y: np.ndarray, ext: np.ndarray) -> None:
        if self.var is None:
            self.var = np.zeros((Y.shape[0], self.n_t))
        self.var[:, i] = np.sum(np.abs(Y[ext]) ** 2, axis=1)

    def result(self) -> dict:
        return {"var": self.var}


def systems(n_supports: int = 40) -> dict[str, tuple]:
    """Each case's (engine class, linear system, output map) with a track of ``n_supports`` supports."""
    structure = load_track_structure("ballasted_uic60")
    span, mass = 12.0, 1.0e4
    ei = (2 * np.pi * 8.0 / (np.pi / span) ** 2) ** 2 * mass
    deck = simply_supported_modes([span], ei, 1e3 * ei, 1e3 * ei, mass, mass, 0.02, 130.0)
    fe = track_on_deck(track_model(structure, n_supports, elements_per_bay=4), deck, DECK_START)
    track = modal_track(fe, max_frequency=3000.0)
    alone = ModalTrack(bridge=deck, damping=np.diag(2 * deck.damping_ratios * deck.omega), modes=np.eye(deck.n_modes))

    def case(body: ModalTrack, starts: np.ndarray, damping: str, mid: np.ndarray) -> tuple:
        lin = wheel_on_modal_track(body, M_W, K_H, V, starts, damping=damping)
        stations = np.zeros((1, 3, body.bridge.n_modes))
        stations[0, 1] = mid
        channels = [Channel(f"wheel{i}.force_z", "N", "contact", i) for i in range(starts.size)]
        channels += [Channel("wheel0.z", "m", "node", 0, 2, 0), Channel("wheel0.az", "m/s2", "node", 0, 2, 2),
                     Channel("deck.mid.z", "m", "bridge", 0, 1, 0), Channel("deck.mid.az", "m/s2", "bridge", 0, 1, 2)]
        return lin, output_map(channels, lambda node: lin.wheel[6 * node:6 * node + 6], stations)

    mid_deck = deck.rail_shapes(np.array([span / 2])).z[0]
    mid_track = mid_deck @ track.modes[fe.deck_dofs]
    full = case(track, STARTS, "full", mid_track)
    return {"deck": (BatchedEngine, *case(alone, STARTS - DECK_START, "full", mid_deck), True),
            "track, modal damping": (BatchedEngine, *case(track, STARTS, "modal", mid_track), True),
            "track, full damping": (BatchedEngine, *full, True),
            "track, full, two products": (BatchedEngine, *full, False),
            "dense (track, full damping)": (DenseEngine, *full, True)}


def _median_cpu(fn, repeat: int = 5) -> float:  # noqa: ANN001
    times = []
    for _ in range(repeat):
        c0 = time.process_time()
        fn()
        times.append(time.process_time() - c0)
    return statistics.median(times)


def fe_step(n_supports: int, width: int = 128) -> None:
    """One step's bridge part for ``width`` real columns: the modal form's two dense products (up to 200
    supports: its eigen-solution is dense) against the finite-element form's sparse products and solve."""
    from scipy.sparse.linalg import splu

    structure = load_track_structure("ballasted_uic60")
    span, mass = 12.0, 1.0e4
    ei = (2 * np.pi * 8.0 / (np.pi / span) ** 2) ** 2 * mass
    deck = simply_supported_modes([span], ei, 1e3 * ei, 1e3 * ei, mass, mass, 0.02, 130.0)
    fe = track_on_deck(track_model(structure, n_supports, elements_per_bay=4), deck, DECK_START)
    h = 0.6 / V / 96
    bp, gp = 1.0 / (0.25 * h * h), 0.5 / (0.25 * h)  # Newmark's average acceleration: the same sparsity
    lu = splu((bp * fe.M + gp * fe.C + fe.K).tocsc())
    rng = np.random.default_rng(0)
    X = rng.standard_normal((fe.n_dof, width))
    K, C = fe.K.tocsr(), fe.C.tocsr()
    t_fe = _median_cpu(lambda: lu.solve(-(K @ X) - (C @ X)))
    line = f"{n_supports} supports: finite elements {fe.n_dof} DOFs, {1e3 * t_fe:.2f} ms"
    if n_supports <= 200:
        nb = modal_track(fe, max_frequency=3000.0).bridge.n_modes
        P, Q = rng.standard_normal((nb, nb)), rng.standard_normal((nb, width))
        t_modal = _median_cpu(lambda: P @ Q + P @ Q)
        line += f"; modal {nb} modes, two dense products {1e3 * t_modal:.2f} ms"
    print(line + f" (per step, {width} real columns, CPU)")


def scenario_times(repeat: int) -> None:
    """PEM of the test's track scenario and of the same without its track (module docstring)."""
    import os
    import resource
    import warnings

    from tb_exudyn import load_scenario, run_pem

    sc = load_scenario("yang_yau_sprung_mass")
    sc = sc.replace(bridge=sc.bridge.replace(track_height=1.0, spans=(10.0,)),
                    track=sc.track.replace(lead_in=6.0, taper_length=3.0, run_out=0.0)).replace(speed_kmh=180.0)

    def cpu() -> float:
        r = resource.getrusage(resource.RUSAGE_SELF)
        c = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime + c.ru_utime + c.ru_stime

    for structure in ("", "ballasted_uic60"):
        med = {}
        for n in (2, 8):
            s_n = sc.replace(track=sc.track.replace(structure=structure), analysis=sc.analysis.replace(n_freq=n))
            wall, used = [], []
            for _ in range(repeat):
                t0, c0 = time.perf_counter(), cpu()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    run_pem(s_n, engine="batched", workers=1, progress=False)
                wall.append(time.perf_counter() - t0)
                used.append(cpu() - c0)
            med[n] = (statistics.median(wall), statistics.median(used))
        per = [(med[8][i] - med[2][i]) / 6 for i in range(2)]
        print(f"track {structure or 'none':16s} PEM 2 freqs wall {med[2][0]:6.2f} s cpu {med[2][1]:6.2f} s; "
              f"8 freqs wall {med[8][0]:6.2f} s cpu {med[8][1]:6.2f} s; per frequency wall {per[0]:.3f} s "
              f"cpu {per[1]:.3f} s (load {os.getloadavg()[0]:.1f})")


def columns(m: int) -> HarmonicColumns:
    freqs = np.linspace(2.0, 100.0, m)
    return HarmonicColumns(kinds=np.zeros(m, int), omega=2 * np.pi * freqs / V, amplitude=np.ones(m),
                           units=("angle",) * m, scale=np.ones(m), type_index=np.zeros(m, int),
                           freq_index=np.arange(m), df=np.ones(m), n_types=1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--columns", type=int, nargs="+", default=[8, 64])
    parser.add_argument("--supports", type=int, nargs="+", default=[40])
    parser.add_argument("--dense-columns", type=int, default=8, help="run the dense engine up to this many columns")
    parser.add_argument("--fe-supports", type=int, nargs="*", default=[], help="only the per-step comparison")
    parser.add_argument("--scenario", action="store_true", help="only PEM of a scenario with and without the track")
    args = parser.parse_args(argv)
    if args.scenario:
        scenario_times(args.repeat)
        return 0
    if args.fe_supports:
        with single_threaded_blas():
            for n_supports in args.fe_supports:
                fe_step(n_supports)
        return 0
    steps = run_steps(0.5, 0.6 / V / 96, 2 * 0.6 / V / 96)
    with single_threaded_blas():
        for n_supports in args.supports:
            cases = systems(n_supports)
            print(f"{n_supports} supports, {steps.n_steps} steps; coordinates: "
                  + ", ".join(f"{k} {v[1].n}" for k, v in cases.items()))
            run_cases(cases, steps, args)
    return 0


def run_cases(cases: dict[str, tuple], steps, args) -> None:  # noqa: ANN001
    """Every case at every number of columns."""
    for m in args.columns:
        source = columns(m)
        base = None
        for name, (cls, lin, om, basis) in cases.items():
            if cls is DenseEngine and m > args.dense_columns:
                continue
            coupled.DIAGONAL_STIFFNESS_BASIS = basis  # the coupled block in its eigenbasis, or as given
            engine = cls.on_system(lin, steps, 0.9, om)
            engine.integrate(columns(2), _Sum(steps.n_outputs))  # warm: the compiled step loaded
            wall, cpu = [], []
            for _ in range(args.repeat):
                t0, c0 = time.perf_counter(), time.process_time()
                engine.integrate(source, _Sum(steps.n_outputs))
                wall.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
            coupled.DIAGONAL_STIFFNESS_BASIS = True
            w, c = statistics.median(wall), statistics.median(cpu)
            base = base or c
            print(f"{m:4d} columns  {name:28s} wall {w:7.3f} s  cpu {c:7.3f} s  "
                  f"per column {1e3 * c / m:8.2f} ms cpu  x{c / base:6.2f} of the deck's")


if __name__ == "__main__":
    sys.exit(main())
