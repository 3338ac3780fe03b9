"""The batched engine: every column of a task in one time integration of the linear model.

The train-bridge model is linear and every column shares its time-varying matrices; only the input
differs. So all columns of a task (PEM: one complex column per irregularity type and frequency, the
real part the cosine run and the imaginary part the sine run; Monte Carlo: two real samples per
complex column) are integrated together, with exactly Exudyn's generalized-alpha step
(:mod:`tb_exudyn.engines.alpha`), on the very model the Exudyn runs use: M, K0, D0 from Exudyn's
``ComputeLinearizedSystem`` and the rows of the ``WheelRailCoupling`` (penalty rows and general
linear rows, :class:`~tb_exudyn.system.coupling.RowMaps`). The model being linear, each step is
solved exactly (Exudyn to its Newton tolerance). Initial accelerations from M qdd0 = f(q0, v0, 0)
and a0 = qdd0 (Exudyn's computeInitialAccelerations); the step h = end_time / n_steps and the
output grid are the Exudyn engine's (:func:`~tb_exudyn.system.conventions.run_steps`).

What makes it fast:

- the contact forces by Woodbury over the contact rows of the vehicles with an axle on the bridge;
  vehicles off the bridge advance by a constant folded operator (:mod:`.run`);
- the time-only data of a step (axle positions, taper, rail shapes) and the bridge parts of the
  per-step operators computed for blocks of steps at once (:mod:`.steps`, :meth:`.run._Run.prepare`);
- independent components (e.g. the vertical in-plane and lateral out-of-plane motion of a symmetric
  car on a symmetric track) each integrate only the columns that excite them, and coordinates no
  input reaches are not integrated at all (:mod:`tb_exudyn.system.components`);
- complex columns computed on their real view, in-place BLAS (:mod:`.kernels`), in float64 or, as an
  option, float32 (faster: measured in docs/speed.md; see :class:`BatchedOptions` for its error);
- single-threaded BLAS, one process per core, each owning large slices of the columns (tasks);
- outputs reduced at every output step by the method's reducer, never stored as histories, and only
  for the selected channels.

Options (:class:`BatchedOptions`): the precision, and where the mean comes from (Exudyn's
deterministic run, or the same linear model with the gravity load as one more column:
:mod:`.mean`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import CapabilityError, SettingError
from ...execution.threads import single_threaded_blas
from ...system.components import find_components
from ..base import Engine, init_linear, on_linear_system, typed_options
from .kernels import PRECISIONS
from .loop import CHUNK_BYTES, MIN_CHUNK, chunks, integrate
from .mean import linear_mean

#: the linear mean's cost in columns of the sweep: measured on the reference study (2026-12-02, one
#: process) 0.9 s against 6.8 s for 240 columns, i.e. about 32 columns; used only to size the slices
LINEAR_MEAN_COLUMNS = 32.0
#: resident memory of the compiled step in a process (Numba and llvmlite imported, the code loaded
#: from the cache): measured 110 MB (2026-12-03: 82 -> 140 MB on import, -> 250 MB after the first
#: run against 195 MB for the numpy step; quick with 1000 frequencies: peak 197 -> 293 MB)
COMPILED_STEP_BYTES = 100 * 10**6
#: where a linear engine's mean comes from
MEANS: tuple[str, ...] = ("auto", "exudyn", "linear")
#: how a step of harmonic columns is computed (:class:`BatchedOptions`)
STEPS: tuple[str, ...] = ("compiled", "numpy")


@dataclass(frozen=True)
class BatchedOptions:
    """Options of the batched engine.

    Attributes
    ----------
    precision : "float64" (default: the reference) or "float32" (state and products in single
        precision: faster, as measured in docs/speed.md; its sigma within 1e-5 of each channel's
        largest sigma, the PSD map within 2e-3 of its largest value; accelerations of stiff parts
        driven far below their frequency carry about 6e-8 (f_n / f)^2 relative error:
        docs/speed.md, tests/engines/test_batched_kernels.py)
    mean : "linear" (the model linearised about the static state under the dead loads, the gravity
        load integrated like one more column, :mod:`.mean`: no Exudyn run; on the reference study
        within 1.1e-3 of each channel's largest |mean| and 3e-5 of its largest sigma of Exudyn's
        run, what remains being the finite rotations, docs/speed.md; refused where it does not
        apply: a bridge loaded at t = 0, moving point loads), "exudyn" (Exudyn's deterministic run: a
        full-model run that no other core can share, 3-8 s of the reference study) or "auto"
        (default: "linear" where it applies, else "exudyn", the reason in the provenance's
        ``mean_engine``)
    grid_error_precision : the precision of the columns that only feed the a posteriori grid-error
        estimate (PEM's midpoint sweep, :mod:`tb_exudyn.methods.grid_error`): "float32" (default:
        on the reference study the refined sigma within 1.1e-5 of each channel's largest sigma of
        the float64 sweep, three orders below the 1 % the estimate is read against, and the midpoint
        sweep 17 % faster: docs/speed.md) or "float64"
    step : how a step of harmonic (PEM) columns is computed: "compiled" (default: a block of steps per
        call of a Numba function, :mod:`.compiled`, making the numpy step's BLAS calls in its order:
        the same numbers to round-off, docs/speed.md) or "numpy" (a Python call per product; no
        Numba import). Monte Carlo samples and the linear mean always take the numpy step.
    """

    precision: str = "float64"
    mean: str = "auto"
    grid_error_precision: str = "float32"
    step: str = "compiled"

    def __post_init__(self) -> None:
        if self.precision not in PRECISIONS:
            raise SettingError("BatchedOptions", "precision", self.precision, " or ".join(map(repr, PRECISIONS)))
        if self.mean not in MEANS:
            raise SettingError("BatchedOptions", "mean", self.mean, " or ".join(map(repr, MEANS)))
        if self.step not in STEPS:
            raise SettingError("BatchedOptions", "step", self.step, " or ".join(map(repr, STEPS)))
        if self.grid_error_precision not in PRECISIONS:
            raise SettingError("BatchedOptions", "grid_error_precision", self.grid_error_precision,
                               " or ".join(map(repr, PRECISIONS)))


class BatchedEngine(Engine):
    """The linear model's columns integrated together (options: :class:`BatchedOptions`)."""

    name = "batched"
    full_model = False
    linear_rows = True  # general linear rows (creep) through the coupling's RowMaps
    options_type = BatchedOptions

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False, system: Any = None) -> None:
        with single_threaded_blas():
            super().__init__(scenario, options, wheel_forces, system)
            self.options = _options(options)
            init_linear(self)
            self.components = find_components(self.lin, self.output_time)

    @classmethod
    def on_system(cls, lin: Any, steps: Any, spectral_radius: float, outputs: Any, options: Any = None) -> "BatchedEngine":
        """The engine on a linear system built by hand (:func:`~tb_exudyn.engines.base.on_linear_system`)."""
        engine = on_linear_system(cls, lin, steps, spectral_radius, outputs, _options(options))
        engine.components = find_components(lin, engine.output_time)
        return engine


    @classmethod
    def default_options(cls) -> BatchedOptions:
        return BatchedOptions()

    @classmethod
    def describe_options(cls, options: Any) -> dict[str, Any]:
        opts = _options(options)
        return {"precision": opts.precision, "mean": opts.mean, "grid_error_precision": opts.grid_error_precision,
                "step": opts.step}

    @classmethod
    def linear_mean(cls, options: Any) -> bool:
        """Whether the mean may be the linear model's (the parent then builds its inputs once)."""
        return _options(options).mean in ("linear", "auto")

    @classmethod
    def compiled_precisions(cls, options: Any, harmonic: bool = True) -> tuple[str, ...]:
        """The precisions a run compiles code for (:mod:`tb_exudyn.methods.warm_up` compiles them ahead):
        with the compiled step, PEM's (``harmonic``) float64 columns and float32 grid-error columns,
        else (Monte Carlo) only the float64 linear mean's; none with the numpy step."""
        opts = _options(options)
        if opts.step != "compiled":
            return ()
        if harmonic:
            return tuple(dict.fromkeys(("float64", opts.precision, opts.grid_error_precision)))
        return ("float64",) if opts.mean in ("linear", "auto") else ()

    @classmethod
    def mean_cost_columns(cls, options: Any) -> float | None:
        """The linear mean (static state, its linear system and components, one column): about
        LINEAR_MEAN_COLUMNS columns; Exudyn's run: not known."""
        return LINEAR_MEAN_COLUMNS if _options(options).mean in ("linear", "auto") else None

    def code_bytes(self, harmonic: bool) -> int:
        """The compiled step's memory in a worker integrating with it (harmonic columns; without
        ``harmonic``, a Monte Carlo run's mean task, the linear mean's gravity column): Numba, llvmlite
        and the loaded code, COMPILED_STEP_BYTES."""
        if self.options.step != "compiled":
            return 0
        return COMPILED_STEP_BYTES if harmonic or self.options.mean in ("linear", "auto") else 0

    @property
    def precision(self) -> str:
        return self.options.precision

    def describe(self) -> dict[str, Any]:
        ga = self.alpha
        return {
            "engine": self.name,
            "linearization": self.lin.linearization,
            "precision": self.precision,
            "grid_error_precision": self.options.grid_error_precision,
            "step": self.options.step,
            "generalized_alpha": {"spectral_radius": ga.rho, "alpha_m": ga.alpha_m, "alpha_f": ga.alpha_f,
                                  "gamma": ga.gamma, "beta": ga.beta, "time_step_s": ga.h, "steps": self.n_steps},
            "components": [{"coordinates": c.size, "bridge_modes": c.n_bridge, "contacts": int(c.rows.size),
                            "kinds": [("vertical", "alignment", "cross_level")[k] for k in c.kinds],
                            **({"coupled_bridge": True} if c.coupled else {})}  # a track's block: numpy step
                           for c in self.components],
            "coordinates": self.lin.n,
        }

    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        with single_threaded_blas():
            return integrate(self, source, reducer, step=self.options.step)

    def integrate_estimate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        """:meth:`integrate` in ``options.grid_error_precision`` (columns that only feed an estimate)."""
        with single_threaded_blas():
            return integrate(self, source, reducer, precision=self.options.grid_error_precision, step=self.options.step)

    def mean(self) -> dict[str, np.ndarray]:
        if self._mean is not None:
            return self._mean
        if self.options.mean in ("linear", "auto"):
            try:
                with single_threaded_blas():
                    return linear_mean(self)
            except CapabilityError as exc:
                if self.options.mean == "linear":
                    raise
                reason = exc.reason
        else:
            return super().mean()
        out = super().mean()  # "auto" where the linear mean does not apply
        prov = json.loads(str(out["provenance"]))
        prov["mean_engine"] = f"exudyn (the linear mean does not apply: {reason})"
        out["provenance"] = np.array(json.dumps(prov))
        return out


def _options(options: Any) -> BatchedOptions:
    return typed_options(options, BatchedOptions)


__all__ = ["BatchedEngine", "BatchedOptions", "CHUNK_BYTES", "MEANS", "STEPS", "MIN_CHUNK", "chunks", "integrate"]
