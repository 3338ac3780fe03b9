"""The engine protocol: what a method asks of an engine, and what every engine shares.

An engine integrates the columns of a column source (:mod:`tb_exudyn.system.columns`: PEM's harmonic
pseudo-excitations, Monte Carlo's sampled profiles) over the crossing and hands the outputs of every
output time to a reducer (the method's: PSD and sigma^2 for PEM, sample moments for Monte Carlo).
An engine instance is built once per worker and then integrates many column blocks. The Exudyn
engine builds the scenario's Exudyn model; a linear engine (batched, dense) receives a
:class:`~.linear_model.LinearModel` built once in the parent from the same model (its linear system,
output map and channels: :func:`~.exudyn_runs.linear_model`) and imports no Exudyn; it builds the
model (:attr:`Engine.model`, loaded by name on first use) only for what only Exudyn gives (its
``mean="exudyn"``). Given no LinearModel (tests, scripts) it makes one itself.

The reducer, the column source and the engine are the protocols of :mod:`.protocols` (``Engine``
implements ``ColumnEngine``).

Capabilities (class attributes) say what an engine can do; :meth:`Engine.check` refuses the rest
with a :class:`~tb_exudyn.errors.CapabilityError` before any run.
"""

from __future__ import annotations

import importlib
import json
import time as _time
from abc import ABC, abstractmethod
from typing import Any, ClassVar

import numpy as np

from ..scenario.model import LINEAR_ROW_KINDS
from ..errors import CapabilityError, SettingError
from ..system.derived_values import derived_values
from ..storage import json_default
from ..system.channels import OutputMap, evaluate, output_map
from ..system.conventions import scenario_steps
from ..system.linear import LINEARIZATIONS
from .alpha import GeneralizedAlpha
from .linear_model import LinearModel

#: the engines' Exudyn side (the model, the Exudyn mean, the LinearModel), loaded by name on first use
EXUDYN_SIDE = "tb_exudyn.engines.exudyn_runs"


def exudyn_side() -> Any:
    """:mod:`tb_exudyn.engines.exudyn_runs` (imports Exudyn): loaded when an engine needs the model."""
    return importlib.import_module(EXUDYN_SIDE)


def typed_options(options: Any, kind: type) -> Any:
    """An engine's options: ``kind()`` for None, the object itself if it is a ``kind``, else a
    SettingError naming the class to use (the linear engines' options dataclasses)."""
    if options is None:
        return kind()
    if not isinstance(options, kind):
        raise SettingError("engine options", "options", type(options).__name__,
                           f"a {kind.__name__} ({kind.__module__}.{kind.__name__}) or None")
    return options


class Engine(ABC):
    """An integrator of column sources on a scenario's model (build one per worker); it implements
    :class:`~.protocols.ColumnEngine`.

    Class attributes (capabilities)
    -------------------------------
    name : the registry name
    full_model : True when the engine integrates the full (nonlinear, rigid-body) Exudyn model, so
        that a sampled profile's response includes gravity and the mean; False for a linear engine,
        whose responses are deviations from the mean (the deterministic run)
    linearizations : the linearization points (``analysis.linearization``) it integrates
    single_columns : True when columns are separate runs (tasks of one column each); False when it
        integrates many columns at once (a few large tasks)
    linear_rows : True when the engine integrates the coupling's general linear rows (the creep
        rows of ``creep_car`` vehicles: :data:`~tb_exudyn.scenario.model.LINEAR_ROW_KINDS`); an
        engine without them would leave the wheelsets' lateral guidance out, so it is refused

    Parameters
    ----------
    scenario : the scenario
    options : engine options (see each engine; None: defaults)
    wheel_forces : also output every vertical wheel-rail force (``*.force_z``) the scenario's
        channels leave out, after the selected channels (Monte Carlo's loss-of-contact check)
    system : a linear engine's :class:`~.linear_model.LinearModel` (built with the same
        ``wheel_forces``; None: made here from the scenario's model)
    """

    name: ClassVar[str]
    full_model: ClassVar[bool]
    linearizations: ClassVar[tuple[str, ...]] = LINEARIZATIONS
    single_columns: ClassVar[bool] = False
    linear_rows: ClassVar[bool] = False
    #: the options dataclass :meth:`check` accepts (None: the engine checks its options itself)
    options_type: ClassVar[type | None] = None

    def code_bytes(self, harmonic: bool) -> int:
        """Memory a worker holds for the engine's compiled code while it integrates (``harmonic``:
        PEM columns) [bytes]; none unless an engine says otherwise."""
        return 0

    def __init__(self, scenario: Any, options: Any = None, wheel_forces: bool = False,
                 system: LinearModel | None = None) -> None:
        self.scenario = scenario
        self.options = options
        self.wheel_forces = wheel_forces
        #: the run's time grid (:func:`~tb_exudyn.system.conventions.run_steps`)
        self.steps = scenario_steps(scenario)
        self._model: Any = None
        self._mean: dict[str, np.ndarray] | None = None
        if self.full_model:
            model = self.model
            #: the outputs (tb_exudyn.system.derived.engine_outputs): the selected channels first, then the
            #: derived channels' inputs and the recorded derivatives, then (``wheel_forces``) the wheel forces
            self.outputs: OutputMap = output_map(model.output_channels(wheel_forces), model.node_indices,
                                                 model.output_shapes)
            self.system = None
            self.selected = tuple((c.name, c.unit) for c in model.selected)
            self.derived = tuple(model.derived)
            self.warnings = tuple(model.warnings)
            self.n_coordinates = int(model.n_ode2)
            return
        if system is None:
            system = exudyn_side().linear_model(self.model, wheel_forces, mean=True)
        self.system = system
        self.outputs = system.outputs
        self.selected, self.derived, self.warnings = system.selected, system.derived, system.warnings
        self.n_coordinates = system.n_coordinates

    @property
    def model(self) -> Any:
        """The scenario's Exudyn model: the Exudyn engine's own; a linear engine's built on first use
        (only for what only Exudyn gives: the Exudyn mean)."""
        if self._model is None:
            self._model = exudyn_side().build_model(self.scenario)
        return self._model

    @property
    def output_channels(self) -> list[Any]:
        """The channels of the outputs (``outputs.names`` order), of the model (what an Exudyn
        recording is evaluated on)."""
        if getattr(self, "_output_channels", None) is None:
            self._output_channels = self.model.output_channels(self.wheel_forces)
        return self._output_channels

    # ------------------------------------------------------------------ capabilities
    @classmethod
    def check(cls, scenario: Any, options: Any = None, others: str = "") -> None:
        """Refuse what the engine cannot do (before any run); ``others`` says which engines can."""
        kinds = sorted({v.kind for v in scenario.train.vehicles} & set(LINEAR_ROW_KINDS))
        if kinds and not cls.linear_rows:
            raise CapabilityError(
                f"engine {cls.name!r}", "train.vehicles", ", ".join(kinds),
                "vehicles without general linear contact rows" + (f"; {others}" if others else ""),
                f"the {cls.name} engine does not integrate the creep rows of {', '.join(kinds)} vehicles",
            )
        if cls.options_type is not None:
            typed_options(options, cls.options_type)
        lin = scenario.analysis.linearization
        if lin not in cls.linearizations:
            raise CapabilityError(
                f"engine {cls.name!r}", "analysis.linearization", lin,
                " or ".join(repr(x) for x in cls.linearizations) + (f"; {others}" if others else ""),
                f"the {cls.name} engine cannot linearise about {lin!r}",
            )

    @classmethod
    def default_options(cls) -> Any:
        return None

    @classmethod
    def describe_options(cls, options: Any) -> dict[str, Any]:
        """The options as plain data (for provenance and checkpoint fingerprints)."""
        return {}

    @classmethod
    def linear_mean(cls, options: Any) -> bool:
        """Whether the mean may be the engine's linear model's (its inputs are then built in the
        parent, :class:`~.linear_model.LinearMeanInputs`); by default not."""
        return False

    @classmethod
    def mean_cost_columns(cls, options: Any) -> float | None:
        """What the mean task costs in columns of the engine's sweep (to size the slices that share a
        worker with it: :func:`tb_exudyn.methods.pem.default_slices`); None: not known (an Exudyn run,
        about half a slice)."""
        return None

    # ------------------------------------------------------------------ outputs
    @property
    def n_selected(self) -> int:
        """Number of the scenario's channels (the first of ``outputs.names``)."""
        return len(self.selected)

    @property
    def fs(self) -> float:
        """Output rate [Hz] (1 / output step)."""
        return 1.0 / (self.steps.h * self.steps.ratio)

    @property
    def force_rows(self) -> np.ndarray:
        """Rows (``outputs.names`` order) of the vertical wheel-rail forces."""
        return np.array([i for i, n in enumerate(self.outputs.names) if n.endswith(".force_z")], dtype=np.int64)

    def channel_values(self, recording: Any) -> np.ndarray:
        """The outputs (``outputs.names`` order) of an Exudyn recording, (n_outputs, n_t)."""
        values = evaluate(self.output_channels, recording, self.model.output_shapes, self.model.rail_rows)
        return np.stack([values[n] for n in self.outputs.names])

    def linear_mean_arrays(self, outputs: np.ndarray, provenance: dict[str, Any], start: float) -> dict[str, np.ndarray]:
        """The arrays of :meth:`mean` from a linear engine's own mean run: ``outputs`` every engine
        output (``outputs.names`` order, (n_outputs, n_t)); the selected channels, then the derived
        channels evaluated on them as on Exudyn's run (:func:`~tb_exudyn.system.derived_values.derived_values`),
        the vertical wheel forces (in the model's channel order, as :meth:`mean` gives them); cached
        as :meth:`mean`'s."""
        om, derived_channels = self.outputs, self.derived
        n_sel = self.n_selected
        names = list(om.names[:n_sel])
        units = list(om.units[:n_sel])
        rows = [outputs[:n_sel]]
        if derived_channels:
            derived = derived_values(derived_channels, dict(zip(om.names, outputs)), self.fs)
            rows.append(np.stack([derived[d.name] for d in derived_channels]))
            names += [d.name for d in derived_channels]
            units += [d.unit for d in derived_channels]
        force_names = self.system.force_channels if self.system is not None else ()
        forces = [om.names.index(name) for name in force_names] if self.wheel_forces else []
        self._mean = {
            "force_mean": outputs[forces] if forces else np.zeros((0, outputs.shape[1])), "outputs": outputs,
            "mean": np.concatenate(rows), "time": self.steps.output_times,
            "names": np.array(names, dtype=str), "units": np.array(units, dtype=str),
            "provenance": np.array(json.dumps(provenance, default=json_default)),
            "warnings": np.array(self.warnings, dtype=str).reshape(-1),
            "seconds": np.array(_time.perf_counter() - start),
        }
        return self._mean

    # ------------------------------------------------------------------ the work
    @abstractmethod
    def integrate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        """Integrate every column of ``source`` over the crossing, handing the outputs of each output
        time to ``reducer.record``; return ``reducer.result()`` and the engine's arrays."""

    def integrate_estimate(self, source: Any, reducer: Any) -> dict[str, np.ndarray]:
        """:meth:`integrate` for columns that only feed an error estimate (PEM's grid-error midpoint
        sweep). An engine may integrate them more cheaply, at an error it states far below the
        estimate's tolerance (the batched engine: ``BatchedOptions.grid_error_precision``); by default
        the same as :meth:`integrate`."""
        return self.integrate(source, reducer)

    def describe(self) -> dict[str, Any]:
        """Provenance of the engine (what it integrated, with which parameters)."""
        return {"engine": self.name}

    def mean(self) -> dict[str, np.ndarray]:
        """The mean: the deterministic run (gravity, static start, no irregularity) on the engine's
        model: Exudyn's here (a linear engine may give its own linear model's instead, with "mean_engine"
        in its provenance: the batched engine's default, :mod:`.batched.mean`), as plain arrays
        (checkpointable): the selected and derived channels' values ("mean"), their names and units,
        the time, every engine output of the run ("outputs", in ``outputs.names`` order: what the
        reducers need to form derived channels about the mean), the vertical wheel forces of the run
        (all of them, selected or not), the run's provenance (JSON) and the scenario's warnings. Run
        once per engine: later calls return the same arrays (a linear Monte Carlo worker needs the
        mean for its samples' extremes and ratios)."""
        if self._mean is None:
            self._mean = exudyn_side().exudyn_mean(self)
        return self._mean


def on_linear_system(cls: type, lin: Any, steps: Any, spectral_radius: float, outputs: OutputMap,
                     options: Any = None) -> Any:
    """An instance of the linear engine class ``cls`` on a linear system built by hand (no scenario,
    no Exudyn model): ``lin`` a :class:`~tb_exudyn.system.linear.LinearSystem`, ``steps`` its
    :class:`~tb_exudyn.system.conventions.RunSteps`, ``outputs`` the channels to integrate. It can
    ``integrate`` column sources (not ``mean``, which needs the model); for tests of the engines on
    small systems and couplings the builder does not make."""
    engine = cls.__new__(cls)
    engine.scenario, engine._model, engine.wheel_forces, engine.system = None, None, False, None
    engine.options, engine.lin, engine.steps, engine.outputs = options, lin, steps, outputs
    engine.selected, engine.derived, engine.warnings, engine.n_coordinates = (), (), (), lin.n
    _time_stepping(engine, steps, spectral_radius)
    return engine


def init_linear(engine: Engine) -> None:
    """What the linear engines (batched, dense) set up from their :class:`~.linear_model.LinearModel`:
    the linear system about ``analysis.linearization`` and the time stepping (:func:`_time_stepping`)."""
    engine.lin = engine.system.lin  # type: ignore[attr-defined]
    _time_stepping(engine, engine.steps, engine.scenario.analysis.spectral_radius)


def _time_stepping(engine: Any, steps: Any, spectral_radius: float) -> None:
    """A linear engine's step count, output ratio, generalised-alpha constants and output times
    from its :class:`~tb_exudyn.system.conventions.RunSteps` (one place for both engines and for
    systems built by hand)."""
    engine.n_steps, engine.ratio = steps.n_steps, steps.ratio
    engine.alpha = GeneralizedAlpha(float(spectral_radius), steps.h)
    engine.output_time = steps.output_times


__all__ = ["EXUDYN_SIDE", "Engine", "exudyn_side", "init_linear", "on_linear_system", "typed_options"]
