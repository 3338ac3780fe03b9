"""The linear system of a built model (:class:`~tb_exudyn.system.linear.LinearSystem`)."""

from __future__ import annotations

from ..errors import SettingError
from ..system.linear import LINEARIZATIONS, LinearSystem, without_block
from .model import TrainBridgeModel


def linear_system(model: TrainBridgeModel, linearization: str = "rest") -> LinearSystem:
    """M, K0, D0 of the model without the contact, from Exudyn's ``ComputeLinearizedSystem`` at t = 0
    (every axle on the rigid approach) minus the coupling's own Jacobians at that time (frozen: no
    convective term), at the linearization point ("rest" or "static", see
    :mod:`tb_exudyn.system.linear`). Leaves the model without excitation and gravity, at rest (the
    state of the pseudo-excitation runs)."""
    if linearization not in LINEARIZATIONS:
        raise SettingError("linear_system", "linearization", linearization, " or ".join(map(repr, LINEARIZATIONS)))
    cp = model.coupling
    model.set_excitation(None)
    if cp.contact_state(0.0).on_bridge and cp.bridge.rail_extent is None:  # on a track: the wheels stand on it
        raise ValueError("an axle stands on the bridge at t = 0: the linear engines need a lead-in")
    state = None
    if linearization == "static":
        model.set_gravity(True)
        state = model.static_state(0.0)
    model.set_gravity(False)
    M, K, D = model.linearized_system(0.0, state)
    with cp.frozen(0.0):
        Kc, Dc = cp.jacobians(0.0)
    ci = model.coupling_indices()
    lin = LinearSystem(
        M=M, K0=without_block(K, Kc, ci), D0=without_block(D, Dc, ci), bridge=ci[: cp.n_bridge],
        wheel=ci[cp.n_bridge:], k=cp.contacts.stiffness, c=cp.contacts.damping, G=cp.contacts.wheel_map,
        coupling=cp, linearization=linearization,
    )
    model.reset("rest")
    return lin
