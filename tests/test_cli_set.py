"""``--set KEY=VALUE`` (issue 26): any scenario key from the command line, checked as in a file and
recorded in the result; a warning that asks for a change names the --set that makes it."""

from __future__ import annotations

import pytest

import tb_exudyn as tbx
from tb_exudyn.cli import main
from tb_exudyn.cli.text import with_set_hint
from tb_exudyn.scenario.io import parse_setting, with_settings


def test_settings_are_read_through_the_schema():
    """Exact: nested keys, a list index and a bare word; the changed scenario equals the one built by
    replace() (the same values through the same checks)."""
    sc = tbx.load_scenario("quick")
    got = with_settings(sc, [parse_setting("track.lead_in=150"), parse_setting("analysis.freq_spacing=linear"),
                             parse_setting("train.vehicles.0.body.mass=5.0e4")])
    car = sc.train.vehicles[0]
    want = sc.replace(track=sc.track.replace(lead_in=150.0), analysis=sc.analysis.replace(freq_spacing="linear"),
                      train=sc.train.replace(vehicles=(car.replace(body=car.body.replace(mass=5.0e4)),)))
    assert got == want


@pytest.mark.parametrize("setting, expect", [
    ("track.lead_in=abc", "track.lead_in: a number > 0"),
    ("track.lead_inn=3", "lead_in"),  # the keys the table holds
    ("analysis.n_freq=8.5", "analysis.n_freq: an integer"),
    ("train.vehicles.5.body.mass=1", "an index 0 ... 0"),
    ("lead_in", "KEY=VALUE"),
])
def test_a_bad_setting_is_one_line_naming_it(setting, expect, capsys):
    assert main(["show", "quick", "--set", setting]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "'--set'" in err and repr(setting) in err and expect in err, err
    assert "Traceback" not in err


def test_a_setting_is_recorded_in_the_result(tmp_path, capsys):
    """Exact problem: the deterministic run of ``quick`` with --set track.lead_in=120 and a nested
    analysis key; the saved result's scenario holds both values."""
    out = tmp_path / "out"
    assert main(["run", "quick", "--method", "det", "--no-figures", "--no-progress", "--out", str(out),
                 "--set", "track.lead_in=120", "--set", "analysis.output_step=0.02"]) == 0
    result = tbx.load_results(out / "det")
    result = result if not isinstance(result, dict) else next(iter(result.values()))
    assert result.scenario.track.lead_in == 120.0 and result.scenario.analysis.output_step == 0.02


def test_a_warning_asking_for_a_change_names_its_set():
    assert with_set_hint("not settled on the approach: use track.lead_in >= 110 m").endswith(
        "(--set track.lead_in=110)")
    assert with_set_hint("use analysis.time_step <= 0.000125 s or a smaller contact stiffness").endswith(
        "(--set analysis.time_step=0.000125)")
    assert with_set_hint("nothing to change") == "nothing to change"


def test_the_terminal_fits_an_engineers_screen(tmp_path, capsys):
    """Exact problem: ``tb-exudyn run quick`` (PEM, adaptive grid, one car over one span). Reference:
    issue 26's screen, lines of about 100 characters (at most 105: a verdict line with a long
    location) and each warning once in at most two lines; the whole terminal under 50 lines."""
    assert main(["run", "quick", "--out", str(tmp_path / "q"), "--no-figures", "--no-progress"]) == 0
    cap = capsys.readouterr()
    lines = (cap.out + cap.err).splitlines()
    assert len(lines) < 50, len(lines)
    assert max(map(len, lines)) <= 105, max(lines, key=len)
    warnings = [i for i, ln in enumerate(cap.err.splitlines()) if ln.startswith("tb-exudyn: warning:")]
    assert warnings and len(cap.err.splitlines()) <= 2 * len(warnings)
    assert len(set(cap.err.splitlines())) == len(cap.err.splitlines())  # each once


def test_a_long_warning_keeps_its_set_hint():
    from tb_exudyn.cli.text import terminal_warning

    text = with_set_hint("the frequency grid is too coarse for 242 of 559 channels: their max sigma changes by more "
                         "than 1 % when the grid is refined (largest -17 % on car2.bogie1.acc_rz; e.g. car1.body."
                         "disp_y); use analysis.freq_spacing = 'adaptive' or more frequencies (analysis.n_freq)")
    lines = terminal_warning(text)
    assert len(lines) == 2 and max(map(len, lines)) <= 100
    assert lines[-1].endswith("--set analysis.freq_spacing=adaptive") and "(report)" in lines[-1]
