"""Result folders: load any saved result, find the results in a folder (read defensively:
:mod:`tb_exudyn.storage`)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Union

from ..errors import ResultsError
from .random_response import READABLE_FORMATS as RANDOM_RESPONSE_FORMATS
from .random_response import RandomResponse, load_random_response
from .metadata import meta_str, open_result_folder
from ..storage import load_json
from .time_history import FORMAT as TIME_HISTORY_FORMAT
from .time_history import TimeHistory, load_time_history

Result = Union[TimeHistory, RandomResponse]
FORMATS = (TIME_HISTORY_FORMAT, *RANDOM_RESPONSE_FORMATS)


def load_results(folder: str | Path) -> Union[TimeHistory, RandomResponse]:
    """Load a saved result folder of any kind (time history or random response).

    Raises ResultsError (one line, naming the file) when the folder is missing, of an unknown
    format, damaged or hostile (see :mod:`tb_exudyn.storage`).
    """
    folder = open_result_folder(folder)
    path = folder / "meta.json"
    fmt = meta_str(load_json(path), "format", path, choices=FORMATS)
    return load_time_history(folder) if fmt == TIME_HISTORY_FORMAT else load_random_response(folder)


def find_results(folder: str | Path) -> list[tuple[Path, Result]]:
    """The result in ``folder``, or the results in its immediate sub-folders (sorted by name).

    A sub-folder is a result when it holds an entry ``meta.json``; a result that cannot be read
    (damaged, hostile, or of a format this version does not know) is an error, not skipped. Raises
    ResultsError naming the folder when it holds no result, or naming the file that fails.
    """
    folder = open_result_folder(folder)
    if os.path.lexists(folder / "meta.json"):
        return [(folder, load_results(folder))]
    subs = []
    for entry in sorted(os.scandir(folder), key=lambda e: e.name):
        if entry.name.startswith("."):
            continue  # hidden: leftovers of interrupted writes, or not ours
        if entry.is_dir(follow_symlinks=False) and os.path.lexists(os.path.join(entry.path, "meta.json")):
            subs.append(Path(entry.path))
    if not subs:
        raise ResultsError(f"{folder}: no tb_exudyn result here (a folder with meta.json and arrays.npz, "
                           "or a folder of such folders)")
    return [(p, load_results(p)) for p in subs]


__all__ = ["FORMATS", "Result", "find_results", "load_results"]
