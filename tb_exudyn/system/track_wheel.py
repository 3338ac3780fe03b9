"""A wheel rolling at constant speed on the discrete track (tb_exudyn.system.track_model): the contact force's
response to a harmonic vertical irregularity, by pseudo-excitation in the time domain. Pure numpy / scipy.

The wheel (mass m_w, vertical z_w, z up; a free half wheelset, no suspension above it) touches the rail at
x(t) = x0 + v t through the linearised Hertz spring k_H. The contact row is the coupling's form (tb_exudyn.
system.coupling: B = [S, -G]), here with the rail's Hermite row N(x) for S and 1 for G:

    delta = N(x(t)) q + r(x(t)) - z_w,     F = k_H delta   (the rail on the wheel, + up: compression),

    M q'' + C q' + K q = -N^T F,    m_w z_w'' = F.

The irregularity r(x) = e^{i 2 pi f x / v} (a unit pseudo-excitation, fixed in space) is at the contact
e^{i w t} up to a constant phase. Newmark's average acceleration (unconditionally stable, period error
(w h)^2 / 12) with the contact as a rank-one update of the constant matrix: one sparse LU of the track, each
step one solve with a column per frequency plus the contact's column, and Sherman-Morrison. All
frequencies are integrated together, each a complex column.

After ``settle`` seconds (the transients gone), the demodulated force g(t) = F(t) e^{-i w t} over a whole
number of bays is the transfer from irregularity to force as the wheel passes the sleepers: its mean over
the bays is H(f) (the PSD of the force is |H|^2 S_r), its variation within a bay the position effect
(the parametric excitation by the supports shows in g as a component periodic with the bay).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import scipy.sparse as sp

from .contact_rows import ContactRows
from .coupling import VERTICAL, WheelRailCoupling
from .linear import LinearSystem
from .track_model import ModalTrack, TrackModel


@dataclass(frozen=True)
class WheelOnTrackResponse:
    """``freqs`` (n_f,) [Hz]; ``transfer`` (n_f,) complex H: contact force per unit irregularity [N/m], mean
    over the bays passed; ``position`` (n_p,) the wheel's place in a bay [m] (0: above a sleeper);
    ``transfer_at`` (n_p, n_f) complex: the demodulated force at those places, averaged over the bays;
    ``speed`` [m/s], ``time_step`` [s], ``bays`` the bays averaged."""

    freqs: np.ndarray
    transfer: np.ndarray
    position: np.ndarray = field(repr=False)
    transfer_at: np.ndarray = field(repr=False)
    speed: float
    time_step: float
    bays: int

    @property
    def position_effect(self) -> np.ndarray:
        """(n_f,): (max - min) / mean of |H|^2 over the places within a bay."""
        power = np.abs(self.transfer_at) ** 2
        return (power.max(axis=0) - power.min(axis=0)) / (np.abs(self.transfer) ** 2)


def wheel_on_track(track: TrackModel, wheel_mass: float, hertz_stiffness: float, speed: float,
                   freqs: np.ndarray, x_start: float, bays: int, settle: float = 0.25,
                   steps_per_bay: int = 96) -> WheelOnTrackResponse:
    """The contact force per unit harmonic irregularity at ``freqs`` of a wheel starting at ``x_start`` and
    rolling at ``speed`` for ``settle`` seconds and then ``bays`` bays (module docstring). The time step is
    a bay over ``steps_per_bay``; the wheel must stay on the rail."""
    freqs = np.atleast_1d(np.asarray(freqs, dtype=float))
    a = float(track.support_x[1] - track.support_x[0]) if track.support_x.size > 1 else track.length
    h = a / speed / steps_per_bay
    n_settle = int(np.ceil(settle / h / steps_per_bay)) * steps_per_bay
    n_steps = n_settle + bays * steps_per_bay
    if x_start < 0 or x_start + speed * h * n_steps > track.length:
        raise ValueError(f"the wheel leaves the rail: {x_start:g} ... {x_start + speed * h * n_steps:g} m "
                         f"on a rail of {track.length:g} m")
    n, m = track.n_dof, freqs.size
    w = 2 * np.pi * freqs
    mass = sp.block_diag([track.M, sp.csr_matrix([[wheel_mass]])], format="csc")
    damp = sp.block_diag([track.C, sp.csr_matrix((1, 1))], format="csc")
    stiff = sp.block_diag([track.K, sp.csr_matrix((1, 1))], format="csc")
    from scipy.sparse.linalg import splu

    lu = splu((stiff + (2.0 / h) * damp + (4.0 / h**2) * mass).tocsc())
    u = np.zeros((n + 1, freqs.size), dtype=complex)
    v = np.zeros_like(u)
    acc = np.zeros_like(u)
    g = np.empty((bays * steps_per_bay, freqs.size), dtype=complex)
    b = np.zeros(n + 1)
    b[n] = -1.0
    for step in range(1, n_steps + 1):
        t = step * h
        row = track.shape(x_start + speed * t)
        b[:n] = row.toarray().ravel()
        r = np.exp(1j * w * t)
        rhs = -hertz_stiffness * np.outer(b, r) + mass @ ((4.0 / h**2) * u + (4.0 / h) * v + acc) \
            + damp @ ((2.0 / h) * u + v)
        z = lu.solve(np.column_stack([rhs.real, rhs.imag, b]))  # a real LU: the parts apart
        zb = z[:, -1]
        z = z[:, :m] + 1j * z[:, m:2 * m]
        u_new = z - np.outer(zb, hertz_stiffness * (b @ z) / (1.0 + hertz_stiffness * (b @ zb)))
        v_new = (2.0 / h) * (u_new - u) - v
        acc = (4.0 / h**2) * (u_new - u) - (4.0 / h) * v - acc
        u, v = u_new, v_new
        if step > n_settle:
            force = hertz_stiffness * (b @ u + r)
            g[step - n_settle - 1] = force * np.exp(-1j * w * t)
    by_place = g.reshape(bays, steps_per_bay, freqs.size).mean(axis=0)
    x0 = (x_start + speed * h * (n_settle + 1 + np.arange(steps_per_bay)) - track.support_x[0]) % a
    order = np.argsort(x0)
    return WheelOnTrackResponse(freqs=freqs, transfer=g.mean(axis=0), position=x0[order],
                                transfer_at=by_place[order], speed=speed, time_step=h, bays=bays)


def wheel_on_modal_track(track: ModalTrack, wheel_mass: float, hertz_stiffness: float, speed: float,
                         x_start: float | Sequence[float], damping: str = "full") -> LinearSystem:
    """The wheel on the track as the project's linear system (tb_exudyn.system.linear): the track's modes
    as the coupling's bridge coordinates (its rail shapes are the rail's Hermite rows), one wheel node
    (coordinate z used; the other five free and unforced) and one vertical penalty row, stiffness
    ``hertz_stiffness``, no contact damping, the irregularity's vertical input, the wheel starting at
    ``x_start`` with no taper. ``x_start`` a sequence: as many free wheels (each its own node, row and
    axle, in that order), e.g. to put several contacts on the track at once. ``damping`` "full": D0 holds
    the track's damping Phi^T C Phi (both linear engines take it; the batched engine as a coupled bridge
    block); "modal": its diagonal only (modal damping ratios, an approximation of the pads' and the
    ballast's dampers: up to 18 % in the force at 100 Hz, docs/track.md)."""
    if damping not in ("full", "modal"):
        raise ValueError(f"damping 'full' or 'modal', not {damping!r}")
    starts = np.atleast_1d(np.asarray(x_start, dtype=float))
    n_w = starts.size
    rows = ContactRows()
    for i in range(n_w):
        rows.add(name=f"wheel{i}.force_z" if n_w > 1 else "wheel.force_z", axle=i, direction=VERTICAL,
                 rail_offset=0.0, stiffness=hertz_stiffness, damping=0.0, wheel_terms={(i, 2): 1.0},
                 inputs=(1.0, 0.0, 0.0))
    cp = WheelRailCoupling(track.bridge, axle_start=list(starts), speed=speed,
                           contacts=rows.layout({i: 6 * i for i in range(n_w)}, 6 * n_w), half_gauge=0.75,
                           taper_length=0.0)
    nb = track.bridge.n_modes
    om = track.bridge.omega
    M = np.diag(np.concatenate((np.ones(nb), np.full(6 * n_w, wheel_mass))))
    K0 = np.zeros((nb + 6 * n_w, nb + 6 * n_w))
    D0 = np.zeros_like(K0)
    K0[:nb, :nb] = np.diag(om**2)
    D0[:nb, :nb] = track.damping if damping == "full" else np.diag(np.diag(track.damping))
    return LinearSystem(M=M, K0=K0, D0=D0, bridge=np.arange(nb), wheel=nb + np.arange(6 * n_w),
                        k=cp.contacts.stiffness, c=cp.contacts.damping, G=cp.contacts.wheel_map, coupling=cp,
                        linearization="rest")


__all__ = ["WheelOnTrackResponse", "wheel_on_modal_track", "wheel_on_track"]
