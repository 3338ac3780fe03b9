"""The code trains: HSLM-A1 ... A10 generated from EN 1991-2 Table E.1 / Figure E.1, and the real trains
composed of vehicle models (models/trains).

References written here: the table's rows (N, D, d, P) copied from EN 1991-2:2003 Table E.1; the axle
geometry of Figure E.1 (power car 0, 3, 14, 17 m; end coach's outer bogie 3.525 m behind, spacing d;
articulated bogies D apart; the rear half mirrored), hence 2 N + 14 axles and a first-to-last length of
37.525 + (N + 2) D; the ICE and AVE axle loads by hand from the vehicle files' masses. Positions are
sums of decimal lengths, so they are compared to 1e-9 m.
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.codes.trains import hslm_a, load_train, resolve_trains, train_files, train_names
from tb_exudyn.errors import ScenarioError, SettingError

#: EN 1991-2:2003 Table E.1: number -> (N, D [m], d [m], P [kN])
TABLE_E1 = {1: (18, 18, 2.0, 170), 2: (17, 19, 3.5, 200), 3: (16, 20, 2.0, 180), 4: (15, 21, 3.0, 190),
            5: (14, 22, 2.0, 170), 6: (13, 23, 2.0, 180), 7: (13, 24, 2.0, 190), 8: (12, 25, 2.5, 190),
            9: (11, 26, 2.0, 210), 10: (11, 27, 2.0, 210)}


@pytest.mark.parametrize("number", sorted(TABLE_E1))
def test_hslm_a_axles_symmetry_and_length(number):
    n, big_d, d, p = TABLE_E1[number]
    t = hslm_a(number)
    x = t.positions
    assert t.name == f"HSLM-A{number}"
    assert t.n_axles == 2 * n + 14
    assert np.all(np.diff(x) > 0) and x[0] == 0.0
    assert t.length == pytest.approx(37.525 + (n + 2) * big_d, abs=1e-9)
    np.testing.assert_allclose(x, t.length - x[::-1], atol=1e-9)  # symmetric: the rear half mirrors the front
    np.testing.assert_allclose(x[:6], [0, 3, 14, 17, 20.525, 20.525 + d], atol=1e-9)
    # the N + 1 articulated bogies: axle pairs d apart, centres D apart, the first at 17 + 3.525 / 2 + D
    bogies = x[6:6 + 2 * (n + 1)].reshape(n + 1, 2)
    np.testing.assert_allclose(bogies[:, 1] - bogies[:, 0], d, atol=1e-9)
    centres = bogies.mean(axis=1)
    np.testing.assert_allclose(np.diff(centres), big_d, atol=1e-9)
    assert centres[0] == pytest.approx(17 + 3.525 / 2 + big_d, abs=1e-9)
    np.testing.assert_array_equal(t.loads, 1e3 * p)
    assert t.regular_length == big_d


def test_hslm_a1_is_397_525_m_long_with_50_axles():
    """The figure usually quoted for HSLM-A1: 50 axles, 397.525 m from the first to the last."""
    t = hslm_a(1)
    assert (t.n_axles, t.length) == (50, pytest.approx(397.525, abs=1e-9))


def test_ice_train_from_the_vehicle_files():
    """ICE M+T+T+M: cars 24.775 m, axles at 0, 2.5, 17.375, 19.875 m of each car (half wheelbase 1.25,
    half bogie spacing 8.6875); axle loads (48000 + 2 * 3200 + 4 * 2400) * 9.81 / 4 = 156 960 N (motor)
    and (44000 + 2 * 2400 + 4 * 2400) * 9.81 / 4 = 143 226 N (trailer)."""
    t = load_train(train_files()["ice_mttm"])
    car = np.array([0.0, 2.5, 17.375, 19.875])
    np.testing.assert_allclose(t.positions, np.concatenate([car + 24.775 * k for k in range(4)]), atol=1e-9)
    motor, trailer = 156_960.0, 143_226.0
    np.testing.assert_allclose(t.loads, [motor] * 4 + [trailer] * 8 + [motor] * 4, rtol=1e-12)
    assert t.regular_length == pytest.approx(24.775)


def test_ave_s103_eight_cars_two_lighter_middle_coaches():
    """8 cars of ave_s103: (47800 + 2 * 3500 + 4 * 1800) * 9.81 / 4 = 152 055 N per axle, the two middle
    coaches with a 41 200 kg body (41200 + 14200) * 9.81 / 4 = 135 868.5 N."""
    t = load_train(train_files()["ave_s103"])
    assert t.n_axles == 32
    heavy, light = 152_055.0, 135_868.5
    np.testing.assert_allclose(t.loads, [heavy] * 12 + [light] * 8 + [heavy] * 12, rtol=1e-12)


def test_selection_by_group_and_name():
    assert [t.name for t in resolve_trains(["hslm_a"])] == [f"HSLM-A{i}" for i in range(1, 11)]
    assert [t.name for t in resolve_trains(["HSLM-A3", "hslm_a3", "ice_mttm"])] == ["HSLM-A3", "ice_mttm"]
    assert {"HSLM-A10", "ice_mttm", "ave_s103"} <= set(train_names())


def test_unknown_train_names_the_key_and_the_names():
    with pytest.raises(SettingError) as info:
        resolve_trains(["HSLM-A11"], "command line", "--trains")
    text = str(info.value)
    assert text.startswith("command line: key '--trains' = 'HSLM-A11': unknown train") and "ice_mttm" in text


def test_bad_train_file_names_file_and_key(tmp_path):
    bad = tmp_path / "t.toml"
    bad.write_text('name = "x"\n[[cars]]\nvehicle = "ice_motor"\ncount = 0\n')
    with pytest.raises(ScenarioError) as info:
        load_train(bad)
    assert str(bad) in str(info.value) and "cars[0].count" in str(info.value)
    bad.write_text('name = "x"\n[[cars]]\nvehicle = "moving_force_100kn"\n')
    with pytest.raises(ScenarioError, match="two bogies"):
        load_train(bad)


def test_a_force_train_checks_its_arrays():
    from tb_exudyn.codes.trains import ForceTrain

    ForceTrain("ok", [0.0, 2.5], [1e5, 1e5], 2.5)
    for positions, loads in (([1.0, 2.5], [1e5, 1e5]), ([0.0, -1.0], [1e5, 1e5]), ([0.0, 2.5], [1e5]),
                             ([0.0, 2.5], [1e5, np.nan]), ([0.0, 1500.0], [1e5, 1e5])):
        with pytest.raises(SettingError, match="ForceTrain 'x'"):
            ForceTrain("x", positions, loads, 2.5)
