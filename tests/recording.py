"""A recorder for the engines' ``integrate``: every output at every output time, for tests that compare
engines (or an engine and an independent solver) output by output."""

from __future__ import annotations

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
