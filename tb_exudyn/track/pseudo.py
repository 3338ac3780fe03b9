"""Pseudo-excitation (PEM) inputs for several wheels.

Wheel j trails the leading wheel by a_j >= 0 [m]; the leading wheel is at x = v t (+ a constant the
coupling adds). For spatial frequency omega_k with quadrature width d_omega_k:

    r~_jk(t) = sqrt(G(omega_k) d_omega_k) exp(i omega_k (v t - a_j)),   dr~/dt = i omega_k v r~.

Then sum_k |r~_jk|^2 = sum_k G(omega_k) d_omega_k (the discretised band variance) for every wheel
and time, and r~_jk / r~_0k = exp(-i omega_k (a_j - a_0)).
A real-valued integrator gets the response y~ = y(Re input) + i y(Im input) by linearity.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .bands import _check_speed
from .spectra import Spectrum, SpectrumError

QUADRATURE_RULES = ("midpoint", "trapezoid")


def quadrature_weights(grid: ArrayLike, rule: str = "midpoint") -> NDArray[np.float64]:
    """Weights w_k with integral g ~ sum_k g(x_k) w_k on a strictly increasing grid (any spacing).

    "midpoint": each node is the centre of its cell; cell edges lie halfway between nodes and the
    outer edges half a neighbour spacing outside the end nodes. On a linear grid x_k = x_1 + (k - 1/2) dx
    every weight is dx and the cells tile [x_1 - dx/2 ... ] exactly: the mid-point rule of the
    spectral representation. "trapezoid": nodes are cell edges, w = (x_{k+1} - x_{k-1}) / 2 inside,
    half a spacing at the two ends.
    """
    x = np.asarray(grid, dtype=float)
    if x.ndim != 1 or x.size < 2 or np.any(np.diff(x) <= 0):
        raise SpectrumError("quadrature grid must be 1-D, strictly increasing, with at least two points")
    if rule not in QUADRATURE_RULES:
        raise SpectrumError(f"quadrature rule must be one of {QUADRATURE_RULES}, got {rule!r}")
    h = np.diff(x)
    if rule == "trapezoid":
        return np.concatenate(([h[0] / 2], (h[:-1] + h[1:]) / 2, [h[-1] / 2]))
    edges = np.concatenate(([x[0] - h[0] / 2], (x[:-1] + x[1:]) / 2, [x[-1] + h[-1] / 2]))
    return np.diff(edges)


def pseudo_excitation(spectrum: Spectrum, omega_k: ArrayLike, d_omega: ArrayLike, v: float, t: ArrayLike,
                      wheel_offsets: ArrayLike) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Complex pseudo-irregularity at every wheel and its time derivative.

    Parameters
    ----------
    spectrum : one-sided spatial PSD G [unit^2/(rad/m)].
    omega_k : spatial frequencies [rad/m], 1-D, inside ``spectrum.validity``.
    d_omega : quadrature widths [rad/m], scalar or same shape as omega_k (see ``quadrature_weights``).
    v : speed [m/s].
    t : times [s], scalar or 1-D.
    wheel_offsets : a_j [m], 1-D: how far wheel j trails the leading wheel.

    Returns
    -------
    r, r_dot : complex arrays of shape (n_omega, n_wheels, n_times) (a scalar t counts as one time),
        r[k, j, i] = sqrt(G(omega_k) d_omega_k) exp(i omega_k (v t_i - a_j)),  r_dot = i omega_k v r.
    """
    _check_speed(v)
    omega = np.atleast_1d(np.asarray(omega_k, dtype=float))
    width = np.broadcast_to(np.asarray(d_omega, dtype=float), omega.shape)
    if omega.ndim != 1 or omega.size == 0:
        raise SpectrumError("omega_k must be a non-empty 1-D array")
    if np.any(width <= 0):
        raise SpectrumError("quadrature widths d_omega must be > 0")
    lo, hi = spectrum.validity
    if omega.min() <= 0 or omega.min() < lo * (1 - 1e-9) or omega.max() > hi * (1 + 1e-9):
        raise SpectrumError(f"omega_k in [{omega.min():g}, {omega.max():g}] rad/m must be > 0 and inside the "
                            f"validity [{lo:g}, {hi:g}] rad/m of spectrum {spectrum.name!r}")
    a = np.atleast_1d(np.asarray(wheel_offsets, dtype=float))
    times = np.atleast_1d(np.asarray(t, dtype=float))
    amp = np.sqrt(spectrum.psd(omega) * width)
    r = amp[:, None, None] * np.exp(1j * omega[:, None, None] * (v * times[None, None, :] - a[None, :, None]))
    return r, 1j * (omega * v)[:, None, None] * r


def pseudo_excitation_hz(spectrum: Spectrum, f: ArrayLike, v: float, t: ArrayLike, wheel_offsets: ArrayLike,
                         df: ArrayLike | None = None, rule: str = "midpoint"
                         ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """``pseudo_excitation`` on a temporal frequency grid f [Hz] at speed v.

    omega_k = 2 pi f_k / v, d_omega_k = 2 pi df_k / v, so |r~|^2 = G d_omega = S_hz(f) df with
    S_hz the one-sided temporal PSD per Hz. ``df`` gives the widths [Hz] directly (scalar for a
    linear grid); when None they are ``quadrature_weights(f, rule)`` (default mid-point: a linear
    grid f_k = f_1 + (k - 1/2) df gets df everywhere). Same shapes and r_dot = i 2 pi f r.
    """
    _check_speed(v)
    f = np.asarray(f, dtype=float)
    widths = quadrature_weights(f, rule) if df is None else np.asarray(df, dtype=float)
    return pseudo_excitation(spectrum, 2 * math.pi * f / v, 2 * math.pi * widths / v, v, t, wheel_offsets)
