"""The damping guard on the shipped scenarios and on li_zhu_2011 with a yaw damper, and the
`tb-exudyn modes` command (acceptance of issue 14)."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from tb_exudyn.builder.system_modes import damping_guard, system_modes  # noqa: E402
from tb_exudyn.cli import main  # noqa: E402
from tb_exudyn.scenario import Train, YawDamper, load_scenario  # noqa: E402

pytestmark = pytest.mark.exudyn

#: a test value, not data of any vehicle: per damper, 1.35 m off the centre line (no source gives
#: the ICE's yaw dampers; see the report of issue 14)
TEST_YAW_DAMPER = YawDamper(c_x=1.0e5, half_span=1.35)


def with_yaw_dampers(name: str):
    sc = load_scenario(name)
    return sc.replace(train=Train(vehicles=tuple(v.replace(yaw_damper=TEST_YAW_DAMPER) for v in sc.train.vehicles)))


def rounded(warnings) -> list[float]:
    return sorted(round(w.frequency, 1) for w in warnings)


def test_li_zhu_bogie_yaw_modes_and_their_warnings():
    """li_zhu_2011 (ICE M+T+T+M, no primary lateral damping in the data): the table lists the
    motor cars' bogie yaw at 8.3 Hz and the trailers' at 12.4 Hz, four each (two cars, two bogies),
    with damping ratios below 1e-3 (docs/findings.md section 4: 9.8e-5 and 2.5e-4); the guard warns
    of exactly these eight modes, each with the channels of its car."""
    sc = load_scenario("li_zhu_2011")
    table = system_modes(sc)
    yaw = [i for i, lab in enumerate(table.label) if lab.endswith("bogie, yaw")]
    assert sorted(round(table.frequency[i], 1) for i in yaw) == [8.3] * 4 + [12.4] * 4
    assert all(table.damping_ratio[i] < 1e-3 for i in yaw)
    warnings = damping_guard(sc)
    assert rounded(warnings) == [8.3] * 4 + [12.4] * 4
    for w in warnings:
        car = w.label.split(" (")[0].replace(" ", "")  # "car 2" -> "car2"
        assert w.channels == (f"{car}.*",) and w.damping_ratio < 1e-3 and w.decay_time > sc.duration


def test_li_zhu_with_yaw_dampers_does_not_warn():
    """The same train with a yaw damper pair per bogie (a test value, 100 kN s/m per damper at
    1.35 m): the bogie yaw modes are damped (zeta > 0.1) and no mode warns."""
    sc = with_yaw_dampers("li_zhu_2011")
    table = system_modes(sc)
    yaw = [i for i, lab in enumerate(table.label) if lab.endswith("bogie, yaw")]
    assert len(yaw) == 8 and all(table.damping_ratio[i] > 0.1 for i in yaw)
    assert damping_guard(sc) == []


def test_shipped_scenarios():
    """Which shipped scenarios the guard fires for, and why:
    - quick and li_zhu_2011_mc_check (one ICE motor car): its two bogie yaw modes at 8.34 Hz only;
      with yaw dampers (test value) nothing, so every other mode in their bands is well damped;
    - yang_yau_sprung_mass: the undamped sprung mass (2.65 Hz) and the undamped beam's vertical
      modes in the band (4.09, 16.4 Hz) - the validation case has no damping at all; its lateral
      and torsion modes are not excited (vertical profile, centred vertical vehicle) and do not
      warn; with test damping (suspension zeta 0.05, beam 5 %: decay times 1.2 s and 0.78 s
      against the 1.8 s run) nothing (beam 2 % would still warn: 1.95 s);
    - fryba_moving_force: no irregularity, so no random run and no warning."""
    for name in ("quick", "li_zhu_2011_mc_check"):
        assert rounded(damping_guard(load_scenario(name))) == [8.3, 8.3]
        assert damping_guard(with_yaw_dampers(name)) == []
    sc = load_scenario("yang_yau_sprung_mass")
    ws = damping_guard(sc)
    assert rounded(ws) == [2.7, 4.1, 16.4]
    assert {w.label for w in ws} == {"car 1 (yang_yau_1997), body, bounce", "bridge, vertical 1", "bridge, vertical 2"}
    veh = sc.train.vehicles[0]
    damped = sc.replace(train=Train(vehicles=(veh.replace(damping=0.05 * 2 * (veh.stiffness * veh.mass) ** 0.5),)),
                        bridge=sc.bridge.replace(damping_ratio=0.05))
    assert damping_guard(damped) == []
    assert damping_guard(load_scenario("fryba_moving_force")) == []


def test_modes_command(capsys):
    """`tb-exudyn modes li_zhu_2011` prints the table (frequency, damping ratio, label) with the
    bogie yaw modes and the guard's warnings by frequency; a bad --band is a user error (exit 2)."""
    assert main(["modes", "li_zhu_2011", "--band", "8", "13"]) == 0
    out = capsys.readouterr().out
    # frequencies to 4 significant digits (what a mode's frequency means; the table's convention)
    assert "8.342" in out and "12.42" in out and "9.84e-05" in out and "leading bogie, yaw" in out
    assert "4 lightly damped modes at 8.342 Hz" in out and "4 lightly damped modes at 12.42 Hz" in out
    assert main(["modes", "quick", "--position", "0", "20"]) == 0
    out = capsys.readouterr().out
    assert "the first axle at 2 positions" in out and "x = 0 m (" in out and "x = 20 m (" in out  # a column each
    assert main(["modes", "quick", "--band", "30", "10"]) == 2
    assert "--band" in capsys.readouterr().err
