"""What a run may do to its output folder: refuse another run's files, or clear them when told to.

A run (PEM, Monte Carlo, the deterministic run) owns two entries of its output folder
(:class:`RunFiles`): its result folder (``pem/``, ``mc/``, ``mc_linear/``, ``det/``) and its checkpoint
folder (``checkpoint/``, ...). Several runs of different methods share an output folder (``pem/`` and
``mc/`` side by side, compared by ``tb-exudyn compare DIR DIR``); the folder's comparison figures and its
report are drawn from all of them.

Without ``resume`` a run refuses a folder whose entries hold another run's files (a result, or a
checkpoint with finished tasks), unless told to overwrite; with ``overwrite`` it clears that run's
files: its checkpoint and figures at once, the folder's comparison figures and report (drawn from the
old result), and its result when the new one is saved (the result folder is replaced as a whole, so a
run killed before that leaves the old result, complete). Nothing else in the folder is touched. With
``resume`` a folder whose result has no checkpoint to resume from is refused (nothing to resume:
overwrite instead). Refusals change nothing; an output folder that a refused (or interrupted) command
created and left unused is removed again (:func:`removed_if_left_empty`).
"""

from __future__ import annotations

import os
import shutil
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Sequence

from ..errors import OutputFolderError, UserError
from ..files import entry_kind, owning_folder

#: files of an output folder drawn from all its results (tb_exudyn.plotting.files.plot_folder writes
#: ``figures/<channel>.pem_vs_mc.<format>``, tb_exudyn.report.write_report ``report.html``)
FOLDER_FIGURES = "figures"
COMPARISON_FIGURE = ".pem_vs_mc."
REPORT = "report.html"
#: a speed sweep's figure and page, drawn from its table (``tb-exudyn sweep``)
SWEEP_FIGURE = "speed_sweep.png"
SWEEP_PAGE = "speed_sweep.html"
#: a result's own figures (``<result>/figures/``)
RESULT_FIGURES = "figures"


@dataclass(frozen=True)
class RunFiles:
    """The entries of an output folder a run writes: its result folder and its checkpoint folder
    (names inside the output folder; no checkpoint for the deterministic run), and the files drawn
    from that result beside it (``drawn``: a sweep's figure and page), removed when it is overwritten."""

    result: str
    checkpoint: str | None = None
    drawn: tuple[str, ...] = ()
    #: a run whose result is files at the folder's top written as one group at its end (the EN 1991-2
    #: check: check.csv, check.png, check.html), not a result folder: ``result`` is then what the messages
    #: call it ('check'); the files are refused as :func:`refuse_earlier_files` says and never cleared
    #: before the new group replaces them (an interrupted --overwrite leaves the old ones whole)
    group: tuple[str, ...] = ()


#: how a message names the options (the function arguments; a caller that names them otherwise, the
#: command line, respells them when it prints the message)
_OPTIONS = {"overwrite": "overwrite=True", "resume": "resume=True", "out": "another out folder"}


def _has_files(path: Path) -> bool:
    if path.is_symlink() or (path.exists() and not path.is_dir()):
        return True
    return path.is_dir() and any(path.iterdir())


def holdings(folder: Path, files: RunFiles) -> list[str]:
    """What of ``files`` already holds something in ``folder``: 'result <name>/', 'checkpoint <name>/ (N
    finished tasks)'. A checkpoint without finished tasks holds nothing."""
    out = []
    if _has_files(folder / files.result):
        out.append(f"the result {files.result}/")
    if files.checkpoint is not None:
        tasks = folder / files.checkpoint / "tasks"
        n = sum(1 for p in tasks.glob("*.npz")) if tasks.is_dir() and not tasks.is_symlink() else 0
        if n:
            out.append(f"the checkpoint {files.checkpoint}/ ({n} finished tasks)")
    return out


def remove_entry(path: Path) -> None:
    """Remove a file, a symbolic link (not what it points to) or a folder tree."""
    if path.is_symlink() or path.is_file():
        path.unlink()
    elif path.is_dir():
        shutil.rmtree(path)
    elif os.path.lexists(path):
        path.unlink()


def clear_run(folder: Path, files: RunFiles) -> None:
    """Remove the old run's checkpoint, figures and drawn files, and the folder's comparison figures
    and report (the result itself is replaced when the new one is saved)."""
    if files.checkpoint is not None:
        remove_entry(folder / files.checkpoint)
    result = folder / files.result
    if result.is_dir() and not result.is_symlink():
        remove_entry(result / RESULT_FIGURES)
    figures = folder / FOLDER_FIGURES
    if figures.is_dir() and not figures.is_symlink():
        for f in figures.iterdir():
            if COMPARISON_FIGURE in f.name and (f.is_file() or f.is_symlink()):
                f.unlink()
    if os.path.lexists(folder / REPORT):
        remove_entry(folder / REPORT)
    for name in files.drawn:
        if os.path.lexists(folder / name):
            remove_entry(folder / name)


def prepare_folder(folder: Path, files: RunFiles, *, resume: bool, overwrite: bool, where: str) -> None:
    """Refuse (OutputFolderError naming the folder, what it holds and the options) or clear, as the
    module docstring says; call with the folder's lock held."""
    if files.group:
        _prepare_group(folder, files, resume=resume, overwrite=overwrite, where=where)
        return
    opt = _OPTIONS
    held = holdings(folder, files)
    if resume:
        if files.checkpoint is None:
            return
        checkpoint = folder / files.checkpoint
        has_checkpoint = (os.path.lexists(checkpoint / "manifest.json")
                          or any(h.startswith("the checkpoint") for h in held))
        if _has_files(folder / files.result) and not has_checkpoint:
            raise OutputFolderError(
                f"{where}: output folder {str(folder)!r} holds {held[0]} but no checkpoint to resume from: use "
                f"{opt['overwrite']} to run again, or {opt['out']}", where=where, key="out", value=str(folder),
                allowed=f"{opt['overwrite']} to run again, or {opt['out']}")
        return
    if not held:
        return
    if not overwrite:
        cont = f"{opt['resume']} to continue it, " if any(h.startswith("the checkpoint") for h in held) else ""
        raise OutputFolderError(
            f"{where}: output folder {str(folder)!r} holds {' and '.join(held)} of an earlier run: use {cont}"
            f"{opt['overwrite']} to replace it, or {opt['out']}", where=where, key="out", value=str(folder),
            allowed=f"{cont}{opt['overwrite']} to replace it, or {opt['out']}")
    clear_run(folder, files)


def _finished_tasks(folder: Path, checkpoint: str | None) -> int:
    tasks = folder / checkpoint / "tasks" if checkpoint is not None else None
    return sum(1 for _ in tasks.glob("*.npz")) if tasks is not None and tasks.is_dir() and not tasks.is_symlink() else 0


def _prepare_group(folder: Path, files: RunFiles, *, resume: bool, overwrite: bool, where: str) -> None:
    """:func:`prepare_folder` for a run of ``files.group`` (see :class:`RunFiles`): the group's earlier files
    refused without ``overwrite`` (with ``resume`` too unless a checkpoint is there to continue), an earlier
    checkpoint with finished tasks refused without ``resume`` or ``overwrite`` and removed with ``overwrite``."""
    finished = _finished_tasks(folder, files.checkpoint)
    refuse_earlier_files(folder, files.group, files.result, overwrite=overwrite or (resume and finished > 0),
                         where=where)
    if resume or not finished:
        return
    if not overwrite:
        allowed = f"{_OPTIONS['resume']} to continue it, {_OPTIONS['overwrite']} to replace it, or {_OPTIONS['out']}"
        raise OutputFolderError(
            f"{where}: output folder {str(folder)!r} holds the checkpoint {files.checkpoint}/ ({finished} finished "
            f"tasks) of an earlier {files.result}: use {allowed}", where=where, key="out", value=str(folder),
            allowed=allowed)
    remove_entry(folder / files.checkpoint)  # type: ignore[operator]


def refuse_earlier_files(folder: str | Path, names: Sequence[str], what: str, *, overwrite: bool, where: str) -> None:
    """Check the fixed file ``names`` that a command writes into ``folder`` without a result folder of
    its own (the EN 1991-2 check), before any work; call with the folder's lock held, so that the test
    and the write are one step for other runs. OutputFolderError (nothing changed) when:

    - an entry of one of the names is not a file (a folder, a FIFO, ...): no option replaces it;
    - ``folder`` lies inside a result or checkpoint folder, which holds only its own files;
    - it holds any of them (a symbolic link counts: with ``overwrite`` the link itself is replaced, never
      what it points to) of an earlier ``what`` and not ``overwrite``."""
    folder = Path(folder)
    move = f"move it away, or {_OPTIONS['out']}"
    for name in names:
        kind = entry_kind(folder / name)
        if kind is not None:
            raise OutputFolderError(f"output folder {str(folder)!r} holds {name}, {kind}, where the {what} writes its "
                                    f"file: not replaced (allowed: {move})", where=where, key="out",
                                    value=str(folder), allowed=move)
    owner = owning_folder(Path(os.path.realpath(folder)) / names[0])
    if owner is not None:
        allowed = f"{_OPTIONS['out']}, outside result and checkpoint folders"
        raise OutputFolderError(f"output folder {str(folder)!r} is inside {owner}, which holds only the result's own "
                                f"files (allowed: {allowed})", where=where, key="out", value=str(folder),
                                allowed=allowed)
    held = [n for n in names if os.path.lexists(folder / n)]
    if held and not overwrite:
        allowed = f"{_OPTIONS['overwrite']} to replace it, or {_OPTIONS['out']}"
        raise OutputFolderError(f"output folder {str(folder)!r} holds {', '.join(held)} of an earlier {what} "
                                f"(allowed: {allowed})", where=where, key="out", value=str(folder), allowed=allowed)


@contextmanager
def removed_if_left_empty(folder: str | Path) -> Iterator[None]:
    """On an exception in the block, remove ``folder`` and the parents of it that did not exist when the
    block began, as far as they are left unused: a command refused (or interrupted) after its output
    folder was created (e.g. by :func:`tb_exudyn.storage.check_writable`) leaves no new empty
    folder. After a refusal (a :class:`~tb_exudyn.errors.UserError`) a new folder that holds only
    checkpoints without a finished task (``manifest.json`` beside an empty ``tasks/``: a run refused
    when its tasks were set up, e.g. by the memory estimate) is unused too, and so is such a checkpoint
    folder that the block made inside an existing ``folder``. Nothing else is removed: a folder that
    holds anything more, or that existed before, is kept."""
    new = []  # the folder and its missing parents, innermost first
    path = Path(os.path.abspath(folder))
    while not os.path.lexists(path) and path != path.parent:
        new.append(path)
        path = path.parent
    target = Path(os.path.abspath(folder))
    before = set(os.listdir(target)) if not new and target.is_dir() and not target.is_symlink() else None
    try:
        yield
    except BaseException as exc:
        refused = isinstance(exc, UserError)
        if refused and before is not None:  # an existing folder: the unstarted checkpoints this run made
            for name in sorted(set(os.listdir(target)) - before):
                child = target / name
                if child.is_dir() and not child.is_symlink() and _only_unstarted_checkpoints(child):
                    shutil.rmtree(child, ignore_errors=True)
        for path in new:
            try:
                if path.is_symlink() or not path.is_dir():
                    break
                if refused and _only_unstarted_checkpoints(path):
                    shutil.rmtree(path)
                else:
                    path.rmdir()  # only an empty folder
            except OSError:
                break
        raise


def _only_unstarted_checkpoints(folder: Path) -> bool:
    """Whether ``folder`` holds nothing but folders and checkpoint manifests whose ``tasks/`` beside them
    is empty or missing (no symbolic link, no other file)."""
    for dirpath, dirnames, filenames in os.walk(folder):
        here = Path(dirpath)
        if any((here / d).is_symlink() for d in dirnames):
            return False
        for name in filenames:
            tasks = here / "tasks"
            if name != "manifest.json" or (here / name).is_symlink() or (
                    tasks.is_dir() and any(tasks.iterdir())):
                return False
    return True


__all__ = ["SWEEP_FIGURE", "SWEEP_PAGE", "RunFiles", "clear_run", "holdings", "prepare_folder", "refuse_earlier_files",
           "remove_entry", "removed_if_left_empty"]
