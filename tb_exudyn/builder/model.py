"""Build a scenario into an Exudyn system: the train-bridge model, built once, excited many times.

The model: the bridge as one modal body (mass-normalised modes: M = I, K = diag w^2,
D = diag 2 zeta w), the vehicles as rigid bodies and spring-dampers in a frame moving with the
train (:mod:`.vehicles`), and ONE ObjectGenericODE2 over the bridge's modal node and all wheel
nodes whose force and Jacobian user functions call the plain-numpy :class:`WheelRailCoupling`
(:mod:`.coupling`). Off the bridge the rail is rigid.

A built model is re-run without rebuilding: :meth:`TrainBridgeModel.set_excitation` swaps the
irregularity input (data the coupling reads), :meth:`TrainBridgeModel.set_gravity` switches the
dead loads, :meth:`TrainBridgeModel.reset` sets the initial state (static equilibrium on the
approach track, or rest).
"""

from __future__ import annotations

import math
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, replace
from typing import Iterator, Literal

import exudyn as exu
import numpy as np
import scipy.sparse as sp
from exudyn import itemInterface as ei
from numpy.typing import NDArray

from ..errors import CapabilityError
from ..execution.resources import check_system_size
from ..scenario.errors import ScenarioError
from ..scenario.model import Scenario, SimpleBeam
from ..scenario.sections import track_lines
from ..scenario.track_structure import refuse_unbuilt_track
from ..structure import StructureError, located, modal_bridge
from ..structure.modal import ModalBridge, simply_supported_modes
from ..system import channels as chan
from ..system import derived as dch
from ..system.conventions import scenario_steps
from .bridge_body import add_modal_bridge_body
from ..system.coupling import WheelRailCoupling
from ..system.excitation import Excitation, as_excitation
from ..system.track_bridge import TrackBridge, scenario_extent, scenario_track, track_channels, track_forces
from .vehicles import VEHICLE_BUILDERS, TrainParts

#: fewest time steps per period of the stiffest contact mode before a warning
CONTACT_STEPS_PER_PERIOD = 4.0
#: linearisations a model keeps (:meth:`TrainBridgeModel.linearized_system`: about rest and the static state)
LINEARIZED_KEPT = 2
#: fewest time steps on the approach track before the first axle reaches the bridge (else: error)
MIN_LEAD_IN_STEPS = 10


# ============================================================================================
# bridge


def bridge_modes(scenario: Scenario) -> ModalBridge:
    """The scenario's bridge as a modal model from the finite-element model
    (:func:`tb_exudyn.structure.modal_bridge`): modes up to ``analysis.mode_max_frequency``, at most
    ``analysis.max_modes`` (0: no limit)."""

    an = scenario.analysis
    try:
        return modal_bridge(scenario.bridge, an.mode_max_frequency, an.max_modes)
    except StructureError as exc:  # named in the scenario's (or the bridge's) file
        raise located(exc, scenario) from None


def closed_form_modes(bridge: SimpleBeam, max_frequency: float, max_modes: int = 0) -> ModalBridge:
    """Closed-form modes of a :class:`SimpleBeam` (EI_vertical = E I_y, EI_lateral = E I_z, GJ = G J):
    the FE model's independent check, and a cheap bridge for benchmarks (``build_model(modal_bridge=...)``)."""
    gd = bridge.sections  # one per span
    return simply_supported_modes(
        bridge.spans, EI_vertical=[g.E * g.I_y for g in gd], EI_lateral=[g.E * g.I_z for g in gd],
        GJ=[g.G * g.J for g in gd], mass_per_length=[g.mass_per_length for g in gd],
        rot_mass_per_length=[g.rot_mass_per_length for g in gd],
        damping_ratio=bridge.damping_ratio, max_frequency=max_frequency,
        max_modes=max_modes, tracks=track_lines(bridge),
    )


def _sparse_zero(n: int) -> exu.MatrixContainer:
    """An n x n all-zero matrix in sparse form (the coupling object has no mass of its own; a
    dense zero matrix made every residual evaluation multiply it, 30 % of the run time)."""
    mc = exu.MatrixContainer()
    mc.SetWithSparseMatrix(sp.csr_matrix((n, n)))
    return mc


# ============================================================================================
# checks



def _round_up(x: float, digits: int = 3) -> float:
    """x rounded up to ``digits`` significant digits: a bound a warning asks for ("use ... >= X") that
    the rounded value still meets."""
    if not (math.isfinite(x) and x > 0):
        return x
    scale = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return math.ceil(x / scale - 1e-9) * scale


def _dividing_step(bound: float, output_step: float) -> float:
    """The largest time step <= ``bound`` that divides ``output_step`` into a round number of steps (2^a 5^b:
    10, 16, 20, 25, ...), so that the step a warning asks for ("use analysis.time_step <= X") is one the
    scenario takes as given (analysis.output_step must be a whole multiple of it)."""
    if not (math.isfinite(bound) and bound > 0):
        return bound
    counts = sorted(2 ** a * 5 ** b for a in range(40) for b in range(18) if 2 ** a * 5 ** b <= 10 ** 12)
    return next((output_step / n for n in counts if output_step / n <= bound), bound)


def scenario_checks(scenario: Scenario, contact_frequencies: list[float], vehicle_frequencies: list[float]) -> list[str]:
    """Warnings about a scenario's resolution; raises ValueError for a scenario that cannot run.

    Errors: the first axle reaches the bridge within ``MIN_LEAD_IN_STEPS`` time steps (no
    approach track to start on). Warnings: the approach is shorter than one period of the
    slowest vehicle mode (a run started at rest, as pseudo-excitation and Monte Carlo runs are,
    has not settled when it reaches the bridge); the time step gives fewer than
    ``CONTACT_STEPS_PER_PERIOD`` steps per period of the stiffest wheel-rail contact mode
    (sqrt(k_contact / wheel mass) / 2 pi); or fewer than 10 per period of the analysed band's
    upper frequency (``analysis.freq_max``).
    """
    an, v = scenario.analysis, scenario.speed
    dt = an.time_step
    out: list[str] = []
    t_in = scenario.track.lead_in / v
    if t_in < MIN_LEAD_IN_STEPS * dt:
        raise ScenarioError(
            scenario.where, "track.lead_in", scenario.track.lead_in,
            f">= {v / min(vehicle_frequencies or [1.0]):.3g} m (the slowest vehicle mode's period; at least "
            f"{MIN_LEAD_IN_STEPS * dt * v:.3g} m)",
            f"no approach track to settle (bridge at {t_in:.3g} s)",
        )
    if scenario.track.irregularities and scenario.track.taper_length > scenario.track.lead_in:
        out.append(
            f"track.taper_length = {scenario.track.taper_length:g} m is longer than track.lead_in = "
            f"{scenario.track.lead_in:g} m: the irregularity is still rising when the first axle reaches the bridge"
        )
    if vehicle_frequencies:
        f_min = min(vehicle_frequencies)
        if t_in * f_min < 1.0:
            out.append(
                f"track.lead_in = {scenario.track.lead_in:g} m: the first axle reaches the bridge after "
                f"{t_in:.3g} s, less than one period ({1 / f_min:.3g} s) of the slowest vehicle mode "
                f"({f_min:.3g} Hz); runs that start at rest (pseudo-excitation, Monte Carlo) have not "
                f"settled on the approach: use track.lead_in >= {_round_up(v / f_min):g} m"
            )
    if contact_frequencies:
        f_c = max(contact_frequencies)
        if f_c * dt * CONTACT_STEPS_PER_PERIOD > 1.0:
            out.append(
                f"analysis.time_step = {dt:g} s resolves the wheel-rail contact mode "
                f"(sqrt(k_contact / wheel mass) / 2 pi = {f_c:.4g} Hz) with only {1 / (f_c * dt):.2g} steps "
                f"per period (< {CONTACT_STEPS_PER_PERIOD:g}): use analysis.time_step <= "
                f"{_dividing_step(1 / (CONTACT_STEPS_PER_PERIOD * f_c), an.output_step):.12g} s or a smaller contact "
                "stiffness"
            )
    if an.freq_max * dt * 10.0 > 1.0 + 1e-12:
        out.append(
            f"analysis.time_step = {dt:g} s gives fewer than 10 steps per period at the band's upper "
            f"frequency freq_max = {an.freq_max:g} Hz"
        )
    return out


# ============================================================================================
# the model


@dataclass(frozen=True)
class NodeRecord:
    """The sensors recording one node (displacement, velocity, acceleration)."""

    node: int
    sensors: tuple[int, int, int]


class TrainBridgeModel:
    """A scenario built into an Exudyn system (build with :func:`build_model`).

    Attributes
    ----------
    scenario, bridge : the scenario and its modal bridge
    mbs : the Exudyn MainSystem (its SystemContainer is kept alive by the model)
    coupling : the wheel-rail coupling (plain numpy; also usable by other integrators)
    channels : every channel of the model; ``selected``: those matching analysis.channels
    derived_catalogue : the derived channels the model can give (tb_exudyn.system.derived);
        ``derived``: those matching analysis.channels
    warnings : scenario warnings found while building
    """

    def __init__(self, scenario: Scenario, bridge: ModalBridge, track: TrackBridge | None = None) -> None:
        self.scenario = scenario
        self.bridge = bridge
        #: the track between wheel and deck (track.structure), whose modes ``bridge`` holds with the deck's
        self.track = track
        self.system_container = exu.SystemContainer()
        self.mbs = self.system_container.AddSystem()
        self.gravity_on = True
        self.warnings: list[str] = []
        self._build()

    # ------------------------------------------------------------------ building
    def _build(self) -> None:
        sc, mbs = self.scenario, self.mbs
        an = sc.analysis
        ground_node = mbs.AddNode(ei.NodePointGround(visualization=ei.VNodePointGround(show=False)))
        ground_marker = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0))
        self.bridge_body = add_modal_bridge_body(mbs, self.bridge, variant="generic")
        self.bridge_node = int(self.bridge_body.node)
        parts = TrainParts(
            ground_marker=ground_marker, gravity=an.gravity, contact_damping_ratio=an.contact_damping_ratio,
            half_gauge=sc.track.half_gauge, contact_stiffness_z=an.contact_stiffness_z,
            contact_stiffness_y=an.contact_stiffness_y, speed=sc.speed,
        )
        axle_offsets = np.asarray(sc.train.axle_positions, dtype=float)
        axle = 0
        for k, veh in enumerate(sc.train.vehicles):
            if veh.kind not in VEHICLE_BUILDERS:
                raise CapabilityError("build_model", f"train.vehicles[{k}]", veh.name,
                                      " or ".join(VEHICLE_BUILDERS), f"the {veh.kind} kind is not built yet")
            VEHICLE_BUILDERS[veh.kind](mbs, parts, veh, f"car{k + 1}", axle, -axle_offsets[axle])
            axle += len(veh.axle_offsets)
        self.parts = parts
        self.warnings = scenario_checks(sc, parts.contact_frequencies, parts.vehicle_frequencies)
        self._add_coupling(axle_offsets)
        self._add_sensors()
        self.channels = chan.catalogue(
            self.bridge.station_names,
            [(b.name, b.node, b.components) for b in parts.bodies],
            self.contact_names, parts.load_names,
        )
        if self.track is not None:  # the track's channels after the deck's
            n_deck = sum(c.name.startswith("bridge.") for c in self.channels)
            self.channels[n_deck:n_deck] = track_channels(self.track, len(self.bridge.station_names))
            self.channels = chan.catalogue_order(self.channels + chan.rail_channels(
                self.contact_names[:self.coupling.n_contacts], self.coupling.contacts.direction))
        steps = scenario_steps(sc)
        self.derived_catalogue = dch.derived_catalogue(
            self.channels, dch.station_positions(self.bridge.station_names, sc.bridge.spans), self.bridge,
            sc.track.half_gauge, steps.n_outputs * steps.h * steps.ratio)
        if self.track is not None:
            self.derived_catalogue = replace(self.derived_catalogue,
                                             channels=self.derived_catalogue.channels + tuple(track_forces(self.track)))
        self.selected, self.derived = dch.select_channels(self.channels, self.derived_catalogue, an.channels, sc.where)
        #: the station shapes extended by the derived channels' auxiliary rows (what outputs index)
        self.output_shapes = dch.extended_shapes(self.bridge.station_shapes, self.derived_catalogue)
        mbs.Assemble()
        self.n_ode2 = mbs.systemData.ODE2Size()
        self._static_cache: dict[tuple[float, bool], NDArray[np.float64]] = {}
        self._linearized: dict[tuple[float, bytes], tuple[NDArray[np.float64], ...]] = {}

    def _add_coupling(self, axle_offsets: NDArray[np.float64]) -> None:
        """The wheel-rail coupling: ONE ObjectGenericODE2 over [bridge node, wheel nodes] whose
        user functions call the numpy coupling (forces of all wheels at once, analytic Jacobian)."""
        sc, mbs, parts = self.scenario, self.mbs, self.parts
        offsets, n_w = {}, 0
        for node, n_coords in parts.wheel_nodes:
            offsets[node] = n_w
            n_w += n_coords
        layout = parts.contacts.layout(offsets, n_w)
        if self.track is not None:  # the track's modes left out: their static flexibility in series at each contact
            layout = self.track.series_contacts(layout)
        axle_start = -sc.track.lead_in - axle_offsets
        self.coupling = WheelRailCoupling(
            self.bridge, axle_start, sc.speed, layout, parts.load_axle, parts.load_force,
            half_gauge=sc.track.half_gauge, taper_length=sc.track.taper_length,
        )
        self.contact_names = tuple(parts.contacts.all_names)
        coupling = self.coupling

        def force_uf(mbs_, t, item, q, q_t):  # noqa: ANN001 - Exudyn's signature
            return coupling.forces(t, np.asarray(q), np.asarray(q_t))

        def jacobian_uf(mbs_, t, item, q, q_t, f_q, f_qt):  # noqa: ANN001
            K, D = coupling.jacobians(t)
            return f_q * K + f_qt * D

        self._user_functions = (force_uf, jacobian_uf)  # keep alive
        self.coupling_object = mbs.AddObject(ei.ObjectGenericODE2(
            nodeNumbers=[self.bridge_node] + [n for n, _ in parts.wheel_nodes],
            massMatrix=_sparse_zero(coupling.n),
            forceUserFunction=force_uf, jacobianUserFunction=jacobian_uf,
            visualization=ei.VObjectGenericODE2(show=False)))

    def _add_sensors(self) -> None:
        """Displacement, velocity and acceleration sensors (stored internally, written at the
        output step) on the bridge's modal node and every vehicle node."""
        mbs, parts = self.mbs, self.parts
        nodes = [self.bridge_node] + [b.node for b in parts.bodies]
        nodes += [n for n, _ in parts.wheel_nodes if n not in nodes]
        self.records: dict[int, NodeRecord] = {}
        kinds = (exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t,
                 exu.OutputVariableType.Coordinates_tt)
        for node in nodes:
            sensors = tuple(
                mbs.AddSensor(ei.SensorNode(nodeNumber=node, storeInternal=True, writeToFile=False,
                                            outputVariableType=kind, visualization=ei.VSensorNode(show=False)))
                for kind in kinds
            )
            self.records[node] = NodeRecord(node, sensors)  # type: ignore[arg-type]

    # ------------------------------------------------------------------ excitation, loads
    def set_excitation(self, excitation: Excitation | None) -> None:
        """Use a new irregularity input from the next run on (no rebuild)."""
        new = as_excitation(excitation)
        if new == self.coupling.excitation:
            return
        self.coupling.set_excitation(new)
        self._static_cache.clear()

    @property
    def excitation(self) -> Excitation:
        return self.coupling.excitation

    def set_gravity(self, on: bool) -> None:
        """Switch the dead loads (gravity on every body and the moving point loads)."""
        self.gravity_on = bool(on)
        for load, param, value in self.parts.gravity_loads:
            zero = [0.0, 0.0, 0.0] if isinstance(value, list) else 0.0
            self.mbs.SetLoadParameter(load, param, value if on else zero)
        self.coupling.load_factor = 1.0 if on else 0.0

    # ------------------------------------------------------------------ indices, matrices
    def node_indices(self, node: int) -> NDArray[np.int64]:
        """Global ODE2 indices of a node's coordinates."""
        return np.asarray(self.mbs.systemData.GetNodeLTGODE2(node), dtype=np.int64)

    def coupling_indices(self) -> NDArray[np.int64]:
        """Global ODE2 indices of the coupling's local coordinates u = [q_b; q_w]."""
        return np.asarray(self.mbs.systemData.GetObjectLTGODE2(self.coupling_object), dtype=np.int64)

    def _set_initial(self, q: NDArray[np.float64], qd: NDArray[np.float64]) -> None:
        initial = exu.ConfigurationType.Initial
        self.mbs.systemData.SetODE2Coordinates(q.tolist(), configuration=initial)
        self.mbs.systemData.SetODE2Coordinates_t(qd.tolist(), configuration=initial)
        self.mbs.systemData.SetODE2Coordinates_tt(np.zeros(self.n_ode2).tolist(), configuration=initial)

    def linearized_system(
        self, t: float = 0.0, state: NDArray[np.float64] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """M, K, D of the whole system linearised at the reference configuration (or at the
        displacements ``state``, e.g. ``static_state()``: then K includes the geometric stiffness of
        the forces carried there, the suspensions' preload under gravity), with the train standing
        at its positions of time t (no convective terms). Sets the initial state to rest.

        The last :data:`LINEARIZED_KEPT` results are kept by (t, state) (the set-up's mode table, the
        damping guard, the linear model and the static state ask for the same ones; copies are
        returned). A bridge body with a coupled damping matrix (a track's: Exudyn differentiates its
        object numerically, n^3 for n modes, 40 s at 1736) has its known blocks K = diag(omega^2)
        and D (:meth:`_known_body_blocks`) inserted instead."""
        zero = np.zeros(self.n_ode2)
        q = zero if state is None else np.asarray(state, dtype=float)
        key = (float(t), q.tobytes())
        kept = self._linearized.pop(key, None)
        if kept is None:
            self._set_initial(q, zero)
            with self.coupling.frozen(t), self._known_body_blocks() as blocks:
                M, K, D = (np.asarray(a) for a in self.mbs.ComputeLinearizedSystem(exu.SimulationSettings()))
            if blocks is not None:
                ix, Kb, Db = blocks
                K[np.ix_(ix, ix)] += Kb
                D[np.ix_(ix, ix)] += Db
            kept = (M, K, D)
        self._linearized[key] = kept
        while len(self._linearized) > LINEARIZED_KEPT:
            self._linearized.pop(next(iter(self._linearized)))
        self._set_initial(zero, zero)
        return kept[0].copy(), kept[1].copy(), kept[2].copy()

    @contextmanager
    def _known_body_blocks(self) -> Iterator[tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]] | None]:
        """With a coupled bridge damping (a track's), the bridge body's stiffness and damping matrices
        set to zero inside the block (restored after), yielding (its global indices, diag(omega^2), D),
        the blocks to add to Exudyn's linearisation; else nothing changes and None is yielded (a run
        without a track takes Exudyn's linearisation as before, bitwise)."""
        br = self.bridge
        if br.coupled_damping is None:
            yield None
            return
        obj, n = self.bridge_body.object, br.n_modes
        kept = {p: self.mbs.GetObjectParameter(obj, p) for p in ("stiffnessMatrix", "dampingMatrix")}
        try:
            for p in kept:
                self.mbs.SetObjectParameter(obj, p, _sparse_zero(n))
            yield self.node_indices(self.bridge_node), np.diag(br.omega**2), np.asarray(br.coupled_damping, dtype=float)
        finally:
            for p, value in kept.items():
                self.mbs.SetObjectParameter(obj, p, value)

    def dead_load(self, t: float = 0.0) -> NDArray[np.float64]:
        """Generalised static load vector: gravity (if on), point loads and the irregularity
        input of the train standing at its positions of time t."""
        F = np.zeros(self.n_ode2)
        if self.gravity_on:
            for node, coord, w in self.parts.weights:
                F[self.node_indices(node)[coord]] += w
        F[self.coupling_indices()] += self.coupling.static_force(t)
        return F

    def static_state(self, t: float = 0.0) -> NDArray[np.float64]:
        """Static equilibrium (global ODE2 displacements) of the train standing at its positions of
        time t: an exact linear solve K u = F (the suspensions and contacts are linear; the weak
        springs make K regular). Cached until the excitation or gravity changes."""
        key = (float(t), self.gravity_on)
        if key not in self._static_cache:
            _, K, _ = self.linearized_system(t)
            self._static_cache[key] = np.linalg.solve(K, self.dead_load(t))
        return self._static_cache[key].copy()

    def reset(self, initial: Literal["static", "rest"] = "static") -> None:
        """Initial state of the next run.

        "static": static equilibrium of the train standing on the approach track at its t = 0
        positions under the dead loads (if on) and the irregularity there, with the wheels moving
        with the rail (their velocities follow the input rate at t = 0, so the stiff contact starts
        without a jolt); the bridge, which no wheel is on, unloaded at rest. "rest": every
        coordinate and velocity zero.
        """
        zero = np.zeros(self.n_ode2)
        if initial == "static":
            self._set_initial(self.static_state(0.0), self._rail_following_velocities())
        elif initial == "rest":
            self._set_initial(zero, zero)
        else:
            raise ValueError(f"initial must be 'static' or 'rest', got {initial!r}")

    def _rail_following_velocities(self) -> NDArray[np.float64]:
        """Velocities with every wheel moving as the rail input at t = 0 (zero gap rate), least squares."""
        v = np.zeros(self.n_ode2)
        st = self.coupling.contact_state(0.0)
        if self.coupling.n_wheel and np.any(st.r_dot):
            w_dot = np.linalg.lstsq(self.coupling.contacts.wheel_map, st.r_dot, rcond=None)[0]
            v[self.coupling_indices()[self.coupling.n_bridge:]] = w_dot
        return v

    # ------------------------------------------------------------------ outputs
    def recording(self) -> chan.Recording:
        """The sensor data of the last run as a :class:`channels.Recording` (with contact forces)."""
        nodes = {}
        times = None
        for node, rec in self.records.items():
            data = [np.asarray(self.mbs.GetSensorStoredData(s)) for s in rec.sensors]
            if times is None:
                times = data[0][:, 0].copy()
            nodes[node] = tuple(d[:, 1:] for d in data)
        assert times is not None
        nb = self.coupling.n_bridge
        qb, qdb, _ = nodes[self.bridge_node]
        wheel = [nodes[n] for n, _ in self.parts.wheel_nodes]
        if wheel:
            qw = np.hstack([w[0] for w in wheel])
            qdw = np.hstack([w[1] for w in wheel])
        else:
            qw = qdw = np.zeros((times.size, 0))
        forces = self.coupling.contact_force_history(times, qb[:, :nb], qdb[:, :nb], qw, qdw)
        return chan.Recording(times=times, nodes=nodes, bridge_node=self.bridge_node,  # type: ignore[arg-type]
                              contact_forces=forces, load_forces=self.coupling.point_load_history(times))

    def channel_values(self, rec: chan.Recording, patterns: tuple[str, ...] | None = None) -> dict[str, NDArray[np.float64]]:
        """Values of the selected channels (or of those matching ``patterns``)."""
        selected = self.selected if patterns is None else chan.select(self.channels, patterns)
        return chan.evaluate(selected, rec, self.bridge.station_shapes, self.rail_rows)

    def rail_rows(self, t: float) -> NDArray[np.float64]:
        """The rail under each penalty contact at time t, (n_c, n_modes) (the rail channels' rows:
        :func:`~tb_exudyn.system.channels.rail_rows`)."""
        return chan.rail_rows(self.coupling, t)

    def channel_units(self) -> dict[str, str]:
        return {c.name: c.unit for c in self.channels}

    def output_channels(self, wheel_forces: bool = False) -> list[chan.Channel]:
        """What an engine of this model outputs (:func:`tb_exudyn.system.derived.engine_outputs`): the
        selected channels, then the derived channels' inputs and the recorded derivatives, then (with
        ``wheel_forces``) every vertical wheel force; their bridge rows index ``output_shapes``."""
        return dch.engine_outputs(self.selected, self.derived, self.channels, self.derived_catalogue,
                                  wheel_forces=wheel_forces)


def build_model(
    scenario: Scenario,
    excitation: Excitation | None = None,
    *,
    modal_bridge: ModalBridge | None = None,
    warn: bool = True,
) -> TrainBridgeModel:
    """Build a scenario into an Exudyn train-bridge model.

    Parameters
    ----------
    scenario : the scenario (train, bridge, track, speed, analysis settings)
    excitation : irregularity input (None: smooth track); change later with ``set_excitation``
    modal_bridge : use these bridge modes instead of :func:`bridge_modes` (e.g. closed-form modes)
    warn : issue the scenario's warnings with ``warnings.warn``

    Returns
    -------
    TrainBridgeModel, with gravity on and the initial state not yet set (call ``reset``).
    """
    refuse_unbuilt_track(scenario)  # what the track layer does not carry, before any work
    bridge = (modal_bridge if modal_bridge is not None else bridge_modes(scenario)).on_track(scenario.track.on)
    track = None
    if scenario.track.structure:  # the track between wheel and deck: one modal body of the track and the deck
        scenario_extent(scenario)  # its size, before its modes are solved
        track = scenario_track(scenario, bridge)
        bridge = track.bridge
    check_system_size(scenario, bridge.n_modes)  # before the vehicles are built
    model = TrainBridgeModel(scenario, bridge, track)
    if excitation is not None:
        model.set_excitation(excitation)
    if warn:
        for message in model.warnings:
            warnings.warn(message, stacklevel=2)
    return model


def channel_list(scenario: Scenario, modal_bridge: ModalBridge | None = None) -> list[tuple[str, str]]:
    """(name, unit) of every output channel of a scenario's model, in output order (for listings;
    ``analysis.channels`` then selects among them with glob patterns)."""
    model = build_model(scenario, modal_bridge=modal_bridge, warn=False)
    return [(c.name, c.unit) for c in model.channels]
