"""An independent reference for the mode tables' eigenvalues, written for the tests.

The reference is numpy's eigenvalues of the companion matrix [[0, I], [-M^-1 K, -M^-1 D]] (not the
mass-normalised pencil the product solves). Which of a double root's two round-off forms LAPACK
returns, two reals lambda (1 +- d) or a conjugate pair lambda +- i d, depends on the BLAS kernel
(OPENBLAS_CORETYPE), and so would the count of roots with Im >= 0. The reference decides it by the
rule the product documents, written again here: an imaginary part below 1e-6 |lambda| (a damping
ratio above 1 - 5e-13) plus an absolute floor of 1e3 eps ||A||_1, and a real part below that floor,
are zero (tb_exudyn.system.modes.REAL_SNAP and ROUND_OFF). No physical root of these cars lies
near either threshold: the smallest |Im| / |lambda| of an oscillating mode is 0.4 (the creep car's
slowest pair), the smallest real part of a damped mode 0.49 1/s, the floor 3e-7 1/s.
"""

from __future__ import annotations

import numpy as np

RELATIVE_SNAP = 1e-6
FLOOR_IN_EPS_NORM = 1e3


def reference_eigenvalues(M: np.ndarray, K: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Eigenvalues with Im >= 0 of M q'' + D q' + K q = 0 (companion matrix, numpy), with the
    round-off parts set to zero as the module docstring says."""
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ D]])
    lam = np.linalg.eigvals(A)
    floor = FLOOR_IN_EPS_NORM * np.finfo(float).eps * np.abs(A).sum(axis=0).max()
    im = np.where(np.abs(lam.imag) <= RELATIVE_SNAP * np.abs(lam) + floor, 0.0, lam.imag)
    re = np.where(np.abs(lam.real) <= floor, 0.0, lam.real)
    lam = re + 1j * im
    return lam[lam.imag >= 0.0]
