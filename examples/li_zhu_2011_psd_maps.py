"""The reference study's PSD maps (Li & Zhu, figures 3-5): time-dependent PSD of the lateral responses.

Four ICE cars (motor + trailer + trailer + motor) cross three 32 m simply supported spans on 15 m piers
at 220 km/h over German low-interference vertical, alignment and cross-level irregularities (scenario
``li_zhu_2011``). PEM gives the one-sided PSD S(f, t) of every channel; this script draws it as
time-frequency maps and as slices at the time of maximum sigma for

- figure 3: the bridge mid-span (middle span) lateral displacement and acceleration,
  ``bridge.span2.mid.disp_y``, ``bridge.span2.mid.acc_y``;
- figure 4: the car body of the first motor car, ``car1.body.disp_y``, ``car1.body.acc_y``;
- figure 5: its leading bogie, ``car1.bogie1.disp_y``, ``car1.bogie1.acc_y``;

and prints, per channel, the frequency of the PSD peak (over all times), the frequencies holding
99 % of the peak-time variance, and the largest sigma, next to what the study reports.

The PEM result is saved to ``OUT/pem`` (mean, sigma and PSD maps of the channels above plus the
bridge mid-span, car body and first-wheelset channels the envelope script needs), so that
``li_zhu_2011_envelopes.py --from OUT`` draws figures 6-8 without a second sweep.

    python examples/li_zhu_2011_psd_maps.py [--quick] [--n-freq N] [--spacing log] [--workers N] [--out DIR] [--resume]
                                            [--scenario li_zhu_2011_creep]

Full setting: the study's 200 frequencies 0.3-60 Hz (600 tasks of two runs each). With the batched
engine (the default when available) this takes about 20 s on 2 cores; with ``--engine exudyn`` over an
hour (``--n-freq 60 --spacing log`` took 25 minutes). ``--resume`` continues an interrupted sweep
from ``OUT/checkpoint``. The bridge responses are converged at 200 frequencies; the wheel-rail forces,
which the lightly damped bogie modes reach, need 400 (``--n-freq 400``, docs/findings.md).
``--quick``: one motor car, 40 m lead-in, 5 m run-out, 4 frequencies 1-25 Hz, bridge modes to 40 Hz,
2 ms time step with a softer contact: a smoke run of the pipeline (well under a minute), not a result.
"""

from __future__ import annotations

import argparse
import inspect
import math
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

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.results import RandomResponse
from tb_exudyn.scenario import Scenario
from tb_exudyn.methods import run_pem
from tb_exudyn.execution import single_threaded_workers as single_threaded_blas

NAME = "li_zhu_2011_psd_maps"

#: (figure, channel, what the study reports: peak frequency [Hz], frequency range [Hz])
FIGURES = (
    ("3a", "bridge.span2.mid.disp_y", "peak 0.9 Hz, range 0.3-2.5 Hz"),
    ("3b", "bridge.span2.mid.acc_y", "peak 3.3 Hz, range 0.3-30 Hz"),
    ("4a", "car1.body.disp_y", "peak 0.3 Hz, range 0.3-2.5 Hz"),
    ("4b", "car1.body.acc_y", "peak 0.3 Hz, range 0.3-30 Hz"),
    ("5a", "car1.bogie1.disp_y", "peak 0.3 Hz, range 0.3-1.5 Hz"),
    ("5b", "car1.bogie1.acc_y", "peak 7.8 Hz, range 0.3-40 Hz"),
)

#: channels kept in the result: those of figures 3-8 (the envelope script reads the same result) and
#: the leading bogie's yaw (the lightly damped bogie lateral/yaw mode, docs/findings.md)
CHANNELS = (
    "bridge.span2.mid.disp_[yz]", "bridge.span2.mid.acc_[yz]",
    "car1.body.disp_[yz]", "car1.body.acc_[yz]",
    "car1.bogie1.disp_y", "car1.bogie1.acc_y", "car1.bogie1.disp_rz", "car1.bogie1.acc_rz",
    "car1.axle1.left.force_z", "car1.axle1.right.force_z", "car1.axle1.force_y",
)


def has_engine_option() -> bool:
    """True when run_pem takes ``engine`` (the batched engine is available)."""
    return "engine" in inspect.signature(run_pem).parameters


def add_common_arguments(parser: argparse.ArgumentParser, name: str) -> None:
    """--quick, --out, --workers (and --engine when run_pem has one) for the example scripts."""
    parser.add_argument("--quick", action="store_true", help="small smoke setting (well under a minute)")
    parser.add_argument("--out", default=str(Path("examples_out") / name),
                        help=f"output folder (default ./examples_out/{name})")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    if has_engine_option():
        parser.add_argument("--engine", default="batched",
                            help="PEM engine: 'batched' (default, all runs at once) or 'exudyn' (one Exudyn run each)")


#: the scenarios the study's scripts run: the reference study and its version with creep-guided
#: wheelsets (issue 19, docs/findings.md section 6)
STUDY_SCENARIOS = ("li_zhu_2011", "li_zhu_2011_creep")


def add_scenario_argument(parser: argparse.ArgumentParser) -> None:
    """--scenario: which of :data:`STUDY_SCENARIOS` the study's scripts run."""
    parser.add_argument("--scenario", choices=STUDY_SCENARIOS, default="li_zhu_2011",
                        help="li_zhu_2011 (default: the reference study) or li_zhu_2011_creep (its cars with "
                             "creep-guided wheelsets)")


def study_scenario(quick: bool = False, n_freq: int | None = None, spacing: str | None = None,
                   channels=CHANNELS, name: str = "li_zhu_2011") -> Scenario:
    """The reference study (``li_zhu_2011``, or ``name`` from :data:`STUDY_SCENARIOS`), its output
    channels restricted to ``channels``.

    ``n_freq``, ``spacing``: a coarser frequency grid over the same band 0.3-60 Hz, linear (the
    study's) or logarithmic (better at low frequencies for the same count). ``quick``: one motor car,
    40 m lead-in (the car has not settled when it reaches the bridge), 5 m run-out, 4 frequencies
    1-25 Hz, bridge modes to 40 Hz, time step 2 ms (output every 20 ms) with a softer wheel-rail
    contact (5e8 N/m) that this step resolves.
    """
    sc = tbx.load_scenario(name)
    an = sc.analysis.replace(channels=tuple(channels))
    if n_freq is not None:
        an = an.replace(n_freq=n_freq)
    if spacing is not None:
        an = an.replace(freq_spacing=spacing)
    if quick:
        motor = sc.train.vehicles[0]
        an = an.replace(freq_min=1.0, freq_max=25.0, n_freq=n_freq or 4, mode_max_frequency=40.0,
                        time_step=0.002, output_step=0.02, contact_stiffness_z=5e8, contact_stiffness_y=5e8)
        return sc.replace(train=sc.train.replace(vehicles=(motor,)),
                          track=sc.track.replace(lead_in=40.0, run_out=5.0), analysis=an)
    return sc.replace(analysis=an)


def run_study_pem(sc: Scenario, out: Path | None, workers: int, engine: str | None = None, resume: bool = False,
                  progress: bool = True, keep_psd: bool = True, executor=None) -> RandomResponse:
    """PEM of ``sc`` on a process pool of ``workers`` (or the given executor); saved to ``out/pem``."""
    kwargs = {"engine": engine} if engine is not None and has_engine_option() else {}
    if "psd_channels" in inspect.signature(run_pem).parameters:
        kwargs["psd_channels"] = "all"  # the scenario's channels are already those of the figures
    if out is not None and not resume and "overwrite" in inspect.signature(run_pem).parameters:
        kwargs["overwrite"] = True  # a second run of the script replaces its own earlier result
    if executor is not None or workers <= 1:
        return run_pem(sc, workers=1 if executor is None else None, executor=executor, out=out, resume=resume,
                       progress=progress, keep_psd=keep_psd, **kwargs)
    spawn = multiprocessing.get_context("spawn")
    with single_threaded_blas(), ProcessPoolExecutor(workers, mp_context=spawn) as pool:
        return run_pem(sc, executor=pool, out=out, resume=resume, progress=progress, keep_psd=keep_psd, **kwargs)


def quiet_quick_warnings() -> None:
    """The short approach of --quick is deliberate: silence the builder's advice about it."""
    warnings.filterwarnings("ignore", message="track.lead_in", category=UserWarning)


# ------------------------------------------------------------------------------- what the maps show
def psd_row(pem: RandomResponse, channel: str) -> int:
    """Row of ``channel``'s PSD map in ``pem.psd`` (results of older versions keep every channel's)."""
    row = pem.psd_row(channel) if hasattr(pem, "psd_row") else pem.index(channel)
    if row is None:
        raise SystemExit(f"the result keeps no PSD map of {channel} (run with psd_channels='all')")
    return row


def psd_peak(pem: RandomResponse, channel: str, share: float = 0.99) -> dict[str, float]:
    """Where the PSD map of ``channel`` peaks, and the band holding ``share`` of the variance.

    Returns peak frequency and time (of max S over the map), the time of max sigma, the lowest and
    highest grid frequency of the smallest set of grid cells that holds ``share`` of sigma^2 at that
    time, and max sigma.
    """
    row = pem.index(channel)
    S = pem.psd[psd_row(pem, channel)]
    k, j = np.unravel_index(int(np.argmax(S)), S.shape)
    jt = int(np.argmax(pem.std[row]))
    var = S[:, jt] * pem.df
    order = np.argsort(var)[::-1]
    cum = np.cumsum(var[order])
    n = int(np.searchsorted(cum, share * cum[-1])) + 1 if cum[-1] > 0 else 1
    cells = pem.freq[order[:n]]
    return {"f_peak": float(pem.freq[k]), "t_peak": float(pem.time[j]), "t_max_sigma": float(pem.time[jt]),
            "f_low": float(cells.min()), "f_high": float(cells.max()), "sigma_max": float(pem.std[row, jt])}


#: frequency bands [Hz] of the variance shares printed per channel
BANDS = ((0.0, 2.5), (2.5, 5.0), (5.0, 10.0), (10.0, 30.0), (30.0, math.inf))


def band_shares(pem: RandomResponse, channel: str, t: float) -> list[float]:
    """Share of sigma^2 at time ``t`` in each of :data:`BANDS` (by grid frequency)."""
    j = int(np.argmin(np.abs(pem.time - t)))
    var = pem.psd[psd_row(pem, channel), :, j] * pem.df
    total = var.sum()
    return [float(var[(pem.freq >= lo) & (pem.freq < hi)].sum() / total) if total > 0 else 0.0 for lo, hi in BANDS]


def peak_table(pem: RandomResponse) -> str:
    """One line per figure channel: our peak frequency and 99 % band against the study's."""
    head = (f"{'fig':<4}{'channel':<26}{'unit':<7}{'f_peak':>8}{'t_peak':>8}{'99% band [Hz]':>16}"
            f"{'max sigma':>12}  study")
    lines = [head]
    for fig, ch, study in FIGURES:
        p = psd_peak(pem, ch)
        band = f"{p['f_low']:.3g}-{p['f_high']:.3g}"
        lines.append(f"{fig:<4}{ch:<26}{pem.unit(ch):<7}{p['f_peak']:>8.3g}{p['t_peak']:>8.3g}{band:>16}"
                     f"{p['sigma_max']:>12.4g}  {study}")
    lines.append(f"(f_peak, t_peak: maximum of S(f, t); 99% band: grid cells holding 99 % of sigma^2 at the time "
                 f"of max sigma; sigma over {pem.band[0]:.3g}-{pem.band[1]:.3g} Hz, {pem.freq.size} frequencies)")
    names = [f"{lo:g}-{hi:g} Hz" if math.isfinite(hi) else f">{lo:g} Hz" for lo, hi in BANDS]
    lines += ["", f"{'share of sigma^2 at max sigma':<30}" + "".join(f"{n:>12}" for n in names)]
    for _, ch, _ in FIGURES:
        p = psd_peak(pem, ch)
        lines.append(f"{ch:<30}" + "".join(f"{v:>12.1%}" for v in band_shares(pem, ch, p["t_max_sigma"])))
    return "\n".join(lines)


def save_figures(pem: RandomResponse, folder: Path) -> list[Path]:
    from tb_exudyn.plotting import plot_psd_map, plot_psd_slices, save_figure

    paths = []
    for fig, ch, _ in FIGURES:
        paths.append(save_figure(plot_psd_map(pem, ch), folder / f"fig{fig}.{ch}.psd_map.png"))
        paths.append(save_figure(plot_psd_slices(pem, ch), folder / f"fig{fig}.{ch}.psd_slices.png"))
    return paths


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_common_arguments(parser, NAME)
    add_scenario_argument(parser)
    parser.add_argument("--n-freq", type=int, default=None,
                        help="number of PEM frequencies over 0.3-60 Hz (default: the study's 200)")
    parser.add_argument("--spacing", choices=("linear", "log"), default=None,
                        help="spacing of the frequency grid (default: the study's linear)")
    parser.add_argument("--resume", action="store_true", help="continue an interrupted sweep from OUT/checkpoint")
    args = parser.parse_args(argv)
    if args.quick:
        quiet_quick_warnings()
    sc = study_scenario(args.quick, args.n_freq, args.spacing, name=args.scenario)
    out = Path(args.out)
    t0 = time.perf_counter()
    pem = run_study_pem(sc, out, args.workers, getattr(args, "engine", None), resume=args.resume,
                        progress=not args.quick)
    seconds = time.perf_counter() - t0
    text = (f"{sc.name}: {sc.description}\n"
            f"{len(sc.train.vehicles)} cars at {sc.speed_kmh:g} km/h; PEM {pem.freq.size} frequencies "
            f"{sc.analysis.freq_min:g}-{sc.analysis.freq_max:g} Hz ({sc.analysis.freq_spacing}) x "
            f"{len(pem.types)} types, engine "
            f"{pem.provenance.get('engine')}, {args.workers} workers: {seconds:.1f} s\n\n" + peak_table(pem))
    print(text)
    (out / "psd_peaks.txt").write_text(text + "\n", encoding="utf-8")
    try:
        paths = save_figures(pem, out / "figures")
    except ImportError:  # plotting is optional (matplotlib)
        paths = []
    print(f"result in {(out / 'pem').resolve()}; {len(paths)} figures in {(out / 'figures').resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
