"""What a result is: declared once per kind, asked by every reader instead of the name of its method.

A result records the method that made it (``RandomResponse.method``: "pem", "monte_carlo",
"monte_carlo_linear", saved in meta.json); its :class:`ResultKind` (``result.kind``; a TimeHistory's is
:data:`DETERMINISTIC`) says what a reader may do with it:

- ``random``: statistics over the track irregularity (else one deterministic run: no probability);
- ``gaussian``: a Gaussian process of the pseudo-excitation method (PSDs, Rice's rate, first passage and
  exceedance levels in closed form, Sperling from the expected energy);
- ``sampled``: Monte Carlo samples (empirical statistics with intervals, sample extremes);
- ``linear_samples``: samples of the linear model (the batched or dense engine), not of the full model;
- ``folder``: its result folder in an output folder; ``label``: its name in the report and figures;
  ``mean``: what its mean is.

Only tb_exudyn/methods/ names its methods; tests/architecture/test_result_kinds.py checks that no other
module compares a result's method string.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ResultKind:
    """What a result of one method is (the module docstring)."""

    method: str
    random: bool
    gaussian: bool
    sampled: bool
    linear_samples: bool
    folder: str
    label: str
    mean: str

    def __str__(self) -> str:
        return self.method


PEM = ResultKind("pem", True, True, False, False, "pem", "PEM", "the deterministic run with gravity, no irregularity")
MONTE_CARLO = ResultKind("monte_carlo", True, False, True, False, "mc", "Monte Carlo", "sample mean")
MONTE_CARLO_LINEAR = ResultKind("monte_carlo_linear", True, False, True, True, "mc_linear",
                                "Monte Carlo of the linear model", "sample mean")
DETERMINISTIC = ResultKind("deterministic", False, False, False, False, "det", "deterministic run",
                           "the run's values")
#: the kinds of a RandomResponse, by the method it records
RANDOM_KINDS: dict[str, ResultKind] = {k.method: k for k in (PEM, MONTE_CARLO, MONTE_CARLO_LINEAR)}


__all__ = ["DETERMINISTIC", "MONTE_CARLO", "MONTE_CARLO_LINEAR", "PEM", "RANDOM_KINDS", "ResultKind"]
