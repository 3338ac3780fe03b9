"""The reference study with the ballasted track (issue 47): li_zhu_2011's PEM with and without
``track.structure = "ballasted_uic60"``, side by side in one run.

Each PEM runs in a fresh process (the batched engine, ``--workers`` worker processes): its wall time, its CPU
seconds (the process and its workers: user + system), its peak memory (the largest of the process and of any
worker) and, from the result, the largest sigma over the run of three channel groups: the deck's EN 1990
acceleration (``bridge.*.acc_z_en1990``), the wheel-rail forces (``car*.axle*.*force_*``: vertical per wheel,
lateral per wheelset) and the car bodies (``car*.body*.acc_*``). Medians of ``--repeats`` runs; the ratios
with / without the track of the same run. The load average (``uptime``) before and after: under load, read the
CPU ratio beside the wall ratio.

The track's settings (the defaults: what makes the study run in minutes on 2 cores, docs/track.md 7):
``--approach`` (``track.structure_approach``, m: the track structure reaches that far before and after the
bridge, the wheels on the rigid line beyond it) and ``--track-max-frequency``
(``analysis.track_mode_max_frequency``, Hz: the track-and-deck body's modes kept; the left-out modes' static
flexibility in series at each contact).

``--n-freq`` the frequency grids measured (default: 2 and 4; the scenario's is 200): the time per frequency
is the difference of the two grids' medians, the fixed part (the model, the track's modes, the mean) the rest,
and both are extrapolated to ``--full-n-freq`` (default: the scenario's grid). ``--n-freq 200`` runs the
study's own grid (hours with the track on 2 cores: see docs/track.md 7).

    python benchmarks/bench_track_reference.py                      # 2 and 4 frequencies, 3 runs each
    python benchmarks/bench_track_reference.py --n-freq 2 --repeats 1

Not part of the test suite.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GROUPS = {
    "deck EN 1990 acceleration [m/s^2]": ("bridge.", ".acc_z_en1990"),
    "wheel-rail vertical force [kN]": ("car", ".force_z"),
    "wheel-rail lateral force [kN]": ("car", ".force_y"),
    "car body vertical acceleration [m/s^2]": ("car", "body.acc_z"),
    "car body lateral acceleration [m/s^2]": ("car", "body.acc_y"),
}


def _scenario(track: bool, n_freq: int, approach: float, track_max_frequency: float,  # noqa: ANN202
              name: str = "li_zhu_2011"):
    import tb_exudyn as tbx

    sc = tbx.load_scenario(name)
    sc = sc.replace(analysis=sc.analysis.replace(n_freq=n_freq))
    if track:
        sc = sc.replace(track=sc.track.replace(structure="ballasted_uic60", structure_approach=approach),
                        analysis=sc.analysis.replace(track_mode_max_frequency=track_max_frequency))
    return sc


def child(args: argparse.Namespace) -> None:
    """One PEM in this process; prints one JSON line."""
    import warnings

    import numpy as np

    from tb_exudyn import run_pem

    sc = _scenario(args.track, args.child_n_freq, args.approach, args.track_max_frequency, args.scenario)
    w0, c0 = time.perf_counter(), time.process_time()
    with tempfile.TemporaryDirectory() as out, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_pem(sc, engine="batched", workers=args.workers, out=out, progress=False)
    wall = time.perf_counter() - w0
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = time.process_time() - c0 + kids.ru_utime + kids.ru_stime
    peak = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, kids.ru_maxrss) / 1024
    windows = on_bridge_windows(sc, r.time)
    sig, on = {}, {}
    for group, (start, end) in GROUPS.items():
        names = [c for c in r.channels if c.startswith(start) and c.endswith(end)]
        scale = 1e-3 if "[kN]" in group else 1.0
        sig[group] = max((float(np.max(r[c].std)) * scale for c in names), default=float("nan"))
        on[group] = max((float(np.max(r[c].std[windows(c)], initial=0.0)) * scale for c in names), default=float("nan"))
    modes = r.provenance.get("bridge_modes")
    print(json.dumps({"wall": wall, "cpu": cpu, "peak_mb": peak, "sigma": sig, "sigma_on_bridge": on, "modes": modes,
                      "channels": len(r.channels), "mean_engine": r.provenance.get("mean_engine")}))


def on_bridge_windows(sc, time):  # noqa: ANN001, ANN201
    """channel -> the output times at which what it measures is on the bridge: a wheel's force while its axle
    is on the deck, a car body's motion while all its axles are, a bridge channel always (so that the rails'
    start, where a wheel rolls from the rigid line onto the track, is left out of the vehicle channels)."""
    import numpy as np

    length = sc.bridge.length
    start = -sc.track.lead_in - np.asarray(sc.train.axle_positions, dtype=float)
    x = start[None, :] + sc.speed * np.asarray(time)[:, None]
    on = (x >= 0.0) & (x <= length)
    first, cars = 0, {}
    for k, v in enumerate(sc.train.vehicles):
        cars[f"car{k + 1}"] = list(range(first, first + len(v.axle_offsets)))
        first += len(v.axle_offsets)

    def window(channel: str):  # noqa: ANN202
        parts = channel.split(".")
        if parts[0] not in cars:
            return np.ones(len(time), dtype=bool)
        axles = cars[parts[0]]
        if parts[1].startswith("axle"):
            return on[:, axles[int(parts[1][4:]) - 1]]
        return np.all(on[:, axles], axis=1)

    return window


def _run(track: bool, n_freq: int, args: argparse.Namespace) -> dict:
    cmd = [sys.executable, __file__, "--child", "--child-n-freq", str(n_freq), "--workers", str(args.workers),
           "--approach", str(args.approach), "--track-max-frequency", str(args.track_max_frequency),
           "--scenario", args.scenario]
    if track:
        cmd.append("--track")
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"a run failed (track={track}, n_freq={n_freq}):\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def _ratio(a: float, b: float) -> float:
    return a / b if b > 0.0 else float("nan")


def _uptime() -> str:
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="li_zhu_2011", help="the study (a name or a .toml file)")
    parser.add_argument("--n-freq", type=int, nargs="+", default=[2, 4], help="frequency grids measured")
    parser.add_argument("--full-n-freq", type=int, default=0, help="grid extrapolated to (0: the scenario's)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--approach", type=float, default=20.0, help="track.structure_approach [m]")
    parser.add_argument("--track-max-frequency", type=float, default=300.0,
                        help="analysis.track_mode_max_frequency [Hz]")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--child-n-freq", type=int, default=2, help=argparse.SUPPRESS)
    parser.add_argument("--track", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args)
        return
    import tb_exudyn as tbx

    full = args.full_n_freq or tbx.load_scenario(args.scenario).analysis.n_freq
    print(f"{args.scenario} PEM (batched engine, {args.workers} workers), with track.structure = ballasted_uic60 "
          f"(structure_approach {args.approach:g} m, track modes up to {args.track_max_frequency:g} Hz) and without; "
          f"load average before: {_uptime()}", flush=True)
    med: dict[tuple[bool, int], dict] = {}
    for n in args.n_freq:
        for track in (False, True):
            runs = [_run(track, n, args) for _ in range(args.repeats)]
            m = {k: statistics.median(r[k] for r in runs) for k in ("wall", "cpu", "peak_mb")}
            m.update({k: runs[-1][k] for k in ("sigma", "sigma_on_bridge", "modes", "channels")})
            med[(track, n)] = m
            walls = ", ".join(f"{r['wall']:.1f}" for r in runs)
            print(f"  {n:4d} frequencies, {'with' if track else 'without':7s} the track ({m['modes']} modes, "
                  f"{m['channels']} channels): wall {m['wall']:8.1f} s  CPU {m['cpu']:8.1f} s  peak {m['peak_mb']:6.0f} MB"
                  f"  (median of {len(runs)}; walls {walls})", flush=True)
        a, b = med[(False, n)], med[(True, n)]
        print(f"  {n:4d} frequencies: with / without the track: wall x{b['wall'] / a['wall']:.2f}, "
              f"CPU x{b['cpu'] / a['cpu']:.2f}, peak memory x{b['peak_mb'] / a['peak_mb']:.2f}", flush=True)
    if len(args.n_freq) >= 2:
        lo, hi = min(args.n_freq), max(args.n_freq)
        est = {}
        for track in (False, True):
            for key in ("wall", "cpu"):
                per = (med[(track, hi)][key] - med[(track, lo)][key]) / (hi - lo)
                fixed = med[(track, lo)][key] - per * lo
                est[(track, key)] = (fixed, per, fixed + per * full)
        for track in (False, True):
            (fw, pw, tw), (fc, pc, tc) = est[(track, "wall")], est[(track, "cpu")]
            print(f"  {'with' if track else 'without':7s} the track: fixed part wall {fw:.1f} s / CPU {fc:.1f} s, per "
                  f"frequency wall {pw:.2f} s / CPU {pc:.2f} s: {full} frequencies about wall {tw:.0f} s, CPU {tc:.0f} s")
        print(f"  {full} frequencies (extrapolated): with / without the track: wall x{est[(True, 'wall')][2] / est[(False, 'wall')][2]:.1f}, "
              f"CPU x{est[(True, 'cpu')][2] / est[(False, 'cpu')][2]:.1f} (issue 47's target: at most 4x)")
    n = max(args.n_freq)
    print(f"  max sigma, {n} frequencies (a coarse grid: the change, not the study's values), over the run and (a "
          f"vehicle's) while on the bridge:")
    for group in GROUPS:
        a, b = med[(False, n)]["sigma"][group], med[(True, n)]["sigma"][group]
        ao, bo = med[(False, n)]["sigma_on_bridge"][group], med[(True, n)]["sigma_on_bridge"][group]
        print(f"    {group:40s} without {a:9.4g}  with {b:9.4g}  x{_ratio(b, a):5.2f};  on the bridge {ao:9.4g}  {bo:9.4g}  "
              f"x{_ratio(bo, ao):5.2f}")
    print(f"  load average after: {_uptime()}")


if __name__ == "__main__":
    main()
