"""Fixtures of the builder tests: the ICE cars of docs/references.md (vehicles) as dataclasses."""

from __future__ import annotations

import pytest

from tb_exudyn.scenario import Car15, Car15Geometry, RigidBodyInertia, Suspension, WheelsetInertia


def _ice(motor: bool) -> Car15:
    """ICE motor car / trailer, 15-DOF ICE parameters of the Xia/Zhang research code (values per side)."""
    return Car15(
        name="ice_motor" if motor else "ice_trailer",
        body=RigidBodyInertia(mass=48000.0 if motor else 44000.0, inertia_roll=1.15e5 if motor else 1.0e5,
                              inertia_pitch=2.7e6, inertia_yaw=2.7e6),
        bogie=RigidBodyInertia(mass=3200.0, inertia_roll=3200.0, inertia_pitch=7200.0, inertia_yaw=6800.0) if motor
        else RigidBodyInertia(mass=2400.0, inertia_roll=2400.0, inertia_pitch=5400.0, inertia_yaw=5100.0),
        wheelset=WheelsetInertia(mass=2400.0, inertia_roll=1200.0),
        geometry=Car15Geometry(
            half_bogie_spacing=8.6875, half_wheelbase=1.25, half_primary_span=1.0, half_secondary_span=0.95,
            body_cg_above_secondary=0.8, secondary_above_bogie_cg=0.3 if motor else 0.2,
            bogie_cg_above_axle=-0.05 if motor else 0.1, wheel_radius=0.46, length=24.775,
        ),
        primary=Suspension(k_z=1.04e6, k_y=3.0e6, c_z=5.0e4, c_y=0.0) if motor
        else Suspension(k_z=7.0e5, k_y=5.0e6, c_z=5.0e4, c_y=0.0),
        secondary=Suspension(k_z=4.0e5, k_y=4.8e5, c_z=6.0e4, c_y=3.0e4) if motor
        else Suspension(k_z=3.0e5, k_y=5.6e5, c_z=6.0e4, c_y=2.5e4),
    )


@pytest.fixture
def ice_motor() -> Car15:
    return _ice(True)


@pytest.fixture
def ice_trailer() -> Car15:
    return _ice(False)
