"""PEM sweep on the Exudyn engine: wall time and peak memory (issue 6 benchmark).

Runs a scenario's PEM sweep on a reduced frequency grid (``--n-freq``), prints the wall time, the time
per task (one spectrum and frequency: a real and an imaginary run), the peak memory of this process
and of the worker processes, and extrapolates the wall time to the scenario's full grid. The PSD
map's size for the full grid is computed exactly (channels x frequencies x output times x 8 bytes).

    python benchmarks/bench_pem.py li_zhu_2011 --n-freq 6 --workers 2
    python benchmarks/bench_pem.py li_zhu_2011_mc_check --n-freq 10 --workers 2

Not part of the test suite.
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time

import tb_exudyn as tbx
from tb_exudyn.methods import run_pem


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="li_zhu_2011")
    parser.add_argument("--n-freq", type=int, default=6, help="frequencies of the reduced grid")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=1, help="runs of the sweep (median printed)")
    args = parser.parse_args()

    full = tbx.load_scenario(args.scenario)
    a = full.analysis
    reduced = full.replace(analysis=a.replace(n_freq=args.n_freq))
    times = []
    for _ in range(args.repeats):
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            r = run_pem(reduced, workers=args.workers, out=out, progress=False, engine="exudyn")
            times.append(time.perf_counter() - t0)
    wall = sorted(times)[len(times) // 2]
    det = r.provenance.get("total_time_s", 0.0)
    n_tasks = r.provenance["tasks"]
    per_task = (wall - det) * args.workers / n_tasks
    full_tasks = a.n_freq * len(full.track.irregularities)  # frequencies outside the wavelength band are skipped
    est = det + per_task * full_tasks / args.workers
    nc, nt = len(r.channels), r.time.size
    psd_bytes = nc * a.n_freq * nt * 8
    self_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    child_peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"scenario {full.name}: {len(full.train.vehicles)} vehicles, {nc} channels, {nt} output times, "
          f"{r.provenance.get('bridge_modes')} bridge modes, {r.provenance.get('steps')} steps per run")
    print(f"reduced sweep: {args.n_freq} frequencies x {len(full.track.irregularities)} types = {n_tasks} tasks "
          f"({2 * n_tasks} Exudyn runs) on {args.workers} workers: median wall {wall:.1f} s of {len(times)} "
          f"(deterministic run {det:.1f} s), {per_task:.2f} s per task per worker")
    print(f"full sweep ({a.n_freq} frequencies, at most {full_tasks} tasks): estimated {est / 60:.1f} min "
          f"on {args.workers} workers")
    print(f"peak memory: main process {self_peak:.0f} MB, largest worker {child_peak:.0f} MB; "
          f"full PSD map {psd_bytes / 2**20:.0f} MB (plus sigma by type {3 * nc * nt * 8 / 2**20:.1f} MB)")


if __name__ == "__main__":
    main()
