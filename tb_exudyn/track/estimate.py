"""Estimate the one-sided spatial PSD of a sampled profile, in the units of the spectra."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray


def welch_psd(profile_values: ArrayLike, dx: float, nperseg: int | None = None,
              **welch_kwargs: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Welch estimate of the one-sided PSD of a profile sampled at spacing dx [m].

    scipy.signal.welch returns S(n) per cycle/m at n [1/m]; converted one-sidedly to rad/m:
    omega = 2 pi n, S(omega) = S(n) / (2 pi), so ``sum S(omega) d_omega`` is the variance, as for
    ``Spectrum.psd``. Defaults: Hann window, 50 % overlap, mean removed, ``nperseg`` = min(len, 4096).
    Extra keyword arguments go to scipy.signal.welch (``scaling`` is fixed to "density").

    Returns
    -------
    omega [rad/m], psd [unit^2/(rad/m)] (the zero frequency included, as welch returns it).
    """
    values = np.asarray(profile_values, dtype=float)
    if values.ndim != 1 or values.size < 8:
        raise ValueError(f"profile_values must be 1-D with at least 8 points, got shape {values.shape}")
    if not (math.isfinite(dx) and dx > 0):
        raise ValueError(f"dx must be finite and > 0 m, got {dx!r}")
    from scipy.signal import welch  # here: importing scipy.signal costs 0.5 s per worker process

    if welch_kwargs.pop("scaling", "density") != "density":
        raise ValueError("welch_psd only computes a density (scaling='density')")
    n, s_n = welch(values, fs=1.0 / dx, nperseg=min(values.size, nperseg or 4096), scaling="density",
                   return_onesided=True, **welch_kwargs)
    return 2 * math.pi * n, s_n / (2 * math.pi)
