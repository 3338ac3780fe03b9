"""The a posteriori frequency-grid error of a PEM result, per channel.

Estimate: the same sweep on a refined grid (the grid's nodes and its cell midpoints, see
:func:`tb_exudyn.methods.adaptive_grid.midpoint_grid`; the refined variance reuses every finished
column: var_refined = (var_grid + var_midpoints) / 2). The grid's error is estimated as

    e(t) = sigma_grid(t) - sigma_refined(t)

which is the true error e_true = sigma_grid - sigma_exact up to the refined grid's own error. When
halving the spacing at least halves the error (the trapezoid rule's h^2 on smooth parts, faster once
the spacing resolves the run's length near a lightly damped mode: the aliasing error then falls
away), the estimate lies within a factor of 2 of the true error; docs/adaptive_grid.md measures it.
The refined result is the better one; the estimate bounds its error from above in that regime.

The local estimate ("local" of :data:`GRID_ESTIMATES`) refines only the cells wider than the spacing
the adaptive grid's rules ask for there (:func:`~.grid.estimate_cells`): a sweep on their midpoints
(M) and the sum on their nodes with those cells' trapezoid weights (T) give var_refined = var_grid +
(M - T) / 2 (:func:`~.grid.locally_refined_variance`); the other cells are taken as converged. T
needs no sweep of its own: it is the grid's own columns at those nodes, weighted by
:func:`~.grid.local_node_factors` in the grid tasks' reducer.

Per channel the result states the relative error of max over time of sigma, (max sigma_grid -
max sigma_refined) / max sigma_refined, and the largest deviation over time, max_t |e(t)| / max
sigma_refined, with the time where it occurs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..results.random_response import RandomResponse
from ..track import quadrature_weights
from .grid import LOCAL_RATIO, refined_variance

#: the estimates (``run_pem(grid_error=...)``, the method option's one home): "midpoints", the sweep on
#: every cell's midpoint (as many columns again); "local", only the cells coarser than the adaptive
#: grid's rules (:func:`~.grid.estimate_cells`): a sweep on their midpoints, the nodes' sum from the grid's
#: own columns (docs/speed.md measures both)
GRID_ESTIMATES = ("midpoints", "local")
DEFAULT_GRID_ESTIMATE = "local"


def local_method(chosen: int, cells: int) -> str:
    """The ``method`` of the local estimate refining ``chosen`` of the grid's ``cells``."""
    return (f"refined locally: the midpoints of the {chosen} of {cells} cells wider than {LOCAL_RATIO:g} x the "
            f"adaptive grid's required spacing, the other cells taken as converged")


@dataclass(frozen=True)
class GridError:
    """Estimated grid error of a PEM result, per channel (module docstring).

    Attributes
    ----------
    channels : channel names
    max_sigma : (nc,) max over time of sigma on the grid [channel unit]
    max_sigma_refined : (nc,) the same on the refined grid [channel unit]
    rel_error_max_sigma : (nc,) (max_sigma - max_sigma_refined) / max_sigma_refined [-], signed
        (positive: the grid overstates the largest sigma)
    rel_deviation : (nc,) max over time of |sigma - sigma_refined| / max_sigma_refined [-]
    time_of_deviation : (nc,) the time of that largest deviation [s]
    method : how the refined result was obtained
    """

    channels: tuple[str, ...]
    max_sigma: NDArray[np.float64]
    max_sigma_refined: NDArray[np.float64]
    rel_error_max_sigma: NDArray[np.float64]
    rel_deviation: NDArray[np.float64]
    time_of_deviation: NDArray[np.float64]
    method: str = "refined: the grid's nodes and cell midpoints"

    def exceeding(self, tolerance: float = 0.01) -> list[str]:
        """Channels whose |relative error of max sigma| or largest deviation over time exceeds tolerance."""
        bad = (np.abs(self.rel_error_max_sigma) > tolerance) | (self.rel_deviation > tolerance)
        return [c for c, b in zip(self.channels, bad) if b]

    def as_dict(self) -> dict[str, object]:
        """JSON-ready form (e.g. for a result's provenance): the method and, per channel, the relative
        error of max sigma, the largest relative deviation and its time [s]."""
        return {"method": self.method,
                "channels": {c: {"rel_error_max_sigma": e, "rel_deviation": d, "time_of_deviation_s": t}
                             for c, e, d, t in self.rows()}}

    def rows(self) -> list[tuple[str, float, float, float]]:
        """(channel, relative error of max sigma, largest relative deviation, its time [s]) per channel."""
        return [(c, float(e), float(d), float(t)) for c, e, d, t in
                zip(self.channels, self.rel_error_max_sigma, self.rel_deviation, self.time_of_deviation)]


def grid_error_from_sigma(time: NDArray[np.float64], channels: Sequence[str], sigma: NDArray[np.float64],
                          sigma_refined: NDArray[np.float64], method: str = GridError.method) -> GridError:
    """The grid error from sigma on the grid and on the refined grid, both (nc, nt) over ``time`` (nt,).

    A channel whose refined sigma is zero throughout (no response) gets zero errors.
    """
    time = np.asarray(time, dtype=float)
    s, r = np.asarray(sigma, dtype=float), np.asarray(sigma_refined, dtype=float)
    if s.shape != r.shape or s.ndim != 2 or s.shape != (len(channels), time.size):
        raise ValueError(f"sigma {s.shape} and sigma_refined {r.shape} must both be (channels, times) = "
                         f"{(len(channels), time.size)}")
    max_s, max_r = s.max(axis=1), r.max(axis=1)
    scale = np.where(max_r > 0, max_r, 1.0)
    dev = np.abs(s - r)
    k = dev.argmax(axis=1)
    return GridError(
        channels=tuple(channels), max_sigma=max_s, max_sigma_refined=max_r,
        rel_error_max_sigma=np.where(max_r > 0, (max_s - max_r) / scale, 0.0),
        rel_deviation=np.where(max_r > 0, dev.max(axis=1) / scale, 0.0),
        time_of_deviation=time[k], method=method,
    )


def grid_error(result: RandomResponse, refined: RandomResponse) -> GridError:
    """The grid error of a PEM ``result`` from the same scenario's result on a refined grid.

    ``refined`` is e.g. :func:`refined_response` of the result and its midpoint sweep, or any sweep on
    a finer grid (then ``method`` says a finer grid). ValueError if channels or times differ.
    """
    if tuple(result.channels) != tuple(refined.channels):
        raise ValueError("the two results have different channels")
    if result.time.shape != refined.time.shape or not np.allclose(result.time, refined.time, rtol=0, atol=1e-9):
        raise ValueError("the two results have different output times")
    f, g = np.asarray(result.freq), np.asarray(refined.freq)
    is_union = g.size == 2 * f.size - 1 and np.allclose(g[::2], f, rtol=1e-12, atol=0)
    method = GridError.method if is_union else f"a finer grid of {g.size} frequencies"
    return grid_error_from_sigma(result.time, result.channels, result.std, refined.std, method)


def refined_response(result: RandomResponse, midpoints: RandomResponse) -> RandomResponse:
    """The PEM result on the grid's nodes and midpoints together, from ``result`` (trapezoid grid) and
    ``midpoints`` (the same scenario swept on :func:`~tb_exudyn.methods.adaptive_grid.midpoint_grid` of
    its grid): variances (trapezoid + midpoint) / 2, frequencies interleaved with their trapezoid
    weights, the PSD maps (per Hz, independent of the weights) interleaved when both are kept.
    """
    f, fm = np.asarray(result.freq, dtype=float), np.asarray(midpoints.freq, dtype=float)
    if f.size < 2 or fm.size != f.size - 1 or not np.allclose(fm, (f[1:] + f[:-1]) / 2, rtol=1e-12, atol=0):
        raise ValueError("midpoints must be the sweep on the result's cell midpoints")
    if (tuple(result.channels) != tuple(midpoints.channels) or result.var_by_type is None
            or midpoints.var_by_type is None):
        raise ValueError("both results need the same channels and their variance by type")
    var = refined_variance(result.var_by_type, midpoints.var_by_type)
    freq = np.empty(2 * f.size - 1)
    freq[::2], freq[1::2] = f, fm
    psd = None
    if result.psd is not None and midpoints.psd is not None:
        psd = np.empty((result.psd.shape[0], freq.size, result.psd.shape[2]))
        psd[:, ::2, :], psd[:, 1::2, :] = result.psd, midpoints.psd
    seconds = float(result.provenance.get("seconds", 0.0)) + float(midpoints.provenance.get("seconds", 0.0))
    provenance = {**result.provenance, "n_frequencies": int(freq.size), "quadrature": "trapezoid",
                  "refined_from": int(f.size), "seconds": seconds}
    return RandomResponse(
        method=result.method, time=result.time, channels=result.channels, units=result.units, mean=result.mean,
        std=np.sqrt(var.sum(axis=0)), band=result.band, scenario=result.scenario, freq=freq,
        df=quadrature_weights(freq, "trapezoid"), psd=psd, var_by_type=var, types=result.types, provenance=provenance,
    )
