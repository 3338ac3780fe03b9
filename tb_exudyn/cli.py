"""The ``tb-exudyn`` command: a thin layer over the library.

Parses arguments, loads the scenario, calls the methods, saves and prints. A user error (bad
scenario file, impossible setting) is printed as one message and exits with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import textwrap
import warnings
from typing import Sequence

from .engines import DEFAULT_ENGINE, ENGINES
from .errors import SettingError, UserError
from .execution.output import SWEEP_FIGURE, removed_if_left_empty
from ._version import __version__
from . import cli_check, cli_flags, cli_modes, cli_results, cli_scenario, cli_show, cli_sweep, cli_text, cli_uq
from .cli_flags import WHERE, flag
from .cli_results import folder_lock_of, report_package
from .atomic import write_text_atomic
from .results import find_results
from .results.checks import default_limits
from .storage import check_writable
from .structure.guards import check_scenario_size
from .scenario import Analysis, Scenario
from .scenario.show import LISTING_WIDTH, run_label, scenario_table

EXIT_OK, EXIT_USER_ERROR = 0, 2


def _cmd_list(args: argparse.Namespace) -> int:
    print(cli_text.library_listing())
    return EXIT_OK


def _cmd_show(args: argparse.Namespace) -> int:
    kind, model = cli_show.command_model(args)
    if kind == "scenario":
        an = model.analysis
        rows = cli_show.frequency_rows(model.bridge, an.mode_max_frequency, an.max_modes, key="(derived) bridge ")
        text = scenario_table(model, rows)
    else:
        text = {"bridge": cli_show.bridge_text, "vehicle": cli_show.vehicle_text, "train": cli_show.train_text}[kind](model)
    note = cli_show.homonym_note(args.scenario, kind)
    print(cli_text.fitted(text if note is None else f"{note}\n{text}", LISTING_WIDTH))
    return EXIT_OK


def _cmd_modes(args: argparse.Namespace) -> int:
    methods = _methods()
    if args.band is not None and not 0.0 <= args.band[0] < args.band[1]:
        raise SettingError("command line", "--band", args.band, "F_MIN F_MAX with 0 <= F_MIN < F_MAX [Hz]")
    for x in args.position or ():
        if not math.isfinite(x):
            raise SettingError("command line", "--position", x, "finite positions X [m] of the first axle along the "
                               "track (0: the bridge start)", "not finite")
    kind, scenario = cli_show.command_model(args)
    if kind != "scenario" and args.position:
        raise SettingError("command line", "--position", args.position[0], "--position with a scenario (a train on "
                           f"its bridge)", f"{args.scenario!r} is a {kind}")
    if kind == "bridge":
        print(cli_show.bridge_modes_text(scenario, args.band))
        return EXIT_OK
    if kind in ("vehicle", "train"):
        print("\n".join(cli_show.vehicle_modes(args, kind, scenario, methods)))
        return EXIT_OK
    check_scenario_size(scenario)  # the run's checks (the damping guard follows the whole run), before the build
    print("\n".join(cli_show.scenario_modes(args, scenario, methods)))
    return EXIT_OK


#: the main job: the reference study (README), with the everyday engine
DEFAULT_SCENARIO = "li_zhu_2011"
DEFAULT_OUT = "tb_exudyn_out"
#: the channel table of a run, written into its output folder (the terminal shows a short summary)
TABLE_FILE = "channels.txt"
def _methods():  # noqa: ANN202
    """The methods (they build Exudyn models): imported when a command runs one."""
    from . import methods

    return methods


def _figures():  # noqa: ANN202
    """The report package (plot_folder, write_report, save_figure, write_sweep_report; matplotlib):
    imported when a command draws or reports."""
    return report_package()


def _cmd_run(args: argparse.Namespace) -> int:
    base = cli_scenario.load(args)
    scenario = cli_scenario.with_options(base, args)
    check_scenario_size(scenario)  # before the output folder is made
    if cli_scenario.speed_rule_line(base, scenario) is not None:  # at another speed: the sweep's rule, said
        scenario = _methods().sweep.with_least_count(scenario)
        print(textwrap.fill(cli_scenario.speed_rule_line(base, scenario), cli_text.TERMINAL_WIDTH,
                            subsequent_indent="  ", break_on_hyphens=False))
    elif cli_scenario.adaptive_count_free(args):  # adaptive asked for, its count left free: what it needs
        chosen, scenario = scenario, _methods().sweep.with_least_count(scenario)
        if (line := cli_scenario.least_count_line(chosen, scenario)) is not None:
            print(textwrap.fill(line, cli_text.TERMINAL_WIDTH, subsequent_indent="  ", break_on_hyphens=False))
    default_limits()  # the limit files of the verdicts, checked before any work: a broken one writes nothing
    with removed_if_left_empty(args.out):  # a run refused after this leaves no new empty --out
        out = check_writable(args.out)
        with folder_lock_of(out):
            return _run(args, scenario, out)


def _run(args: argparse.Namespace, scenario: Scenario, out) -> int:  # noqa: ANN001
    methods = _methods()
    print(textwrap.fill(f"scenario {scenario.name}: {run_label(scenario)}", cli_text.TERMINAL_WIDTH,
                        subsequent_indent="  ", break_on_hyphens=False))
    common = {"workers": args.workers, "out": out, "resume": args.resume, "progress": not args.no_progress,
              "engine": args.engine, "overwrite": args.overwrite,
              "max_memory": args.max_memory, "keep_checkpoint": args.keep_checkpoint, "where": "command line"}
    if args.method == "det":
        execution = methods.Execution(out=out, overwrite=args.overwrite, max_memory=args.max_memory,
                                      where="command line")
        th = methods.simulate(scenario, "deterministic", execution=execution)
        print(methods.summarize(th))
    elif args.method == "pem":
        psd = args.psd_channels or ["key"]
        result = methods.run_pem(scenario, psd_channels=psd[0] if psd in (["key"], ["all"]) else psd, **common)
        print(f"PEM ({result.provenance['engine']} engine, {len(result.freq)} frequencies): "
              f"{result.provenance['tasks']} tasks ({result.provenance['tasks_run']} run, "
              f"{result.provenance['tasks_from_checkpoint']} from the checkpoint) in {result.provenance['seconds']:.1f} s")
    else:
        result = methods.run_monte_carlo(scenario, keep_samples=args.keep_samples, **common)
        p = result.provenance
        what = f"Monte Carlo of the LINEAR model ({args.engine} engine)" if result.method == "monte_carlo_linear" \
            else "Monte Carlo"
        print(f"{what}: {result.n_samples} samples (seed {p.get('seed')}) in {p.get('seconds', 0.0):.1f} s; "
              f"samples with loss of wheel-rail contact: {p.get('samples_with_loss_of_contact', 0)}")
    if args.method != "det":
        table = out / TABLE_FILE
        write_text_atomic(table, cli_text.summary_table(result) + "\n")
        print(cli_text.short_summary(result, table))
    if not args.no_figures:
        reporting = _figures()
        folder = {"pem": "pem", "monte_carlo": "mc", "monte_carlo_linear": "mc_linear"}.get(getattr(result, "method", ""), "det")
        found = [(p, result if p.name == folder else r) for p, r in find_results(out)]  # the run's checks once
        # the page draws its figures (the standard ones, in parallel) and embeds them: one pass, no second read
        report = reporting.write_report(out, found=found, progress=not args.no_progress)
        figures = reporting.figure_jobs(out, found)  # the figures the page drew (and embeds)
        print(f"{len(figures)} figures and the report: {report}; results in {out.resolve()}")
    else:
        print(f"results in {out.resolve()}")
    return EXIT_OK


def _cmd_sweep(args: argparse.Namespace) -> int:
    methods = _methods()
    sweep = methods.sweep
    scenario = cli_scenario.load(args)
    if (args.speeds_kmh is None) == (args.line_speed_kmh is None):
        raise SettingError("command line", "--speeds-kmh", args.speeds_kmh,
                           "exactly one of --speeds-kmh START:STOP:STEP and --line-speed-kmh V")
    if args.speeds_kmh is not None:  # both checked (range, count, distinct) before the series is made
        speeds = sweep.parse_speeds(args.speeds_kmh, where="command line")
    else:
        speeds = sweep.en1991_speeds(args.line_speed_kmh, args.speed_step_kmh, where="command line")
    if args.freq_spacing is not None and args.freq_spacing not in sweep.FREQ_SPACINGS:
        raise SettingError("command line", "--freq-spacing", args.freq_spacing, " or ".join(sweep.FREQ_SPACINGS))
    default_limits()  # the limit files of each speed's checks, before the folder is made
    options = None
    if args.precision != "float64":
        options = methods.BatchedOptions(precision=args.precision)
    # what the sweep would refuse, refused before --out is created or written, naming the option
    try:
        sweep.check_sweep(scenario, speeds, channels=args.channels, n_freq=args.n_freq, options=options,
                          freq_spacing=args.freq_spacing)
    except SettingError as exc:  # run_sweep's speeds came from --speeds-kmh or --line-speed-kmh: the typed one
        typed = {"speeds_kmh": ("speeds_kmh", args.speeds_kmh) if args.speeds_kmh is not None else
                 ("line_speed_kmh", args.line_speed_kmh), "channels": ("channels", args.channels)}
        if exc.where != "run_sweep" or exc.key not in typed:
            raise
        key, value = typed[exc.key]
        raise exc.restated(WHERE, flag(key), value) from None
    print(f"scenario {scenario.name}: {len(speeds)} speeds {cli_text.kmh(speeds[0])}-{cli_text.kmh(speeds[-1])} km/h")
    with removed_if_left_empty(args.out):  # one refused later (or interrupted) leaves no new empty --out
        out = check_writable(args.out)
        with folder_lock_of(out):
            return _sweep(args, methods, scenario, speeds, out, options)


def _sweep(args: argparse.Namespace, methods, scenario: Scenario, speeds, out, options) -> int:  # noqa: ANN001
    result = methods.sweep.run_sweep(scenario, speeds, workers=args.workers, out=out, resume=args.resume,
                                     progress=not args.no_progress, n_freq=args.n_freq, options=options,
                                     channels=args.channels, overwrite=args.overwrite,
                                     keep_checkpoint=args.keep_checkpoint, freq_spacing=args.freq_spacing)
    for line in cli_sweep.rule_lines(result) + cli_sweep.quantity_table(result) + cli_sweep.verdict_lines(result):
        print(line)
    print(f"({len(speeds)} speed{'s' if len(speeds) != 1 else ''} in {result.provenance['seconds']:.1f} s, "
          f"{result.provenance['tasks_from_checkpoint']} from the checkpoint)")
    figure, png = "", None
    reporting = _figures()
    if not args.no_figures:
        reporting.save_figure(result.plot(), out / SWEEP_FIGURE)
        figure, png = f", {SWEEP_FIGURE}", (out / SWEEP_FIGURE).read_bytes()
    page = reporting.write_sweep_report(result, out, png)
    print(f"speed_sweep.csv{figure} and {page.name} (each speed's result in <speed>/pem) in {out.resolve()}")
    return EXIT_OK


class _Parser(argparse.ArgumentParser):
    """argparse's parser with a one-line error (no usage block), naming the command's --help; exit 2."""

    def error(self, message: str):  # noqa: ANN201 - argparse's hook; never returns
        command = self.prog.partition(" ")[2]
        self.exit(EXIT_USER_ERROR, f"tb-exudyn: error: {command + ': ' if command else ''}{message} "
                                   f"(the options: {self.prog} --help)\n")


#: what show and modes take
MODEL_HELP = "a scenario, bridge, vehicle or train: a name (see `tb-exudyn list`) or a .toml file"


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="tb-exudyn",
        description="Random vibration of a train crossing a bridge (Exudyn, pseudo-excitation method, Monte Carlo).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="""examples:
  tb-exudyn run                        the reference study li_zhu_2011 (PEM, batched engine) and its report
  tb-exudyn run quick --out q          the small default scenario into ./q
  tb-exudyn run li_zhu_2011 --speed-kmh 300 --channels 'bridge.*' 'car1.*'
  tb-exudyn run li_zhu_2011_mc_check --method mc --samples 500
  tb-exudyn modes li_zhu_2011          natural frequencies, damping ratios, the damping guard
  tb-exudyn export tb_exudyn_out --format netcdf --output study.nc
""",
    )
    parser.add_argument("--version", action="version", version=f"tb-exudyn {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    p = sub.add_parser("list", help="named vehicles, bridges, scenarios and track spectra")
    p.set_defaults(func=_cmd_list)
    p = sub.add_parser("show", help="a scenario, bridge, vehicle or train as a table (a bridge: with f1 and f3)")
    p.add_argument("scenario", metavar="MODEL", help=MODEL_HELP)
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.set_defaults(func=_cmd_show)

    p = sub.add_parser("modes", help="natural frequencies, damping ratios and what moves (of a scenario, a bridge "
                                     "alone, a vehicle alone)")
    p.add_argument("scenario", metavar="MODEL", help=MODEL_HELP)
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.add_argument("--position", type=float, nargs="+", default=None, metavar="X",
                   help="the train's first axle at X [m] along the track (0: bridge start), one table each; default: "
                        "the start of the run (vehicles on rigid track, the bridge alone)")
    p.add_argument("--band", type=float, nargs=2, default=None, metavar=("F_MIN", "F_MAX"),
                   help="only modes with undamped frequency in this band [Hz]")
    p.add_argument("--all", action="store_true", help="also the decoupled weak-spring modes")
    p.set_defaults(func=_cmd_modes)

    p = sub.add_parser("run", help="run a scenario: deterministic (det), PEM (pem) or Monte Carlo (mc)",
                       formatter_class=argparse.RawDescriptionHelpFormatter, epilog="""examples:
  tb-exudyn run                                  li_zhu_2011, PEM on the batched engine, figures and report
  tb-exudyn run quick --out q --no-figures       the small scenario, numbers only
  tb-exudyn run li_zhu_2011 --engine exudyn      the reference engine (most of an hour)
  tb-exudyn run li_zhu_2011 --n-freq 400 --freq-spacing adaptive
  tb-exudyn run li_zhu_2011_mc_check --method mc --samples 500 --engine exudyn
""")
    p.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO,
                   help=f"scenario name or .toml path (default: {DEFAULT_SCENARIO})")
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.add_argument("--method", choices=("det", "pem", "mc"), default="pem", help="default: pem")
    p.add_argument("--workers", default=None, help="worker processes (default: all cores)")
    p.add_argument("--out", default=DEFAULT_OUT, help=f"output folder (default: ./{DEFAULT_OUT})")
    p.add_argument("--resume", action="store_true", help="skip tasks already finished in --out (each checkpoint file "
                   "is checked first; one that fails is computed again, with a notice naming it)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the result and checkpoint an earlier run of this method left in --out (with its "
                        "figures and the folder's report); without it or --resume such a folder is refused")
    p.add_argument("--keep-checkpoint", dest="keep_checkpoint", action="store_true",
                   help="keep --out/checkpoint* after the result is saved (default: removed then; kept after an "
                        "interrupted run, for --resume)")
    p.add_argument("--max-memory", default=None, metavar="SIZE",
                   help="refuse a run estimated to need more memory than SIZE (e.g. 4GB; default: what this machine "
                        "has available)")
    p.add_argument("--engine", choices=tuple(ENGINES), default=DEFAULT_ENGINE,
                   help="batched (default): all pseudo-excitations, or all samples, integrated together on the "
                        "model linearised about rest (Monte Carlo results labelled monte_carlo_linear); exudyn: one "
                        "Exudyn run per PEM frequency and part, or per Monte Carlo sample (the reference); dense: "
                        "the linear model on full matrices (a small reference)")
    p.add_argument("--speed-kmh", dest="speed_kmh", type=float, default=None,
                   help="train speed [km/h]: the scenario run there by the speed rule of a sweep (band and approach "
                        "scaled by V / the scenario's speed, docs/speed.md)")
    p.add_argument("--n-freq", dest="n_freq", type=int, default=None, help="PEM frequencies (analysis.n_freq)")
    p.add_argument("--freq-spacing", dest="freq_spacing", choices=("linear", "log", "adaptive"), default=None,
                   help="PEM grid (analysis.freq_spacing; adaptive: placed for the system's modes, and without "
                        "--n-freq at least as many frequencies as its rules need)")
    p.add_argument("--channels", nargs="+", default=None, metavar="PATTERN",
                   help="output channels, glob patterns (analysis.channels), e.g. 'bridge.*' 'car1.body.*'")
    p.add_argument("--psd-channels", dest="psd_channels", nargs="+", default=None, metavar="PATTERN",
                   help="PEM: whose PSD maps to keep: key (default: the checked channels, those of the reference "
                        "study's figures, a short list per component), all, or glob patterns; sigma and the mean "
                        "are kept for every channel")
    p.add_argument("--linearization", choices=("rest", "static"), default=None,
                   help="batched engine: linearise about rest (default; PEM's model, as the Exudyn PEM engine) or "
                        "about the static equilibrium under gravity (adds the suspension preload's stiffness, which "
                        "the Exudyn model with gravity has)")
    p.add_argument("--samples", default=None, help="Monte Carlo samples, >= 2 (default: the scenario's)")
    p.add_argument("--seed", default=None, help="Monte Carlo seed, >= 0 (default: the scenario's)")
    p.add_argument("--keep-samples", action="store_true",
                   help="Monte Carlo: keep every sample's channels in the result (N x channels x output times)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figures and no report")
    p.set_defaults(func=_cmd_run)

    p = sub.add_parser("sweep", help="PEM at a series of speeds (batched engine): table and figure of the key quantities")
    p.add_argument("scenario", help="scenario name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--set", dest="settings", action="append", metavar="KEY=VALUE",
                   help=cli_scenario.SET_HELP)
    p.add_argument("--speeds-kmh", default=None, metavar="START:STOP:STEP",
                   help="speeds [km/h], STOP included (or a comma list, e.g. 160,220,300); at most 1000 speeds, "
                        "each > 0 and <= 1000 km/h")
    p.add_argument("--line-speed-kmh", type=float, default=None, metavar="V",
                   help="EN 1991-2 (6.4.6.2): speeds up to 1.2 x the maximum line speed V, from V/2 in "
                        "--speed-step-kmh steps (instead of --speeds-kmh)")
    p.add_argument("--speed-step-kmh", type=float, default=10.0,
                   help="step of --line-speed-kmh (default 10; > 0, at most 1000 speeds)")
    p.add_argument("--out", default="sweep", help="output folder (default: ./sweep)")
    p.add_argument("--workers", default=None, help="worker processes (default: all cores)")
    p.add_argument("--resume", action="store_true", help="reuse finished speeds (and tasks) in --out")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an earlier sweep's table, checkpoint and speeds in --out (without it or --resume such "
                        "a folder is refused)")
    p.add_argument("--keep-checkpoint", dest="keep_checkpoint", action="store_true",
                   help="keep --out/checkpoint-sweep after the table is written")
    p.add_argument("--n-freq", dest="n_freq", default=None,
                   help="PEM frequencies per speed (default: the scenario's n_freq; with --freq-spacing adaptive the "
                        "least, raised at each speed to what the grid's rules need)")
    p.add_argument("--freq-spacing", dest="freq_spacing", default=None, metavar="SPACING",
                   help="linear, log or adaptive (converged grids: fine at the system's modes and for the run's "
                        "length, docs/adaptive_grid.md; default: the scenario's freq_spacing)")
    p.add_argument("--channels", nargs="+", default=None,
                   help="channel patterns of the key quantities, each must match a channel, derived ones included "
                        "(default: deck accelerations, bridge.*.acc_z_en1990 with its EN 1990 check among them, car "
                        "body accelerations, wheel forces)")
    p.add_argument("--precision", choices=("float64", "float32"), default="float64",
                   help="float32: faster (measured in docs/speed.md), sigma within 1e-5 of each channel's largest")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="no figure (the report is written without it)")
    p.set_defaults(func=_cmd_sweep)

    cli_check.add_parser(sub)
    cli_results.add_parsers(sub)
    cli_modes.add_parser(sub)
    cli_uq.add_parser(sub, _methods)
    return parser


#: options naming a file or folder (an empty one would silently mean the current folder)
PATH_OPTIONS = {"scenario": "SCENARIO", "out": "--out", "folder": "FOLDER", "pem_dir": "PEM_DIR", "mc_dir": "MC_DIR",
                "html": "--html", "output": "--output"}
MIN_SAMPLES = 2  # a sample standard deviation needs two samples (as run_monte_carlo checks)


def _int_option(text: str | None, option: str, low: int, high: int | None = None, why: str = "") -> int | None:
    """The whole number given to ``option`` (None if not given); SettingError naming the option."""
    if text is None:
        return None
    allowed = f"a whole number >= {low}" + (f" and <= {high}" if high is not None else "") + (f" ({why})" if why else "")
    try:
        value = int(text)
    except ValueError:
        raise SettingError("command line", option, text, allowed, "not a whole number") from None
    if value < low or (high is not None and value > high):
        raise SettingError("command line", option, value, allowed, "out of range")
    return value


def check_arguments(args: argparse.Namespace) -> argparse.Namespace:
    """Check the options argparse cannot (empty paths, numbers and their ranges, option pairs) and
    convert the numbers; SettingError ``command line: key '--OPTION'`` naming the option, before any work."""
    for attr, option in PATH_OPTIONS.items():
        if getattr(args, attr, None) is not None and not str(getattr(args, attr)).strip():
            raise SettingError("command line", option, getattr(args, attr), "a file or folder path", "empty")
    if args.command == "check":
        args.workers = _int_option(args.workers, "--workers", 1)
    if args.command == "sweep":
        n_freq = next(f.metadata["check"] for f in dataclasses.fields(Analysis) if f.name == "n_freq")
        args.workers = _int_option(args.workers, "--workers", 1)
        args.n_freq = _int_option(args.n_freq, "--n-freq", 1, int(n_freq.high), "as analysis.n_freq")
    if args.command != "run":
        return args
    # the ranges of the scenario keys these options override (the schema's checks)
    checks = {f.name: f.metadata["check"] for f in dataclasses.fields(Analysis) if f.name in ("n_samples", "seed")}
    args.workers = _int_option(args.workers, "--workers", 1)
    args.samples = _int_option(args.samples, "--samples", MIN_SAMPLES, int(checks["n_samples"].high),
                               "Monte Carlo samples, as analysis.n_samples")
    args.seed = _int_option(args.seed, "--seed", 0, int(checks["seed"].high), "as analysis.seed")
    if args.linearization is not None and args.engine == "exudyn" and args.method != "det":
        if args.method == "mc" or args.linearization != "rest":
            raise SettingError("command line", "--linearization", args.linearization,
                               "--linearization with --engine batched (the Exudyn engine: PEM about rest, Monte Carlo "
                               "on the full model)", "not with --engine exudyn")
    return args


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    """Warnings and notices, each once, in at most two lines of 100 characters (no source line), with
    the --set a change needs; the report has them in full."""
    text = cli_text.with_set_hint(cli_flags.notice_as_flags(" ".join(str(message).split())))
    if text in _SHOWN:  # each warning once (a sweep repeats a speed's)
        return
    _SHOWN.add(text)
    print("\n".join(cli_text.terminal_warning(text)), file=sys.stderr if file is None else file)


#: the warnings printed by this command (each once)
_SHOWN: set[str] = set()


def main(argv: Sequence[str] | None = None) -> int:
    _SHOWN.clear()  # each command shows each warning once (main may be called again in one process)
    parser = build_parser()
    args = parser.parse_args(argv)
    shown = warnings.showwarning
    warnings.showwarning = _one_line_warning
    try:
        return int(args.func(check_arguments(args)))
    except UserError as exc:  # ScenarioError, SettingError, CheckpointError, ResultsError, ...
        print(f"tb-exudyn: error: {cli_flags.as_flags(exc)}", file=sys.stderr)  # library keys told as flags
        return EXIT_USER_ERROR
    except OSError as exc:  # a file or folder the user named cannot be read or written
        print(f"tb-exudyn: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except MemoryError as exc:  # the memory estimate's margin was not enough: the size, not a bug
        print(f"tb-exudyn: error: command {args.command!r}: out of memory ({exc or 'an allocation failed'}): the run's "
              "estimate did not foresee it (allowed: a run this machine can hold: fewer --workers, a smaller "
              "analysis.n_freq or fewer analysis.channels, or --psd-channels key; finished tasks are kept for --resume)",
              file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:  # a command without --resume has nothing to resume (check: cli_check says what is left)
        kept = "; finished tasks are kept (run again with --resume)" if hasattr(args, "resume") else ""
        print(f"tb-exudyn: interrupted{kept}", file=sys.stderr)
        return cli_check.EXIT_INTERRUPTED
    finally:
        warnings.showwarning = shown


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
