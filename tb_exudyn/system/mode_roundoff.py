"""What only round-off decides in a mode table, fixed so that tables are the same on every machine
(numpy's OpenBLAS picks a kernel per CPU, OPENBLAS_CORETYPE): eigenvalue parts within round-off
set to zero (:func:`snap_round_off`) and rows that round-off alone tells apart ordered by label
(:func:`table_order`). Used by :mod:`tb_exudyn.system.modes`; tests/system/test_modes_blas_kernels.py
compares the tables under four kernels."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: a mode whose undamped frequency is below this [Hz] is a rigid-body (zero-frequency) motion
RIGID_FREQUENCY = 1e-3
#: eigenvalues closer than this (relative to their modulus) count as equal (a degenerate set)
DEGENERATE_RTOL = 1e-8
#: an eigenvalue with |Im lambda| below this fraction of |lambda| is real (:func:`snap_round_off`): a
#: critically damped motion's double root (a weak spring at zeta = 1) is split by round-off into a
#: pair lambda (1 +- d) or lambda +- i d |lambda| with d of order sqrt(eps) = 1.5e-8, which of the two
#: depending on the BLAS kernel; both become two real rows. |Im| / |lambda| = sqrt(1 - zeta^2), so a
#: mode is snapped only if zeta >= 1 - 5e-13.
REAL_SNAP = 1e-6
#: the eigenvalues' absolute round-off, in units of eps times the first-order matrix's norm: an
#: eigenvalue's real or imaginary part below ROUND_OFF * eps * ||A|| is zero (:func:`snap_round_off`).
#: A tiny root (a wheelset's slow spin root, -7e-4 1/s, on a matrix of norm 2e6 from the 2e9 N/m
#: contacts) carries an error of eps ||A|| = 4e-10 in each part, far more than eps |lambda|: a
#: double root of two identical wheelsets came as a pair -7e-4 +- 2.5e-14 i on one kernel (one
#: row) and as two reals on another (two rows); an undamped bogie yaw mode's real part as +-1e-14
#: (a damping ratio of either sign). 1e3 eps ||A|| is 3e-7 1/s there: a mode of 1 Hz loses a
#: damping ratio below 5e-8.
ROUND_OFF = 1e3

def snap_round_off(lam: NDArray[np.complex128], A: FloatArray, B: FloatArray | None) -> NDArray[np.complex128]:
    """The eigenvalues with what round-off decides set to zero, so that the rows of a mode table do
    not depend on the BLAS kernel: an imaginary part below :data:`REAL_SNAP` |lambda| plus the
    absolute floor ROUND_OFF eps ||A|| (:data:`ROUND_OFF`) and a real part below the floor. A double
    real eigenvalue (two equal, independent motions, such as the two bogies' overdamped pitch, or a
    critically damped motion's double root) comes either as two reals or as a conjugate pair
    lambda +- i d: snapped, both members are real with Im = 0 and both are kept, two rows on every
    kernel. ``B`` (the singular-M pencil's right side) scales the floor by ||B^-1|| >= 1 / ||B||,
    which a floor of eps ||A|| / ||B|| bounds from below."""
    fin = np.isfinite(lam)
    scale = np.linalg.norm(A, 1) / (1.0 if B is None else max(np.linalg.norm(B, 1), 1.0))
    floor = ROUND_OFF * np.finfo(float).eps * scale
    re, im = lam.real.copy(), lam.imag.copy()
    mod = np.where(fin, np.abs(lam), 0.0)
    im[fin & (np.abs(im) <= REAL_SNAP * mod + floor)] = 0.0
    re[fin & (np.abs(re) <= floor)] = 0.0
    return np.where(fin, re + 1j * im, lam)


def table_order(freq: FloatArray, zeta: FloatArray, labels: Sequence[str]) -> NDArray[np.int64]:
    """Rows by undamped frequency, then damping ratio; rows that round-off alone tells apart (equal
    modes of two identical parts, such as the leading and trailing bogie's longitudinal mode, whose
    frequencies differ by 1e-13 in an order that depends on the BLAS kernel) by their label, so that
    the table's order is the same on every machine. Equal: frequencies within
    :data:`DEGENERATE_RTOL` of the set's first (at least of :data:`RIGID_FREQUENCY`) and damping
    ratios within DEGENERATE_RTOL."""
    z = np.nan_to_num(zeta, nan=-1.0)
    first = np.lexsort((z, freq))
    out: list[int] = []
    i = 0
    while i < first.size:
        f0, z0 = freq[first[i]], z[first[i]]
        j = i + 1
        while (j < first.size and abs(freq[first[j]] - f0) <= DEGENERATE_RTOL * max(f0, RIGID_FREQUENCY)
               and abs(z[first[j]] - z0) <= DEGENERATE_RTOL):
            j += 1
        out.extend(sorted(first[i:j].tolist(), key=lambda k: labels[k]))
        i = j
    return np.asarray(out, dtype=np.int64)


__all__ = ["DEGENERATE_RTOL", "REAL_SNAP", "RIGID_FREQUENCY", "ROUND_OFF", "snap_round_off", "table_order"]
