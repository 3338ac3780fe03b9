"""Exudyn's generalized-alpha step, reproduced for the linear engines (batched, dense).

Generalized-alpha as Exudyn does it (``CSolverImplicitSecondOrderTimeInt``, Arnold & Bruls'
algorithm 1; docs/RST/ImplicitTrapezoidalRulebasedNewmarkAndGeneralizedalphaSolver.rst): with
spectral radius rho, alpha_m = (2 rho - 1) / (rho + 1), alpha_f = rho / (rho + 1),
gamma = 1/2 + alpha_f - alpha_m, beta = (gamma + 1/2)^2 / 4, a step of size h from (q, v, qdd, a)
predicts

    a~ = (alpha_f qdd - alpha_m a) / (1 - alpha_m)
    q~ = q + h v + h^2 (1/2 - beta) a + h^2 beta a~,    v~ = v + h (1 - gamma) a + h gamma a~

and Newton solves M qdd + f(q, v, t_{n+1}) = 0 for the increment Delta of q = q~ + Delta,
v = v~ + gamma' Delta, qdd = beta' Delta, with beta' = (1 - alpha_m) / (h^2 beta (1 - alpha_f)) and
gamma' = gamma / (h beta); then a = a~ + (1 - alpha_f) / (1 - alpha_m) qdd. The model being
linear, the batched engine solves that equation exactly (Exudyn to its Newton tolerance). Initial
accelerations from M qdd0 = f(q0, v0, 0) and a0 = qdd0 (Exudyn's computeInitialAccelerations);
the step h = end_time / n_steps and the output grid are the Exudyn engine's.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def spectral_radius_alphas(rho: float) -> tuple[float, float, float, float]:
    """Exudyn's generalized-alpha parameters (alpha_m, alpha_f, gamma, beta) for spectral radius rho
    (CSolverImplicitSecondOrderTimeInt::PreInitializeSolverSpecific)."""
    alpha_m = (2.0 * rho - 1.0) / (rho + 1.0)
    alpha_f = rho / (rho + 1.0)
    gamma = 0.5 + alpha_f - alpha_m
    beta = 0.25 * (gamma + 0.5) ** 2
    return alpha_m, alpha_f, gamma, beta


@dataclass(frozen=True)
class GeneralizedAlpha:
    """Exudyn's generalized-alpha coefficients for spectral radius ``rho`` and step ``h``."""

    rho: float
    h: float
    alpha_m: float = field(init=False)
    alpha_f: float = field(init=False)
    gamma: float = field(init=False)
    beta: float = field(init=False)

    def __post_init__(self) -> None:
        for name, value in zip(("alpha_m", "alpha_f", "gamma", "beta"), spectral_radius_alphas(self.rho)):
            object.__setattr__(self, name, value)

    @property
    def beta_p(self) -> float:
        """d qdd / d Delta = (1 - alpha_m) / (h^2 beta (1 - alpha_f))."""
        return (1.0 - self.alpha_m) / (self.h**2 * self.beta * (1.0 - self.alpha_f))

    @property
    def gamma_p(self) -> float:
        """d v / d Delta = gamma / (h beta)."""
        return self.gamma / (self.h * self.beta)

    def first_predictor(self, qdd0: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(q~, v~, a~) of the first step from rest with accelerations qdd0 (a0 = qdd0)."""
        h, g, b, am, af = self.h, self.gamma, self.beta, self.alpha_m, self.alpha_f
        ap = (af - am) / (1.0 - am) * qdd0
        return h * h * (0.5 - b) * qdd0 + h * h * b * ap, h * (1.0 - g) * qdd0 + h * g * ap, ap

    def update_coefficients(self) -> tuple[float, float, float, float, float, float]:
        """(nu_a, nu_d, rho_a, rho_d, mu_a, mu_d) of the corrector fused with the next predictor:
        q~' = q~ + h v~ + nu_a a~ + nu_d D,  v~' = v~ + rho_a a~ + rho_d D,  a~' = mu_a a~ + mu_d D."""
        h, g, b, am, af = self.h, self.gamma, self.beta, self.alpha_m, self.alpha_f
        bp, gp = self.beta_p, self.gamma_p
        c1 = (1.0 - af) / (1.0 - am)
        mu_a = -am / (1.0 - am)
        mu_d = bp * (af - am * c1) / (1.0 - am)
        return (h * h * (0.5 - b) + h * h * b * mu_a, 1.0 + h * gp + h * h * (0.5 - b) * c1 * bp + h * h * b * mu_d,
                h * (1.0 - g) + h * g * mu_a, gp + h * (1.0 - g) * c1 * bp + h * g * mu_d, mu_a, mu_d)


__all__ = ["GeneralizedAlpha", "spectral_radius_alphas"]
