"""Bridge mid-span acceleration against train speed: max |mean| + 3 sigma, vertical and lateral.

The reference study's train and bridge (scenario ``li_zhu_2011``: four ICE cars over three 32 m spans
on piers, German low interference) at speeds from 160 to 350 km/h. At each speed, PEM gives the mean
(deterministic run) and sigma of the middle span's mid-span acceleration ``bridge.span2.mid.acc_z``
(vertical) and ``bridge.span2.mid.acc_y`` (lateral); the design value by the 3-sigma rule is
max over time of |mean| + 3 sigma.

The frequency grid follows the speed so that every speed sees the same irregularity wavelengths
(the track's 1-210 m): f from v / 210 m to v / 1 m (at most 0.1 / time_step, the highest frequency
the time step resolves), ``--n-freq`` points, logarithmically spaced. The approach is at least the
study's 100 m and at least its 1.64 s (longer at higher speeds), so runs started at rest settle
before the bridge as they do at 220 km/h. Writes ``speed_sweep.csv`` (one
row per speed: band, max |mean|, max sigma, max |mean| + 3 sigma per channel, run time) and
``speed_sweep.png``; each speed's result goes to ``OUT/v<speed>/pem`` (sigma only, no PSD maps), and
a speed already there is loaded, not recomputed (delete the folder to recompute).

    python examples/speed_sweep.py [--quick] [--speeds 160:350:10] [--n-freq N] [--workers N] [--out DIR]

Full setting (20 speeds, 400 frequencies, 4 cars): about 4 minutes with the batched engine on 2 cores
(400 frequencies: the vertical acceleration changes by 8 % from 200 to 400 and is converged at 400,
docs/findings.md). With ``--engine exudyn`` every frequency costs 6 Exudyn runs: use ``--n-freq 60``
(about 25 minutes per speed on 2 cores, hours for the sweep) and a coarser ``--speeds`` (e.g.
160:350:30). ``--quick``: one motor car, 40 m lead-in,
5 m run-out, two speeds (220 and 350 km/h), 3 frequencies over wavelengths 2-210 m, 2 ms time step
with a softer contact: a smoke run of the pipeline, not a result.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from contextlib import ExitStack
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # the PSD-map script's helpers

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.results import RandomResponse
from tb_exudyn.scenario import Scenario
from tb_exudyn.execution import single_threaded_workers as single_threaded_blas
from tb_exudyn.results.export import write_table_csv

from li_zhu_2011_psd_maps import add_common_arguments, quiet_quick_warnings, run_study_pem, study_scenario

NAME = "speed_sweep"
CHANNELS = ("bridge.span2.mid.acc_z", "bridge.span2.mid.acc_y")


def parse_speeds(text: str) -> list[float]:
    """'160:350:10' (start:stop:step, stop included) or '160,220,300' [km/h]."""
    if ":" in text:
        start, stop, step = (float(x) for x in text.split(":"))
        if step <= 0 or stop < start:
            raise argparse.ArgumentTypeError(f"{text!r}: start:stop:step with step > 0 and stop >= start")
        return [float(v) for v in np.arange(start, stop + step / 2, step)]
    speeds = [float(x) for x in text.split(",") if x.strip()]
    if not speeds or min(speeds) <= 0:
        raise argparse.ArgumentTypeError(f"{text!r}: positive speeds in km/h")
    return speeds


def at_speed(base: Scenario, speed_kmh: float, n_freq: int) -> Scenario:
    """``base`` at ``speed_kmh`` with a grid over the track's wavelength band at that speed and an
    approach at least as long as the base's, in metres and in seconds (a faster train gets a longer
    lead-in, so that runs started at rest have settled as well as at the base speed)."""
    lead_in = max(base.track.lead_in, base.track.lead_in * speed_kmh / base.speed_kmh)
    sc = base.replace(speed_kmh=speed_kmh, track=base.track.replace(lead_in=lead_in))
    v, tr, an = sc.speed, sc.track, sc.analysis
    f_min = v / tr.wavelength_max
    f_max = min(v / tr.wavelength_min, 0.1 / an.time_step)
    return sc.replace(analysis=an.replace(freq_min=f_min, freq_max=f_max, n_freq=n_freq, freq_spacing="log"))


def sweep_scenarios(quick: bool, speeds: list[float], n_freq: int | None) -> list[Scenario]:
    base = study_scenario(quick, channels=CHANNELS)
    if quick:  # the quick band's wavelengths: at most 0.1 / (2 ms) = 50 Hz, so short waves are cut at speed
        base = base.replace(track=base.track.replace(wavelength_min=2.0))
    return [at_speed(base, s, n_freq or (3 if quick else 400)) for s in speeds]


def summary_row(sc: Scenario, pem: RandomResponse, seconds: float) -> dict:
    row = {"speed_kmh": sc.speed_kmh, "f_min_hz": pem.band[0], "f_max_hz": pem.band[1], "n_freq": pem.freq.size}
    for ch in CHANNELS:
        i, tag = pem.index(ch), ch.rsplit(".", 1)[1]
        row[f"{tag}_max_abs_mean"] = float(np.max(np.abs(pem.mean[i])))
        row[f"{tag}_max_sigma"] = float(np.max(pem.std[i]))
        row[f"{tag}_max_abs_mean_plus_3sigma"] = float(np.max(np.abs(pem.mean[i]) + 3 * pem.std[i]))
    row["seconds"] = seconds
    return row


def plot(rows: list[dict], title: str):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 4.5), layout="constrained")
    ax = fig.subplots()
    v = [r["speed_kmh"] for r in rows]
    for ch, colour in zip(CHANNELS, ("tab:blue", "tab:red")):
        tag = ch.rsplit(".", 1)[1]
        label = {"acc_z": "vertical", "acc_y": "lateral"}[tag]
        ax.plot(v, [r[f"{tag}_max_abs_mean_plus_3sigma"] for r in rows], "o-", color=colour,
                label=f"{label}: max |mean| + 3 sigma")
        ax.plot(v, [r[f"{tag}_max_abs_mean"] for r in rows], "s--", color=colour, alpha=0.6, ms=4,
                label=f"{label}: max |mean|")
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("bridge mid-span acceleration [m/s^2]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(title, fontsize="small")
    return fig


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_common_arguments(parser, NAME)
    parser.add_argument("--speeds", type=parse_speeds, default=None,
                        help="km/h: start:stop:step (stop included) or a comma list (default 160:350:10; "
                             "quick 220,350)")
    parser.add_argument("--n-freq", type=int, default=None, help="PEM frequencies per speed (default 400; quick 3)")
    args = parser.parse_args(argv)
    if args.quick:
        quiet_quick_warnings()
    speeds = args.speeds or ([220.0, 350.0] if args.quick else parse_speeds("160:350:10"))
    scenarios = sweep_scenarios(args.quick, speeds, args.n_freq)
    out = Path(args.out)
    engine = getattr(args, "engine", None)
    rows = []
    t_all = time.perf_counter()
    with ExitStack() as stack:  # one pool for all speeds: workers start (and import Exudyn) once
        pool = None
        if args.workers > 1:
            stack.enter_context(single_threaded_blas())
            spawn = multiprocessing.get_context("spawn")
            pool = stack.enter_context(ProcessPoolExecutor(args.workers, mp_context=spawn))
        for sc in scenarios:
            folder = out / f"v{sc.speed_kmh:g}"
            t0 = time.perf_counter()
            if (folder / "pem" / "meta.json").exists():
                pem = tbx.load_results(folder / "pem")
                if pem.scenario != sc:
                    raise SystemExit(f"{folder / 'pem'} holds a different setting: delete it or choose another --out")
                seconds = float(pem.provenance.get("seconds", float("nan")))
            else:
                pem = run_study_pem(sc, folder, args.workers, engine, progress=not args.quick, keep_psd=False,
                                    executor=pool)
                seconds = time.perf_counter() - t0
            rows.append(summary_row(sc, pem, seconds))
            r = rows[-1]
            print(f"{sc.speed_kmh:6g} km/h  band {r['f_min_hz']:.3g}-{r['f_max_hz']:.3g} Hz: "
                  f"vertical {r['acc_z_max_abs_mean_plus_3sigma']:.4g}, "
                  f"lateral {r['acc_y_max_abs_mean_plus_3sigma']:.4g} "
                  f"m/s^2 (max |mean| + 3 sigma); {seconds:.1f} s", flush=True)
    sc0 = scenarios[0]
    write_table_csv(rows, out / "speed_sweep.csv")
    title = (f"{sc0.name}: {len(sc0.train.vehicles)} cars, bridge.span2.mid; PEM {rows[0]['n_freq']} frequencies over "
             f"wavelengths {sc0.track.wavelength_min:g}-{sc0.track.wavelength_max:g} m")
    try:
        from tb_exudyn.plotting import save_figure

        save_figure(plot(rows, title), out / "speed_sweep.png")
        figure = " and speed_sweep.png"
    except ImportError:  # plotting is optional (matplotlib)
        figure = ""
    print(f"{len(rows)} speeds in {time.perf_counter() - t_all:.1f} s; speed_sweep.csv{figure} in {out.resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
