"""The bridge as an Exudyn body: the modal equations q'' + D q' + K q = f of a ModalBridge.

Two forms of the same equations:

- ``variant="generic"`` (default): one ``NodeGenericODE2`` with the n modal coordinates and an
  ``ObjectGenericODE2`` with M = I, K = diag(omega^2), D = diag(2 zeta omega) as sparse matrices.
  With a track (``ModalBridge.coupled_damping``: the pads' and the ballast's dampers) D is that full
  matrix. This is the fixed-frame form of a reduced floating-frame (FFRF) body; it is several times faster
  than ``ObjectFFRFreducedOrder`` because it has no reference-frame terms.
- ``variant="ffrf"``: an ``ObjectFFRFreducedOrder`` with a rigid-body reference node fixed to the
  ground (six coordinate constraints) and the same modal node and matrices (the damping, too, the full
  matrix where the bridge has one: ``ModalBridge.coupled_damping``); its mesh is the
  finite-element nodes with their translational mode shapes (visualisation, cross-checks). It
  needs a ModalBridge from the finite-element model (``node_positions``, ``node_shapes``,
  ``node_masses``). The reference-frame inertia terms (mass, inertia, mPsiTildePsi, ...) are
  computed from the lumped nodal masses; with the reference node fixed they only enter the
  constraint reactions, never the modal equations. They must be given with
  ``computeFFRFterms=True``: with ``computeFFRFterms=False`` the object computes no mass matrix of
  its own and the modal mass silently becomes zero (checked in the tests).

Modal coordinates are the coordinates of the returned ``node`` in both variants: read them with
:meth:`BridgeBody.coordinates` (or a ``SensorNode`` with ``OutputVariableType.Coordinates``), load
mode k through ``MarkerNodeCoordinate(nodeNumber=node, coordinate=k)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import exudyn as exu
import exudyn.itemInterface as ei
import numpy as np
import scipy.sparse as sp
from exudyn.rigidBodyUtilities import ComputeSkewMatrix

from ..structure.modal import ModalBridge

VARIANTS = ("generic", "ffrf")


@dataclass(frozen=True)
class BridgeBody:
    """What :func:`add_modal_bridge_body` added to the system.

    Attributes
    ----------
    variant : 'generic' or 'ffrf'
    node : the NodeGenericODE2 whose coordinates are the modal coordinates q (n_modes of them)
    object : the ObjectGenericODE2 or ObjectFFRFreducedOrder
    n_modes : number of modal coordinates
    reference_node : ffrf only: the rigid-body reference node (fixed to the ground)
    """

    variant: str
    node: int
    object: int
    n_modes: int
    reference_node: int | None = None

    def coordinates(self, mbs: exu.MainSystem, configuration=exu.ConfigurationType.Current) -> np.ndarray:
        """Modal coordinates q (n_modes,) of the current (or given) configuration."""
        return np.asarray(mbs.GetNodeOutput(self.node, exu.OutputVariableType.Coordinates, configuration))

    def velocities(self, mbs: exu.MainSystem, configuration=exu.ConfigurationType.Current) -> np.ndarray:
        """Modal velocities q' (n_modes,)."""
        return np.asarray(mbs.GetNodeOutput(self.node, exu.OutputVariableType.Coordinates_t, configuration))

    def accelerations(self, mbs: exu.MainSystem, configuration=exu.ConfigurationType.Current) -> np.ndarray:
        """Modal accelerations q'' (n_modes,)."""
        return np.asarray(mbs.GetNodeOutput(self.node, exu.OutputVariableType.Coordinates_tt, configuration))

    def ode2_indices(self, mbs: exu.MainSystem) -> np.ndarray:
        """Indices of q in the system's ODE2 coordinate vector (after ``mbs.Assemble()``)."""
        return mbs.GetNodeODE2Index(self.node) + np.arange(self.n_modes)


def _diagonal(values: np.ndarray) -> exu.MatrixContainer:
    mc = exu.MatrixContainer()
    mc.SetWithSparseMatrix(sp.diags(np.asarray(values, dtype=float)).tocsr())
    return mc


def _damping(bridge: ModalBridge) -> exu.MatrixContainer:
    """The body's damping: diag(2 zeta omega), or its coupled matrix (the track's pads and ballast)."""
    if bridge.coupled_damping is None:
        return _diagonal(2.0 * bridge.damping_ratios * bridge.omega)
    mc = exu.MatrixContainer()
    mc.SetWithSparseMatrix(sp.csr_matrix(bridge.coupled_damping))
    return mc


def _modal_node(mbs: exu.MainSystem, n: int, name: str) -> int:
    zeros = [0.0] * n
    return mbs.AddNode(ei.NodeGenericODE2(
        name=name, numberOfODE2Coordinates=n, referenceCoordinates=zeros,
        initialCoordinates=zeros, initialCoordinates_t=zeros,
    ))


@dataclass(frozen=True)
class FFRFTerms:
    """Reference-frame inertia terms of ObjectFFRFreducedOrder for a lumped-mass mesh.

    Formulas of Zwoelfer & Gerstmayr's nodal-based FFRF with modal reduction, as in Exudyn's
    ``ObjectFFRFreducedOrderInterface``, with the nodal mass matrix diag(m_i) on translations.
    """

    mode_basis: np.ndarray
    reference_positions: np.ndarray
    mass: float
    inertia: np.ndarray
    center_of_mass: np.ndarray
    m_psi_tilde_psi: np.ndarray
    m_psi_tilde_psi_tilde: np.ndarray
    m_phit_t_psi: np.ndarray
    m_phit_t_psi_tilde: np.ndarray
    m_xref_tilde_psi: np.ndarray
    m_xref_tilde_psi_tilde: np.ndarray


def ffrf_terms(positions: np.ndarray, shapes: np.ndarray, masses: np.ndarray) -> FFRFTerms:
    """FFRF terms of nodes at ``positions`` (N, 3) with translational modes ``shapes`` (N, 3, n)
    and lumped masses ``masses`` (N,)."""
    n_nodes, _, n = shapes.shape
    psi = shapes.reshape(3 * n_nodes, n)
    m3 = np.repeat(np.asarray(masses, dtype=float), 3)  # diagonal of the nodal mass matrix
    x_ref = np.asarray(positions, dtype=float).reshape(-1)
    phit = np.kron(np.ones((n_nodes, 1)), np.eye(3))  # (3N, 3) rigid translations
    x_ref_tilde = ComputeSkewMatrix(x_ref)  # (3N, 3)
    psi_tilde = ComputeSkewMatrix(psi)  # (3N, 3n)
    total = float(m3.sum() / 3.0)
    mpsi = m3[:, None] * psi
    mpsi_tilde = m3[:, None] * psi_tilde
    return FFRFTerms(
        mode_basis=psi,
        reference_positions=x_ref,
        mass=total,
        inertia=x_ref_tilde.T @ (m3[:, None] * x_ref_tilde),
        center_of_mass=(phit.T @ (m3 * x_ref)) / total,
        m_psi_tilde_psi=psi_tilde.T @ mpsi,
        m_psi_tilde_psi_tilde=psi_tilde.T @ mpsi_tilde,
        m_phit_t_psi=phit.T @ mpsi,
        m_phit_t_psi_tilde=phit.T @ mpsi_tilde,
        m_xref_tilde_psi=x_ref_tilde.T @ mpsi,
        m_xref_tilde_psi_tilde=x_ref_tilde.T @ mpsi_tilde,
    )


def _add_generic(mbs: exu.MainSystem, bridge: ModalBridge, name: str) -> BridgeBody:
    n, om = bridge.n_modes, bridge.omega
    node = _modal_node(mbs, n, f"{name}.modes")
    obj = mbs.AddObject(ei.ObjectGenericODE2(
        name=name, nodeNumbers=[node], massMatrix=_diagonal(np.ones(n)),
        stiffnessMatrix=_diagonal(om**2), dampingMatrix=_damping(bridge),
        visualization=ei.VObjectGenericODE2(show=False),
    ))
    return BridgeBody("generic", int(node), int(obj), n)


def _add_ffrf(mbs: exu.MainSystem, bridge: ModalBridge, name: str, show: bool) -> BridgeBody:
    if bridge.node_positions is None or bridge.node_shapes is None or bridge.node_masses is None:
        raise ValueError(
            "variant='ffrf' needs the finite-element mesh of the bridge (node_positions, node_shapes, "
            "node_masses): build the ModalBridge with tb_exudyn.structure.modal_bridge"
        )
    n, om = bridge.n_modes, bridge.omega
    t = ffrf_terms(bridge.node_positions, bridge.node_shapes, bridge.node_masses)
    ref = mbs.AddNode(ei.NodeRigidBodyRxyz(name=f"{name}.reference"))
    node = _modal_node(mbs, n, f"{name}.modes")
    obj = mbs.AddObject(ei.ObjectFFRFreducedOrder(
        name=name, nodeNumbers=[ref, node],
        massMatrixReduced=_diagonal(np.ones(n)), stiffnessMatrixReduced=_diagonal(om**2),
        dampingMatrixReduced=_damping(bridge),
        modeBasis=t.mode_basis, referencePositions=t.reference_positions,
        mass=t.mass, inertia=t.inertia, centerOfMass=t.center_of_mass,
        mPsiTildePsi=t.m_psi_tilde_psi, mPsiTildePsiTilde=t.m_psi_tilde_psi_tilde,
        mPhitTPsi=t.m_phit_t_psi, mPhitTPsiTilde=t.m_phit_t_psi_tilde,
        mXRefTildePsi=t.m_xref_tilde_psi, mXRefTildePsiTilde=t.m_xref_tilde_psi_tilde,
        computeFFRFterms=True,
        visualization=ei.VObjectFFRFreducedOrder(show=show, showNodes=show),
    ))
    ground = mbs.AddNode(ei.NodePointGround(name=f"{name}.ground"))
    m_ground = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    for i in range(6):
        m_ref = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=ref, coordinate=i))
        mbs.AddObject(ei.ObjectConnectorCoordinate(markerNumbers=[m_ground, m_ref],
                                                   visualization=ei.VObjectConnectorCoordinate(show=False)))
    return BridgeBody("ffrf", int(node), int(obj), n, reference_node=int(ref))


def add_modal_bridge_body(
    mbs: exu.MainSystem, modal_bridge: ModalBridge, variant: str = "generic", name: str = "bridge",
    show: bool = False,
) -> BridgeBody:
    """Add the bridge's modal equations to ``mbs``.

    Parameters
    ----------
    mbs : the Exudyn system
    modal_bridge : mass-normalised modes (frequencies, damping ratios; node data for 'ffrf')
    variant : 'generic' (NodeGenericODE2 + ObjectGenericODE2) or 'ffrf' (ObjectFFRFreducedOrder
        on a fixed reference node, for cross-checks and visualisation)
    name : item name prefix
    show : 'ffrf' only: draw the finite-element nodes in Exudyn's renderer (the generic body has
        no geometry to draw)

    Returns
    -------
    BridgeBody with the modal node (its coordinates are q), the object and, for 'ffrf', the
    reference node.
    """
    if variant not in VARIANTS:
        raise ValueError(f"variant = {variant!r}: must be one of {', '.join(VARIANTS)}")
    if modal_bridge.n_modes < 1:
        raise ValueError("the modal bridge has no modes")
    if variant == "ffrf":
        return _add_ffrf(mbs, modal_bridge, name, show)
    return _add_generic(mbs, modal_bridge, name)
