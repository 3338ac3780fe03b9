"""A result folder is written whole or not at all: an error or a SIGKILL during a save leaves the old
result or the new one, never the old metadata over the new arrays; leftovers of killed writes are
cleaned (or put in place) the next time the folder is written or loaded."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tb_exudyn.errors import OutputFolderError
from tb_exudyn.results import RandomResponse, TimeHistory, load_results
from tb_exudyn import storage
from tb_exudyn.storage import _host_tag, iter_leftovers

from .cases import rr_arrays, rr_meta
from .kill import outcome, save_in_child

ROOT = Path(__file__).resolve().parents[2]
NAMES = ("bridge.span1.mid.disp_z", "car1.body.acc_z")


def history(tag: str, value: float, nt: int = 51) -> TimeHistory:
    return TimeHistory(time=np.arange(nt) * 0.01, channels={n: np.full(nt, value) for n in NAMES},
                       units=dict(zip(NAMES, ("m", "m/s^2"))), provenance={"tag": tag})


def response(tag: str, value: float) -> RandomResponse:
    from tb_exudyn.scenario import load_scenario

    a, m = rr_arrays(), rr_meta()
    return RandomResponse(method="pem", time=a["time"], channels=NAMES, units=("m", "m/s^2"), mean=a["mean"] + value,
                          std=a["std"] * value, band=(0.5, 3.5), scenario=load_scenario("quick"), freq=a["freq"],
                          df=a["df"], types=tuple(m["types"]), provenance={"tag": tag})


def tag_and_values(folder: Path) -> tuple[str, set[float]]:
    r = load_results(folder)
    values = np.array([r[n] for n in r.names]) if isinstance(r, TimeHistory) else r.std
    return r.provenance["tag"], set(np.unique(values).tolist())


def dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


@pytest.mark.parametrize("make", [history, response], ids=["time history", "random response"])
@pytest.mark.parametrize("fail", ["meta.json", "rename"])
def test_error_between_the_two_files_keeps_the_old_result(tmp_path, monkeypatch, make, fail):
    """A write that raises after arrays.npz is written (before meta.json), or between the two renames
    that swap the folders: the old result loads as it was, and nothing is left over."""
    folder = tmp_path / "res"
    make("old", 1.0).save(folder)
    write_file, rename = storage._write_file, os.rename

    def failing_write(path, write):
        if path.name == "meta.json":
            raise OSError(28, "No space left on device")
        write_file(path, write)

    def failing_rename(src, dst):
        if str(src).endswith(".new"):
            raise KeyboardInterrupt
        rename(src, dst)

    if fail == "meta.json":
        monkeypatch.setattr(storage, "_write_file", failing_write)
    else:
        monkeypatch.setattr(storage.os, "rename", failing_rename)
    with pytest.raises((OSError, KeyboardInterrupt)):
        make("new", 2.0).save(folder)
    monkeypatch.undo()
    assert tag_and_values(folder) == ("old", {1.0})
    assert not list(iter_leftovers(folder)) and sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_sigkill_during_a_large_save_leaves_the_old_or_the_new_result(tmp_path):
    """The child saves 80 MB over an older result and is ended 0 to 0.6 s of its CPU time into the save
    (a save takes about 0.3-1 s here; CPU time, not wall time: the same points under any load): each time the folder reads back as the old result or the new one,
    and after that read no leftover remains. Kills after the save finished must give the new one."""
    folder = tmp_path / "det"
    seen = []
    for delay in (0.0, 0.1, 0.25, 0.6):
        save_in_child(ROOT, folder, "old", 1.0, None)
        finished = save_in_child(ROOT, folder, "new", 2.0, delay)
        got = outcome(ROOT, folder)
        assert got in ("old", "new"), f"killed {delay} s into the save: {got}"
        assert got == "new" or not finished
        assert not list(iter_leftovers(folder)), list(iter_leftovers(folder))
        seen.append(got)
    assert "old" in seen  # at least one kill landed before the new result was in place


def _leftover(folder: Path, pid: int, state: str) -> Path:
    return folder.parent / f".{folder.name}.tb-{_host_tag()}-{pid}-abcd1234.{state}"


def test_leftovers_of_a_dead_writer_are_removed_when_the_folder_is_loaded(tmp_path):
    folder = history("old", 1.0).save(tmp_path / "det")
    pid = dead_pid()
    writing = _leftover(folder, pid, "writing")
    writing.mkdir()
    (writing / "arrays.npz").write_bytes(b"half")
    history("other", 3.0).save(tmp_path / "x")
    os.rename(tmp_path / "x", _leftover(folder, pid, "old"))
    legacy = folder / ".arrays.npz.k2j4h5.tmp"
    legacy.write_bytes(b"\0" * 1000)
    assert len(list(iter_leftovers(folder))) == 3
    assert tag_and_values(folder) == ("old", {1.0})
    assert not list(iter_leftovers(folder)) and sorted(p.name for p in tmp_path.iterdir()) == ["det"]


@pytest.mark.parametrize("state, tag", [("new", "new"), ("old", "old")])
def test_a_complete_leftover_takes_the_place_of_a_missing_folder(tmp_path, state, tag):
    """Killed between the two renames: the folder is missing; a complete new result is put in place
    (else the old one is restored) when the folder is next loaded."""
    folder = tmp_path / "det"
    history(tag, 1.0 if tag == "old" else 2.0).save(tmp_path / "x")
    os.rename(tmp_path / "x", _leftover(folder, dead_pid(), state))
    assert tag_and_values(folder) == (tag, {1.0 if tag == "old" else 2.0})
    assert not list(iter_leftovers(folder))


def test_leftovers_of_a_running_writer_are_left_alone(tmp_path):
    folder = history("old", 1.0).save(tmp_path / "det")
    # alive until the test closes its stdin (an event: a delay could run out on a loaded machine)
    proc = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE)
    try:
        writing = _leftover(folder, proc.pid, "writing")
        writing.mkdir()
        assert tag_and_values(folder) == ("old", {1.0})
        history("new", 2.0).save(folder)
        assert writing.is_dir() and tag_and_values(folder) == ("new", {2.0})
    finally:
        proc.kill()
        proc.wait()


def test_leftovers_are_also_cleaned_by_the_next_save(tmp_path):
    folder = history("old", 1.0).save(tmp_path / "det")
    _leftover(folder, dead_pid(), "writing").mkdir()
    (folder / ".meta.json.x1y2.tmp").write_text("{")
    history("new", 2.0).save(folder)
    assert tag_and_values(folder) == ("new", {2.0}) and not list(iter_leftovers(folder))


def test_save_replaces_an_old_result_with_its_figures_but_refuses_other_files(tmp_path):
    """The old result's figures and report go with it; a folder holding anything else is not
    replaced (nothing of the user's is lost) and stays as it was."""
    folder = history("old", 1.0).save(tmp_path / "det")
    (folder / "figures").mkdir()
    (folder / "figures" / "old.png").write_bytes(b"png")
    (folder / "report.html").write_text("<html>")
    history("new", 2.0).save(folder)
    assert sorted(p.name for p in folder.iterdir()) == ["arrays.npz", "meta.json"]
    (folder / "notes.txt").write_text("mine")
    with pytest.raises(OutputFolderError, match="notes.txt"):
        history("newer", 3.0).save(folder)
    assert (folder / "notes.txt").read_text() == "mine" and tag_and_values(folder) == ("new", {2.0})
    assert not list(iter_leftovers(folder))


def test_save_through_a_symlinked_folder_replaces_its_target(tmp_path):
    target = history("old", 1.0).save(tmp_path / "target")
    os.symlink(target, tmp_path / "link")
    history("new", 2.0).save(tmp_path / "link")
    assert (tmp_path / "link").is_symlink() and tag_and_values(target) == ("new", {2.0})


def test_saved_files_stay_plain_numpy_and_json(tmp_path):
    """The format is unchanged: np.load (allow_pickle=False) and json read the files, and the file
    permissions are the usual ones (not a temporary file's 0600)."""
    import json

    folder = history("old", 1.0).save(tmp_path / "det")
    with np.load(folder / "arrays.npz", allow_pickle=False) as z:
        assert z["values"].shape == (2, 51)
    assert json.loads((folder / "meta.json").read_text())["format"] == "tb_exudyn.time_history/1"
    umask = os.umask(0)
    os.umask(umask)
    assert (folder / "meta.json").stat().st_mode & 0o777 == 0o666 & ~umask
