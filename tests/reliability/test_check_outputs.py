"""The outputs of `tb-exudyn check` are never lost or half-written (issue 49).

The check: single_span_32m (ballasted, three mass cases) under HSLM-A1 at a line speed of 120 km/h, so
that its series is the one speed 144 km/h (40 m/s, the series' start, above 1.2 x 120): three rows, the
analysis in well under a second, the figure and the page drawn as always.

- Two checks into one --out: the first is held in its analysis (a child process waiting on its stdin,
  no sleep), the second is refused with one line (with and without --overwrite) and writes nothing; the
  first then writes its files, and a third without --overwrite is refused, nothing replaced.
- Ctrl-C: SIGINT sent to a child held in its analysis; and, in this process, SIGINT the command sends
  itself at an exact point (handled as a terminal's Ctrl-C is): in the analysis, while the page is drawn
  (after the figure), after the first temporary file is complete, and just after check.csv is put in
  place. Before the renames: no check file of the new check (an old check untouched byte for byte); before
  any task finished --out as it was (a new one gone) and the message's hint (run the same command again)
  works; after the tasks finished they wait in --out/checkpoint-check and the hint (--resume) works; during
  the renames: every file in place, whole, and the message says so.
- --out refused before the analysis (the integration never runs) and in under 2 s: a file, a FIFO, a path
  under a file, an unwritable folder, /proc.
- Trains by name: a train given twice is one train; two different trains with one name are refused
  naming both (also tests/reliability/cases_en1991.py); a 7 m span, whose first mode lies above the
  check's first mode limit of 60 Hz, is checked (it was refused naming max_frequency).
- The writes' own guarantee: a SIGINT during write_atomic_group's renames is held until they are done.
"""

from __future__ import annotations

import csv
import importlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn import atomic
from tb_exudyn.cli import main
from tb_exudyn.codes.trains import ForceTrain, resolve_trains
from tb_exudyn.errors import SettingError

from .execution_helpers import ROOT

FILES = ("check.csv", "check.html", "check.png")
#: the module (tb_exudyn.codes.check is also the name of its function, which the package exports)
check_module = importlib.import_module("tb_exudyn.codes.check")
#: the check's method on the driver, whose tasks integrate (this small check runs them in this process)
method_module = importlib.import_module("tb_exudyn.methods.check")


def argv(out: Path, *more: str) -> list[str]:
    return ["check", "single_span_32m", "--line-speed-kmh", "120", "--trains", "HSLM-A1", "--out", str(out),
            "--no-progress", *more]


def env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1"}


#: the command in a child process, held in its analysis (before its first integration's work) until a
#: line comes on its stdin
CHILD = r"""
import importlib, sys
chk = importlib.import_module("tb_exudyn.methods.check")
real = chk.moving_force_response

def held(*a, **k):
    print("analysing", flush=True)
    sys.stdin.readline()
    return real(*a, **k)

chk.moving_force_response = held
from tb_exudyn.cli import main
sys.exit(main(sys.argv[1:]))
"""


def held_child(args: list[str], cwd: Path) -> subprocess.Popen:
    """The command in a child process, held in its analysis; returns once it got there."""
    proc = subprocess.Popen([sys.executable, "-c", CHILD, *args], env=env(), cwd=cwd, text=True,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    line = proc.stdout.readline()
    if line.strip() != "analysing":
        proc.kill()
        raise AssertionError(f"the child did not reach its analysis: {line!r} {proc.communicate()[1]}")
    return proc


def interrupt_at(point: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Make this process send itself SIGINT (a real Ctrl-C's signal, handled as the command handles it)
    once, at ``point`` of the next check: 'analysis' (its first integration), 'drawing' (the page, after
    the figure), 'temporary' (the first temporary file complete, before any rename), 'renames' (just
    after check.csv is put in place: a hard link for a new file, a rename over an old one)."""
    sent: list[int] = []

    def interrupt() -> None:
        if not sent:
            sent.append(1)
            os.kill(os.getpid(), signal.SIGINT)

    def wrap(owner, name, before=None, after=None) -> None:  # noqa: ANN001
        real = getattr(owner, name)

        def hooked(*a, **k):  # noqa: ANN002, ANN003, ANN202
            if before:
                before(*a)
            out = real(*a, **k)
            if after:
                after(*a)
            return out
        monkeypatch.setattr(owner, name, hooked)

    if point == "analysis":
        wrap(method_module, "moving_force_response", before=lambda *a: interrupt())
    elif point == "drawing":
        wrap(importlib.import_module("tb_exudyn.report.check"), "render_check_report", before=lambda *a: interrupt())
    elif point == "temporary":  # atomic.write_atomic_group sets each complete temporary file's mode (a check
        # file's, not a checkpoint task file's)
        wrap(os, "chmod", after=lambda path, *a: interrupt() if str(path).endswith(".tmp") and
             os.path.basename(path).startswith(".check.") else None)
    else:
        for name in ("link", "replace"):
            wrap(os, name, after=lambda src, dst, *a: interrupt() if os.path.basename(dst) == "check.csv" else None)


def entries(root: Path) -> dict[str, bytes | None]:
    """Every entry under ``root``: a file's bytes, None for a folder."""
    out: dict[str, bytes | None] = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames:
            out[os.path.relpath(os.path.join(dirpath, name), root)] = None
        for name in filenames:
            out[os.path.relpath(os.path.join(dirpath, name), root)] = Path(dirpath, name).read_bytes()
    return out


def assert_whole(out: Path, track_limit: str = "3.5") -> None:
    """The three files of one complete check: the table's three rows (one per mass case, the given
    track's limit), a PNG, and the page to its end."""
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)
    with open(out / "check.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["case"] for r in rows] == ["lower", "nominal", "upper"] and {r["limit"] for r in rows} == {track_limit}
    assert (out / "check.png").read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    assert (out / "check.html").read_text().endswith("</html>\n")


# ------------------------------------------------------------------------------- two checks, one --out
def test_a_second_check_into_a_busy_out_is_refused_and_replaces_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    first = held_child(argv(out), tmp_path)
    try:
        for more in ((), ("--overwrite",)):
            assert main(argv(out, *more)) == 2
            err = capsys.readouterr().err
            assert len(err.strip().splitlines()) == 1 and "in use by another run" in err and "--out" in err, err
            assert sorted(os.listdir(out)) == [".tb_exudyn.lock", "checkpoint-check"]  # the first's, nothing else
        first.stdin.write("\n")
        first.stdin.flush()
        stdout, stderr = first.communicate(timeout=300)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert first.returncode == 0, stderr
    assert_whole(out)
    before = entries(out)
    assert main(argv(out, "--track", "direct")) == 2
    err = capsys.readouterr().err
    assert "of an earlier check" in err and "--overwrite" in err
    assert entries(out) == before


# ---------------------------------------------------------------------------------------- Ctrl-C
def test_a_ctrl_c_from_outside_leaves_nothing(tmp_path):
    """SIGINT sent to a check held in its analysis (as a terminal's Ctrl-C reaches it): exit 130, one line
    saying nothing was written and that the same command can be run again; the new --out is gone."""
    out = tmp_path / "out"
    proc = held_child(argv(out), tmp_path)
    try:
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, stderr
    # one line of ours (a fresh matplotlib may log its font cache's building first: not the command's)
    assert [x for x in stderr.splitlines() if x.startswith("tb-exudyn")] == [
        f"tb-exudyn: interrupted before the check's files were written: --out {str(out)!r} is as it was; "
        "run the same command again"], stderr
    assert entries(tmp_path) == {}


@pytest.mark.parametrize("point", ["analysis", "drawing", "temporary", "renames"])
def test_ctrl_c_leaves_all_or_nothing_and_the_hint_works(point, tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    with monkeypatch.context() as patched:
        interrupt_at(point, patched)
        assert main(argv(out)) == 130
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    if point == "analysis":  # no task finished: nothing kept
        assert "before the check's files were written" in err and "run the same command again" in err
        assert entries(tmp_path) == {}, "a new --out is removed again, with no temporary file"
        assert main(argv(out)) == 0  # the hint, as given
        assert_whole(out)
        return
    if point != "renames":  # every task finished: kept in the checkpoint, no check file, no temporary file
        assert "before the check's files were written" in err and "run the same command with --resume" in err, err
        assert entries(tmp_path) and all(p == "out" or p.startswith("out/checkpoint-check") for p in entries(tmp_path))
        assert main(argv(out)) == 2 and "--resume to continue it" in capsys.readouterr().err
        assert main(argv(out, "--resume")) == 0  # the hint, as given
        assert_whole(out)
        return
    assert "written whole: check.csv, check.png, check.html" in err  # the renames finished first
    assert_whole(out)
    assert not [p for p in entries(tmp_path) if p.endswith(".tmp")]
    assert main(argv(out)) == 2 and "--overwrite" in capsys.readouterr().err
    assert main(argv(out, "--overwrite")) == 0


@pytest.mark.parametrize("point", ["temporary", "renames"])
def test_ctrl_c_over_an_earlier_check(point, tmp_path, capsys, monkeypatch):
    """--overwrite of an earlier check (direct track, limit 5), interrupted: before the renames the old
    files are there byte for byte; during them every file is the new one (ballasted, limit 3.5)."""
    out = tmp_path / "out"
    assert main(argv(out, "--track", "direct")) == 0
    old = entries(out)
    with monkeypatch.context() as patched:
        interrupt_at(point, patched)
        assert main(argv(out, "--overwrite")) == 130
    err = capsys.readouterr().err
    if point == "temporary":  # the old files byte for byte; the new check's tasks wait in its checkpoint
        assert {p: v for p, v in entries(out).items() if not p.startswith("checkpoint-check")} == old
        assert "--resume" in err, err
    else:
        assert_whole(out, "3.5")
        assert "written whole" in err, err
    assert not [p for p in entries(tmp_path) if p.endswith(".tmp")]


# ------------------------------------------------------------------------ --out refused at once
def _unwritable(tmp_path: Path) -> Path:
    """A folder this process cannot create files in: read-only for a normal user; for root, whom
    permissions do not stop, a sysfs folder (no one can create files there)."""
    if os.geteuid() != 0:
        folder = tmp_path / "read_only"
        folder.mkdir()
        folder.chmod(0o555)
        return folder
    folder = Path("/sys/kernel")
    try:
        fd, name = __import__("tempfile").mkstemp(dir=folder)
    except OSError:
        return folder
    os.close(fd)
    os.unlink(name)
    pytest.skip("running as root on a machine whose /sys/kernel takes files: no folder here is unwritable to root")


def _target(kind: str, tmp_path: Path) -> Path:
    if kind == "file":
        (tmp_path / "a_file").write_text("x\n")
        return tmp_path / "a_file"
    if kind == "fifo":
        os.mkfifo(tmp_path / "a_fifo")
        return tmp_path / "a_fifo"
    if kind == "under a file":
        (tmp_path / "a_file").write_text("x\n")
        return tmp_path / "a_file" / "out"
    if kind == "unwritable folder":
        return _unwritable(tmp_path)
    if kind == "new folder in an unwritable one":
        return _unwritable(tmp_path) / "out"
    return Path("/proc")


@pytest.mark.parametrize("kind", ["file", "fifo", "under a file", "unwritable folder",
                                  "new folder in an unwritable one", "/proc"])
def test_out_is_refused_before_the_analysis_in_under_2_s(kind, tmp_path, capsys, monkeypatch):
    """The integration (moving_force_response) must not start; the one line names --out's path, why and
    what is allowed. 2 s is the issue's bound: the refusals take milliseconds (a read-only look at the
    path) up to the FE modes of the three mass cases (a folder only a write can test, for root). Timed as this
    process's CPU time, so that a loaded machine (the suite beside a CPU hog) cannot fail it."""
    target = _target(kind, tmp_path)

    def analysis(*a, **k):
        raise AssertionError("the analysis ran")

    monkeypatch.setattr(method_module, "moving_force_response", analysis)
    before = sorted(os.listdir(tmp_path))
    t0 = time.process_time()  # this process's CPU time: the work done, not how long a loaded machine made it wait
    code = main(argv(target))
    seconds = time.process_time() - t0
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert str(target) in err and "not writable" in err and "allowed: a folder this user can create files in" in err
    assert seconds < 2.0, f"{seconds:.2f} s"
    assert sorted(os.listdir(tmp_path)) == before


# ------------------------------------------------------------------------------- trains and bridges
def test_a_train_given_twice_is_one_train(tmp_path, monkeypatch):
    """hslm_a with HSLM-A3 is the ten trains; a train file by two spellings of its path is one train; two
    ForceTrain objects with one name are refused naming both, the same object twice is one; so is a train
    named HSLM-B beside the HSLM-B that stands in for HSLM-A on a 5 m span."""
    assert [t.name for t in resolve_trains(["hslm_a", "HSLM-A3", "hslm_a3"])] == [f"HSLM-A{i}" for i in range(1, 11)]
    p = tmp_path / "t.toml"
    p.write_text('name = "t"\n[[cars]]\naxles = [0.0, 2.5, 17.5, 20.0]\naxle_load = 170e3\nlength = 25.0\n')
    monkeypatch.chdir(tmp_path)
    assert len(resolve_trains([str(p), "t.toml", "./t.toml"])) == 1
    a = ForceTrain("mine", [0.0, 3.0], [1e5, 1e5], 20.0)
    b = ForceTrain("mine", [0.0, 3.0], [2e5, 2e5], 20.0)
    assert len(check_module.check("single_span_32m", 120.0, trains=[a, a]).trains()) == 1
    with pytest.raises(SettingError, match="two trains named 'mine': the ForceTrain object 'mine' and the ForceTrain"):
        check_module.check("single_span_32m", 120.0, trains=[a, b])
    # a 5 m span takes HSLM-B for hslm_a (EN 1991-2 Annex E): a train of that name besides it is refused too
    short = check_module.load_bridge("single_span_32m").replace(spans=(5.0,))
    with pytest.raises(SettingError, match="two trains named 'HSLM-B'.*EN 1991-2's HSLM-B"):
        check_module.check(short, 120.0, trains=["hslm_a", ForceTrain("HSLM-B", [0.0, 3.0], [1e5, 1e5], 20.0)])


def test_a_7_m_span_is_checked_and_named_by_its_file(tmp_path):
    """single_span_32m's file with a 7 m span (HSLM-A's shortest, EN 1991-2 Annex E): its first mode is
    above 60 Hz, the check's first mode limit, which the check raises (was: refused naming
    'max_frequency', which the check cannot change). The result names the file given."""
    p = tmp_path / "span_7m.toml"
    p.write_text((ROOT / "models" / "bridges" / "single_span_32m.toml").read_text().replace("spans = [32.0]",
                                                                                          "spans = [7.0]"))
    r = check_module.check(str(p), 120.0, trains=["HSLM-A1"])
    assert min(r.vertical_frequencies) > check_module.FIRST_MODE_LIMIT_HZ and len(r) == 3
    assert r.bridge == "single_span_32m" and r.bridge_file == str(p) and str(p) in r.summary()


# ----------------------------------------------------------------------------- the writes themselves
@pytest.mark.parametrize("replace", [True, False])
def test_a_sigint_during_the_renames_is_held_until_the_group_is_in_place(replace, tmp_path, monkeypatch):
    """write_atomic_group of three files; SIGINT sent at the first rename (or hard link): the three are in
    place, whole, and then KeyboardInterrupt is raised; no temporary file is left."""
    paths = [tmp_path / f"f{i}.txt" for i in range(3)]
    place = "replace" if replace else "link"
    real = getattr(os, place)

    def placed(src, dst, *a, **k):
        real(src, dst, *a, **k)
        if Path(dst) == paths[0]:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(os, place, placed)
    handler = signal.getsignal(signal.SIGINT)
    with pytest.raises(KeyboardInterrupt):
        atomic.write_atomic_group([(p, lambda tmp, i=i: Path(tmp).write_text(f"file {i}\n"))
                                   for i, p in enumerate(paths)], replace=replace)
    assert [p.read_text() for p in paths] == ["file 0\n", "file 1\n", "file 2\n"]
    assert sorted(os.listdir(tmp_path)) == ["f0.txt", "f1.txt", "f2.txt"]
    assert signal.getsignal(signal.SIGINT) is handler  # put back


# ------------------------------------------------------------------------------- --netcdf
def test_netcdf_writes_the_typed_records_with_the_group_and_a_check_without_it_removes_them(tmp_path, capsys):
    """``--netcdf`` adds check.nc to the group: the file read back by xarray is ``CheckResult.to_xarray()`` of the
    same check (every variable equal, NaN where the CSV is empty: the same numbers, no tolerance) and its rows are
    the CSV's (train, speed, case, peak deck acceleration). The same check again with --overwrite and without
    --netcdf removes check.nc with the same renames (a stale file would describe another check)."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    out = tmp_path / "out"
    assert main(argv(out, "--netcdf", "--no-figures")) == 0
    assert "check.nc" in capsys.readouterr().out  # the last line names it
    assert sorted(p.name for p in out.iterdir()) == ["check.csv", "check.html", "check.nc"]
    ref = check_module.check("single_span_32m", 120.0, trains=["HSLM-A1"], workers=1).to_xarray()
    with xr.open_dataset(out / "check.nc", engine="h5netcdf") as ds:
        ds.load()
    assert set(ds.data_vars) == set(ref.data_vars) and ds.sizes == ref.sizes
    for name in ref.data_vars:
        a, b = ds[name].values, ref[name].values
        assert a.dtype.kind == b.dtype.kind and (np.array_equal(a, b, equal_nan=True) if a.dtype.kind == "f"
                                                 else np.array_equal(a, b)), name
    with open(out / "check.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["case"] for r in rows] == [str(c) for c in ds["case"].values]
    assert [float(r["max_deck_acc_z"]) for r in rows] == [float(v) for v in ds["max_deck_acc_z"].values]
    assert main(argv(out, "--no-figures", "--overwrite")) == 0
    assert sorted(p.name for p in out.iterdir()) == ["check.csv", "check.html"]


def test_netcdf_without_its_packages_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    """--netcdf with h5netcdf missing (find_spec made to say so): exit 2, one line naming --netcdf and the extra to
    install, before the analysis (the integration never runs) and with --out not made."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "h5netcdf" else real(name, *a))
    monkeypatch.setattr(method_module, "moving_force_response", lambda *a, **k: pytest.fail("the analysis ran"))
    out = tmp_path / "out"
    assert main(argv(out, "--netcdf")) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--netcdf" in err and 'pip install "tb_exudyn[netcdf]"' in err, err
    assert not out.exists()
