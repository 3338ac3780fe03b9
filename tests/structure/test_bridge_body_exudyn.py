"""The Exudyn bridge body: the generic (NodeGenericODE2 + ObjectGenericODE2) and the FFRF
(ObjectFFRFreducedOrder on a fixed reference node) forms of the same modal equations.

References: the modal equations themselves (M = I, K = diag(omega^2), D = diag(2 zeta omega)),
the static modal solution q = f / omega^2 (closed form), and an independent average-acceleration
Newmark recurrence written in the test. The two variants must agree to 1e-6 relative (acceptance);
each against its reference to round-off of the linear solve (1e-9).
"""

from __future__ import annotations

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
import exudyn.itemInterface as ei  # noqa: E402
from exudyn.solver import ComputeLinearizedSystem  # noqa: E402

from tb_exudyn.builder.bridge_body import add_modal_bridge_body, ffrf_terms  # noqa: E402
from tb_exudyn.scenario.model import BeamSection, Bearings, Frame, Pier  # noqa: E402
from tb_exudyn.structure import modal_bridge, simply_supported_modes  # noqa: E402

pytestmark = pytest.mark.exudyn

GIRDER = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.650,
                     mass_per_length=3.39e4, rot_mass_per_length=3.8e5)
PIER = Pier(height=15.0, section=BeamSection(E=3.25e10, G=1.354e10, area=19.0, I_y=13.0, I_z=66.0, J=42.0,
                                             mass_per_length=4.77e4, rot_mass_per_length=2.0e5))
FRAME = Frame(name="exu_frame", spans=(32.0, 32.0), girder=GIRDER, pier=PIER, bearings=Bearings(height=1.5),
              damping_ratio=0.05, elements_per_span=8, elements_per_pier=4, track_offset=2.5, track_height=1.64)
LOADS = {0: 2.0e5, 2: -1.5e5, 4: 3.0e5}  # modal forces on three modes [N (per unit modal coordinate)]
DT, STEPS = 2e-3, 150


@pytest.fixture(scope="module")
def bridge():
    return modal_bridge(FRAME, 30.0, max_modes=6)


def _system(bridge, variant):
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    body = add_modal_bridge_body(mbs, bridge, variant)
    for k, f in LOADS.items():
        marker = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=body.node, coordinate=k))
        mbs.AddLoad(ei.LoadCoordinate(markerNumber=marker, load=f))
    mbs.Assemble()
    return sc, mbs, body


def _settings(newmark: bool = False):
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = STEPS
    ss.timeIntegration.endTime = STEPS * DT
    ss.timeIntegration.verboseMode = 0
    ss.staticSolver.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = DT
    if newmark:
        ss.timeIntegration.generalizedAlpha.useNewmark = True
        ss.timeIntegration.generalizedAlpha.newmarkBeta = 0.25
        ss.timeIntegration.generalizedAlpha.newmarkGamma = 0.5
    return ss


@pytest.mark.parametrize("variant", ["generic", "ffrf"])
def test_linearised_matrices_are_the_modal_ones(bridge, variant):
    """The system's mass, stiffness and damping on the modal coordinates are I, diag(omega^2),
    diag(2 zeta omega) (round-off). For 'ffrf' this shows the FFRF terms are computed: with
    computeFFRFterms=False the mass would be zero (next test)."""
    _, mbs, body = _system(bridge, variant)
    m, k, d = ComputeLinearizedSystem(mbs, _settings())[:3]
    idx = body.ode2_indices(mbs)
    om = bridge.omega
    assert np.allclose(m[np.ix_(idx, idx)], np.eye(bridge.n_modes), rtol=0, atol=1e-12)
    assert np.allclose(k[np.ix_(idx, idx)], np.diag(om**2), rtol=1e-12, atol=1e-9 * om.max() ** 2)
    assert np.allclose(d[np.ix_(idx, idx)], np.diag(2 * 0.05 * om), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("variant", ["generic", "ffrf"])
def test_a_coupled_damping_matrix_is_the_bodys_whole(bridge, variant):
    """A bridge whose damping is not modal (ModalBridge.coupled_damping: a track's pads and ballast,
    docs/track.md 5b): the system's damping on the modal coordinates is that full matrix, in both variants
    (the FFRF body took the diagonal of the modal ratios before). Reference: the matrix given, here
    diag(2 zeta omega) plus a symmetric coupling of every pair of modes (round-off)."""
    from dataclasses import replace

    om = bridge.omega
    coupling = 0.01 * np.sqrt(np.outer(om, om)) * np.cos(np.add.outer(np.arange(om.size), np.arange(om.size)))
    damping = np.diag(2 * 0.05 * om) + coupling
    _, mbs, body = _system(replace(bridge, coupled_damping=damping), variant)
    d = ComputeLinearizedSystem(mbs, _settings())[2]
    idx = body.ode2_indices(mbs)
    assert np.count_nonzero(np.abs(damping - np.diag(np.diag(damping))) > 1e-3) == om.size * (om.size - 1)
    assert np.allclose(d[np.ix_(idx, idx)], damping, rtol=1e-12, atol=1e-12 * np.abs(damping).max())


def test_ffrf_without_ffrf_terms_has_no_modal_mass(bridge):
    """Exudyn pitfall the ffrf variant avoids: ObjectFFRFreducedOrder with computeFFRFterms=False
    and no user function assembles a zero mass matrix for the modal coordinates (it expects the
    user functions of FEM.ObjectFFRFreducedOrderInterface to provide it)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    n = bridge.n_modes
    t = ffrf_terms(bridge.node_positions, bridge.node_shapes, bridge.node_masses)
    ref = mbs.AddNode(ei.NodeRigidBodyRxyz())
    node = mbs.AddNode(ei.NodeGenericODE2(numberOfODE2Coordinates=n, referenceCoordinates=[0.0] * n,
                                          initialCoordinates=[0.0] * n, initialCoordinates_t=[0.0] * n))
    mbs.AddObject(ei.ObjectFFRFreducedOrder(
        nodeNumbers=[ref, node], massMatrixReduced=np.eye(n), stiffnessMatrixReduced=np.diag(bridge.omega**2),
        modeBasis=t.mode_basis, referencePositions=t.reference_positions, mass=t.mass, inertia=t.inertia,
        centerOfMass=t.center_of_mass, computeFFRFterms=False))
    mbs.Assemble()
    m = ComputeLinearizedSystem(mbs, _settings())[0]
    idx = mbs.GetNodeODE2Index(node) + np.arange(n)
    assert np.all(m[np.ix_(idx, idx)] == 0.0)


@pytest.mark.parametrize("variant", ["generic", "ffrf"])
def test_static_modal_load(bridge, variant):
    """Constant modal forces f_k: the static solution is q_k = f_k / omega_k^2 (closed form),
    zero for unloaded modes; linear, so round-off tolerance (1e-9)."""
    _, mbs, body = _system(bridge, variant)
    mbs.SolveStatic(_settings())
    q = body.coordinates(mbs)
    expected = np.zeros(bridge.n_modes)
    for k, f in LOADS.items():
        expected[k] = f / bridge.omega[k] ** 2
    assert np.allclose(q, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def _run(bridge, variant, newmark=False):
    _, mbs, body = _system(bridge, variant)
    sensor = mbs.AddSensor(ei.SensorNode(nodeNumber=body.node, outputVariableType=exu.OutputVariableType.Coordinates,
                                         storeInternal=True, writeToFile=False))
    ss = _settings(newmark)
    mbs.SolveDynamic(ss)
    assert mbs.systemData.GetTime() == pytest.approx(STEPS * DT, abs=1e-12)  # reached its end time
    return mbs.GetSensorStoredData(sensor)


def test_generic_and_ffrf_dynamic_step_response_agree(bridge):
    """Modal step loads from rest, 150 steps of 2 ms with the default generalised-alpha
    integrator: the two variants integrate the same equations, so their modal histories agree to
    1e-6 relative (acceptance; observed ~1e-12)."""
    a = _run(bridge, "generic")
    b = _run(bridge, "ffrf")
    assert a.shape == b.shape == (STEPS + 1, 1 + bridge.n_modes)
    assert np.abs(a[:, 1:] - b[:, 1:]).max() <= 1e-6 * np.abs(a[:, 1:]).max()


def test_generic_body_follows_an_independent_newmark_recurrence(bridge):
    """With Newmark average acceleration (beta 1/4, gamma 1/2) the modal histories equal the same
    scheme written out per mode in the test (q'' + 2 zeta w q' + w^2 q = f, a0 = f at rest):
    the equations are linear, so one Newton step is exact and the tolerance is round-off (1e-9)."""
    data = _run(bridge, "generic", newmark=True)
    om, zeta = bridge.omega, bridge.damping_ratios
    f = np.zeros(bridge.n_modes)
    for k, v in LOADS.items():
        f[k] = v
    q, v, a = np.zeros_like(f), np.zeros_like(f), f.copy()
    ref = [q.copy()]
    c, kk = 2 * zeta * om, om**2
    for _ in range(STEPS):
        q_pred = q + DT * v + 0.25 * DT**2 * a
        v_pred = v + 0.5 * DT * a
        a = (f - c * v_pred - kk * q_pred) / (1.0 + 0.5 * DT * c + 0.25 * DT**2 * kk)
        q, v = q_pred + 0.25 * DT**2 * a, v_pred + 0.5 * DT * a
        ref.append(q.copy())
    ref = np.array(ref)
    assert np.abs(data[:, 1:] - ref).max() <= 1e-9 * np.abs(ref).max()


def test_ffrf_needs_finite_element_modes():
    """The closed-form ModalBridge has no mesh: variant='ffrf' says so; unknown variants too."""
    closed = simply_supported_modes((32.0,), 1e11, 1e12, 1e11, 3e4, 3e5, 0.02, 20.0)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    with pytest.raises(ValueError, match="finite-element mesh"):
        add_modal_bridge_body(mbs, closed, "ffrf")
    with pytest.raises(ValueError, match="variant"):
        add_modal_bridge_body(mbs, closed, "cms")
    body = add_modal_bridge_body(mbs, closed)
    assert body.variant == "generic" and body.n_modes == closed.n_modes
