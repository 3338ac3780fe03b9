"""Column sources: the irregularity inputs an engine integrates, as complex columns.

Every engine integrates columns of one source at once (the batched and dense engines) or one by one
(the Exudyn engine, two real runs per complex column). Two sources:

- :class:`HarmonicColumns` (PEM): column j is the pseudo-excitation of kind ``kinds[j]`` and
  spatial frequency ``omega[j]``, r_j(x) = s_j w(x) exp(i Omega_j (x - x_ref)) with the complex
  amplitude's real part the cosine run and its imaginary part the sine run
  (:func:`~.conventions.harmonic_phase`), s_j = ``scale[j]`` the pseudo-amplitude in the model's
  units (:func:`~.conventions.cross_level_scale` applied);
- :class:`ProfileColumns` (Monte Carlo): sampled profiles on a uniform grid, interpolated by cubic
  splines held in Hermite form (values and knot slopes, evaluated by :func:`hermite_cubic`); two
  real samples per complex column (sample 2j the real part, 2j + 1 the imaginary part).

:meth:`contact_inputs` of both is the reference evaluation of the inputs at the contacts of a
coupling (r and r' per contact row and column), :meth:`rail_values` that of the tapered rail inputs
and slopes at the axles, from which :func:`linear_row_inputs` forms the input forces f_in of the
general linear rows (e.g. creep: alignment and cross-level as rail motion) and :func:`row_inputs`
those of every row; the same physics as :func:`~.excitation.rail_inputs` for one real run; the
batched engine's fast per-step forms are tested against them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from .conventions import cross_level_scale, harmonic_phase
from .excitation import KINDS, HarmonicExcitation, ProfileExcitation, taper

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
ComplexArray = NDArray[np.complex128]
#: columns of samples whose knot slopes are computed at once (bounds CubicSpline's temporaries)
SPLINE_CHUNK = 32


# ====================================================================================== harmonic
@dataclass(frozen=True)
class HarmonicColumns:
    """Pseudo-excitation columns, frequency-major: the columns of one frequency side by side, in the
    same type order for every frequency.

    Attributes
    ----------
    kinds : (m,) input kind per column (index into ``KINDS``: 0 vertical, 1 alignment, 2 cross-level)
    omega : (m,) spatial circular frequency [rad/m]
    amplitude : (m,) pseudo-amplitude sqrt(S_hz df) in the spectrum's unit
    units : (m,) cross-level unit of each column's spectrum ("angle" or "height"; "angle" otherwise)
    scale : (m,) the pseudo-amplitude in the model's units (a cross-level height over 2 b)
    type_index : (m,) irregularity type (position in ``track.irregularities``) of each column
    freq_index, df : (n_f,) grid indices of the frequencies and their widths [Hz]
    n_types : number of columns per frequency
    """

    kinds: IntArray
    omega: FloatArray
    amplitude: FloatArray
    units: tuple[str, ...]
    scale: FloatArray
    type_index: IntArray
    freq_index: IntArray
    df: FloatArray
    n_types: int

    @property
    def width(self) -> int:
        """Number of complex columns."""
        return int(self.kinds.size)

    def columns_for(self, kinds: Sequence[int]) -> IntArray:
        """The columns a component excited by ``kinds`` integrates: those of its kinds."""
        return np.flatnonzero(np.isin(self.kinds, kinds))

    def excitations(self, j: int, amplitude: float) -> tuple[HarmonicExcitation, HarmonicExcitation]:
        """The real and imaginary runs of column j at the working ``amplitude`` (scale the response
        by ``self.amplitude[j] / amplitude``)."""
        kind = KINDS[int(self.kinds[j])]
        return tuple(HarmonicExcitation(kind=kind, spatial_frequency=float(self.omega[j]), amplitude=amplitude,  # type: ignore[return-value]
                                        part=part, cross_level_unit=self.units[j]) for part in ("real", "imag"))

    def rail_values(self, coupling: Any, t: float) -> tuple[ComplexArray, ComplexArray]:
        """The tapered rail inputs and their slopes d/dx (3 kinds, n_axles, m) at the axles at time t
        (the complex form of :func:`~.excitation.rail_inputs`): column j's kind carries
        s w(x) exp(i phase) and s (w' + i Omega w) exp(i phase), the other kinds zero."""
        x = coupling.positions(t)
        x_ref = float(coupling.axle_start[0])
        w, dw = taper(x, x_ref, coupling.taper_length)
        phase = self.scale[None, :] * np.exp(1j * harmonic_phase(self.omega, x, x_ref))  # (n_axles, m)
        value = np.zeros((len(KINDS), x.size, self.width), dtype=complex)
        slope = np.zeros_like(value)
        cols = np.arange(self.width)
        value[self.kinds, :, cols] = (w[:, None] * phase).T
        slope[self.kinds, :, cols] = ((dw[:, None] + 1j * self.omega[None, :] * w[:, None]) * phase).T
        return value, slope

    def contact_inputs(self, coupling: Any, t: float) -> tuple[ComplexArray, ComplexArray]:
        """Complex inputs r, r' (n_c, m) at the contacts at time t: r_c = W[c, kind] s w(x_c)
        exp(i phase), r'_c = v W s (w' + i Omega w) exp(i phase) at the position x_c of contact c's axle."""
        x = coupling.positions(t)
        x_ref = float(coupling.axle_start[0])
        w, dw = taper(x, x_ref, coupling.taper_length)
        a = coupling.contacts.axle
        W = coupling.contacts.input_map[:, self.kinds] * self.scale[None, :]
        phase = np.exp(1j * harmonic_phase(self.omega, x[a], x_ref))
        r = W * w[a, None] * phase
        r_dot = coupling.speed * W * (dw[a, None] + 1j * self.omega[None, :] * w[a, None]) * phase
        return r, r_dot


# ======================================================================================= profiles
def hermite_cubic(values: FloatArray, slopes: FloatArray, x_start: float, dx: float, x: FloatArray
                  ) -> tuple[FloatArray, FloatArray]:
    """Value and slope at positions x (1-D) of the cubic Hermite interpolant through ``values`` and
    knot ``slopes`` on the grid x_start + dx k (axis 0 of both; further axes are carried along:
    the result has shape x.shape + values.shape[1:]).

    Raises ValueError for positions outside the grid (the sampled track must cover every wheel).
    """
    n_points = values.shape[0]
    s = (x - x_start) / dx
    if s.size and (s.min() < -1e-9 or s.max() > n_points - 1 + 1e-9):
        raise ValueError(f"positions in [{x.min():g}, {x.max():g}] m outside the sampled track "
                         f"[{x_start:g}, {x_start + dx * (n_points - 1):g}] m")
    i = np.clip(s.astype(np.intp), 0, n_points - 2)
    t = (s - i).reshape(s.shape + (1,) * (values.ndim - 1))
    y0, y1, d0, d1 = values[i], values[i + 1], slopes[i], slopes[i + 1]
    t2 = t * t
    t3 = t2 * t
    dy = y1 - y0
    value = y0 + (3.0 * t2 - 2.0 * t3) * dy + dx * ((t3 - 2.0 * t2 + t) * d0 + (t3 - t2) * d1)
    slope = (6.0 * (t - t2) / dx) * dy + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (3.0 * t2 - 2.0 * t) * d1
    return value, slope


def spline_slopes(x: FloatArray, values: FloatArray, dx: float, out: FloatArray) -> None:
    """Knot slopes (into ``out``, same shape as ``values``: points along axis 0) of the not-a-knot
    cubic splines through ``values`` (scipy's CubicSpline: the slope at knot k is its piece's linear
    coefficient; at the last knot the last piece's derivative)."""
    from scipy.interpolate import CubicSpline  # on first use (Monte Carlo): 0.2 s at import otherwise

    c = CubicSpline(x, values, axis=0).c  # (4, n - 1, ...): powers 3, 2, 1, 0
    out[:-1] = c[2]
    out[-1] = (3.0 * c[0, -1] * dx + 2.0 * c[1, -1]) * dx + c[2, -1]


class SplineProfile:
    """A profile callable ``x -> (value, slope)``: the not-a-knot cubic splines through values on a
    uniform grid, evaluated by :func:`hermite_cubic`.

    ``values`` is one profile (n,) or several on the same grid (k, n); the result has the same
    leading shape. With several rows, ``row(i)`` gives a callable for profile i alone: the rows
    share one evaluation per position array (the last result is kept), so the three irregularity
    kinds of a sample cost one evaluation per time step, not three.
    """

    def __init__(self, x_start: float, dx: float, values: Any) -> None:
        v = np.asarray(values, dtype=float)
        if v.ndim not in (1, 2) or v.shape[-1] < 4 or not dx > 0:
            raise ValueError("a spline profile needs dx > 0 and at least 4 values per row (1-D or 2-D array)")
        self.x_start, self.dx, self.n, self.rows = float(x_start), float(dx), v.shape[-1], v.ndim == 2
        self.x_end = self.x_start + self.dx * (self.n - 1)
        self._values = np.ascontiguousarray(np.atleast_2d(v).T)  # (n, k)
        self._slopes = np.zeros_like(self._values)
        spline_slopes(self.x_start + self.dx * np.arange(self.n), self._values, self.dx, self._slopes)
        self._last: tuple[FloatArray, FloatArray, FloatArray] | None = None

    @classmethod
    def from_knots(cls, x_start: float, dx: float, values: FloatArray, slopes: FloatArray) -> "SplineProfile":
        """A profile of k rows from values and knot slopes (n, k) already computed."""
        self = cls.__new__(cls)
        self.x_start, self.dx, self.n, self.rows = float(x_start), float(dx), values.shape[0], True
        self.x_end = self.x_start + self.dx * (self.n - 1)
        self._values, self._slopes = np.ascontiguousarray(values), np.ascontiguousarray(slopes)
        self._last = None
        return self

    def __call__(self, x: Any) -> tuple[FloatArray, FloatArray]:
        x = np.asarray(x, dtype=float)
        value, slope = hermite_cubic(self._values, self._slopes, self.x_start, self.dx, x.ravel())  # (m, k)
        if self.rows:  # (k, shape of x)
            return value.T.reshape((-1,) + x.shape), slope.T.reshape((-1,) + x.shape)
        return value[:, 0].reshape(x.shape), slope[:, 0].reshape(x.shape)

    def row(self, index: int):
        """Profile ``index`` alone as a callable ``x -> (value, slope)`` sharing evaluations."""

        def profile(x: FloatArray) -> tuple[FloatArray, FloatArray]:
            last = self._last
            if last is None or last[0].shape != np.shape(x) or not (last[0] == x).all():
                x_copy = np.array(x, dtype=float)
                value, slope = self(x_copy)
                self._last = last = (x_copy, value.reshape((-1,) + x_copy.shape), slope.reshape((-1,) + x_copy.shape))
            return last[1][index], last[2][index]

        return profile


class ProfileColumns:
    """Sampled irregularity profiles as columns: complex column j holds sample 2j (real part) and
    2j + 1 (imaginary part); an odd count is padded with a zero sample.

    Parameters
    ----------
    grids : kind -> (n_points, n_samples) profile values on the grid x_start + dx k (cross-level in
        ``cross_level_unit``)
    x_start, dx : the grid [m]
    cross_level_unit : "angle" or "height"
    half_gauge : b [m], for a cross-level given as a height difference
    """

    def __init__(self, grids: Mapping[str, FloatArray], x_start: float, dx: float, cross_level_unit: str,
                 half_gauge: float) -> None:
        kinds = [k for k in KINDS if k in grids]
        self.n_samples = int(next(iter(grids.values())).shape[1]) if grids else 0
        self.width = (self.n_samples + 1) // 2
        self.kind_index = np.array([KINDS.index(k) for k in kinds], dtype=np.int64)
        self.cross_level_unit = cross_level_unit
        #: factor to the model's units (the cross-level angle), as ``rail_inputs`` applies it
        self.kind_scale = np.array([cross_level_scale(cross_level_unit, half_gauge) if k == "cross_level" else 1.0
                                    for k in kinds])
        self.x_start, self.dx = float(x_start), float(dx)
        self.n_points = int(next(iter(grids.values())).shape[0]) if grids else 0
        shape = (self.n_points, self.kind_index.size, 2 * self.width)
        self.values, self.slopes = np.zeros(shape), np.zeros(shape)
        x = self.x_start + self.dx * np.arange(self.n_points)
        for j, kind in enumerate(kinds):
            v = grids[kind]
            self.values[:, j, : self.n_samples] = v
            for c0 in range(0, self.n_samples, SPLINE_CHUNK):
                c1 = min(c0 + SPLINE_CHUNK, self.n_samples)
                spline_slopes(x, v[:, c0:c1], self.dx, self.slopes[:, j, c0:c1])

    @staticmethod
    def profile_bytes(n_points: int, n_kinds: int) -> int:
        """Bytes of profile storage per sample."""
        return 2 * n_points * n_kinds * 8

    def columns_for(self, kinds: Sequence[int]) -> IntArray:
        """Every column, for a component that some sampled kind excites (a sample carries every kind)."""
        if np.isin(self.kind_index, kinds).any():
            return np.arange(self.width, dtype=np.int64)
        return np.zeros(0, dtype=np.int64)

    def at(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Profile values and slopes (n_x, kinds, 2 width) at positions x (1-D)."""
        return hermite_cubic(self.values, self.slopes, self.x_start, self.dx, x)

    def excitation(self, sample: int) -> ProfileExcitation:
        """Sample ``sample`` alone as an excitation of a model (one run of the Exudyn engine)."""
        kinds = [KINDS[k] for k in self.kind_index]
        spline = SplineProfile.from_knots(self.x_start, self.dx, self.values[:, :, sample], self.slopes[:, :, sample])
        return ProfileExcitation(**{k: spline.row(i) for i, k in enumerate(kinds)},  # type: ignore[arg-type]
                                 cross_level_unit=self.cross_level_unit)

    def rail_values(self, coupling: Any, t: float) -> tuple[ComplexArray, ComplexArray]:
        """The tapered rail inputs w p and their slopes w' p + w p' (3 kinds, n_axles, width) at the
        axles at time t, samples 2j + i (2j + 1) (the complex form of :func:`~.excitation.rail_inputs`)."""
        x = coupling.positions(t)
        w, dw = taper(x, float(coupling.axle_start[0]), coupling.taper_length)
        v, s = self.at(x)  # (n_axles, kinds, 2 width)
        value = np.zeros((len(KINDS), x.size, 2 * self.width))
        slope = np.zeros_like(value)
        for j, k in enumerate(self.kind_index):
            value[k] = self.kind_scale[j] * w[:, None] * v[:, j]
            slope[k] = self.kind_scale[j] * (dw[:, None] * v[:, j] + w[:, None] * s[:, j])
        return value.view(np.complex128), slope.view(np.complex128)

    def contact_inputs(self, coupling: Any, t: float) -> tuple[ComplexArray, ComplexArray]:
        """Complex inputs r, r' (n_c, width) at the contacts at time t (samples 2j + i (2j + 1)):
        r = W w p, r' = v W (w' p + w p') with p, p' the profiles at the contact's axle."""
        x = coupling.positions(t)
        w, dw = taper(x, float(coupling.axle_start[0]), coupling.taper_length)
        value, slope = self.at(x)  # (n_axles, kinds, 2 width)
        W = coupling.contacts.input_map[:, self.kind_index] * self.kind_scale[None, :]
        a = coupling.contacts.axle
        p = np.einsum("ck,ckm->cm", W, value[a])
        dp = np.einsum("ck,ckm->cm", W, slope[a])
        r = w[a, None] * p
        r_dot = coupling.speed * (dw[a, None] * p + w[a, None] * dp)
        return r.view(np.complex128), r_dot.view(np.complex128)


# =================================================================================== static load
@dataclass(frozen=True)
class StaticLoadColumns:
    """The gravity load as one column of the linear model: the linear engines' mean.

    With u_s the static equilibrium of the train standing on the approach at t = 0 under the dead
    loads (the initial state of Exudyn's deterministic run) and u = u_s + delta, the linear model
    (:class:`~.coupling.RowMaps`: row forces f = F^k u + F^d u', Q = -P^T f) becomes, for the
    deviation delta from rest,

        M delta'' + D0 delta' + K0 delta = F_c - P(t)^T (F^k delta + F^d delta' + f_s),
        f_s = F^k(t) u_s,   F_c = P(0)^T f_s

    where F_c, the rows' static reaction at t = 0, balances the dead loads there (the static
    equilibrium; about linearization "static" K0 is the tangent there, so the deviation form holds
    for both points). So it is a column whose rows' input is the static row force f_s and which
    carries the constant generalised force F_c. The rows' forces come out whole (f_s included); the
    displacements are u_s + delta. ``f_s`` is constant because the bridge is unloaded in u_s (no
    rail shape of u_s enters); sources with moving point loads are not modelled
    (:func:`static_load_columns` refuses them).

    Attributes
    ----------
    static : (n,) u_s [m, rad]
    row_force : (n_rows,) f_s, penalty rows then general rows [N]
    force : (n,) F_c [N]
    """

    static: FloatArray
    row_force: FloatArray
    force: FloatArray

    @property
    def width(self) -> int:
        return 1

    def columns_for(self, kinds: Sequence[int]) -> IntArray:
        """The one column, for every component (the gravity load reaches what the rows reach)."""
        return np.zeros(1, dtype=np.int64)

    def constant_force(self, coords: IntArray) -> ComplexArray:
        """F_c at the global coordinates ``coords``, (len(coords), 1) complex."""
        return self.force[coords].astype(complex)[:, None]

    def rail_values(self, coupling: Any, t: float) -> tuple[ComplexArray, ComplexArray]:
        """No rail input (the row input is f_s itself)."""
        zero = np.zeros((len(KINDS), coupling.axle_start.size, 1), dtype=complex)
        return zero, zero


def static_load_columns(lin: Any, static: FloatArray) -> StaticLoadColumns:
    """The gravity-load column of the linear system ``lin`` (:class:`~.linear.LinearSystem`) from the
    static state u_s of the built model (global ODE2 vector, gravity on, the train at its t = 0
    positions, every axle on the approach). Raises ValueError for a bridge loaded in u_s, an axle on
    the bridge at t = 0 or moving point loads (the column assumes f_s constant and F_c on the wheels)."""
    cp = lin.coupling
    ub, uw = static[lin.bridge], static[lin.wheel]
    if np.any(ub != 0.0) or (cp.load_axle.size and np.any(cp.load_force != 0.0)) or cp.contact_state(0.0).on_bridge:
        raise ValueError("the linear mean needs an unloaded bridge in the static state, every axle on the approach "
                         "at t = 0 and no moving point loads")
    rm = cp.row_maps()
    f_s = -(rm.stiff_wheel @ uw)
    F_c = np.zeros_like(np.asarray(static, dtype=float))
    F_c[lin.wheel] = -(rm.app_wheel.T @ f_s)  # P(0)^T f_s: the rails are rigid at t = 0
    return StaticLoadColumns(static=np.asarray(static, dtype=float), row_force=f_s, force=F_c)


def linear_row_inputs(source: Any, coupling: Any, t: float) -> ComplexArray:
    """Complex input forces f_in (n_g, m) of the coupling's general linear rows for the columns of
    ``source`` at time t: W^v . val + W^s . slope of ``source.rail_values`` at row g's axle (the
    column form of the coupling's real input forces; (0, m) without general rows)."""
    lin = coupling.contacts.linear
    if lin is None:
        return np.zeros((0, source.width), dtype=complex)
    value, slope = source.rail_values(coupling, t)
    a = lin.axle
    return np.einsum("gk,kgm->gm", lin.input_value, value[:, a]) + np.einsum("gk,kgm->gm", lin.input_slope, slope[:, a])


def row_inputs(source: Any, maps: Any, coupling: Any, t: float) -> ComplexArray:
    """The input forces f_in (n_rows, m) of every contact row (:class:`~.coupling.RowMaps`: penalty
    rows' k r + c r', general rows' W^v . val + W^s . slope) for the columns of ``source`` at time t:
    the reference evaluation the linear engines' per-step forms are tested against."""
    if isinstance(source, StaticLoadColumns):
        return source.row_force.astype(complex)[:, None]
    value, slope = source.rail_values(coupling, t)
    a = maps.axle
    return (np.einsum("rk,krm->rm", maps.input_value, value[:, a]) + np.einsum("rk,krm->rm", maps.input_slope, slope[:, a]))


__all__ = ["HarmonicColumns", "ProfileColumns", "SplineProfile", "StaticLoadColumns", "hermite_cubic", "linear_row_inputs",
           "row_inputs",
           "spline_slopes", "static_load_columns"]
