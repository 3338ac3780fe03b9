"""The response of a modal bridge to trains of constant moving forces, at many speeds in one integration.

For modes k (mass-normalised, vertical shape phi_k(x) at the track line) and axles j (load P_j,
distance a_j behind the first axle) the modal equations are

    q_k'' + 2 zeta_k w_k q_k' + w_k^2 q_k = f_k(t),   f_k(t) = - sum_j phi_k(v t - a_j) P_j

(z up, loads down; phi = 0 off the bridge). With the first axle at x = n dx at step n, the modal loads
f_k[n] are the same for every speed: only the time step h = dx / v differs. Each (mode, speed) pair is
integrated exactly for a load varying linearly between the steps (the zero-order-hold matrix
exponential of the SDOF with a first-order-hold input), so all speeds are the columns of one linear
recursion. Peaks are taken over the samples, each local extremum refined by the parabola through it
and its neighbours, with dx chosen for ``samples_per_period`` samples per period of the highest mode
at the lowest speed. Besides the deck's vertical acceleration and displacement at the stations, the twist
over 3 m between the rails (EN 1990 A2.4.4.2.2) at a few stations. Pure numpy/scipy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple, Sequence

import numpy as np

from ..errors import ResourceError, SettingError
from ..structure.modal import ModalBridge
from .load_distribution import LoadDistribution, distributed_train
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
    left the bridge at the highest speed [s]. The deck twist over 3 m between the rails of the track
    (EN 1990 A2.4.4.2.2: GAUGE x |rx(x) - rx(x + 3 m)|, rx the track line's rotation about x):
    ``twist_x`` (n_t,) the first rail section of each twist station (:func:`twist_stations`), ``max_twist``
    (n_t, n_v) its peak [m] and ``static_twist`` (n_t,) the peak at a crawl.
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
    twist_x: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    max_twist: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)), repr=False)
    static_twist: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

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


#: the rails of a standard-gauge track are read this far apart, over this base, for the twist [m] (EN 1990 A2.4.4.2.2)
TWIST_GAUGE, TWIST_BASE = 1.435, 3.0


def twist_stations(spans: Sequence[float]) -> np.ndarray:
    """The first rail sections x of the twist over [x, x + 3 m]: the first and the last 3 m of each span (x = a
    and b - 3, a and b its ends), where the torsion of a deck restrained at its supports changes fastest. Few
    on purpose: each station adds a row to every step's output (two per span put 14 % on the response of
    li_zhu_2011_bridge, seven per span 53 %); the static twist (codes/deformation.py) is read at every node."""
    xs, start = [], 0.0
    for length in spans:
        a, b = start, start + float(length)
        xs += [a, b - TWIST_BASE]
        start = b
    x = np.unique(np.round(np.array(xs), 9))
    return x[(x >= -TWIST_BASE) & (x <= start)]


def _discretisation(omega: np.ndarray, zeta: np.ndarray, h: np.ndarray) -> np.ndarray:
    """(..., 2, 4): [Phi | g0 | g1] of x' = A x + (0, 1) f, A = [[0, 1], [-w^2, -2 zeta w]], with f
    linear over a step h: x_{n+1} = Phi x_n + g0 f_n + g1 (f_{n+1} - f_n). Closed forms (the exponential
    of the augmented matrix [[A h, b h, 0], [0, 0, 1], [0, 0, 0]], written out): Phi = e^{A h} =
    e^{-zeta w h} [cos(w_d h) I + sin(w_d h) / w_d (A + zeta w I)], w_d = w sqrt(1 - zeta^2) (complex
    above critical damping: cosh and sinh; its limit h at w_d = 0), G0 = A^-1 (Phi - I), g0 = G0 b,
    g1 = [G0 - A^-1 (Phi - G0 / h)] b. scipy's expm on the 4 x 4 augmented matrices gave the same to
    1e-13 and cost 15 ms per call (5.4 s of a 5.9 s train on single_span_32m)."""
    shape = np.broadcast_shapes(omega.shape, zeta.shape, h.shape)
    w, z, hh = (np.broadcast_to(np.asarray(a, dtype=float), shape) for a in (omega, zeta, h))
    wd = w * np.sqrt(1.0 - z * z + 0j)
    small = np.abs(wd * hh) < 1e-8
    wd_safe = np.where(small, 1.0, wd)
    c = np.where(small, 1.0, np.cos(wd * hh)).real
    sn = np.where(small, hh, np.sin(wd * hh) / wd_safe).real  # sin(w_d h) / w_d
    decay = np.exp(-z * w * hh)
    a11, a12, a21, a22 = np.zeros(shape), np.ones(shape), -(w ** 2), -2.0 * z * w
    zw = z * w
    phi = np.empty(shape + (2, 2))
    phi[..., 0, 0] = decay * (c + sn * (a11 + zw))
    phi[..., 0, 1] = decay * sn * a12
    phi[..., 1, 0] = decay * sn * a21
    phi[..., 1, 1] = decay * (c + sn * (a22 + zw))
    inv = np.empty(shape + (2, 2))  # A^-1 = (1 / w^2) [[-2 zeta w, -1], [w^2, 0]]
    inv[..., 0, 0], inv[..., 0, 1] = -2.0 * z / w, -1.0 / (w ** 2)
    inv[..., 1, 0], inv[..., 1, 1] = 1.0, 0.0
    eye = np.eye(2)
    g0m = inv @ (phi - eye)
    g1m = g0m - inv @ (phi - g0m / hh[..., None, None])
    out = np.empty(shape + (2, 4))
    out[..., :, :2] = phi
    out[..., :, 2] = g0m[..., :, 1]
    out[..., :, 3] = g1m[..., :, 1]
    return out


def _refined_peaks(y: np.ndarray, tail: np.ndarray | None, peak: np.ndarray) -> np.ndarray:
    """Update ``peak`` (s, v) with the largest |y| of a block y (b, s, v) of samples, each local
    extremum refined by the parabola through it and its two neighbours (vertex y_i - (y_{i-1} -
    y_{i+1})^2 / (8 (y_{i-1} - 2 y_i + y_{i+1}))): the sampled peak of a harmonic with N samples per
    period is low by up to 1 - cos(pi / N) (1.2 % at N = 20), the parabola's by about (pi / N)^4 / 8
    (7e-5). ``tail``: the previous block's last two samples (None at the start); returns this block's."""
    np.maximum(peak, np.abs(y).max(axis=0), out=peak)
    z = y if tail is None else np.concatenate([tail, y], axis=0)
    if z.shape[0] >= 3:
        lo, mid, hi = z[:-2], z[1:-1], z[2:]
        curv = lo - 2.0 * mid + hi
        extremum = (np.abs(mid) >= np.abs(lo)) & (np.abs(mid) >= np.abs(hi)) & (curv != 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = np.where(extremum, mid - (lo - hi) ** 2 / (8.0 * np.where(extremum, curv, 1.0)), 0.0)
        np.maximum(peak, np.abs(vertex).max(axis=0), out=peak)
    return z[-2:].copy()


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


class Steps(NamedTuple):
    """The integration of :func:`moving_force_response`: ``n_steps`` steps of ``dx`` [m], the train's
    passage its first ``n_pass``, then a free tail of ``tail_s`` seconds."""

    n_steps: int
    dx: float
    n_pass: int
    tail_s: float


def integration_steps(length: float, freq: np.ndarray, train: ForceTrain, speeds_kmh: np.ndarray,
                      spans: Sequence[float], samples_per_period: float = 20.0, tail_periods: float = 2.0) -> Steps:
    """The steps of :func:`moving_force_response`'s integration over a bridge ``length`` m long whose
    modes used have frequencies ``freq`` [Hz]: the train's passage and the free tail, at the steps the
    lowest speed and the highest mode set (its docstring). A caller checks them against MAX_STEPS
    before any work."""
    v = np.asarray(speeds_kmh, dtype=float) / 3.6
    freq = np.asarray(freq, dtype=float)
    dx = min(v.min() / (samples_per_period * freq.max()), min(spans) / 100.0)
    tail_s = tail_periods / freq.min()
    n_pass = int(math.ceil((length + train.length) / dx)) + 1
    return Steps(n_pass + int(math.ceil(tail_s * v.max() / dx)), dx, n_pass, tail_s)


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
    distribution: LoadDistribution | None = None,
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
    modes : indices of the modes to use (default: every mode; each acts through its vertical shape at the
        track line, bending plus torsion times the track's offset, so lateral modes without one add nothing)
    samples_per_period : samples per period of the highest mode used at the lowest speed (sets dx; the
        sampled peak of a harmonic is within 1 - cos(pi / samples_per_period) of the true one, 1.2 % at
        20, the parabola-refined peak within about (pi / samples_per_period)^4 / 8, 7e-5)
    tail_periods : free vibration after the last axle left, in periods of the lowest mode used
    block : steps per block of the station output (memory: block x modes x speeds)
    distribution : EN 1991-2's spread of each axle load by rails, sleepers and ballast (6.4.6.4;
        tb_exudyn.codes.load_distribution); None: point loads
    """
    where = "moving_force_response"
    if distribution is not None:
        train = distributed_train(train, distribution)
    v_kmh = np.atleast_1d(np.asarray(speeds_kmh, dtype=float))
    if v_kmh.ndim != 1 or v_kmh.size == 0 or not np.all(np.isfinite(v_kmh)) or np.any(v_kmh <= 0):
        raise SettingError(where, "speeds_kmh", speeds_kmh, "one or more finite speeds > 0 km/h")
    spans = [float(s) for s in spans]
    if not spans or any(not (s > 0) for s in spans) or abs(sum(spans) - bridge.length) > 1e-6 * bridge.length:
        raise SettingError(where, "spans", spans, f"span lengths > 0 m adding up to the bridge length {bridge.length:g} m")
    if modes is None:
        modes = np.arange(bridge.n_modes)
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
    n_steps, dx, n_pass, tail_s = integration_steps(bridge.length, freq, train, v_kmh, spans, samples_per_period,
                                                    tail_periods)
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
    tw_x = twist_stations(spans)
    tw_shapes = TWIST_GAUGE * (bridge.rail_shapes(tw_x).rx[:, modes] - bridge.rail_shapes(tw_x + TWIST_BASE).rx[:, modes])
    both = np.vstack([shapes, tw_shapes])  # displacements and twists: one product per block

    c_damp, c_stiff = (2.0 * zeta * omega)[:, None], (omega**2)[:, None]
    q = np.zeros((modes.size, v.size))
    p = np.zeros_like(q)
    max_acc = np.zeros((x_st.size, v.size))
    max_both = np.zeros((both.shape[0], v.size))
    qb = np.empty((block, modes.size, v.size))
    pb = np.empty_like(qb)
    df = np.diff(f, axis=0, append=f[-1:])
    tail_a = tail_d = None
    for b0 in range(0, n_steps, block):
        nb = min(block, n_steps - b0)
        for i in range(nb):
            n = b0 + i
            qb[i], pb[i] = q, p
            fn, dn = f[n][:, None], df[n][:, None]
            q, p = (p00 * q + p01 * p + g0q * fn + g1q * dn,
                    p10 * q + p11 * p + g0p * fn + g1p * dn)
        acc = f[b0:b0 + nb, :, None] - c_damp * pb[:nb] - c_stiff * qb[:nb]
        a_out = np.matmul(shapes, acc)  # (b, s, v); matmul's BLAS: 2.5x einsum's loop here
        d_out = np.matmul(both, qb[:nb])
        tail_a = _refined_peaks(a_out, tail_a, max_acc)
        tail_d = _refined_peaks(d_out, tail_d, max_both)
    static_both = np.abs((f[:n_pass] / omega**2) @ both.T).max(axis=0)
    n_s = x_st.size
    max_disp, max_twist, static, static_twist = max_both[:n_s], max_both[n_s:], static_both[:n_s], static_both[n_s:]
    return MovingForceResponse(
        train=train.name, speeds_kmh=v_kmh, station_x=x_st, station_names=names, station_span=st_span,
        mid_stations=mids, max_acc=max_acc, max_disp=max_disp, static_disp=static, frequencies=freq,
        damping_ratios=zeta, step_m=dx, tail_s=tail_s, twist_x=tw_x, max_twist=max_twist, static_twist=static_twist,
    )


__all__ = ["MovingForceResponse", "Steps", "TWIST_BASE", "TWIST_GAUGE", "deck_stations", "integration_steps",
           "modal_loads", "moving_force_response", "twist_stations"]
