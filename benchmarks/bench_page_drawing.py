"""Benchmark: the CPU seconds of drawing a report page's figures (issue 49), the default page against all figures.

    python benchmarks/bench_page_drawing.py [--folder OUT] [--repeat 2]

README's main job is run once with ``--no-figures`` into a temporary folder (or ``--folder``: an
``--out`` folder of ``tb-exudyn run`` already there); then the page's figures
(``tb_exudyn.report.page_jobs``: the default page, and with ``all_figures``) are drawn in this one
process, each as the page draws it (``draw_job_for_page``'s figure and its two PNGs, nothing written),
the two sets alternating ``--repeat`` times after one warm-up figure. Per set: the figures, the median
CPU seconds (``time.process_time``: this process only, so other sessions' load changes it little) and
per kind; then the page's share of the all-figures drawing.
"""

from __future__ import annotations

import argparse
import collections
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def draw_cpu(jobs) -> tuple[float, dict[str, float]]:  # noqa: ANN001
    from tb_exudyn.plotting.files import DPI, figure_pngs, make_figure

    by_kind: dict[str, float] = collections.defaultdict(float)
    for job in jobs:
        t0 = time.process_time()
        figure_pngs(make_figure(job.kind, job.channel, job.payload), DPI)
        by_kind[job.kind] += time.process_time() - t0
    return sum(by_kind.values()), dict(by_kind)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", default=None, help="an --out folder of tb-exudyn run (default: run the main job)")
    parser.add_argument("--repeat", type=int, default=2, help="rounds of both sets (default 2)")
    args = parser.parse_args(argv)
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.path.insert(0, str(ROOT))
    with tempfile.TemporaryDirectory(prefix="bench_page_") as tmp:
        folder = Path(args.folder) if args.folder else Path(tmp) / "out"
        if args.folder is None:
            env = {**os.environ, "PYTHONPATH": str(ROOT)}
            subprocess.run([sys.executable, "-m", "tb_exudyn", "run", "--out", str(folder), "--no-figures",
                            "--no-progress"], env=env, check=True, capture_output=True)
        from tb_exudyn.report import page_jobs
        from tb_exudyn.results import find_results

        found = find_results(folder)
        sets = {"page": page_jobs(folder, found)[0], "all": page_jobs(folder, found, all_figures=True)[0]}
        draw_cpu(sets["page"][:1])  # warm-up: fonts, caches
        cpu: dict[str, list[float]] = {k: [] for k in sets}
        kinds: dict[str, dict[str, float]] = {}
        for i in range(args.repeat):
            for name, jobs in sets.items():
                total, kinds[name] = draw_cpu(jobs)
                cpu[name].append(total)
                print(f"round {i + 1}, {name}: {len(jobs)} figures, {total:.2f} CPU s", flush=True)
    med = {k: statistics.median(v) for k, v in cpu.items()}
    for name, jobs in sets.items():
        per = ", ".join(f"{k} {v:.2f}" for k, v in sorted(kinds[name].items()))
        print(f"{name}: {len(jobs)} figures, median {med[name]:.2f} CPU s (last round by kind: {per})")
    print(f"the default page's drawing: {med['page'] / med['all']:.2f} of all figures' "
          f"({100 * (1 - med['page'] / med['all']):.0f} % less); load average {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
