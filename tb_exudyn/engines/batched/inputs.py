"""The input forces f_in of a component's contact rows at every step, for each kind of column source.

Every row, penalty or general, takes its input as f_in = sum_kind value[r, kind] val_kind +
slope[r, kind] slope_kind of the tapered rail inputs at its axle (:class:`~tb_exudyn.system.coupling.RowMaps`:
a penalty row's k r + c r', a general row's W^v . val + W^s . slope). The column sources
(:mod:`tb_exudyn.system.columns`) define the inputs; these are their fast per-step forms (the harmonic
one factors exp(i Omega (x0 + v t - x_ref)) into a constant per row and column and one
exp(i Omega v t) per column and step). Tests check both against :func:`~tb_exudyn.system.columns.row_inputs`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...system.columns import HarmonicColumns, ProfileColumns, StaticLoadColumns
from ...system.conventions import harmonic_phase
from .kernels import in_precision

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


def shared_inputs(source: Any, t: float, zero: bool, x: FloatArray, speed: float, cdtype: Any = np.complex128) -> Any:
    """What every column's input needs at a step, computed once per step: exp(i Omega v t) of the
    harmonic columns (in the runs' complex dtype; for an array of times, one row per time); the
    profiles' values and slopes at the axles (None while every input is zero)."""
    if isinstance(source, HarmonicColumns):  # t may be an array of times: then (n_t, m)
        return np.exp(1j * np.multiply.outer(t, source.omega * speed)).astype(cdtype, copy=False)
    if zero or isinstance(source, StaticLoadColumns):
        return None
    return source.at(x)


def run_inputs(run: Any, source: Any, cols: IntArray, coupling: Any, maps: Any, cdtype: Any) -> Any:
    """The callable filling f_in of a run's contact rows per step."""
    if isinstance(source, HarmonicColumns):
        return _HarmonicInputs(run, source, cols, coupling, maps, cdtype)
    if isinstance(source, ProfileColumns):
        return _ProfileInputs(run, source, coupling, maps)
    if isinstance(source, StaticLoadColumns):
        return _StaticInputs(run, source)
    raise TypeError("the batched engine integrates HarmonicColumns, ProfileColumns or StaticLoadColumns, "
                    f"not {type(source).__name__}")


class _StaticInputs:
    """The static row forces f_s of the gravity-load column (constant)."""

    def __init__(self, run: Any, source: StaticLoadColumns) -> None:
        self.value = source.row_force[run.rows].astype(run.cdtype)[:, None]

    def __call__(self, k: int, block: Any, shared: Any, out: ComplexArray) -> None:
        out[...] = self.value


class _HarmonicInputs:
    """f_in of a run's contact rows for harmonic (PEM) columns: with column j's input
    s w(x) exp(i Omega (x - x_ref)) of its kind, f_in = (a + i Omega b) w P0 z + b w' P0 z, where
    a, b are the row's value and slope weights of the column's kind times s, P0 = exp(i Omega (x0 -
    x_ref)) at the row's axle and z = exp(i Omega v t) (:func:`shared_inputs`)."""

    def __init__(self, run: Any, columns: HarmonicColumns, cols: IntArray, coupling: Any, maps: Any, cdtype: Any) -> None:
        self.sel, self.axle = run.sel, run.axle
        omega = columns.omega[cols]
        kinds = columns.kinds[cols]
        scale = columns.scale[cols][None, :]
        x0 = coupling.positions(0.0)[run.axle]
        P0 = np.exp(1j * harmonic_phase(omega, x0, float(coupling.axle_start[0])))
        a = maps.input_value[np.ix_(run.rows, kinds)] * scale
        b = maps.input_slope[np.ix_(run.rows, kinds)] * scale
        self.Qss = in_precision(P0 * (a + 1j * b * omega[None, :]), cdtype)
        self.Qd = in_precision(b * P0, cdtype)
        self.tmp = np.zeros_like(self.Qss)

    def __call__(self, k: int, block: Any, z_all: ComplexArray, out: ComplexArray) -> None:
        z = z_all[self.sel]
        np.multiply(self.Qss, z, out=out)
        if block.steady[k]:
            return
        out *= block.w[k, self.axle][:, None]
        dwr = block.dw[k, self.axle]
        idx = np.flatnonzero(dwr)
        if idx.size:
            out[idx] += dwr[idx, None] * (self.Qd[idx] * z)


class _ProfileInputs:
    """f_in of a run's contact rows for sample columns: with p, p' the profiles at the rows' axles,
    f_in = w (V p) + w' (S p) + w (S p') (V, S the rows' value and slope weights of the sampled kinds)."""

    def __init__(self, run: Any, source: ProfileColumns, coupling: Any, maps: Any) -> None:
        V = maps.input_value[np.ix_(run.rows, source.kind_index)] * source.kind_scale[None, :]
        S = maps.input_slope[np.ix_(run.rows, source.kind_index)] * source.kind_scale[None, :]
        self.terms = [(j, np.ascontiguousarray(V[:, j:j + 1]), np.ascontiguousarray(S[:, j:j + 1]))
                      for j in range(V.shape[1]) if np.any(V[:, j]) or np.any(S[:, j])]
        self.axle = run.axle
        sel = run.sel  # the run's complex columns -> their real samples
        self.real = (slice(2 * sel.start, 2 * sel.stop) if isinstance(sel, slice)
                     else np.stack((2 * sel, 2 * sel + 1), axis=1).reshape(-1))
        shape = (run.rows.size, 2 * run.cols.size)
        self.Pv, self.Ps, self.Pd, self.tmp = (np.zeros(shape) for _ in range(4))

    def __call__(self, k: int, block: Any, shared: tuple[FloatArray, FloatArray], out: ComplexArray) -> None:
        value, slope = shared  # (n_axles, kinds, 2 width) at this step
        Pv, Ps, Pd, tmp = self.Pv, self.Ps, self.Pd, self.tmp
        for X in (Pv, Ps, Pd):
            X.fill(0.0)
        for j, vj, sj in self.terms:
            val, slo = value[:, j, self.real][self.axle], slope[:, j, self.real][self.axle]
            np.multiply(vj, val, out=tmp)
            Pv += tmp
            np.multiply(sj, val, out=tmp)
            Ps += tmp
            np.multiply(sj, slo, out=tmp)
            Pd += tmp
        w, dw = block.w[k, self.axle][:, None], block.dw[k, self.axle][:, None]
        np.add(Pv, Pd, out=tmp)
        tmp *= w
        np.multiply(Ps, dw, out=Pv)
        tmp += Pv
        out.view(out.real.dtype)[...] = tmp
