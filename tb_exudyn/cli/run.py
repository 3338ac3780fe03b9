"""``tb-exudyn run``: a scenario by one method (deterministic, PEM or Monte Carlo), its table, figures
and report; the run's options and their checks beside the command."""

from __future__ import annotations

import argparse
import dataclasses
import os
import textwrap

from ..atomic import write_text_atomic
from ..engines import DEFAULT_ENGINE, ENGINES
from ..errors import SettingError
from ..execution.output import removed_if_left_empty
from ..execution.standby import standby_pool
from ..results import find_results
from ..results.checks import default_limits
from ..scenario import Analysis, Scenario
from ..scenario.show import run_label
from ..storage import check_writable
from ..structure.guards import check_scenario_size
from . import scenario as cli_scenario, text as cli_text
from .flags import int_option
from .lazy import methods as _methods
from .results import FIGURE_CHOICES, FIGURES_HELP, folder_lock_of, report_package

EXIT_OK = 0

#: the main job: the reference study (README), with the everyday engine
DEFAULT_SCENARIO = "li_zhu_2011"
DEFAULT_OUT = "tb_exudyn_out"
#: the channel table of a run, written into its output folder (the terminal shows a short summary)
TABLE_FILE = "channels.txt"
#: what the figure processes import while the analysis runs (its set-up is one process: a core is free)
FIGURE_MODULES = ("tb_exudyn.plotting.files", "matplotlib.backends.backend_agg", "PIL.PngImagePlugin")
#: figure processes started before the analysis (the others start with the figures): the set-up
#: leaves one core free, and each idle one holds about 100 MB while the analysis runs
FIGURE_PROCESSES_AHEAD = 1


def figure_processes() -> int:
    """The figure processes started before the analysis: one per core but this process's own (which
    draws too, see tb_exudyn.plotting.files.run_jobs)."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return cores - 1


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
    """The analysis, its table, figures and report. The figure processes start first (their imports
    fall in the analysis' set-up) and draw the result's figures as soon as it is saved, while this
    process computes the checks and prints the table (issue 49)."""
    with standby_pool(0 if args.no_figures else figure_processes(), FIGURE_MODULES, FIGURE_PROCESSES_AHEAD) as pool:
        return _analyse(args, scenario, out, pool)


def _analyse(args: argparse.Namespace, scenario: Scenario, out, pool) -> int:  # noqa: ANN001
    methods = _methods()
    print(textwrap.fill(f"scenario {scenario.name}: {run_label(scenario)}", cli_text.TERMINAL_WIDTH,
                        subsequent_indent="  ", break_on_hyphens=False))
    common = {"workers": args.workers, "out": out, "resume": args.resume, "progress": not args.no_progress,
              "engine": args.engine, "overwrite": args.overwrite,
              "max_memory": args.max_memory, "keep_checkpoint": args.keep_checkpoint, "where": "command line"}
    if args.method == "det":
        execution = methods.Execution(out=out, overwrite=args.overwrite, max_memory=args.max_memory,
                                      where="command line")
        result = th = methods.simulate(scenario, "deterministic", execution=execution)
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
        what = f"Monte Carlo of the LINEAR model ({args.engine} engine)" if result.kind.linear_samples \
            else "Monte Carlo"
        print(f"{what}: {result.n_samples} samples (seed {p.get('seed')}) in {p.get('seconds', 0.0):.1f} s; "
              f"samples with loss of wheel-rail contact: {p.get('samples_with_loss_of_contact', 0)}")
    drawing = _start_figures(out, result, pool, args.figures == "all")
    if args.method != "det":
        table = out / TABLE_FILE
        write_text_atomic(table, cli_text.summary_table(result) + "\n")
        print(cli_text.short_summary(result, table))
    if not args.no_figures:
        reporting = report_package()
        folder = result.kind.folder
        found = [(p, result if p.name == folder else r) for p, r in find_results(out)]  # the run's checks once
        # the page draws its figures (the standard ones, in parallel) and embeds them: one pass, no second read
        report = reporting.write_report(out, found=found, progress=not args.no_progress, drawing=drawing,
                                        all_figures=args.figures == "all")
        figures = len(reporting.page_jobs(out, found, all_figures=args.figures == "all")[0])  # the page's figures
        print(f"{figures} figures and the report: {report}; results in {out.resolve()}")
    else:
        print(f"results in {out.resolve()}")
    return EXIT_OK


def _start_figures(out, result, pool, all_figures: bool):  # noqa: ANN001, ANN202
    """The figure processes' drawing (None without them), given now the figures of ``result`` whose
    channels are known without its code checks (tb_exudyn.plotting.data.pattern_channels, those the
    page shows: tb_exudyn.plotting.data.page_channel); the checks' deciding channels follow with the
    report."""
    if pool is None:
        return None
    reporting = report_package()
    drawing = reporting.PageDrawing(pool)
    early = reporting.pattern_channels(result)
    shown = None if all_figures else reporting.pdata.page_channel
    drawing.submit(reporting.figure_jobs(out, [(out / result.kind.folder, result)], early, where="command line",
                                         shown=shown))
    return drawing


MIN_SAMPLES = 2  # a sample standard deviation needs two samples (as run_monte_carlo checks)


def check_arguments(args: argparse.Namespace) -> argparse.Namespace:
    """The run's numbers converted and checked against the ranges of the scenario keys they override
    (the schema's checks), and its option pairs; SettingError naming the option, before any work."""
    checks = {f.name: f.metadata["check"] for f in dataclasses.fields(Analysis) if f.name in ("n_samples", "seed")}
    args.samples = int_option(args.samples, "--samples", MIN_SAMPLES, int(checks["n_samples"].high),
                              "Monte Carlo samples, as analysis.n_samples")
    args.seed = int_option(args.seed, "--seed", 0, int(checks["seed"].high), "as analysis.seed")
    if args.figures is not None and args.no_figures:
        raise SettingError("command line", "--figures", args.figures, "without --no-figures", "not with it")
    args.figures = args.figures or "page"
    if args.linearization is not None and args.engine == "exudyn" and args.method != "det":
        if args.method == "mc" or args.linearization != "rest":
            raise SettingError("command line", "--linearization", args.linearization,
                               "with --engine batched (the Exudyn engine: PEM about rest, Monte Carlo on the full "
                               "model)", "not with --engine exudyn")
    return args


def add_parser(sub: argparse._SubParsersAction) -> None:
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
    p.add_argument("--figures", choices=FIGURE_CHOICES, default=None,
                   help=FIGURES_HELP)
    p.set_defaults(func=_cmd_run, check=check_arguments)


__all__ = ["DEFAULT_OUT", "DEFAULT_SCENARIO", "TABLE_FILE", "add_parser", "check_arguments"]
