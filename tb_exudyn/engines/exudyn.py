"""The Exudyn engine: every real part of a column is one run of the Exudyn model (the reference).

A harmonic column (PEM) is two runs from rest without gravity, the cosine and the sine input at the
working amplitude ``analysis.pem_amplitude`` (Exudyn's Newton was seen to stop early at amplitudes of
1e-6 m and below, and the rigid-body nonlinearity is 5e-7 relative at 1e-5 m), scaled to the column's
pseudo-amplitude: y~ = (y_cos + i y_sin) a_k / A. A sampled profile (Monte Carlo) is one run of the
full model with gravity from static equilibrium on the sampled track: the sample itself, mean included
(``full_model``). The runs reuse the built model: only the excitation and the initial state change.

A scenario with a track layer (``track.structure``, docs/track.md) runs unchanged: the builder's bridge
body is then the track and the deck as one modal body (:mod:`tb_exudyn.system.track_bridge`), an
ObjectGenericODE2 with M = I, K = diag(omega^2) and the track's full damping matrix Phi^T C Phi
(:mod:`tb_exudyn.builder.bridge_body`), and the one contact object reads the rails' mode shapes at the
wheels through the same coupling the linear engines linearise.
"""

from __future__ import annotations

import time as _time
from typing import Any

import numpy as np

from ..system.columns import HarmonicColumns, ProfileColumns
from .base import Engine
from .exudyn_runs import SolverSettings, integrate


class ExudynEngine(Engine):
    """One Exudyn run per real part of a column (options: :class:`SolverSettings`)."""

    name = "exudyn"
    full_model = True
    linearizations = ("rest",)
    single_columns = True
    linear_rows = True

    def __init__(self, scenario: Any, options: SolverSettings | None = None, wheel_forces: bool = False) -> None:
        super().__init__(scenario, options or SolverSettings(), wheel_forces)

    @classmethod
    def default_options(cls) -> SolverSettings:
        return SolverSettings()

    @classmethod
    def describe_options(cls, options: Any) -> dict[str, Any]:
        return (options or SolverSettings()).describe()

    def _run(self, excitation: Any, gravity: bool, initial: str) -> tuple[np.ndarray, np.ndarray, float]:
        """The outputs (n_outputs, n_t) of one run, its output times and its wall time [s]."""
        model = self.model
        model.set_excitation(excitation)
        model.set_gravity(gravity)
        model.reset(initial)  # type: ignore[arg-type]
        rec, info = integrate(model, self.options)
        return self.channel_values(rec), rec.times, info.wall_time

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        start = _time.perf_counter()
        runs: list[tuple[int, int, Any, bool, str, float]] = []  # (column, part, excitation, gravity, initial, scale)
        if isinstance(source, HarmonicColumns):
            A = self.scenario.analysis.pem_amplitude
            for j in range(source.width):
                for part, exc in enumerate(source.excitations(j, A)):
                    runs.append((j, part, exc, False, "rest", float(source.amplitude[j]) / A))
        elif isinstance(source, ProfileColumns):
            for s in range(source.n_samples):
                runs.append((s // 2, s % 2, source.excitation(s), True, "static", 1.0))
        else:
            raise TypeError(f"the Exudyn engine integrates HarmonicColumns or ProfileColumns, not {type(source).__name__}")
        Y: np.ndarray | None = None
        times = []
        for j, part, exc, gravity, initial, scale in runs:
            values, time, wall = self._run(exc, gravity, initial)
            times.append(wall)
            if Y is None:
                Y = np.zeros((values.shape[0], source.width, values.shape[1]), dtype=complex)
            if part == 0:
                Y[:, j, :].real = values * scale if scale != 1.0 else values
            else:
                Y[:, j, :].imag = values * scale if scale != 1.0 else values
        self.model.set_excitation(None)
        assert Y is not None
        ext = np.arange(Y.shape[0])
        for i in range(Y.shape[2]):
            reducer.record(i, np.ascontiguousarray(Y[:, :, i]), ext)
        return {**reducer.result(), "time": time, "run_times": np.array(times),
                "seconds": np.array(_time.perf_counter() - start)}

    def describe(self) -> dict[str, Any]:
        return {"engine": self.name, "solver_settings": self.options.describe(),
                "pem_amplitude": self.scenario.analysis.pem_amplitude}


__all__ = ["ExudynEngine", "SolverSettings"]
