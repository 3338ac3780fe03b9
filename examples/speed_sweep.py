"""Bridge mid-span acceleration against train speed: max |mean| + 3 sigma, vertical and lateral.

The reference study's train and bridge (scenario ``li_zhu_2011``: four ICE cars over three 32 m spans
on piers, German low interference) at speeds from 160 to 350 km/h, with
:func:`tb_exudyn.methods.sweep.run_sweep` (the library's speed sweep, also ``tb-exudyn sweep``). At
each speed, PEM gives the mean and sigma of the middle span's mid-span acceleration
``bridge.span2.mid.acc_z`` (vertical) and ``bridge.span2.mid.acc_y`` (lateral); the design value by
the 3-sigma rule is max over time of |mean| + 3 sigma.

Each speed's scenario follows the speed rule of ``run --speed-kmh`` (tb_exudyn.scenario.speed_rule):
the study's band 0.3-60 Hz at 220 km/h scaled by v / 220 km/h, so that every speed sees the same
irregularity wavelengths (1.02-204 m; at most 0.1 / time_step, the highest frequency the time step
resolves), ``--n-freq`` points (default 400, logarithmically spaced: the vertical acceleration
changes by 8 % from 200 to 400 and is converged at 400, docs/findings.md). The approach is the
study's 100 m, and its 1.64 s at higher speeds, so runs started at rest settle before the bridge as
they do at 220 km/h. Writes ``speed_sweep.csv`` (one row per
speed: band, max |mean|, max sigma, max |mean| + 3 sigma per channel, run time) and
``speed_sweep.png`` (with the resonance speeds v = f1 d / i of the bridge's first modes, d the car
length and the bogie spacing) and ``speed_sweep.html`` (the sweep's page: verdicts, key quantities
and grid error by speed, warnings); each speed's result goes to ``OUT/<speed>/pem`` (sigma only, no PSD
maps) with its checkpoint, and ``--resume`` reuses the speeds already done.

    python examples/speed_sweep.py [--quick] [--speeds 160:350:10] [--n-freq N] [--workers N] [--out DIR]

Full setting (20 speeds, 400 frequencies, 4 cars): several minutes on 2 cores (docs/speed.md gives
the measured times). ``--quick``: one motor car, 40 m lead-in, 5 m run-out, two speeds (220 and
350 km/h), 3 frequencies 1-25 Hz at 220 km/h, 2 ms time step with a softer contact: a smoke run
of the pipeline, not a result.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the PSD-map script's helpers

from tb_exudyn.errors import UserError
from tb_exudyn.methods.sweep import parse_speeds, run_sweep

from li_zhu_2011_psd_maps import add_common_arguments, quiet_quick_warnings, study_scenario

NAME = "speed_sweep"
CHANNELS = ("bridge.span2.mid.acc_z", "bridge.span2.mid.acc_y")


def base_scenario(quick: bool, n_freq: int | None):
    """The study's scenario with log spacing (``--quick``: its small setting, wavelengths from 2 m,
    since the quick band stops at 0.1 / (2 ms) = 50 Hz)."""
    base = study_scenario(quick, channels=CHANNELS)
    base = base.replace(analysis=base.analysis.replace(freq_spacing="log", n_freq=n_freq or (3 if quick else 400)))
    if quick:
        base = base.replace(track=base.track.replace(wavelength_min=2.0))
    return base


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_common_arguments(parser, NAME)
    parser.add_argument("--speeds", default=None,
                        help="km/h: start:stop:step (stop included) or a comma list (default 160:350:10; quick 220,350)")
    parser.add_argument("--n-freq", type=int, default=None, help="PEM frequencies per speed (default 400; quick 3)")
    parser.add_argument("--resume", action="store_true", help="reuse the speeds already done in --out")
    args = parser.parse_args(argv)
    if args.quick:
        quiet_quick_warnings()
    try:
        speeds = parse_speeds(args.speeds or ("220,350" if args.quick else "160:350:10"), where="--speeds")
        base = base_scenario(args.quick, args.n_freq)
        t0 = time.perf_counter()
        sweep = run_sweep(base, speeds, engine=getattr(args, "engine", None) or "batched", workers=args.workers,
                          out=args.out, resume=args.resume, overwrite=not args.resume, progress=not args.quick,
                          channels=CHANNELS)
    except UserError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for r in sweep.rows():
        vertical, lateral = (r[f"{ch}_max_abs_mean_plus_3sigma"] for ch in CHANNELS)
        print(f"{r['speed_kmh']:6g} km/h  band {r['f_min_hz']:.3g}-{r['f_max_hz']:.3g} Hz: vertical {vertical:.4g}, "
              f"lateral {lateral:.4g} m/s^2 (max |mean| + 3 sigma); {r['seconds']:.1f} s", flush=True)
    try:
        from tb_exudyn.plotting import plot_speed_sweep, save_figure

        from tb_exudyn.report import write_sweep_report

        png = Path(args.out) / "speed_sweep.png"
        save_figure(plot_speed_sweep(sweep), png)
        write_sweep_report(sweep, args.out, png.read_bytes())  # the page tb-exudyn sweep writes
        figure = ", speed_sweep.png and speed_sweep.html"
    except ImportError:  # plotting is optional (matplotlib)
        figure = ""
    print(f"{len(speeds)} speeds in {time.perf_counter() - t0:.1f} s; speed_sweep.csv{figure} in {Path(args.out).resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
