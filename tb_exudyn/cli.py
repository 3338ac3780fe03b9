"""The ``tb-exudyn`` command: a thin layer over the library.

Parses arguments, loads the scenario, calls the solvers, saves and prints. A user error (bad
scenario file, impossible setting) is printed as one message and exits with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Sequence

from .engines import ENGINES
from .errors import SettingError, UserError
from .results.compare import compare_folders
from .results.storage import check_writable
from .scenario import Scenario, list_models, load_scenario
from .scenario.show import scenario_table
from .structure import StructureError, modal_bridge
from .system.modes import DIRECTIONS, merged_messages, nth_frequency
from .track import get_spectrum, spectrum_names

EXIT_OK, EXIT_USER_ERROR = 0, 2


def _cmd_list(args: argparse.Namespace) -> int:
    entries = list_models()
    width = max(len(e.name) for e in entries)
    for category in ("vehicles", "bridges", "scenarios"):
        print(f"{category}:")
        for e in (e for e in entries if e.category == category):
            print(f"  {e.name:<{width}}  {e.description}")
    print("spectra (track irregularities; one-sided, spatial frequency in rad/m):")
    names = spectrum_names()
    width = max(len(n) for n in names)
    for name in names:
        print(f"  {name:<{width}}  {get_spectrum(name).describe()}")
    return EXIT_OK


def bridge_frequency_rows(scenario: Scenario) -> list[tuple[str, str, str, str]]:
    """Rows with f1 and f3 of the bridge per direction (vertical, lateral, torsion) [Hz]: the
    finite-element modes of the bridge alone (no train), up to analysis.mode_max_frequency."""
    an = scenario.analysis
    try:
        mb = modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes)
    except StructureError as exc:
        return [("(derived) bridge modes", "not available", "", str(exc))]
    rows = []
    for d in DIRECTIONS:
        f = [nth_frequency(mb.frequencies, mb.mode_types, d, n) for n in (1, 3)]
        text = ", ".join("-" if math.isnan(x) else f"{x:.4g}" for x in f)
        rows.append((f"(derived) bridge f1, f3 {d}", text, "Hz",
                     f"1st and 3rd {d} mode of the whole bridge alone (FE; '-': none up to mode_max_frequency)"))
    return rows


def _cmd_show(args: argparse.Namespace) -> int:
    scenario = load_scenario(args.scenario)
    print(scenario_table(scenario, bridge_frequency_rows(scenario)))
    return EXIT_OK


def _cmd_modes(args: argparse.Namespace) -> int:
    methods = _methods()
    if args.band is not None and not 0.0 <= args.band[0] < args.band[1]:
        raise SettingError("command line", "--band", args.band, "F_MIN F_MAX with 0 <= F_MIN < F_MAX [Hz]")
    scenario = load_scenario(args.scenario)
    model = methods.build_model(scenario, warn=False)
    for position in args.position or [None]:
        table = methods.system_modes(scenario, position, model=model)
        shown = table if args.all else table.select([k != "decoupled" for k in table.kind])
        if args.band is not None:
            shown = shown.in_band(*args.band)
        print(shown.text())
        if len(shown) < len(table):
            print(f"({len(table) - len(shown)} of {len(table)} modes not shown: "
                  f"{'outside --band; ' if args.band else ''}{'' if args.all else 'decoupled weak-spring modes (--all)'})")
        print()
    if not scenario.track.irregularities:
        print("damping guard: not applicable (no track irregularities, so no random run)")
        return EXIT_OK
    warnings = methods.damping_guard(scenario, model=model)
    print(f"damping guard ({scenario.name}, band and run of its random analysis): "
          + ("no lightly damped mode" if not warnings else f"{len(warnings)} lightly damped modes"))
    for line in merged_messages(warnings):
        print(f"  warning: {line}")
    return EXIT_OK


DEFAULT_SCENARIO = "quick"
DEFAULT_OUT = "tb_exudyn_out"


def _summary_table(result, k: float = 3.0) -> str:
    """Per channel: max |mean|, max sigma, max |mean| + k sigma, with units."""
    rows = result.summary_rows(k)
    width = max(len(r[0]) for r in rows)
    band = f"{result.band[0]:.3g}-{result.band[1]:.3g} Hz"
    lines = [f"{'channel':<{width}}  {'unit':<8} {'max|mean|':>11} {'max sigma':>11} {f'max|mean|+{k:g}s':>13}"]
    lines += [f"{n:<{width}}  {u:<8} {m:>11.4e} {s:>11.4e} {p:>13.4e}" for n, u, m, s, p in rows]
    lines.append(f"(sigma over the band {band}; {result.method}, {result.n_samples or len(result.freq)} "
                 f"{'samples' if result.n_samples else 'frequencies'})")
    return "\n".join(lines)


def _methods():  # noqa: ANN202
    """The methods (they build Exudyn models): imported when a command runs one."""
    from . import methods

    return methods


def _figures():  # noqa: ANN202
    """plot_folder and write_report (matplotlib): imported when a command draws."""
    from . import report

    return report.plot_folder, report.write_report


def _cmd_run(args: argparse.Namespace) -> int:
    scenario = load_scenario(args.scenario)
    out = check_writable(args.out)
    methods = _methods()
    print(f"scenario {scenario.name}: {scenario.description}")
    if args.method == "det":
        th = methods.run_deterministic(scenario)
        th.save(out / "det")
        print(methods.summarize(th))
    elif args.method == "pem":
        result = methods.run_pem(scenario, workers=args.workers, out=out, resume=args.resume,
                                 progress=not args.no_progress, engine=args.engine, linearization=args.linearization)
        print(_summary_table(result))
        print(f"PEM: {result.provenance['tasks']} tasks ({result.provenance['tasks_run']} run, "
              f"{result.provenance['tasks_from_checkpoint']} from the checkpoint) in {result.provenance['seconds']:.1f} s")
    else:
        result = methods.run_monte_carlo(scenario, n_samples=args.samples, seed=args.seed, workers=args.workers,
                                         out=out, resume=args.resume, progress=not args.no_progress,
                                         engine=args.engine, linearization=args.linearization)
        print(_summary_table(result))
        p = result.provenance
        what = f"Monte Carlo of the LINEAR model ({args.engine} engine)" if result.method == "monte_carlo_linear" \
            else "Monte Carlo"
        print(f"{what}: {result.n_samples} samples (seed {p.get('seed')}) in {p.get('seconds', 0.0):.1f} s; "
              f"samples with loss of wheel-rail contact: {p.get('samples_with_loss_of_contact', 0)}")
    if not args.no_figures:
        plot_folder, write_report = _figures()
        figures = plot_folder(out)
        report = write_report(out)
        print(f"{len(figures)} figures and the report: {report}")
    print(f"results in {out.resolve()}")
    return EXIT_OK


def _cmd_sweep(args: argparse.Namespace) -> int:
    from .methods import sweep

    scenario = load_scenario(args.scenario)
    if (args.speeds_kmh is None) == (args.line_speed_kmh is None):
        raise SettingError("command line", "speeds-kmh", args.speeds_kmh,
                           "exactly one of --speeds-kmh START:STOP:STEP and --line-speed-kmh V")
    if args.speeds_kmh is not None:
        speeds = sweep.parse_speeds(args.speeds_kmh)
    else:
        if not args.line_speed_kmh > 0:
            raise SettingError("command line", "line-speed-kmh", args.line_speed_kmh, "a speed > 0 km/h")
        speeds = sweep.en1991_speeds(args.line_speed_kmh, args.speed_step_kmh)
    out = check_writable(args.out)
    options = None
    if args.precision != "float64":
        from .engines.batched import BatchedOptions

        options = BatchedOptions(precision=args.precision)
    print(f"scenario {scenario.name}: {len(speeds)} speeds {speeds[0]:g}-{speeds[-1]:g} km/h")
    result = sweep.run_sweep(scenario, speeds, workers=args.workers, out=out, resume=args.resume,
                             progress=not args.no_progress, n_freq=args.n_freq, options=options,
                             channels=args.channels)
    for row in result.rows():
        parts = [f"{row['speed_kmh']:7g} km/h"] + [
            f"{key} {row[f'{key}_max_abs_mean_plus_3sigma']:.4g}" for key, _, _ in result.quantities]
        print("  ".join(parts))
    print(f"(max |mean| + 3 sigma per key quantity; {len(speeds)} speeds in {result.provenance['seconds']:.1f} s, "
          f"{result.provenance['tasks_from_checkpoint']} from the checkpoint)")
    figure = ""
    if not args.no_figures:
        from .plotting import plot_speed_sweep, save_figure

        save_figure(plot_speed_sweep(result), out / "speed_sweep.png")
        figure = " and speed_sweep.png"
    print(f"speed_sweep.csv{figure} in {out.resolve()}; each speed's result in {out.resolve()}/<speed>/pem")
    return EXIT_OK


def _cmd_compare(args: argparse.Namespace) -> int:
    print(compare_folders(args.pem_dir, args.mc_dir, channels=args.channels))
    return EXIT_OK


def _cmd_plot(args: argparse.Namespace) -> int:
    plot_folder, _ = _figures()
    paths = plot_folder(args.folder, channels=args.channels, formats=tuple(args.formats))
    for p in paths:
        print(p)
    return EXIT_OK


def _cmd_report(args: argparse.Namespace) -> int:
    _, write_report = _figures()
    print(write_report(args.folder, args.html))
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="tb-exudyn",
        description="Random vibration of a train crossing a bridge (Exudyn, pseudo-excitation method, Monte Carlo).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    p = sub.add_parser("list", help="named vehicles, bridges, scenarios and track spectra")
    p.set_defaults(func=_cmd_list)
    p = sub.add_parser("show", help="the resolved scenario as a table")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.set_defaults(func=_cmd_show)

    p = sub.add_parser("modes", help="natural frequencies, damping ratios and what moves, and the damping guard")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--position", type=float, nargs="+", default=None, metavar="X",
                   help="the train's first axle at X [m] along the track (0: bridge start), one table each; default: "
                        "the start of the run (vehicles on rigid track, the bridge alone)")
    p.add_argument("--band", type=float, nargs=2, default=None, metavar=("F_MIN", "F_MAX"),
                   help="only modes with undamped frequency in this band [Hz]")
    p.add_argument("--all", action="store_true", help="also the decoupled weak-spring modes")
    p.set_defaults(func=_cmd_modes)

    p = sub.add_parser("run", help="run a scenario: deterministic (det), PEM (pem) or Monte Carlo (mc)")
    p.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO,
                   help=f"scenario name or .toml path (default: {DEFAULT_SCENARIO})")
    p.add_argument("--method", choices=("det", "pem", "mc"), default="pem", help="default: pem")
    p.add_argument("--workers", type=_positive_int, default=None, help="worker processes (default: all cores)")
    p.add_argument("--out", default=DEFAULT_OUT, help=f"output folder (default: ./{DEFAULT_OUT})")
    p.add_argument("--resume", action="store_true", help="skip tasks already finished in --out")
    p.add_argument("--engine", choices=tuple(ENGINES), default="exudyn",
                   help="exudyn: one Exudyn run per PEM frequency and part, or per Monte Carlo sample (the "
                        "reference, default); batched: all pseudo-excitations, or all samples, integrated together "
                        "on the model linearised about rest (Monte Carlo results labelled monte_carlo_linear)")
    p.add_argument("--linearization", choices=("rest", "static"), default=None,
                   help="batched engine: linearise about rest (default; PEM's model, as the Exudyn PEM engine) or "
                        "about the static equilibrium under gravity (adds the suspension preload's stiffness, which "
                        "the Exudyn model with gravity has)")
    p.add_argument("--samples", type=_positive_int, default=None, help="Monte Carlo samples (default: the scenario's)")
    p.add_argument("--seed", type=int, default=None, help="Monte Carlo seed (default: the scenario's)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figures and no report")
    p.set_defaults(func=_cmd_run)

    p = sub.add_parser("sweep", help="PEM at a series of speeds (batched engine): table and figure of the key quantities")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--speeds-kmh", default=None, metavar="START:STOP:STEP",
                   help="speeds [km/h], STOP included (or a comma list, e.g. 160,220,300)")
    p.add_argument("--line-speed-kmh", type=float, default=None, metavar="V",
                   help="EN 1991-2 (6.4.6.2): speeds up to 1.2 x the maximum line speed V, from V/2 in "
                        "--speed-step-kmh steps (instead of --speeds-kmh)")
    p.add_argument("--speed-step-kmh", type=float, default=10.0, help="step of --line-speed-kmh (default 10)")
    p.add_argument("--out", default="sweep", help="output folder (default: ./sweep)")
    p.add_argument("--workers", type=_positive_int, default=None, help="worker processes (default: all cores)")
    p.add_argument("--resume", action="store_true", help="reuse finished speeds (and tasks) in --out")
    p.add_argument("--n-freq", type=_positive_int, default=None,
                   help="PEM frequencies per speed (default: the scenario's n_freq)")
    p.add_argument("--channels", nargs="+", default=None,
                   help="channel patterns of the key quantities (default: deck and car body accelerations, wheel forces)")
    p.add_argument("--precision", choices=("float64", "float32"), default="float64",
                   help="float32: about 15 %% faster, sigma within 1e-5 of each channel's largest (docs/speed.md)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figure")
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser("compare", help="PEM against Monte Carlo: sigma ratio, expected band, mean in standard errors")
    p.add_argument("pem_dir", help="a PEM result folder (or an --out folder holding pem/)")
    p.add_argument("mc_dir", help="a Monte Carlo result folder (or an --out folder holding mc/)")
    p.add_argument("--channels", nargs="+", default=None, help="channel names or glob patterns")
    p.set_defaults(func=_cmd_compare)

    p = sub.add_parser("plot", help="figures from saved results (written next to them)")
    p.add_argument("folder", help="a result folder or an --out folder of `tb-exudyn run`")
    p.add_argument("--channels", nargs="+", default=None, help="channel names or glob patterns")
    p.add_argument("--formats", nargs="+", default=["png"], choices=("png", "pdf", "svg"))
    p.set_defaults(func=_cmd_plot)

    p = sub.add_parser("report", help="one self-contained HTML page of saved results")
    p.add_argument("folder", help="a result folder or an --out folder of `tb-exudyn run`")
    p.add_argument("--html", default=None, help="where to write it (default: FOLDER/report.html)")
    p.set_defaults(func=_cmd_report)
    return parser


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not >= 1")
    return value


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except UserError as exc:  # ScenarioError, SettingError, CheckpointError, ResultsError, ...
        print(f"tb-exudyn: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except OSError as exc:  # a file or folder the user named cannot be read or written
        print(f"tb-exudyn: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        print("tb-exudyn: interrupted; finished tasks are kept (run again with --resume)", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
