"""A new user's first hour on the command line (issue 49): `show` and `modes` of a bridge file, a shipped
bridge and a vehicle; every command's lines at most 200 characters; the commands that report a result
(run, sweep, check, modes, uq) in at most 60 lines; one line per command-line error.

The bounds are the issue's acceptance numbers (a terminal line, a screen); the f1 check states its reference."""

from __future__ import annotations

import math
import shutil

import pytest

from tb_exudyn.cli import main
from tb_exudyn.scenario.registry import model_files

LINE_MAX, RESULT_LINES = 200, 60


def _printed(capsys, argv: list[str]) -> list[str]:
    code = main(argv)
    out = capsys.readouterr()
    assert code == 0, out.err
    lines = (out.out + out.err).splitlines()
    wide = [ln for ln in lines if len(ln) > LINE_MAX]
    assert not wide, f"{' '.join(argv)}: {len(wide)} lines over {LINE_MAX} characters, e.g. {wide[0][:120]}..."
    return lines


def test_list_and_show_of_a_scenario_fit_the_width(capsys):
    _printed(capsys, ["list"])
    lines = _printed(capsys, ["show", "li_zhu_2011"])
    assert any(ln.startswith("train.vehicles[0].kind") and "15-DOF car" in ln for ln in lines)


@pytest.mark.slow
def test_show_and_modes_of_a_bridge_file_a_bridge_name_and_a_vehicle(tmp_path, capsys):
    mine = tmp_path / "my_bridge.toml"
    shutil.copy(model_files("bridges")["li_zhu_2011_bridge"], mine)
    for bridge in (str(mine), "li_zhu_2011_bridge"):
        text = "\n".join(_printed(capsys, ["show", bridge]))
        assert "f1, f3 vertical" in text and "closed form" in text
        # the closed form of the 32 m girder: pi / (2 L^2) sqrt(E I_y / m), E I_y and m (girder + added mass)
        # from the file; the FE f1 is lower, and the row says by how much the bearings below the axis take
        hand = math.pi / (2 * 32.0 ** 2) * math.sqrt(3.45e10 * 10.947 / (22222.25 + 11677.75))
        assert f"{hand:.4g}" in text and "bearings 2.3 m below the girder axis" in text
        modes = _printed(capsys, ["modes", bridge])
        assert len(modes) <= RESULT_LINES and "no vehicle" in modes[0] and any("vertical 1" in ln for ln in modes)
    text = "\n".join(_printed(capsys, ["show", "ice_motor"]))
    assert "15-DOF car" in text and "body.mass" in text
    modes = _printed(capsys, ["modes", "ice_motor"])
    assert len(modes) <= RESULT_LINES and "rigid track" in modes[0] and "bounce" in "\n".join(modes)
    assert not any("bridge" in ln for ln in modes[1:])  # the vehicle's own modes, no bridge's


def test_set_on_a_bridge_and_a_command_line_error_are_one_line(capsys):
    assert main(["show", "li_zhu_2011_bridge", "--set", "damping_ratio=0.02"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--set" in err[0] and "bridge" in err[0]
    with pytest.raises(SystemExit) as info:
        main(["run", "--no-such-option"])
    assert info.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--no-such-option" in err[0] and "usage" not in err[0]


@pytest.mark.slow
def test_modes_of_the_main_job_fit_a_screen(capsys):
    lines = _printed(capsys, ["modes", "li_zhu_2011"])
    assert len(lines) <= RESULT_LINES, len(lines)


@pytest.mark.slow
def test_run_sweep_and_check_fit_a_screen(tmp_path, capsys):
    lines = _printed(capsys, ["run", "quick", "--out", str(tmp_path / "q"), "--no-progress", "--workers", "1"])
    assert len(lines) <= RESULT_LINES, len(lines)
    assert any("criteria" in ln for ln in lines)  # counted by criterion
    _printed(capsys, ["run", "quick", "--method", "mc", "--samples", "4", "--out", str(tmp_path / "q"), "--no-progress",
                      "--no-figures", "--workers", "1"])
    _printed(capsys, ["compare", str(tmp_path / "q" / "pem"), str(tmp_path / "q" / "mc_linear")])
    _printed(capsys, ["report", str(tmp_path / "q")])
    lines = _printed(capsys, ["sweep", "quick", "--speeds-kmh", "200,250", "--out", str(tmp_path / "s"),
                              "--no-progress", "--no-figures", "--workers", "1"])
    assert len(lines) <= RESULT_LINES, len(lines)
    lines = _printed(capsys, ["check", "yang_yau_1997_beam", "--line-speed-kmh", "160", "--trains", "HSLM-A1",
                              "--construction", "prestressed_concrete", "--out", str(tmp_path / "c"), "--no-figures"])
    assert len(lines) <= RESULT_LINES, len(lines)


class _Sweep:
    """A sweep's result as the terminal reads it: 100 speeds, two quantities, one criterion evaluated and
    two not (one reason)."""

    quantities = [("deck_acc_z", None, None), ("wheel_force_y", None, None)]

    def rows(self):
        return [{"speed_kmh": 100.0 + 2.5 * i, "deck_acc_z_max_abs_mean_plus_3sigma": 0.1 + 0.01 * i - 1e-4 * i * i,
                 "wheel_force_y_max_abs_mean_plus_3sigma": 5e4 + (3e4 if i == 37 else 0.0)} for i in range(100)]

    def criterion_values(self):
        from tb_exudyn.results.sweep import CriterionValues

        nan, why = float("nan"), "running safety needs creep-guided wheelsets; " * 4
        return [{"a/x": CriterionValues(0.01 * i, nan, nan, nan, "", "", "OK"),
                 **{c: CriterionValues(nan, nan, nan, nan, "", "", "NOT EVALUATED", reason=why) for c in ("b/y", "c/z")}}
                for i in range(100)]

    def criteria(self):
        return ["a/x", "b/y", "c/z"]

    def quantity_unit(self, key):
        return "m/s^2" if key == "deck_acc_z" else "N"


def test_a_long_sweep_fits_a_screen():
    """100 speeds: at most TABLE_SPEEDS rows, with each quantity's largest (deck_acc_z peaks at i = 50,
    125 km/h + 100 = 225 km/h; wheel_force_y at i = 37, 192.5 km/h); the two criteria not evaluated for one
    reason on one wrapped line, the reason whole."""
    from tb_exudyn.cli.sweep import TABLE_SPEEDS, quantity_table, verdict_lines

    table = quantity_table(_Sweep())
    speeds = [ln.split()[0] for ln in table[3:-1]]
    assert len(speeds) <= TABLE_SPEEDS and {"225", "192.5", "100", "347.5"} <= set(speeds)
    assert table[-1].startswith(f"({len(speeds)} of 100 speeds")
    lines = verdict_lines(_Sweep())
    assert all(len(ln) <= 160 for ln in lines)
    text = " ".join(ln.strip() for ln in lines)
    assert "NOT EVALUATED: b/y, c/z (" in text and text.count("creep-guided") == 4 and "..." not in text


def test_a_name_of_two_kinds_says_which_is_shown(capsys):
    """ave_s103 is a vehicle and a train: show says which it shows and names the other's file."""
    lines = _printed(capsys, ["show", "ave_s103"])
    assert lines[0].startswith("(ave_s103 names a vehicle, shown here, and also the train: ")
    assert lines[0].endswith("models/trains/ave_s103.toml)") and lines[1].startswith("Vehicle ave_s103")
    assert _printed(capsys, ["show", lines[0].split(": ", 1)[1].rstrip(")")])[0].startswith("train ave_s103")


def test_uq_fits_a_screen(tmp_path, capsys):
    """`uq` reports a result: the sprung mass of tests/methods/test_uq_sprung_mass.py (one car, one
    channel, rigid track), its damping uniform +-20 %, order 2 (3 PEM runs): the cheapest study the UQ
    tests use. Its lines fit the width and a screen, and it writes its page uq.html."""
    import sys
    from pathlib import Path

    from tb_exudyn.scenario import save_scenario

    sys.path.insert(0, str(Path(__file__).parent / "methods"))
    from test_uq_sprung_mass import scenario

    path = save_scenario(scenario(), tmp_path / "s.toml")
    path.write_text(path.read_text() + '\n[uncertain."train.vehicles.0.damping"]\ndistribution = "uniform"\n'
                    'relative_bounds = [-0.2, 0.2]\n')
    lines = _printed(capsys, ["uq", str(path), "--order", "2", "--workers", "1", "--out", str(tmp_path / "u"),
                              "--no-progress", "--no-figures"])
    assert len(lines) <= RESULT_LINES, len(lines)
    assert any(ln.startswith("car1.body.acc_z [m/s^2]") for ln in lines), lines
    assert (tmp_path / "u" / "uq.html").is_file()


@pytest.mark.parametrize("argv", [
    ["--set", "track.lead_in=0.5"],  # the approach: the longest of the scenario's checks
    ["--set", "analysis.n_freq=30", "--freq-spacing", "adaptive"],  # too few frequencies for the modes
    ["--set", "track.structure=ballasted_uic60"],  # rails too long for the track's eigen-solution
])
def test_a_new_users_errors_are_one_line_within_the_width(tmp_path, capsys, argv):
    """Errors a new user provokes on a shipped scenario: one line, exit 2, at most 200 characters (the
    shipped file named by its name, not its installed path), before any work."""
    assert main(["run", "quick", *argv, "--no-figures", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tb-exudyn: error: shipped scenario quick.toml: key "), err
    assert len(err[0]) <= LINE_MAX, (len(err[0]), err[0])
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_modes_at_several_positions_fit_a_screen(capsys):
    """`modes --position` with three positions: one table with a column per position (the issue's 60
    lines); every position's vehicle modes shown, the bridge's lowest mode per direction at each."""
    lines = _printed(capsys, ["modes", "li_zhu_2011", "--position", "0", "50", "100"])
    assert len(lines) <= RESULT_LINES, len(lines)
    head = next(ln for ln in lines if ln.startswith("f_n [Hz] of"))
    assert head.split()[-9:] == ["x", "=", "0", "m", "x", "=", "50", "m", "x", "=", "100", "m"][-9:]
    vertical = next(ln for ln in lines if ln.startswith("bridge vertical, lowest mode")).split()[-3:]
    assert len(vertical) == 3 and all(4.0 < float(f) < 6.0 for f in vertical)  # f1 of the 32 m spans, loaded
