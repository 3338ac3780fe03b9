"""The creep_car vehicle kind: its files load, its mistakes are one-line errors, its data feeds the
creep module."""

from __future__ import annotations

import copy
import math
import tomllib

import pytest

from tb_exudyn.scenario import CreepCar, ScenarioError, load_vehicle, model_files
from tb_exudyn.scenario.toml_io import dumps_toml
from tb_exudyn.system.creep import hertz_creep_coefficients

MOTOR = tomllib.loads(model_files("vehicles")["ice_motor_creep"].read_text())


def test_ice_creep_cars_keep_the_reference_study_cars():
    """Exact problem: the creep cars against ice_motor / ice_trailer. Reference: the data files of
    the reference study's cars: every value those files have is the same (masses, geometry,
    vertical and lateral suspension), so the study's train and bridge see the same loads. Exact."""
    for creep, plain in (("ice_motor_creep", "ice_motor"), ("ice_trailer_creep", "ice_trailer")):
        c, p = load_vehicle(creep), load_vehicle(plain)
        assert isinstance(c, CreepCar)
        assert (c.body, c.bogie, c.geometry) == (p.body, p.bogie, p.geometry)
        assert (c.wheelset.mass, c.wheelset.inertia_roll) == (p.wheelset.mass, p.wheelset.inertia_roll)
        for stage in ("primary", "secondary"):
            cs, ps = getattr(c, stage), getattr(p, stage)
            assert (cs.k_y, cs.k_z, cs.c_y, cs.c_z) == (ps.k_y, ps.k_z, ps.c_y, ps.c_z)


def test_static_axle_load_and_creep_coefficients():
    """Exact problem: the ICE motor creep car's static axle load and creep coefficients. Reference: hand
    calculation W = g (48000/4 + 3200/2 + 2400) = 156 960 N at g = 9.81 (the ICE data of docs/references.md,
    vehicles: 157 kN); the coefficients of a 78.5 kN wheel on r0 = 0.46 m, a 0.3 m crown, steel: f11 and f22
    of order 1e7 N (the magnitude the linear-theory literature quotes for such loads), a/b > 1 (the contact
    longer than wide on a conical tread). Tolerance: exact for W; orders of magnitude for f."""
    car = load_vehicle("ice_motor_creep")
    W = car.static_axle_load(9.81)
    assert W == pytest.approx(156960.0, rel=1e-15)
    cr = car.contact.creep
    f, ellipse = hertz_creep_coefficients(W / 2, car.geometry.wheel_radius, cr.rail_transverse_radius,
                                          cr.wheel_transverse_radius, cr.youngs_modulus, cr.poisson_ratio)
    assert 5e6 < f.f22 < f.f11 < 3e7
    assert ellipse.a > ellipse.b and math.isinf(cr.wheel_transverse_radius)


@pytest.mark.parametrize("path, value, key", [
    (("contact", "creep", "kind"), "kalker", "contact.creep.kind"),
    (("contact", "creep", "wheel_transverse_radius"), -0.2, "contact.creep.wheel_transverse_radius"),
    (("contact", "conicity"), 0.0, "contact.conicity"),
    (("primary", "k_x"), -1.0, "primary.k_x"),
])
def test_creep_car_mistakes_name_the_key(tmp_path, path, value, key):
    """Exact problem: one bad value in ice_motor_creep (an unknown creep kind, a concave wheel
    sharper than the rail crown: no Hertz contact, a zero conicity, a negative stiffness).
    Reference: the error contract: a ScenarioError naming the file and the dotted key."""
    data = copy.deepcopy(MOTOR)
    node = data
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    bad = tmp_path / "bad_car.toml"
    bad.write_text(dumps_toml(data))
    with pytest.raises(ScenarioError) as err:
        load_vehicle(bad)
    assert "bad_car.toml" in str(err.value) and key in str(err.value)
