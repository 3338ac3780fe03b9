"""Result folders: load any saved result, find the results in a folder."""

from __future__ import annotations

from pathlib import Path
from typing import Union

from .random_response import FORMAT as RANDOM_RESPONSE_FORMAT
from .random_response import RandomResponse, load_random_response
from .storage import load_json
from .time_history import FORMAT as TIME_HISTORY_FORMAT
from .time_history import TimeHistory, load_time_history

Result = Union[TimeHistory, RandomResponse]


def load_results(folder: str | Path) -> Union[TimeHistory, RandomResponse]:
    """Load a saved result folder of any kind (time history or random response).

    Raises ValueError naming the folder when its ``meta.json`` has an unknown format.
    """
    folder = Path(folder)
    fmt = load_json(folder / "meta.json").get("format")
    if fmt == TIME_HISTORY_FORMAT:
        return load_time_history(folder)
    if fmt == RANDOM_RESPONSE_FORMAT:
        return load_random_response(folder)
    raise ValueError(
        f"{folder}: unknown result format {fmt!r} (expected {TIME_HISTORY_FORMAT!r} or {RANDOM_RESPONSE_FORMAT!r})"
    )


def find_results(folder: str | Path) -> list[tuple[Path, Result]]:
    """The result in ``folder``, or the results in its immediate sub-folders (sorted by name).

    Raises FileNotFoundError naming the folder when it holds none.
    """
    folder = Path(folder)

    def is_result(p: Path) -> bool:
        try:
            return load_json(p / "meta.json").get("format") in (RANDOM_RESPONSE_FORMAT, TIME_HISTORY_FORMAT)
        except (OSError, ValueError):
            return False

    if is_result(folder):
        paths = [folder]
    elif folder.is_dir():
        paths = sorted(p for p in folder.iterdir() if p.is_dir() and is_result(p))
    else:
        paths = []
    if not paths:
        raise FileNotFoundError(f"{folder}: no tb_exudyn result here (a folder with meta.json and arrays.npz, "
                                "or a folder of such folders)")
    return [(p, load_results(p)) for p in paths]


__all__ = ["Result", "find_results", "load_results"]
