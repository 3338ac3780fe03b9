"""EN 1991-2's distribution of an axle load by the rails, sleepers and ballast (6.3.6.1, 6.3.6.2; allowed in
the dynamic analysis by 6.4.6.4): pure functions, no bridge, no Exudyn.

- Through the rail (6.3.6.1, Figure 6.4): a point load Q is shared by three rail supports, Q/4 at the
  sleeper before, Q/2 at the one under it and Q/4 at the one after (sleeper spacing a).
- Through the sleeper and the ballast (6.3.6.2, Figure 6.5): each sleeper's share spreads at 4 (down) to 1
  (along) from the sleeper's underside to the reference plane (the deck): a uniform load over the
  sleeper's bearing width b plus h / 4 on each side, h the ballast depth under the sleeper.

So an axle at x carries onto the deck three uniform patches centred at x - a, x, x + a, each of length
b + h / 2, with 1/4, 1/2 and 1/4 of the load. ``axle_patches`` gives them; ``spread_points`` turns them
into point loads at Gauss-Legendre points (a patch of length l acting on a shape phi is exactly
(1 / l) \\int phi, and the Gauss rule of n points integrates a polynomial of degree 2 n - 1 exactly: for a
bridge mode of wavelength lambda over a patch of 0.5 m the rule of 4 points errs by about (pi l /
lambda)^8 / 10^4, nothing at bridge frequencies). The load stays vertical and its sum is the axle load.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SettingError

#: the shares of the three sleepers under an axle (6.3.6.1, Figure 6.4)
SLEEPER_SHARES = (0.25, 0.5, 0.25)
#: the ballast's spread, vertical to longitudinal (6.3.6.2, Figure 6.5)
BALLAST_SLOPE = 4.0


@dataclass(frozen=True)
class LoadDistribution:
    """The longitudinal distribution of an axle load: ``sleeper_spacing`` a [m], ``sleeper_width`` b [m]
    (the sleeper's bearing width along the track), ``ballast_depth`` h [m] under the sleeper (0: the
    sleeper's share on the deck over its width, as on a slab); ``points`` Gauss points per patch."""

    sleeper_spacing: float
    sleeper_width: float
    ballast_depth: float
    points: int = 4

    def __post_init__(self) -> None:
        where = "LoadDistribution"
        if not (np.isfinite(self.sleeper_spacing) and 0.0 < self.sleeper_spacing <= 5.0):
            raise SettingError(where, "sleeper_spacing", self.sleeper_spacing, "a spacing > 0 and <= 5 m")
        if not (np.isfinite(self.sleeper_width) and 0.0 <= self.sleeper_width <= 2.0):
            raise SettingError(where, "sleeper_width", self.sleeper_width, "a width >= 0 and <= 2 m")
        if not (np.isfinite(self.ballast_depth) and 0.0 <= self.ballast_depth <= 3.0):
            raise SettingError(where, "ballast_depth", self.ballast_depth, "a depth >= 0 and <= 3 m")
        if not (isinstance(self.points, int) and 1 <= self.points <= 32):
            raise SettingError(where, "points", self.points, "an integer 1 ... 32")

    @classmethod
    def from_structure(cls, structure, points: int = 4) -> "LoadDistribution":  # noqa: ANN001
        """The distribution of a ballasted track structure (tb_exudyn.scenario.track_structure): its
        spacing, its sleeper's width and its ballast's depth."""
        if structure.kind != "ballasted":
            raise SettingError(f"track structure {structure.name!r}", "kind", structure.kind,
                               "a ballasted track (EN 1991-2 6.3.6.2 spreads through ballast)")
        return cls(structure.spacing, structure.sleeper.width, structure.ballast.thickness, points)

    @property
    def patch_length(self) -> float:
        """The length of each sleeper's patch on the deck, b + 2 h / 4 [m]."""
        return self.sleeper_width + 2.0 * self.ballast_depth / BALLAST_SLOPE


def axle_patches(d: LoadDistribution) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(centres, lengths, shares) of the three patches of an axle at 0: centres -a, 0, a [m] (x along the
    track), lengths b + h / 2 [m] (0: a point load), shares 1/4, 1/2, 1/4."""
    a = d.sleeper_spacing
    return np.array([-a, 0.0, a]), np.full(3, d.patch_length), np.array(SLEEPER_SHARES)


def spread_points(d: LoadDistribution) -> tuple[np.ndarray, np.ndarray]:
    """(offsets, weights): point loads that stand for one axle's patches, offsets [m] from the axle,
    weights adding up to 1 (each patch's share times its Gauss-Legendre weights over the patch)."""
    centres, lengths, shares = axle_patches(d)
    if d.patch_length == 0.0:
        return centres, shares
    xi, wi = np.polynomial.legendre.leggauss(d.points)
    offsets = (centres[:, None] + 0.5 * lengths[:, None] * xi[None, :]).ravel()
    weights = (shares[:, None] * 0.5 * wi[None, :]).ravel()
    return offsets, weights


def distributed_train(train, d: LoadDistribution):  # noqa: ANN001, ANN201
    """A ForceTrain (tb_exudyn.codes.trains) whose point loads are ``train``'s axles spread by ``d``: each
    axle's load at its ``spread_points``, positions from the first point (the train starts that much
    earlier, which moves no peak of a passage)."""
    offsets, weights = spread_points(d)
    x = (np.asarray(train.positions)[:, None] + offsets[None, :]).ravel()
    p = (np.asarray(train.loads)[:, None] * weights[None, :]).ravel()
    order = np.argsort(x, kind="stable")
    x, p = x[order] - x[order][0], p[order]
    return type(train)(name=train.name, positions=x, loads=p, regular_length=train.regular_length,
                       description=train.description, source=train.source, vehicles=train.vehicles,
                       parts=train.parts)


__all__ = ["BALLAST_SLOPE", "LoadDistribution", "SLEEPER_SHARES", "axle_patches", "distributed_train",
           "spread_points"]
