"""A recorder for the engines' ``integrate``: every output at every output time, for tests that compare
engines (or an engine and an independent solver) output by output."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np


class KeepAll:
    """Keeps the outputs of every output time (channels in ``outputs.names`` order): ``result()["Y"]`` is
    (columns, outputs, output times), complex."""

    def __init__(self, n_t: int) -> None:
        self.n_t, self.Y = n_t, None

    def record(self, i: int, Y: np.ndarray, ext: np.ndarray) -> None:
        if self.Y is None:
            self.Y = np.zeros((Y.shape[0], Y.shape[1], self.n_t), dtype=complex)
        self.Y[:, :, i] = Y[ext]

    def result(self) -> dict:
        return {"Y": self.Y}


@contextmanager
def counted_track_solves() -> Iterator[list[tuple]]:
    """Within the block, every solve of a track-and-deck body (``system.track_bridge.track_and_deck``) is
    recorded as its (x0, n_supports), with no track kept from before: the tests that a sweep or a check
    solves its track once read the list."""
    import pytest

    from tb_exudyn.system import track_bridge

    solved: list[tuple] = []
    solve = track_bridge.track_and_deck

    def counted(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        solved.append(args[2:4])  # (x0, n_supports)
        return solve(*args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(track_bridge, "track_and_deck", counted)
        mp.setattr(track_bridge, "_LAST", {})
        yield solved
