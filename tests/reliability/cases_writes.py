"""Hostile output targets of issue 27 ("outputs that never destroy") as data, in the form of
cases.py: ``tb-exudyn export --output`` and ``tb-exudyn report --html`` onto a result's own files,
into a result or checkpoint folder, onto a FIFO, device, folder or dangling link, onto an existing
file (or sidecar) without ``--overwrite``, and onto a full disk.

Each case must end in exit status 2 with one line naming the file and the option, no traceback,
and nothing under the scratch folder written, moved or deleted (tests/reliability/test_writes.py;
the lead adds CASES_WRITES to cases.CASES for measure.py). A case whose defence, if it failed, would
open a FIFO (and block) runs isolated in a subprocess with a time limit. The full-disk cases patch
the free-space probe in their own process (isolated, so that nothing leaks into the test process).
A write that fails on the full disk itself, and the report's page (drawn, under the folder's lock,
before its size is known), necessarily touch their folders (a temporary file made and removed, the
lock file): those are tested in test_writes.py, on a real tmpfs and with a failing write.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from .cases import Case, Run, report, rr_arrays, rr_meta, th_arrays, th_meta, write_result

GROUP = "writes"


def _th(d: Path) -> Path:
    """A valid time-history result folder ``d/out/det`` (an --out folder holding one result)."""
    return write_result(d / "out" / "det", th_arrays(), th_meta())


def _rr(d: Path) -> Path:
    """A valid PEM result folder ``d/out/pem``."""
    return write_result(d / "out" / "pem", rr_arrays(), rr_meta())


def export(folder: Path, fmt: str, output: Path, *more: str) -> tuple[str, ...]:
    return ("export", str(folder), "--format", fmt, "--output", str(output), *more)


def _output(path: Path, *more: str) -> tuple[str, ...]:
    """What the one line must name: the option and the file."""
    return ("'--output'", str(path), *more)


def _html(path: Path, *more: str) -> tuple[str, ...]:
    return ("'--html'", str(path), *more)


# ------------------------------------------------------------------------------ a result's own files
def _export_netcdf_onto_meta(d: Path) -> Run:
    f = _rr(d)
    return Run(argv=export(f, "netcdf", f / "meta.json"), expect=_output(f / "meta.json", "result folder"))


def _export_csv_onto_arrays_overwrite(d: Path) -> Run:
    f = _th(d)  # --overwrite does not make a result's own file writable
    return Run(argv=export(f, "csv", f / "arrays.npz", "--overwrite"),
               expect=_output(f / "arrays.npz", "result folder"))


def _export_mat_onto_other_results_meta(d: Path) -> Run:
    f, other = _th(d), write_result(d / "other" / "pem", rr_arrays(), rr_meta())
    return Run(argv=export(f, "mat", other / "meta.json", "--overwrite"),
               expect=_output(other / "meta.json", "result folder"))


def _report_html_onto_meta(d: Path) -> Run:
    f = _th(d)
    return Run(argv=report(f, "--html", str(f / "meta.json"), "--overwrite"),
               expect=_html(f / "meta.json", "result folder"))


def _export_new_file_in_result_folder(d: Path) -> Run:
    f = _rr(d)  # a new file there would make the folder "not a result" for the next run --overwrite
    return Run(argv=export(f, "netcdf", f / "pem.nc"), expect=_output(f / "pem.nc", "result folder"))


def _export_into_result_figures(d: Path) -> Run:
    f = _rr(d)
    (f / "figures").mkdir()
    return Run(argv=export(f, "csv", f / "figures" / "x.csv"), expect=_output(f / "figures" / "x.csv", "result folder"))


def _export_csv_sidecar_is_meta(d: Path) -> Run:
    f = _th(d)  # --output .../det/meta: its sidecar would be .../det/meta.json
    return Run(argv=export(f, "csv", f / "meta"), expect=_output(f / "meta", "result folder"))


def _export_link_to_meta(d: Path) -> Run:
    f = _th(d)
    os.symlink(f / "meta.json", d / "link.nc")  # a link to a result's file is the result's file
    return Run(argv=export(f, "netcdf", d / "link.nc", "--overwrite"), expect=_output(d / "link.nc", "result folder"))


def _export_into_checkpoint(d: Path) -> Run:
    f = _th(d)
    cp = d / "out" / "checkpoint"
    (cp / "tasks").mkdir(parents=True)
    (cp / "manifest.json").write_text(json.dumps({"format": "tb_exudyn.checkpoint/2", "fingerprint": "0" * 64}))
    return Run(argv=export(f, "mat", cp / "x.mat"), expect=_output(cp / "x.mat", "checkpoint folder"))


# ------------------------------------------------------------------------------ not a regular file
def _export_onto_fifo(d: Path) -> Run:
    f = _th(d)
    os.mkfifo(d / "pipe.csv")
    return Run(argv=export(f, "csv", d / "pipe.csv", "--overwrite"), expect=_output(d / "pipe.csv", "FIFO"),
               isolate=True)


def _export_onto_link_to_fifo(d: Path) -> Run:
    f = _rr(d)
    os.mkfifo(d / "pipe")
    os.symlink(d / "pipe", d / "link.nc")
    return Run(argv=export(f, "netcdf", d / "link.nc", "--overwrite"),
               expect=_output(d / "link.nc", "symbolic link", "FIFO"), isolate=True)


def _export_sidecar_is_fifo(d: Path) -> Run:
    f = _th(d)
    os.mkfifo(d / "x.csv.json")
    return Run(argv=export(f, "csv", d / "x.csv", "--overwrite"),
               expect=_output(d / "x.csv", str(d / "x.csv.json"), "sidecar", "FIFO"), isolate=True)


def _report_onto_fifo(d: Path) -> Run:
    f = _th(d)
    os.mkfifo(d / "page.html")
    return Run(argv=report(f, "--html", str(d / "page.html"), "--overwrite"), expect=_html(d / "page.html", "FIFO"),
               isolate=True)


def _report_default_page_is_fifo(d: Path) -> Run:
    f = _th(d)  # the default page is rewritten each time, but a FIFO there is not replaced
    os.mkfifo(f / "report.html")
    return Run(argv=report(f), expect=_html(f / "report.html", "FIFO"), isolate=True)


def _report_default_page_is_a_link(d: Path) -> Run:
    _th(d)  # the --out folder's own page is not written through a link (here to a file outside)
    out = d / "out"
    (d / "notes.txt").write_text("someone's notes")
    os.symlink(d / "notes.txt", out / "report.html")
    # refused already when the folder is read (it holds only its own files), else by the page's check
    return Run(argv=report(out), expect=(str(out / "report.html"), "symbolic link"))


def _export_onto_link_to_device(d: Path) -> Run:
    f = _th(d)
    os.symlink("/dev/null", d / "null.mat")
    return Run(argv=export(f, "mat", d / "null.mat", "--overwrite"), expect=_output(d / "null.mat", "device"),
               isolate=True)


def _export_onto_folder(d: Path) -> Run:
    f = _th(d)
    (d / "dir.nc").mkdir()
    return Run(argv=export(f, "netcdf", d / "dir.nc", "--overwrite"), expect=_output(d / "dir.nc", "directory"))


def _report_onto_folder(d: Path) -> Run:
    f = _th(d)
    (d / "pages").mkdir()
    return Run(argv=report(f, "--html", str(d / "pages"), "--overwrite"), expect=_html(d / "pages", "directory"))


def _export_onto_dangling_link(d: Path) -> Run:
    f = _th(d)
    os.symlink(d / "nowhere" / "x.csv", d / "x.csv")
    return Run(argv=export(f, "csv", d / "x.csv", "--overwrite"), expect=_output(d / "x.csv", "does not exist"))


def _export_below_a_file(d: Path) -> Run:
    f = _th(d)
    (d / "file").write_text("a file, not a folder")
    return Run(argv=export(f, "mat", d / "file" / "x.mat"), expect=_output(d / "file" / "x.mat", "cannot be written"))


# ------------------------------------------------------------------------------ existing files
def _export_existing_file(d: Path) -> Run:
    f = _rr(d)
    (d / "study.nc").write_bytes(b"someone's data")
    return Run(argv=export(f, "netcdf", d / "study.nc"), expect=_output(d / "study.nc", "exists", "--overwrite"))


def _export_existing_sidecar(d: Path) -> Run:
    f = _th(d)
    (d / "x.csv.json").write_text("{}")
    return Run(argv=export(f, "csv", d / "x.csv"),
               expect=_output(d / "x.csv", str(d / "x.csv.json"), "sidecar", "exists", "--overwrite"))


def _export_mat_existing(d: Path) -> Run:
    f = _th(d)
    (d / "x.mat").write_bytes(b"MATLAB 5.0 someone's data")
    return Run(argv=export(f, "mat", d / "x.mat"), expect=_output(d / "x.mat", "exists", "--overwrite"))


def _report_existing_page(d: Path) -> Run:
    f = _th(d)
    (d / "page.html").write_text("<p>another page</p>")
    return Run(argv=report(f, "--html", str(d / "page.html")), expect=_html(d / "page.html", "exists", "--overwrite"))


# ------------------------------------------------------------------------------ full disk
#: in the case's own process: the export's free-space probe says 1000 bytes free
_LITTLE_SPACE = """
import tb_exudyn.files as files
files._free_space = lambda folder: (1000, 4096)
from tb_exudyn.cli import main
code = main({argv!r})
raise SystemExit(code)
"""


def _little_space(fmt: str, name: str):
    def build(d: Path) -> Run:
        f = _rr(d)
        argv = export(f, fmt, d / name)
        return Run(code=_LITTLE_SPACE.format(argv=list(argv)), expect=_output(d / name, "free"), isolate=True)
    return build


CASES_WRITES: list[Case] = [
    Case("export netcdf onto the result's meta.json", GROUP, _export_netcdf_onto_meta),
    Case("export csv onto arrays.npz with --overwrite", GROUP, _export_csv_onto_arrays_overwrite),
    Case("export mat onto another result's meta.json", GROUP, _export_mat_onto_other_results_meta),
    Case("report --html onto meta.json", GROUP, _report_html_onto_meta),
    Case("export a new file into a result folder", GROUP, _export_new_file_in_result_folder),
    Case("export into a result's figures", GROUP, _export_into_result_figures),
    Case("export csv whose sidecar is meta.json", GROUP, _export_csv_sidecar_is_meta),
    Case("export onto a link to meta.json", GROUP, _export_link_to_meta),
    Case("export into a checkpoint folder", GROUP, _export_into_checkpoint),
    Case("export onto a FIFO", GROUP, _export_onto_fifo),
    Case("export onto a link to a FIFO", GROUP, _export_onto_link_to_fifo),
    Case("export csv whose sidecar is a FIFO", GROUP, _export_sidecar_is_fifo),
    Case("report --html onto a FIFO", GROUP, _report_onto_fifo),
    Case("report's default page is a FIFO", GROUP, _report_default_page_is_fifo),
    Case("report's default page is a link", GROUP, _report_default_page_is_a_link),
    Case("export onto a link to /dev/null", GROUP, _export_onto_link_to_device),
    Case("export onto a folder", GROUP, _export_onto_folder),
    Case("report --html onto a folder", GROUP, _report_onto_folder),
    Case("export onto a dangling link", GROUP, _export_onto_dangling_link),
    Case("export below a file", GROUP, _export_below_a_file),
    Case("export netcdf onto an existing file", GROUP, _export_existing_file),
    Case("export csv with an existing sidecar", GROUP, _export_existing_sidecar),
    Case("export mat onto an existing file", GROUP, _export_mat_existing),
    Case("report --html onto an existing page", GROUP, _report_existing_page),
    Case("export netcdf, too little free space", GROUP, _little_space("netcdf", "x.nc")),
    Case("export csv, too little free space", GROUP, _little_space("csv", "x.csv")),
    Case("export mat, too little free space", GROUP, _little_space("mat", "x.mat")),
]
