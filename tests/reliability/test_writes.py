"""Issue 27, outputs that never destroy: ``tb-exudyn export --output`` and ``report --html``.

1. Every hostile target of cases_writes.py ends in exit 2, one line naming the file and the option,
   no traceback, and nothing under the scratch folder written, moved or deleted (the assertions of
   test_cases.py).
2. A full disk, for real: a 16 KiB tmpfs (needs root and mount; skipped with the reason otherwise).
   The exports of a 4-channel PEM result (NetCDF 180 KB, MAT 170 KB, CSV 18 KB: each larger than the
   file system) are refused by the free-space check, and with that check disabled they reach the
   kernel's ENOSPC, in a child process: before issue 27 the NetCDF export crashed there in HDF5 with
   exit 139 and left its temporary file; now exit 2, one line, nothing left, an older file kept.
3. The same full disk in this process, by a file write that raises ENOSPC (always runs).
4. What the refusals must not prevent: --overwrite replaces the file and its sidecar with the new
   export (compared with the result's arrays, exactly: CSV holds repr-precision doubles), a link to
   a regular file is written through, the folder's default report is rewritten without --overwrite,
   and a file that appears while the export is written is not replaced.
"""

from __future__ import annotations

import errno
import importlib.util
import io
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tb_exudyn.files as files
from tb_exudyn.atomic import write_atomic_group
from tb_exudyn.cli import main
from tb_exudyn.errors import OutputFolderError
from tb_exudyn.results.export import read_csv

from .cases import snapshot
from .cases_writes import CASES_WRITES
from .test_cases import ROOT, run_case

_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)

ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def _one_line(err: str, *texts: str) -> None:
    assert "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1, err
    for text in texts:
        assert text in err, f"{text!r} not in {err!r}"


# ------------------------------------------------------------------------------------ 1. the cases
@pytest.mark.parametrize("case", CASES_WRITES, ids=[c.id for c in CASES_WRITES])
def test_hostile_target_is_one_clear_error(case, tmp_path, capsys, monkeypatch):
    work, cwd = tmp_path / "work", tmp_path / "cwd"
    work.mkdir()
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    run = case.build(work)
    before = snapshot(tmp_path)
    code, err = run_case(run, cwd, capsys, monkeypatch)
    assert code == 2, f"exit {code}: {err}"
    _one_line(err, *run.expect)
    assert snapshot(tmp_path) == before, "something was written, moved or deleted"


def test_cases_are_in_the_writes_group():
    assert CASES_WRITES and {c.group for c in CASES_WRITES} == {"writes"}
    assert len({c.id for c in CASES_WRITES}) == len(CASES_WRITES)


# ------------------------------------------------------------------------------------ 2. a real full disk
@pytest.fixture
def pem_folder(tmp_path) -> Path:
    """A saved PEM result (4 channels, 40 frequencies, 133 times; random-looking values, so that
    the compressed NetCDF stays about 180 KB)."""
    return synthetic.pem_response(nf=40).save(tmp_path / "out" / "pem")


@pytest.fixture
def full_disk(tmp_path) -> Path:
    """A 16 KiB tmpfs (4 pages), unmounted afterwards."""
    mnt = tmp_path / "fulldisk"
    mnt.mkdir()
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("a full disk needs root and mount (mount -t tmpfs)")
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", str(mnt)], capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip() or proc.returncode}")
    try:
        yield mnt
    finally:
        if subprocess.run(["umount", str(mnt)], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


#: in a child: the CLI with the free-space check disabled, so that the bytes reach the full disk
NO_SPACE_CHECK = """
import sys
import tb_exudyn.files as files
files._free_space = lambda folder: None
from tb_exudyn.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize("fmt", ["netcdf", "csv", "mat"])
def test_export_onto_a_full_disk(fmt, pem_folder, full_disk):
    old = full_disk / "old.bin"
    old.write_bytes(b"an older export")  # 15 bytes: one page of the four
    target = full_disk / f"study.{fmt}"
    argv = ["export", str(pem_folder), "--format", fmt, "--output", str(target)]
    result_before = snapshot(pem_folder)
    # the free-space check refuses first (nothing opened on the full disk)
    proc = subprocess.run([sys.executable, "-m", "tb_exudyn", *argv], capture_output=True, text=True, env=ENV,
                          timeout=120)
    assert proc.returncode == 2, proc.stderr
    _one_line(proc.stderr, str(target), "'--output'", "free")
    assert os.listdir(full_disk) == ["old.bin"]
    # without the check the write itself fails (ENOSPC from the kernel): no crash, no temporary file
    for args in (argv, argv[:-1] + [str(old), "--overwrite"]):
        proc = subprocess.run([sys.executable, "-c", NO_SPACE_CHECK, *args], capture_output=True, text=True, env=ENV,
                              timeout=120)
        assert proc.returncode == 2, f"exit {proc.returncode}: {proc.stderr}"
        _one_line(proc.stderr, args[args.index("--output") + 1], "'--output'", "No space left on device")
        assert os.listdir(full_disk) == ["old.bin"]
        assert old.read_bytes() == b"an older export"
    assert snapshot(pem_folder) == result_before


def test_report_onto_a_full_disk(tmp_path, full_disk, capsys):
    folder = synthetic.time_history().save(tmp_path / "out" / "det")
    page = full_disk / "page.html"
    assert main(["report", str(folder), "--html", str(page)]) == 2
    _one_line(capsys.readouterr().err, str(page), "'--html'", "free")
    assert os.listdir(full_disk) == []


# ------------------------------------------------------------------------------------ 3. ENOSPC in this process
class _Full(io.FileIO):
    """A file whose every write fails as on a full disk."""

    def write(self, data):  # noqa: ANN001
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("fmt", ["netcdf", "csv", "mat"])
def test_export_when_the_disk_fills_while_writing(fmt, pem_folder, tmp_path, capsys, monkeypatch):
    """The write raises ENOSPC (the free-space probe says nothing): one line, exit 2, and nothing
    left: no temporary file, not the folders the export created, an existing file unchanged."""
    monkeypatch.setattr(files, "_free_space", lambda folder: None)
    monkeypatch.setattr(files, "open", lambda path, mode="r": _Full(path, mode.replace("b", "")), raising=False)
    before = snapshot(tmp_path)
    new = tmp_path / "new" / "sub" / f"study.{fmt}"
    assert main(["export", str(pem_folder), "--format", fmt, "--output", str(new)]) == 2
    _one_line(capsys.readouterr().err, str(new), "'--output'", "No space left on device")
    assert snapshot(tmp_path) == before
    old = tmp_path / f"old.{fmt}"
    old.write_bytes(b"an older export")
    before = _files(tmp_path)
    assert main(["export", str(pem_folder), "--format", fmt, "--output", str(old), "--overwrite"]) == 2
    _one_line(capsys.readouterr().err, str(old), "No space left on device")
    assert _files(tmp_path) == before and old.read_bytes() == b"an older export"


def _files(root: Path) -> dict[str, tuple[int, int]]:
    """Every file under ``root`` (size, mtime), not the folders: a write that failed has touched its
    folder (a temporary file made and removed), so only the files can be compared."""
    return {k: (size, mtime) for k, (mode, size, mtime) in snapshot(root).items() if not stat.S_ISDIR(mode)}


def test_report_when_the_disk_is_full(tmp_path, capsys, monkeypatch):
    """The page is refused by the free-space check (the figures, drawn before, are already fresh),
    and with the check silent the write's ENOSPC is the same one line: the old page is kept."""
    from tb_exudyn.report import plot_folder

    folder = synthetic.time_history().save(tmp_path / "out" / "det")
    plot_folder(folder, workers=1)
    page = tmp_path / "page.html"
    page.write_text("the old page")
    before = _files(tmp_path)
    monkeypatch.setattr(files, "_free_space", lambda folder: (1000, 4096))
    assert main(["report", str(folder), "--html", str(page), "--overwrite"]) == 2
    _one_line(capsys.readouterr().err, str(page), "'--html'", "free")
    monkeypatch.setattr(files, "_free_space", lambda folder: None)
    monkeypatch.setattr(files, "open", lambda path, mode="r": _Full(path, mode.replace("b", "")), raising=False)
    assert main(["report", str(folder), "--html", str(page), "--overwrite"]) == 2
    _one_line(capsys.readouterr().err, str(page), "'--html'", "No space left on device")
    assert _files(tmp_path) == before and page.read_text() == "the old page"


# ------------------------------------------------------------------------------------ 4. what still works
def test_overwrite_replaces_the_file_and_its_sidecar(pem_folder, tmp_path, capsys):
    from tb_exudyn.results import load_results

    r = load_results(pem_folder)
    out = tmp_path / "pem.csv"
    out.write_text("old table\n")
    out.with_name("pem.csv.json").write_text("{}")
    assert main(["export", str(pem_folder), "--format", "csv", "--output", str(out)]) == 2
    assert "exists" in capsys.readouterr().err and out.read_text() == "old table\n"
    assert main(["export", str(pem_folder), "--format", "csv", "--output", str(out), "--overwrite"]) == 0
    assert capsys.readouterr().out.split() == [str(out), str(out) + ".json"]
    t, names, values = read_csv(out)  # the result's mean and sigma side by side, bit for bit
    assert np.array_equal(t, r.time) and np.array_equal(values[0::2], r.mean) and np.array_equal(values[1::2], r.std)
    assert '"about"' in out.with_name("pem.csv.json").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "pem.csv", "pem.csv.json"]  # no temporary file


def test_a_link_to_a_regular_file_is_written_through(pem_folder, tmp_path):
    real = tmp_path / "exports" / "study.mat"
    real.parent.mkdir()
    real.write_bytes(b"old")
    link = tmp_path / "study.mat"
    os.symlink(real, link)
    assert main(["export", str(pem_folder), "--format", "mat", "--output", str(link)]) == 2
    assert main(["export", str(pem_folder), "--format", "mat", "--output", str(link), "--overwrite"]) == 0
    assert link.is_symlink() and real.read_bytes().startswith(b"MATLAB 5.0")
    assert os.listdir(real.parent) == ["study.mat"]


def test_the_default_report_is_rewritten_and_a_new_page_written(tmp_path):
    folder = synthetic.time_history().save(tmp_path / "out" / "det")
    for argv in (["report", str(folder)], ["report", str(folder)], ["report", str(folder), "--html",
                                                                      str(folder / "report.html")]):
        assert main(argv) == 0  # the folder's own page: no --overwrite needed
    assert (folder / "report.html").read_text().startswith("<!DOCTYPE html>")
    page = tmp_path / "pages" / "det.html"
    assert main(["report", str(folder), "--html", str(page)]) == 0 and page.read_text().startswith("<!DOCTYPE html>")


def test_a_file_that_appears_while_writing_is_not_replaced(tmp_path):
    target, side = tmp_path / "x.csv", tmp_path / "x.csv.json"

    def intruder(tmp: Path) -> None:  # writing the sidecar; meanwhile someone creates it
        tmp.write_bytes(b"ours")
        side.write_bytes(b"theirs")

    with pytest.raises(OutputFolderError, match=r"key 'path' = .*x\.csv'.*sidecar file .*x\.csv\.json'.*appeared"):
        files.write_output([(target, b"table"), (side, intruder)], named=target, overwrite=False, where="export",
                           key="path")
    assert sorted(os.listdir(tmp_path)) == ["x.csv.json"] and side.read_bytes() == b"theirs"  # ours taken back


def test_a_group_write_that_fails_removes_what_it_created(tmp_path):
    def fails(tmp: Path) -> None:
        raise OSError(errno.EIO, "input/output error")

    with pytest.raises(OSError):
        write_atomic_group([(tmp_path / "a" / "b" / "one", lambda p: p.write_bytes(b"1")),
                            (tmp_path / "a" / "b" / "two", fails)], replace=False)
    assert os.listdir(tmp_path) == []
