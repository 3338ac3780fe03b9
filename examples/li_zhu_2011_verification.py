"""The reference study's verification of PEM by Monte Carlo (Li & Zhu, section 4.2).

One ICE motor car crosses one 32 m simply supported span at 220 km/h (scenario
``li_zhu_2011_mc_check``) over German low-interference vertical, alignment and cross-level
irregularities. PEM (200 frequencies 0.3-60 Hz) against Monte Carlo with 500 and 2500 samples on the
same discretised spectrum: mean and sigma of the bridge midspan lateral displacement
(``bridge.span1.mid.disp_y``, the study's figure 1), the car body lateral acceleration
(``car1.body.acc_y``) and the lateral wheel-rail force on the first wheelset (``car1.axle1.force_y``,
figure 2). The study finds the bridge displacement settled at 500 samples and the two vehicle
quantities visibly closer to PEM at 2500.

The 2500 samples extend the 500 (the checkpoint is reused: samples 0-499 are the same), so the
second run costs 2000 samples, not 2500.

The same 2500 samples also run on the linear model (the batched engine's Monte Carlo, PEM's model:
``mc_linear/``, seconds): against PEM it checks the statistics alone; the Exudyn samples also carry
what the Exudyn model has beyond the linear one (docs/findings.md, section 5).

Writes to OUT: ``pem/``, ``mc500/``, ``mc/`` (2500 samples), ``mc_linear/``, ``comparison.txt`` and
``figures/<channel>.pem_vs_mc.png``; prints the comparison tables.

    python examples/li_zhu_2011_verification.py [--quick] [--workers N] [--out DIR]

``--quick``: 4 frequencies 1-25 Hz, 8 and 24 samples, 40 m lead-in (the car has not settled when it
reaches the bridge: that warning is silenced), 5 m run-out, output channels restricted to the three
above, bridge modes to 40 Hz: a smoke run (about 15 s on 2 free cores), not a result.
Full run (measured on 2 cores, see benchmarks/bench_monte_carlo.py): PEM about 5 min, Monte Carlo
2500 samples about 11 min.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import tb_exudyn as tbx
from tb_exudyn.atomic import write_text_atomic
from tb_exudyn.scenario import Scenario
from tb_exudyn.results.compare import compare
from tb_exudyn.methods import run_monte_carlo
from tb_exudyn.methods import run_pem
from tb_exudyn.execution import single_threaded_workers as single_threaded_blas

CHANNELS = ("bridge.span1.mid.disp_y", "car1.body.acc_y", "car1.axle1.force_y")


def scenario(quick: bool) -> tuple[Scenario, tuple[int, int]]:
    """The study's verification case and its sample counts (a small setting with ``quick``)."""
    sc = tbx.load_scenario("li_zhu_2011_mc_check")
    if not quick:
        return sc, (500, 2500)
    sc = sc.replace(
        track=sc.track.replace(lead_in=40.0, run_out=5.0),
        analysis=sc.analysis.replace(freq_min=1.0, freq_max=25.0, n_freq=4, mode_max_frequency=40.0,
                                     channels=CHANNELS),
    )
    return sc, (8, 24)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small smoke setting (well under a minute)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--out", default="out/li_zhu_2011_verification", help="output folder")
    args = parser.parse_args(argv)
    sc, (n_small, n_large) = scenario(args.quick)
    out = Path(args.out)
    if args.quick:  # the short approach is the point of --quick; the builder's advice is known
        warnings.filterwarnings("ignore", message="track.lead_in", category=UserWarning)
    t0 = time.perf_counter()
    # one pool for the three sweeps: worker processes start (and import Exudyn) once
    spawn = multiprocessing.get_context("spawn")
    with single_threaded_blas(), ProcessPoolExecutor(args.workers, mp_context=spawn) as pool:
        # overwrite=True: a second run of the script replaces its own earlier results
        pem = run_pem(sc, executor=pool, out=out, progress=not args.quick, overwrite=True)
        t_pem = time.perf_counter() - t0
        mc_small = run_monte_carlo(sc, n_samples=n_small, executor=pool, out=out, progress=not args.quick, engine="exudyn",
                                   overwrite=True, keep_checkpoint=True)  # its samples reused below
        mc_small.save(out / f"mc{n_small}")
        mc_large = run_monte_carlo(sc, n_samples=n_large, executor=pool, out=out, resume=True,
                                   progress=not args.quick, engine="exudyn")  # reuses the first n_small samples
        t_all = time.perf_counter() - t0
        # the same n_large samples on the linear model (batched engine): PEM's model, in seconds
        mc_linear = run_monte_carlo(sc, n_samples=n_large, executor=pool, out=out, progress=not args.quick,
                                    engine="batched", overwrite=True)
        t_linear = time.perf_counter() - t0 - t_all
    tables = [compare(pem, mc, CHANNELS).table() for mc in (mc_small, mc_large, mc_linear)]
    header = (f"{sc.name}: {sc.description}\nPEM {pem.provenance['n_frequencies_in_band']} frequencies x "
              f"{len(pem.types)} types in {t_pem:.1f} s; Monte Carlo {n_small} + {n_large - n_small} samples "
              f"in {t_all - t_pem:.1f} s ({args.workers} workers); seed {mc_large.provenance['seed']}; "
              f"the same {n_large} samples on the linear model (batched engine, last table) in {t_linear:.1f} s")
    lost = mc_large.provenance["samples_with_loss_of_contact"]
    footer = (f"minimum vertical wheel force over all samples {mc_large.provenance['min_wheel_force_N']:.4g} N; "
              f"samples with loss of contact: {lost}")
    text = "\n\n".join([header, *tables, footer])
    print(text)
    write_text_atomic(out / "comparison.txt", text + "\n")
    try:
        from tb_exudyn.plotting import plot_pem_vs_mc, save_figure
    except ImportError:  # plotting is optional (matplotlib)
        return 0
    for ch in CHANNELS:
        save_figure(plot_pem_vs_mc(pem, [mc_small, mc_large, mc_linear], ch), out / "figures" / f"{ch}.pem_vs_mc.png")
    print(f"results and figures in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
