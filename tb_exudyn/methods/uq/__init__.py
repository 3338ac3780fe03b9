"""Uncertainty studies: non-intrusive polynomial chaos over PEM runs (issue 46).

pce.py: the expansion over node values (germs, nodes, basis, fit, Sobol indices, leave-one-out; pure
functions, chaospy underneath); summary.py: a node's summary and the expansion of every quantity;
method.py: :class:`UqMethod` on the one driver and :func:`run_uq`.
"""

from .method import UqMethod, run_uq

__all__ = ["UqMethod", "run_uq"]
