"""Non-intrusive polynomial chaos over node values: pure functions, no runner.

The uncertain keys (:class:`tb_exudyn.scenario.uncertain.UncertainKey`) are functions of independent
standard *germs* (:func:`germ`): a normal key is ``mean + std xi`` and a lognormal one
``exp(mu + s xi)``, xi ~ N(0, 1); a uniform key is linear in xi ~ U(-1, 1); a truncated normal one is
``mean + std xi`` with xi a standard normal truncated to the key's bounds. The expansion is in the
germs: chaospy gives each germ's orthonormal polynomials (:func:`chaospy.generate_expansion`), the
nodes (:func:`chaospy.generate_quadrature`: tensor or sparse Gauss; or a Sobol design,
:meth:`chaospy.Distribution.sample`) and their weights; the multivariate basis is the products of
total degree <= order (:func:`multi_indices`).

:func:`fit` projects node values of any shape on the basis (quadrature: the weighted sums; a design:
least squares); :class:`Expansion` has the mean, the variance, Sobol first-order and total indices
(sums of squared coefficients, Sudret 2008) and the leave-one-out error of the least-squares fit on
the same nodes (Blatman & Sudret 2010: the residuals over 1 - h_ii). Every function takes the node
values, so the same code serves PEM runs and a test function with known answers.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ...errors import SettingError
from ...scenario.uncertain import lognormal_parameters

#: the node designs: Gauss quadrature on a tensor grid or a Smolyak sparse grid, or a Sobol
#: low-discrepancy design fitted by least squares
DESIGNS: tuple[str, ...] = ("tensor", "sparse", "sobol")
#: the largest order of an expansion
MAX_ORDER = 8


def germ(distribution: str, low: float = -math.inf, high: float = math.inf) -> Any:
    """The chaospy distribution of a key's standard germ (module docstring); ``low``, ``high``: a
    truncated normal's bounds in standard units."""
    import chaospy

    if distribution in ("normal", "lognormal"):
        return chaospy.Normal(0.0, 1.0)
    if distribution == "uniform":
        return chaospy.Uniform(-1.0, 1.0)
    if distribution == "truncated_normal":
        return chaospy.TruncNormal(low, high, 0.0, 1.0)
    raise ValueError(f"no germ for distribution {distribution!r}")


def key_germ(uk: Any) -> Any:
    """The germ of an uncertain key (:class:`~tb_exudyn.scenario.uncertain.UncertainKey`)."""
    if uk.distribution == "truncated_normal":
        return germ(uk.distribution, (uk.low - uk.mean) / uk.std, (uk.high - uk.mean) / uk.std)
    return germ(uk.distribution)


def key_value(uk: Any, xi: np.ndarray) -> np.ndarray:
    """The key's values at germ values ``xi``."""
    xi = np.asarray(xi, dtype=float)
    if uk.distribution in ("normal", "truncated_normal"):
        return uk.mean + uk.std * xi
    if uk.distribution == "uniform":
        return uk.low + (uk.high - uk.low) * (xi + 1.0) / 2.0
    mu, s = lognormal_parameters(uk.mean, uk.std)
    return np.exp(mu + s * xi)


def key_germ_value(uk: Any, value: Any) -> np.ndarray:
    """The germ values at which the key takes ``value`` (the inverse of :func:`key_value`)."""
    v = np.asarray(value, dtype=float)
    if uk.distribution in ("normal", "truncated_normal"):
        return (v - uk.mean) / uk.std
    if uk.distribution == "uniform":
        return 2.0 * (v - uk.low) / (uk.high - uk.low) - 1.0
    mu, s = lognormal_parameters(uk.mean, uk.std)
    return (np.log(v) - mu) / s


def multi_indices(dim: int, order: int) -> np.ndarray:
    """Every multi-index of ``dim`` degrees of total degree <= ``order``, graded (the constant first)."""
    rows = [a for a in itertools.product(range(order + 1), repeat=dim) if sum(a) <= order]
    rows.sort(key=lambda a: (sum(a), tuple(-x for x in a)))
    return np.array(rows, dtype=np.int64).reshape(-1, dim)


def nodes(germs: Sequence[Any], order: int, design: str = "tensor", n_nodes: int | None = None
          ) -> tuple[np.ndarray, np.ndarray | None]:
    """The germ nodes (dim x n) and quadrature weights (None for a regression design) of an expansion
    of ``order``: Gauss with order + 1 points per germ on a tensor grid, the Smolyak grid of the same
    Gauss rules (``sparse``), or ``n_nodes`` Sobol points (default twice the basis size)."""
    import chaospy

    joint = chaospy.J(*germs)
    if design == "sobol":
        n = n_nodes if n_nodes is not None else 2 * len(multi_indices(len(germs), order))
        x = np.asarray(joint.sample(n, rule="sobol"), dtype=float).reshape(len(germs), n)
        return x, None
    x, w = chaospy.generate_quadrature(order, joint, rule="gaussian", sparse=design == "sparse")
    return np.asarray(x, dtype=float).reshape(len(germs), -1), np.asarray(w, dtype=float)


def basis(germs: Sequence[Any], order: int, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(multi-indices, Psi): the orthonormal product basis evaluated at germ nodes ``x`` (dim x n),
    Psi[n, a] = prod_j P_j,a_j(x_j), P_j the orthonormal polynomials of germ j (chaospy)."""
    import chaospy

    alpha = multi_indices(len(germs), order)
    one_d = []
    for j, g in enumerate(germs):
        polys = chaospy.generate_expansion(order, g, normed=True)
        one_d.append(np.asarray(polys(x[j]), dtype=float).reshape(order + 1, -1))  # (degree, n)
    psi = np.ones((x.shape[1], len(alpha)))
    for j in range(len(germs)):
        psi *= one_d[j][alpha[:, j]].T
    return alpha, psi


@dataclass(frozen=True)
class Expansion:
    """A fitted expansion: ``coefficients`` (basis, *shape of a node value*) on ``alpha`` (basis x dim)."""

    alpha: np.ndarray
    coefficients: np.ndarray
    loo: np.ndarray  # the leave-one-out error per output (relative to the variance; NaN: not estimable)

    @property
    def mean(self) -> np.ndarray:
        return self.coefficients[0]

    @property
    def variance(self) -> np.ndarray:
        return np.sum(self.coefficients[1:] ** 2, axis=0)

    def _share(self, rows: np.ndarray) -> np.ndarray:
        var = self.variance
        part = np.sum(self.coefficients[rows] ** 2, axis=0)
        return np.divide(part, var, out=np.zeros_like(var), where=var > 0)

    def sobol_first(self) -> np.ndarray:
        """First-order Sobol indices (dim, *shape): the terms in germ j alone over the variance."""
        a = self.alpha
        return np.stack([self._share((a[:, j] > 0) & (a.sum(axis=1) == a[:, j])) for j in range(a.shape[1])])

    def sobol_total(self) -> np.ndarray:
        """Total Sobol indices (dim, *shape): every term in germ j over the variance."""
        return np.stack([self._share(self.alpha[:, j] > 0) for j in range(self.alpha.shape[1])])

    def __call__(self, psi: np.ndarray) -> np.ndarray:
        """The surrogate's values at basis rows ``psi`` (n x basis)."""
        return np.tensordot(psi, self.coefficients, axes=1)


def fit(germs: Sequence[Any], order: int, x: np.ndarray, weights: np.ndarray | None, values: Any) -> Expansion:
    """The expansion of node values ``values`` (n, *shape) at germ nodes ``x`` (dim x n): projection with
    the quadrature ``weights``, or least squares (``weights`` None); with its leave-one-out error."""
    y = np.asarray(values, dtype=float)
    shape = y.shape[1:]
    y2 = y.reshape(y.shape[0], -1)
    alpha, psi = basis(germs, order, x)
    if weights is not None:
        coef = psi.T @ (weights[:, None] * y2)
    else:
        coef = np.linalg.lstsq(psi, y2, rcond=None)[0]
    return Expansion(alpha, coef.reshape((len(alpha),) + shape), loo_error(psi, y2).reshape(shape))


def loo_error(psi: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The relative leave-one-out error of the least-squares fit of ``y`` (n x m) on ``psi`` (n x basis):
    mean((y - y_hat)^2 / (1 - h)^2) / var(y); NaN where it cannot be estimated (no more nodes than basis
    functions, a node of leverage 1, a constant output)."""
    n, p = psi.shape
    out = np.full(y.shape[1], np.nan)
    if n <= p:
        return out
    q, _ = np.linalg.qr(psi)
    h = np.sum(q * q, axis=1)
    if np.any(h > 1 - 1e-10):
        return out
    resid = y - q @ (q.T @ y)
    var = np.var(y, axis=0)
    err = np.mean((resid / (1 - h)[:, None]) ** 2, axis=0)
    return np.divide(err, var, out=out, where=var > 1e-300 * np.maximum(1.0, np.max(np.abs(y), axis=0)) ** 2)


def check_design(order: Any, design: str, n_nodes: Any, where: str) -> tuple[int, int | None]:
    """The order (1 ... :data:`MAX_ORDER`), the design and the node count checked; SettingError naming them."""
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 1 <= order <= MAX_ORDER:
        raise SettingError(where, "order", order, f"an integer 1 ... {MAX_ORDER}")
    if design not in DESIGNS:
        raise SettingError(where, "design", design, " or ".join(map(repr, DESIGNS)))
    if n_nodes is not None:
        if design != "sobol":
            raise SettingError(where, "nodes", n_nodes, "a node count only with the sobol design (a quadrature's "
                               "count follows from the order)")
        if isinstance(n_nodes, bool) or not isinstance(n_nodes, (int, np.integer)) or not 2 <= n_nodes <= 100000:
            raise SettingError(where, "nodes", n_nodes, "an integer 2 ... 100000")
    return int(order), None if n_nodes is None else int(n_nodes)


__all__ = ["DESIGNS", "Expansion", "MAX_ORDER", "basis", "check_design", "fit", "germ", "key_germ", "key_germ_value", "key_value",
           "loo_error", "multi_indices", "nodes"]
