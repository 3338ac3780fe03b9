"""What an uncertainty study computes of its nodes' PEM results: one node's summary (in the worker)
and the expansion of every quantity over the nodes (in the parent), through :mod:`.pce` only."""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from ...results.random_response import RandomResponse
from ...results.uq import LOO_WARNING, PERCENTILES
from . import pce

#: the germ samples of the surrogate from which the bands of sigma(t) are read (a Sobol design)
BAND_SAMPLES = 1024


def node_summary(result: RandomResponse, check_values: Any) -> dict[str, np.ndarray]:
    """One node's PEM result as plain arrays (checkpointable): sigma(t), the mean, the channels, and the
    code checks' probability and estimate per criterion (``check_values``: the sweep's hook)."""
    checks = check_values(result)
    crit = sorted(checks)
    return {"std": np.asarray(result.std, dtype=float), "mean": np.asarray(result.mean, dtype=float),
            "time": np.asarray(result.time, dtype=float), "channels": np.array(result.channels, dtype=str),
            "units": np.array(result.units, dtype=str), "criteria": np.array(crit, dtype=str).reshape(-1),
            "probability": np.array([checks[c].probability for c in crit], dtype=float),
            "estimate": np.array([checks[c].estimate for c in crit], dtype=float),
            "seconds": np.array(float(result.provenance.get("seconds", math.nan)))}


def node_quantities(summaries: Sequence[dict[str, np.ndarray]], window: tuple[float, float] | None = None
                    ) -> tuple[list[str], list[str], np.ndarray]:
    """(quantity names, criteria, values (node x quantity)): max sigma per channel (over the times in
    ``window``, default all), then per criterion met at every node its probability and its estimate."""
    t = summaries[0]["time"]
    keep = np.ones(t.size, bool) if window is None else (t >= window[0]) & (t <= window[1])
    channels = [str(c) for c in summaries[0]["channels"]]
    crit = [str(c) for c in summaries[0]["criteria"] if all(str(c) in s["criteria"].tolist() for s in summaries)]
    names = [f"max_sigma:{c}" for c in channels] + [f"probability:{c}" for c in crit] + [f"estimate:{c}" for c in crit]
    rows = []
    for s in summaries:
        where = [s["criteria"].tolist().index(c) for c in crit]
        rows.append(np.concatenate([s["std"][:, keep].max(axis=1), s["probability"][where], s["estimate"][where]]))
    return names, crit, np.array(rows, dtype=float).reshape(len(summaries), len(names))


def expand(germs: Sequence[Any], order: int, x: np.ndarray, w: np.ndarray | None,
           summaries: Sequence[dict[str, np.ndarray]], window: tuple[float, float] | None = None
           ) -> dict[str, np.ndarray]:
    """The arrays of :data:`tb_exudyn.results.uq.UQ_SCHEMA` (but the nodes') from the nodes' summaries
    (``window``: that of the max sigma, :func:`node_quantities`)."""
    std = np.stack([s["std"] for s in summaries])
    mean = np.stack([s["mean"] for s in summaries])
    e_sigma = pce.fit(germs, order, x, w, std)
    e_mean = pce.fit(germs, order, x, w, mean)
    names, crit, values = node_quantities(summaries, window)
    q = pce.fit(germs, order, x, w, values)
    nan_cols = ~np.all(np.isfinite(values), axis=0)
    first, total = q.sobol_first(), q.sobol_total()
    first[:, nan_cols] = total[:, nan_cols] = np.nan
    q_mean, q_std = q.mean.copy(), np.sqrt(q.variance)
    q_mean[nan_cols] = q_std[nan_cols] = np.nan
    pf = q_mean[len(summaries[0]["channels"]):][: len(crit)]
    band = quantity_band(germs, order, q, names)
    band[:, nan_cols] = np.nan
    return {"mean_sigma": np.maximum(e_sigma.mean, 0.0), "std_sigma": np.sqrt(e_sigma.variance),
            "mean_response": e_mean.mean, "sigma_band": sigma_band(germs, order, e_sigma),
            "quantity_mean": q_mean, "quantity_std": q_std, "quantity_band": band, "sobol_first": first, "sobol_total": total,
            "loo": q.loo, "pf": pf, "quantities": names, "criteria": crit, "node_quantities": values}


def band_points(germs: Sequence[Any]) -> np.ndarray:
    """The germ samples the bands are read at (key x :data:`BAND_SAMPLES`): a Sobol design of the germs."""
    import chaospy

    return np.asarray(chaospy.J(*germs).sample(BAND_SAMPLES, rule="sobol"), dtype=float).reshape(len(germs), -1)


def quantity_band(germs: Sequence[Any], order: int, e: pce.Expansion, names: Sequence[str]) -> np.ndarray:
    """The :data:`PERCENTILES` of every quantity over the keys (percentile x quantity): the surrogate at
    :func:`band_points`, a max sigma clipped at 0 and a probability to [0, 1] (a polynomial may leave
    them where the nodes are not)."""
    _, psi = pce.basis(germs, order, band_points(germs))
    values = np.asarray(psi @ e.coefficients, dtype=float).reshape(psi.shape[0], len(names))
    for j, n in enumerate(names):
        if n.startswith("max_sigma:"):
            values[:, j] = np.maximum(values[:, j], 0.0)
        elif n.startswith("probability:"):
            values[:, j] = np.clip(values[:, j], 0.0, 1.0)
    return np.percentile(values, PERCENTILES, axis=0)


def sigma_band(germs: Sequence[Any], order: int, e: pce.Expansion) -> np.ndarray:
    """The :data:`PERCENTILES` of sigma(t) over the keys (percentile x channel x time): the surrogate at
    :data:`BAND_SAMPLES` Sobol points of the germs, channel by channel (bounded memory), clipped at 0."""
    _, psi = pce.basis(germs, order, band_points(germs))
    coef = e.coefficients  # (basis, channel, time)
    out = np.empty((len(PERCENTILES),) + coef.shape[1:])
    for c in range(coef.shape[1]):
        out[:, c] = np.percentile(np.maximum(psi @ coef[:, c], 0.0), PERCENTILES, axis=0)
    return out


#: a probability's expansion is judged by its leave-one-out error only above this mean (far below any
#: target probability, a relative error of the surrogate changes no verdict; such probabilities span many
#: orders of magnitude over the keys, which no low-order polynomial follows)
PROBABILITY_FLOOR = 1e-9


#: nor is a quantity whose leave-one-out RMS error, sqrt(LOO) x std, is below this share of its |mean|
#: (a quantity the keys hardly move: its variance is tiny, so the LOO relative to it is noise)
MEAN_SHARE = 1e-3


def loo_warnings(names: Sequence[str], loo: np.ndarray, means: np.ndarray | None = None,
                 stds: np.ndarray | None = None) -> list[str]:
    """The warning of quantities whose leave-one-out error (relative to their variance) is above
    :data:`LOO_WARNING` (empty: none); left out: probabilities whose mean is below
    :data:`PROBABILITY_FLOOR`, and quantities whose leave-one-out RMS error is below :data:`MEAN_SHARE`
    of their |mean|."""
    means = np.full(len(names), np.inf) if means is None else means
    stds = np.full(len(names), np.inf) if stds is None else stds
    bad = [(n, float(e)) for n, e, m, s in zip(names, loo, means, stds) if math.isfinite(e) and e > LOO_WARNING
           and not (n.startswith("probability:") and not m >= PROBABILITY_FLOOR)
           and not math.sqrt(e) * s < MEAN_SHARE * abs(m)]
    if not bad:
        return []
    n, e = max(bad, key=lambda b: b[1])
    return [f"the polynomial chaos surrogate's leave-one-out error is above {100 * LOO_WARNING:g} % for {len(bad)} "
            f"of {len(names)} quantities (largest {100 * e:.3g} % on {n}): raise --order or use more nodes"]


def keys_json(keys: Sequence[Any]) -> list[dict[str, Any]]:
    """The uncertain keys as plain dicts (the result's metadata)."""
    return [{k: (v if not isinstance(v, float) or math.isfinite(v) else None) for k, v in uk.__dict__.items()}
            for uk in keys]


__all__ = ["BAND_SAMPLES", "band_points", "quantity_band", "MEAN_SHARE", "PROBABILITY_FLOOR", "expand", "keys_json", "loo_warnings", "node_quantities", "node_summary", "sigma_band"]
