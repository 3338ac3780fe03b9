"""``tb-exudyn check``: the EN 1991-2 dynamic check on the command line (cli/__init__.py adds the command).

What the command does to ``--out`` (a folder that may hold other files, e.g. a run's ``pem/``):

- first, read only, ``--out`` as it is (:func:`tb_exudyn.files.check_writable` with ``create=False``: a
  file, a FIFO, a path under a file, a folder this user cannot write in, /proc are refused with one line
  saying what is allowed) and, if it exists, its earlier files (:func:`refuse_earlier_files`: an earlier
  check's files without ``--overwrite`` (or ``--resume``); an entry of an output's name that is not a file,
  with or without it; a folder inside a result folder);
- then the check's other arguments (:func:`tb_exudyn.codes.check` checks them and plans the work: modes,
  speed series, the integrations' sizes), touching nothing;
- then the check runs on the method driver (:mod:`tb_exudyn.methods.check`): ``--out`` is made, locked
  (:func:`tb_exudyn.execution.folder_lock`) and its earlier files tested again under the lock (a second
  check into the same folder is refused at once, naming the first; nothing of the first is replaced); each
  finished task (a mass case and train, a stochastic speed) goes to ``--out/checkpoint-check``;
- the files (check.csv, check.png, check.html, and with ``--netcdf`` check.nc: the typed records as NetCDF,
  ``CheckResult.to_xarray()``) are rendered in memory after the analysis and written as one group (:func:`tb_exudyn.files.write_output`): all of them or none, also on Ctrl-C (a Ctrl-C during
  the renames is held until the group is in place); the checkpoint is removed then (``--keep-checkpoint``:
  kept). ``--overwrite --no-figures`` removes an earlier check.png with the same renames;
- a Ctrl-C before the files are written leaves the earlier files as they were and the finished tasks in
  the checkpoint: the message says to run the same command with ``--resume`` (the same check.csv, to the
  bit); before any task finished, ``--out`` is as it was (a folder the command made is removed again) and
  the message says that the same command can simply be run again.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import tempfile
from pathlib import Path

from .flags import WHERE
from .results import report_package
from . import text as cli_text
from ..codes import CHECK_CSV, CHECK_FIGURE, CHECK_PAGE, check
from ..codes.check import CHECK_DATA, CHECK_FILES
from ..codes.check_plan import CHECKPOINT
from ..codes.a2_verdicts import ALPHA_VALUES
from ..errors import CapabilityError, SettingError
from ..execution.output import holdings, RunFiles
from ..execution.output import refuse_earlier_files, remove_entry, removed_if_left_empty
from ..files import check_writable
from ..results.export import netcdf_content
from ..scenario.show import LISTING_WIDTH

#: exit status after a Ctrl-C (128 + SIGINT, as a shell reports it)
EXIT_INTERRUPTED = 130
#: the files of a check in --out, in the order they are written
FILES = CHECK_FILES


def _speeds(text: str | None) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SettingError(WHERE, "--stochastic-speeds", text, "speeds [km/h] separated by commas, e.g. 250,280.5",
                           "not a number") from None


def _holds(path: Path, data: bytes) -> bool:
    """Whether ``path`` is a regular file holding ``data``."""
    try:
        return path.is_file() and not path.is_symlink() and path.read_bytes() == data
    except OSError:
        return False


def _netcdf_bytes(result) -> bytes:  # noqa: ANN001 - a CheckResult
    """check.nc's bytes: the result's labelled form (``CheckResult.to_xarray()``) as NetCDF4, made in memory
    (:func:`tb_exudyn.results.export.netcdf_content`; through a temporary file with an xarray that writes files only)."""
    content, _ = netcdf_content(result, where=WHERE)
    if not callable(content):
        return bytes(content)
    with tempfile.TemporaryDirectory() as tmp:
        content(Path(tmp) / CHECK_DATA)
        return (Path(tmp) / CHECK_DATA).read_bytes()


def _check_netcdf() -> None:
    """--netcdf's packages (the netcdf extra), before any work: one line naming the flag when one is missing."""
    missing = [m for m in ("xarray", "h5netcdf") if importlib.util.find_spec(m) is None]
    if missing:
        raise CapabilityError(WHERE, "--netcdf", True, 'pip install "tb_exudyn[netcdf]"',
                              f"{' and '.join(missing)} not installed: check.nc cannot be written")


def _finished(out: Path) -> int:
    """The finished tasks in ``out``'s check checkpoint; a checkpoint without any is removed (nothing to resume)."""
    held = holdings(out, RunFiles("check", CHECKPOINT)) if out.is_dir() else []
    if not held and (out / CHECKPOINT).is_dir() and not (out / CHECKPOINT).is_symlink():
        remove_entry(out / CHECKPOINT)
    return sum(1 for _ in (out / CHECKPOINT / "tasks").glob("*.npz")) if held else 0


def _cmd_check(args: argparse.Namespace) -> int:
    """EN 1991-2 dynamic check (tb_exudyn.codes): the table, the figure, the page and the verdict (see the
    module docstring for what it does to --out)."""
    try:
        line_speed = float(args.line_speed_kmh)
    except ValueError:
        raise SettingError(WHERE, "--line-speed-kmh", args.line_speed_kmh, "a speed in [1, 600] km/h",
                           "not a number") from None
    speeds = _speeds(args.stochastic_speeds)
    # --out as it is, read only: what no later step can change is refused at once
    check_writable(args.out, create=False)
    if args.netcdf:
        _check_netcdf()
    if not args.resume:  # with --resume the driver's claim decides (a checkpoint to continue)
        refuse_earlier_files(args.out, FILES, "check", overwrite=args.overwrite, where=WHERE)
    files: dict[str, bytes] = {}

    def render(result) -> dict[str, bytes]:  # noqa: ANN001 - the files, drawn under the lock, written as one
        files.update(report_package().check_files(result, None if args.no_figures else result.plot()))
        if args.netcdf:
            files[CHECK_DATA] = _netcdf_bytes(result)
        return files

    out = Path(args.out)
    try:
        with removed_if_left_empty(args.out):
            try:
                result = check(args.bridge, line_speed, trains=args.trains, track=args.track,
                               construction=args.construction, additional_damping=args.additional_damping,
                               where=WHERE, stochastic=args.stochastic, stochastic_speeds=speeds,
                               stochastic_scenario=args.stochastic_scenario, interaction=args.interaction,
                               alpha=args.alpha, workers=args.workers, progress=not args.no_progress, out=args.out,
                               resume=args.resume, overwrite=args.overwrite, keep_checkpoint=args.keep_checkpoint,
                               render=render)
            except KeyboardInterrupt:
                _finished(out)  # an unstarted checkpoint goes (and a new --out with it)
                raise
    except KeyboardInterrupt:  # in the analysis, the drawing or the writing (whose renames finish first)
        if files and all(_holds(out / name, data) for name, data in files.items()):
            if not args.keep_checkpoint and (out / CHECKPOINT).is_dir() and not (out / CHECKPOINT).is_symlink():
                remove_entry(out / CHECKPOINT)  # the files hold everything (as after a check not interrupted)
            print(f"tb-exudyn: interrupted after the check's files were written whole: {', '.join(files)} in "
                  f"{str(out)!r}", file=sys.stderr)
        elif (n := _finished(out)):
            print(f"tb-exudyn: interrupted before the check's files were written: --out {args.out!r} keeps {n} "
                  f"finished tasks in {CHECKPOINT}/; run the same command with --resume", file=sys.stderr)
        else:
            print(f"tb-exudyn: interrupted before the check's files were written: --out {args.out!r} is as it was; "
                  "run the same command again", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(cli_text.fitted(result.summary(), LISTING_WIDTH))
    ran = result.run
    from_checkpoint = f", {ran['tasks_from_checkpoint']} from the checkpoint" if ran.get("tasks_from_checkpoint") else ""
    print(f"{len(result)} rows in {result.seconds:.1f} s ({ran.get('tasks', 0)} tasks{from_checkpoint}, "
          f"{ran.get('executor', '')}): {(out / CHECK_CSV).resolve()}"
          + "".join(f", {n}" for n in (CHECK_DATA, CHECK_FIGURE) if n in files) + f" and {CHECK_PAGE}")
    return 0


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("check", help="EN 1991-2 dynamic check and EN 1990 A2.4.4's criteria: HSLM-A (HSLM-B under 7 m) and real "
                            "trains as moving forces over a speed series, LM71 and SW/0 for the deformations",
                       formatter_class=argparse.RawDescriptionHelpFormatter, epilog="""examples:
  tb-exudyn check single_span_32m --line-speed-kmh 250            all ten HSLM-A trains, ballasted track
  tb-exudyn check li_zhu_2011_bridge --line-speed-kmh 300 --trains hslm_a ice_mttm --out chk
  tb-exudyn check li_zhu_2011_bridge --line-speed-kmh 250 --trains ice_mttm --stochastic --stochastic-speeds 250,300
""")
    p.add_argument("bridge", help="bridge name (see `tb-exudyn list`) or path to a .toml file")
    p.add_argument("--line-speed-kmh", dest="line_speed_kmh", required=True, metavar="V",
                   help="maximum line speed at the site, [1, 600] km/h: speeds from 40 m/s to 1.2 V (6.4.6.2)")
    p.add_argument("--trains", nargs="+", default=["hslm_a"], metavar="NAME",
                   help="hslm_a (default: HSLM-A1 ... A10), HSLM-A3, a train of models/trains or a train .toml file "
                        "(each train's name once)")
    p.add_argument("--track", default="ballasted", metavar="TRACK",
                   help="ballasted (limit 3.5 m/s^2, default) or direct (direct fastening, 5 m/s^2)")
    p.add_argument("--construction", default=None, metavar="TYPE",
                   help="Table 6.6 damping: steel_composite, prestressed_concrete, reinforced_concrete or filler_beam "
                        "(default: the bridge's own, code.construction of its file)")
    p.add_argument("--additional-damping", dest="additional_damping", action="store_true",
                   help="add eq. 6.13's damping for moving-force models (spans below 30 m)")
    p.add_argument("--out", default="check", help="output folder (default: ./check); one check at a time writes "
                   "into it, and its files are written all together or not at all")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an earlier check's check.csv, check.nc, check.png and check.html in --out (with "
                        "--no-figures: remove the png; without --netcdf the nc)")
    p.add_argument("--no-figures", action="store_true", help="no figure")
    p.add_argument("--netcdf", action="store_true", help="also write check.nc: the typed records (criterion, load "
                   "model, train, speed, case, location, value, limit, utilisation, verdict, caveats) as NetCDF4, "
                   "CheckResult.to_xarray() (needs pip install \"tb_exudyn[netcdf]\")")
    p.add_argument("--stochastic", action="store_true",
                   help="also the PEM of the random track irregularity for the trains given as vehicle models "
                        "(ice_mttm, ave_s103): p_exceed and level_at_target at each speed of the nominal case (one PEM "
                        "run per speed, about 12 s each for ice_mttm over li_zhu_2011_bridge)")
    p.add_argument("--stochastic-speeds", dest="stochastic_speeds", default=None, metavar="V,V,...",
                   help="only these speeds [km/h] for --stochastic (added to the series if not in it; default: every "
                        "speed of the series)")
    p.add_argument("--stochastic-scenario", dest="stochastic_scenario", default=None, metavar="SCENARIO",
                   help="the scenario whose track irregularities and analysis settings --stochastic takes (default: "
                        "li_zhu_2011, German low interference)")
    p.add_argument("--interaction", action="store_true",
                   help="also, per train given as vehicle models, its run with vehicle-bridge interaction (the "
                        "deterministic run, smooth track) at the speed of its largest mid-span peak, beside the moving "
                        "forces and eq. 6.13's damping (one Exudyn run per train; terminal and check.html)")
    p.add_argument("--alpha", type=float, default=None, metavar="ALPHA",
                   help="EN 1991-2 6.3.2(3)'s classified-load factor on LM71, SW/0 and the nosing force in the static "
                        "criteria: one of " + ", ".join(f"{a:g}" for a in ALPHA_VALUES) + " (default: 1, said in the verdicts)")
    p.add_argument("--workers", default=None, help="worker processes of the check's tasks, one per mass case and train "
                   "and one per --stochastic speed (default: all cores; a small check runs in this process); the "
                   "result is the same to the bit for any count")
    p.add_argument("--resume", action="store_true", help="continue an interrupted check in --out: the finished tasks of "
                   "--out/checkpoint-check are read (each file checked first), the others run")
    p.add_argument("--keep-checkpoint", dest="keep_checkpoint", action="store_true",
                   help="keep --out/checkpoint-check after the files are written")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_check)


__all__ = ["EXIT_INTERRUPTED", "FILES", "add_parser"]
