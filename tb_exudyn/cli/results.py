"""The commands on saved results: ``compare``, ``plot``, ``export`` and ``report`` (cli/__init__.py adds them)."""

from __future__ import annotations

import argparse
from contextlib import nullcontext
from pathlib import Path

from ..errors import SettingError
from ..execution import folder_lock
from ..results import find_results
from ..results.checks import default_limits
from ..results.compare import compare_folders
from ..results.export import FORMATS as EXPORT_FORMATS
from ..results.export import export

#: the report page's figures (``tb-exudyn run`` and ``report``): page (default) or all
FIGURE_CHOICES = ("page", "all")
FIGURES_HELP = ("page (default): the figures of the bridge, the leading car and the channels the verdicts name; all: "
                "also the other cars' (about 40 %% more drawing for the main job)")

EXIT_OK = 0


def report_package():  # noqa: ANN202
    """The report package (plot_folder, write_report; matplotlib): imported when a command draws or reports."""
    from .. import report

    return report


def folder_lock_of(folder):  # noqa: ANN001, ANN202
    """The output folder's lock (one run per folder at a time), held over a whole command (none for a
    folder that does not exist: the command says what is missing)."""
    if not Path(folder).is_dir():
        return nullcontext()
    return folder_lock(folder, "command line", "wait for it to end, or use another --out")


def _cmd_export(args: argparse.Namespace) -> int:
    found = find_results(args.folder)
    if args.result is not None:
        found = [(p, r) for p, r in found if p.name == args.result]
        if not found:
            raise SettingError("command line", "--result", args.result, "the name of a result folder in FOLDER")
    elif len(found) > 1:
        raise SettingError("command line", "--result", None,
                           " or ".join(p.name for p, _ in found) + " (FOLDER holds several results)",
                           "which result to export")
    for path in export(found[0][1], args.format, args.output, overwrite=args.overwrite, where="command line",
                       key="--output"):
        print(path)
    return EXIT_OK


def _cmd_compare(args: argparse.Namespace) -> int:
    print(compare_folders(args.pem_dir, args.mc_dir, channels=args.channels))
    return EXIT_OK


def _cmd_plot(args: argparse.Namespace) -> int:
    found = find_results(args.folder)  # read (and refused) before the lock touches the folder
    if args.channels is not None:  # a pattern matching no channel: refused before the lock too
        for path, result in found:  # the report package loads matplotlib: only for commands that draw
            report_package().pdata.select_channels(result, args.channels, where="command line", source=str(path))
    with folder_lock_of(args.folder):
        paths = report_package().plot_folder(args.folder, found=found, channels=args.channels, formats=tuple(args.formats),
                                       where="command line")
    for p in paths:
        print(p)
    return EXIT_OK


def _cmd_report(args: argparse.Namespace) -> int:
    found = find_results(args.folder)  # read (and refused) before the lock touches the folder
    default_limits()  # the verdicts' limit files too: a broken one is an error, not "Verdicts: not computed"
    target = {"overwrite": args.overwrite, "where": "command line", "key": "--html"}
    report_package().report_target(args.folder, args.html, **target)  # refused before the lock too
    with folder_lock_of(args.folder):
        print(report_package().write_report(args.folder, args.html, found=found, all_figures=args.figures == "all",
                                            **target))
    return EXIT_OK


def add_parsers(sub: argparse._SubParsersAction) -> None:
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

    p = sub.add_parser("export", help="saved results as NetCDF (labelled arrays), CSV or MAT")
    p.add_argument("folder", help="a result folder or an --out folder of `tb-exudyn run`")
    p.add_argument("--format", choices=EXPORT_FORMATS, default="netcdf",
                   help="netcdf (xarray + h5netcdf: pip install \".[netcdf]\"), csv (plain pandas.read_csv), mat")
    p.add_argument("--output", required=True, help="the file to write (CSV: and FILE.json beside it); not inside a "
                   "result folder")
    p.add_argument("--overwrite", action="store_true",
                   help="replace --output (and its sidecar) if it exists; without it an existing file is refused")
    p.add_argument("--result", default=None, help="which result of FOLDER (e.g. pem, mc) when it holds several")
    p.set_defaults(func=_cmd_export)

    p = sub.add_parser("report", help="one self-contained HTML page of saved results")
    p.add_argument("folder", help="a result folder or an --out folder of `tb-exudyn run`")
    p.add_argument("--html", default=None, help="where to write it (default: FOLDER/report.html, rewritten each time); "
                   "not inside a result folder")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the --html file if it exists; without it an existing file is refused")
    p.add_argument("--figures", choices=FIGURE_CHOICES, default="page", help=FIGURES_HELP)
    p.set_defaults(func=_cmd_report)


__all__ = ["FIGURE_CHOICES", "FIGURES_HELP", "add_parsers", "folder_lock_of", "report_package"]
