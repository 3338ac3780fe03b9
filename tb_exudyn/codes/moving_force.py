"""The response of a modal bridge to trains of constant moving forces, at many speeds in one integration.

For modes k (mass-normalised, vertical shape phi_k(x) at the track line) and axles j (load P_j,
distance a_j behind the first axle) the modal equations are

    q_k'' + 2 zeta_k w_k q_k' + w_k^2 q_k = f_k(t),   f_k(t) = - sum_j phi_k(v t - a_j) P_j

(z up, loads down; phi = 0 off the bridge). With the first axle at x = n dx at step n, the modal loads
f_k[n] are the same for every speed: only the time step h = dx / v differs. Each (mode, speed) pair is
integrated exactly for a load varying linearly between the steps (the zero-order-hold matrix
exponential of the SDOF with a first-order-hold input), so all speeds are the columns of one linear
recursion. Peaks are taken over the samples, so dx is chosen for ``samples_per_period`` samples per
period of the highest mode at the lowest speed. Pure numpy/scipy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import scipy.linalg as la

from ..errors import ResourceError, SettingError
from ..structure.modal import ModalBridge
from .trains import ForceTrain

#: largest number of steps of one integration (about 15 us each per train on one core; the memory of the
#: modal loads is steps x modes x 8 bytes)
MAX_STEPS = 500_000
#: positions per evaluation of the mode shapes (each forms 6 components of every mode of the bridge)
_SHAPE_CHUNK = 8192


@dataclass(frozen=True)
class MovingForceResponse:
    """Peaks of one train's passage at every speed.

    ``speeds_kmh`` (n_v,); stations: ``station_x`` (n_s,) [m] along the track, ``station_names``
    ('span1.x4/8' = 4/8 of span 1), ``station_span`` (n_s,) span index, ``mid_stations`` the station index
    of each span's mid-span; ``max_acc`` (n_s, n_v) peak |vertical acceleration| [m/s^2], ``max_disp``
    (n_s, n_v) peak |vertical displacement| [m], ``static_disp`` (n_s,) peak |displacement| of the train
    passing at a crawl (the same modes, no inertia) [m]; the modes used: ``frequencies`` [Hz] and
    ``damping_ratios``; ``step_m`` the spatial step dx; ``tail_s`` the free vibration after the last axle
    left the bridge at the highest speed [s].
    """

    train: str
    speeds_kmh: np.ndarray
    station_x: np.ndarray
    station_names: tuple[str, ...]
    station_span: np.ndarray
    mid_stations: np.ndarray
    max_acc: np.ndarray = field(repr=False)
    max_disp: np.ndarray = field(repr=False)
    static_disp: np.ndarray = field(repr=False)
    frequencies: np.ndarray = field(repr=False)
    damping_ratios: np.ndarray = field(repr=False)
    step_m: float = 0.0
    tail_s: float = 0.0

    @property
    def phi_dyn(self) -> np.ndarray:
        """(n_spans, n_v): phi'_dyn = max |y_dyn| / max |y_stat| - 1 at each span's mid-span."""
        mid = self.mid_stations
        return self.max_disp[mid] / self.static_disp[mid, None] - 1.0


def deck_stations(spans: Sequence[float], max_spacing_fraction: float = 1.0 / 8.0) -> tuple[np.ndarray, tuple[str, ...], np.ndarray, np.ndarray]:
    """Output points on every span no more than ``max_spacing_fraction`` L apart, mid-span included:
    L i / n (i = 1 ... n - 1, n the even number >= 1 / fraction). Returns (x, names, span index, index
    of each span's mid-span)."""
    n = int(math.ceil(1.0 / max_spacing_fraction - 1e-9))
    n += n % 2
    xs, names, span, mids, start = [], [], [], [], 0.0
    for s, length in enumerate(spans):
        for i in range(1, n):
            if 2 * i == n:
                mids.append(len(xs))
            xs.append(start + length * i / n)
            names.append(f"span{s + 1}.x{i}/{n}")
            span.append(s)
        start += float(length)
    return np.array(xs), tuple(names), np.array(span, dtype=int), np.array(mids, dtype=int)


def _discretisation(omega: np.ndarray, zeta: np.ndarray, h: np.ndarray) -> np.ndarray:
    """(..., 2, 4): [Phi | g0 | g1] of x' = A x + (0, 1) f with f linear over a step h:
    x_{n+1} = Phi x_n + g0 f_n + g1 (f_{n+1} - f_n). By the exponential of the augmented matrix
    [[A h, b h, 0], [0, 0, 1], [0, 0, 0]]."""
    shape = np.broadcast_shapes(omega.shape, zeta.shape, h.shape)
    w, z, hh = (np.broadcast_to(a, shape).ravel() for a in (omega, zeta, h))
    m = np.zeros((w.size, 4, 4))
    m[:, 0, 1] = hh
    m[:, 1, 0] = -(w**2) * hh
    m[:, 1, 1] = -2.0 * z * w * hh
    m[:, 1, 2] = hh
    m[:, 2, 3] = 1.0
    e = la.expm(m)
    return e[:, :2, :].reshape(shape + (2, 4))


def modal_loads(bridge: ModalBridge, modes: np.ndarray, train: ForceTrain, dx: float, n_steps: int) -> np.ndarray:
    """(n_steps, n_modes): f_k[n] = - sum_j phi_k(n dx - a_j) P_j [N per unit modal mass] (z up)."""
    x_front = dx * np.arange(n_steps)
    out = np.zeros((n_steps, modes.size))
    for a, p in zip(train.positions, train.loads):
        x = x_front - a
        on = np.flatnonzero((x >= 0.0) & (x <= bridge.length))
        for k in range(0, on.size, _SHAPE_CHUNK):  # chunks: the shapes of all modes and components are formed
            idx = on[k:k + _SHAPE_CHUNK]
            out[idx] -= p * bridge.rail_shapes(x[idx]).z[:, modes]
    return out


def moving_force_response(
    bridge: ModalBridge,
    train: ForceTrain,
    speeds_kmh: Sequence[float] | np.ndarray,
    spans: Sequence[float],
    damping_ratio: float | np.ndarray | None = None,
    modes: Sequence[int] | np.ndarray | None = None,
    samples_per_period: float = 20.0,
    tail_periods: float = 2.0,
    block: int = 512,
) -> MovingForceResponse:
    """Peak deck acceleration and displacement of ``train`` crossing ``bridge`` at every speed.

    Parameters
    ----------
    bridge : mass-normalised modes; their vertical shape at the track line (``rail_shapes(x).z``) is used
    train : the moving forces
    speeds_kmh : the speeds [km/h], each > 0
    spans : the span lengths along the track [m] (their sum is the bridge length); stations at L / 8 on
        each (:func:`deck_stations`)
    damping_ratio : one ratio for every mode, or one per mode used (default: the bridge's own)
    modes : indices of the modes to use (default: those of type 'vertical')
    samples_per_period : samples per period of the highest mode used at the lowest speed (sets dx; the
        sampled peak of a harmonic is then within 1 - cos(pi / samples_per_period) of the true one)
    tail_periods : free vibration after the last axle left, in periods of the lowest mode used
    block : steps per block of the station output (memory: block x modes x speeds)
    """
    where = "moving_force_response"
    v_kmh = np.atleast_1d(np.asarray(speeds_kmh, dtype=float))
    if v_kmh.ndim != 1 or v_kmh.size == 0 or not np.all(np.isfinite(v_kmh)) or np.any(v_kmh <= 0):
        raise SettingError(where, "speeds_kmh", speeds_kmh, "one or more finite speeds > 0 km/h")
    spans = [float(s) for s in spans]
    if not spans or any(not (s > 0) for s in spans) or abs(sum(spans) - bridge.length) > 1e-6 * bridge.length:
        raise SettingError(where, "spans", spans, f"span lengths > 0 m adding up to the bridge length {bridge.length:g} m")
    if modes is None:
        modes = np.flatnonzero(np.array([t == "vertical" for t in bridge.mode_types]))
    modes = np.asarray(modes, dtype=int)
    if modes.size == 0:
        raise SettingError(where, "modes", list(modes), "one or more modes of the bridge", "no mode to use")
    freq = bridge.frequencies[modes]
    zeta = bridge.damping_ratios[modes] if damping_ratio is None else np.broadcast_to(
        np.asarray(damping_ratio, dtype=float), freq.shape).copy()
    if not np.all((zeta >= 0) & (zeta < 1)):
        raise SettingError(where, "damping_ratio", damping_ratio, "ratios in [0, 1)")
    omega = 2.0 * np.pi * freq
    v = v_kmh / 3.6
    dx = min(v.min() / (samples_per_period * freq.max()), min(spans) / 100.0)
    tail_s = tail_periods / freq.min()
    n_pass = int(math.ceil((bridge.length + train.length) / dx)) + 1
    n_steps = n_pass + int(math.ceil(tail_s * v.max() / dx))
    if n_steps > MAX_STEPS:
        exc = ResourceError.from_parts(where, "speeds_kmh", f"{v_kmh.min():g}-{v_kmh.max():g} km/h",
                                       f"at most {MAX_STEPS} steps (fewer high modes, higher lowest speed)",
                                       f"{n_steps} steps of {dx:.3g} m")
        exc.steps, exc.step_m = n_steps, dx
        raise exc
    f = modal_loads(bridge, modes, train, dx, n_steps)  # (n, m)
    e = _discretisation(omega[:, None], zeta[:, None], (dx / v)[None, :])  # (m, v, 2, 4)
    p00, p01, g0q, g1q = (e[..., 0, c] for c in range(4))
    p10, p11, g0p, g1p = (e[..., 1, c] for c in range(4))
    x_st, names, st_span, mids = deck_stations(spans)
    shapes = bridge.rail_shapes(x_st).z[:, modes]  # (s, m)
    c_damp, c_stiff = (2.0 * zeta * omega)[:, None], (omega**2)[:, None]
    q = np.zeros((modes.size, v.size))
    p = np.zeros_like(q)
    max_acc = np.zeros((x_st.size, v.size))
    max_disp = np.zeros_like(max_acc)
    qb = np.empty((block, modes.size, v.size))
    pb = np.empty_like(qb)
    df = np.diff(f, axis=0, append=f[-1:])
    for b0 in range(0, n_steps, block):
        nb = min(block, n_steps - b0)
        for i in range(nb):
            n = b0 + i
            qb[i], pb[i] = q, p
            fn, dn = f[n][:, None], df[n][:, None]
            q, p = (p00 * q + p01 * p + g0q * fn + g1q * dn,
                    p10 * q + p11 * p + g0p * fn + g1p * dn)
        acc = f[b0:b0 + nb, :, None] - c_damp * pb[:nb] - c_stiff * qb[:nb]
        np.maximum(max_acc, np.abs(np.einsum("sm,bmv->bsv", shapes, acc)).max(axis=0), out=max_acc)
        np.maximum(max_disp, np.abs(np.einsum("sm,bmv->bsv", shapes, qb[:nb])).max(axis=0), out=max_disp)
    static = np.abs((f[:n_pass] / omega**2) @ shapes.T).max(axis=0)
    return MovingForceResponse(
        train=train.name, speeds_kmh=v_kmh, station_x=x_st, station_names=names, station_span=st_span,
        mid_stations=mids, max_acc=max_acc, max_disp=max_disp, static_disp=static, frequencies=freq,
        damping_ratios=zeta, step_m=dx, tail_s=tail_s,
    )


__all__ = ["MovingForceResponse", "deck_stations", "modal_loads", "moving_force_response"]
