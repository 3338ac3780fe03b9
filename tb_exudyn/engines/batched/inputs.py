"""The inputs k r + c r' of a component's contact rows at every step, for each kind of column source.

The sources (:mod:`tb_exudyn.system.columns`) define the inputs; these are their fast per-step forms
(the harmonic one factors exp(i Omega (x0 + v t - x_ref)) into a constant per row and column and one
exp(i Omega v t) per column and step). Tests check both against the sources' ``contact_inputs``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...system.columns import HarmonicColumns, ProfileColumns
from ...system.conventions import harmonic_phase

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


def shared_inputs(source: Any, step: Any) -> Any:
    """What every column's input needs at a step, computed once per step: exp(i Omega v t) of the
    harmonic columns; the profiles' values and slopes at the axles (None while every input is zero)."""
    if isinstance(source, HarmonicColumns):
        return np.exp(1j * (source.omega * step.speed) * step.t)
    if step.zero:
        return None
    return source.at(step.x)


def run_inputs(run: Any, source: Any, cols: IntArray, coupling: Any) -> Any:
    """The callable filling k r + c r' of a run's contact rows per step."""
    if isinstance(source, HarmonicColumns):
        return _HarmonicInputs(run, source, cols, coupling)
    if isinstance(source, ProfileColumns):
        return _ProfileInputs(run, source, coupling)
    raise TypeError(f"the batched engine integrates HarmonicColumns or ProfileColumns, not {type(source).__name__}")


class _HarmonicInputs:
    """k r + c r' of a run's contact rows for harmonic (PEM) columns: r_c = P0 exp(i Omega v t) w(x_c),
    so k r + c r' = w Qss z + c v w' P0 z with z = exp(i Omega v t) (:func:`shared_inputs`)."""

    def __init__(self, run: Any, columns: HarmonicColumns, cols: IntArray, coupling: Any) -> None:
        self.sel, self.axle = run.sel, run.axle
        omega = columns.omega[cols]
        x0 = coupling.positions(0.0)[run.axle]
        W = coupling.contacts.input_map[np.ix_(run.rows, columns.kinds[cols])] * columns.scale[cols][None, :]
        self.P0 = W * np.exp(1j * harmonic_phase(omega, x0, float(coupling.axle_start[0])))
        self.cv = run.c[:, 0] * coupling.speed
        self.Qss = self.P0 * (run.k + 1j * self.cv[:, None] * omega[None, :])

    def __call__(self, step: Any, z_all: ComplexArray, out: ComplexArray) -> None:
        z = z_all[self.sel]
        np.multiply(self.Qss, z, out=out)
        if step.steady:
            return
        out *= step.w[self.axle][:, None]
        dwr = step.dw[self.axle]
        idx = np.flatnonzero(dwr)
        if idx.size:
            out[idx] += (self.cv[idx] * dwr[idx])[:, None] * (self.P0[idx] * z)




class _ProfileInputs:
    """k r + c r' of a run's contact rows for sample columns: with P = W p and P' = W p' at the rows'
    axles (W the coupling's input map), k r + c r' = (k w + c v w') P + c v w P'."""

    def __init__(self, run: Any, source: ProfileColumns, coupling: Any) -> None:
        W = coupling.contacts.input_map[np.ix_(run.rows, source.kind_index)] * source.kind_scale[None, :]
        self.terms = [(j, np.ascontiguousarray(W[:, j:j + 1])) for j in range(W.shape[1]) if np.any(W[:, j])]
        self.axle = run.axle
        self.k, self.cv = run.k[:, 0], run.c[:, 0] * coupling.speed
        n = 2 * source.width
        self.P, self.Pd, self.tmp = np.zeros((run.rows.size, n)), np.zeros((run.rows.size, n)), np.zeros((run.rows.size, n))

    def __call__(self, step: Any, shared: tuple[FloatArray, FloatArray], out: ComplexArray) -> None:
        value, slope = shared
        P, Pd, tmp = self.P, self.Pd, self.tmp
        P.fill(0.0)
        Pd.fill(0.0)
        for j, wj in self.terms:
            np.multiply(wj, value[self.axle, j], out=tmp)
            P += tmp
            np.multiply(wj, slope[self.axle, j], out=tmp)
            Pd += tmp
        w, dw = step.w[self.axle], step.dw[self.axle]
        of = out.view(np.float64)
        np.multiply((self.k * w + self.cv * dw)[:, None], P, out=of)
        np.multiply((self.cv * w)[:, None], Pd, out=tmp)
        of += tmp
