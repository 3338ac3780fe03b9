"""The tb-exudyn command: exit status 0 on success, 2 on a user error with one message, no traceback."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from tb_exudyn.cli import main


def test_list_prints_models(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in ("ice_motor", "li_zhu_2011_bridge", "li_zhu_2011", "quick", "german_low.vertical"):
        assert name in out


def test_show_prints_the_resolved_scenario(capsys):
    assert main(["show", "li_zhu_2011"]) == 0
    out = capsys.readouterr().out
    assert "speed_kmh" in out and "220" in out and "km/h" in out
    assert "train.vehicles[0].body.mass" in out and "48000" in out


def test_user_error_exits_2_without_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\nspeed_kmh = -1.0\n')
    assert main(["show", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "speed_kmh" in err and "Traceback" not in err


def test_console_entry_point_as_a_process(tmp_path):
    """python -m tb_exudyn runs the same command; exit codes survive the process boundary."""
    ok = subprocess.run([sys.executable, "-m", "tb_exudyn", "show", "quick"], capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr
    bad = subprocess.run([sys.executable, "-m", "tb_exudyn", "show", "no_such_scenario"], capture_output=True, text=True)
    assert bad.returncode == 2
    assert "no_such_scenario" in bad.stderr and "Traceback" not in bad.stderr


@pytest.mark.parametrize("argv", [[], ["frobnicate"]])
def test_bad_command_line_exits_2(argv):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2


@pytest.mark.exudyn
def test_run_det_and_pem_then_plot_and_report(tmp_path, capsys):
    """tb-exudyn run on a tiny scenario (sprung mass, 3 frequencies): exit 0, results saved, summary
    printed with units, figures and the report written; plot and report work on the saved folder."""
    from tb_exudyn.results import load_results
    from tb_exudyn.scenario import save_scenario

    from .methods.test_pem import sprung_mass_scenario

    sc = sprung_mass_scenario(lead_in=25.0, run_out=2.0, f_min=2.0, f_max=12.0, n_freq=3,
                              channels=("bridge.span1.mid.*", "car1.body.acc_z"))
    path = save_scenario(sc, tmp_path / "tiny.toml")
    out = tmp_path / "out"
    assert main(["run", str(path), "--method", "det", "--out", str(out), "--no-progress"]) == 0
    assert load_results(out / "det").scenario == sc
    assert list((out / "det" / "figures").glob("*.history.png")) and (out / "report.html").exists()
    assert main(["run", str(path), "--engine", "exudyn", "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "key channels" in text and "channels.txt in the output folder" in text and str(out.resolve()) in text and "report.html" in text
    table = (out / "channels.txt").read_text()
    assert "max|mean|+3s" in table and "m/s^2" in table and "2-12 Hz" in table
    assert (out / "pem" / "arrays.npz").exists() and (out / "report.html").exists()
    pngs = list(out.glob("*/figures/*.png"))  # the page's figures of pem/ and of det/ (run before it)
    # the run draws what its page shows and no more: each figure file once in the page (issue 49)
    assert list((out / "pem" / "figures").glob("*.png")) and (out / "report.html").read_text().count('src="data:image/png;base64,') == len(pngs)
    assert f"{len(pngs)} figures and the report" in text
    assert main(["report", str(out)]) == 0
    assert main(["plot", str(out), "--channels", "car1.body.acc_z"]) == 0
    assert main(["run", str(path), "--engine", "batched", "--out", str(tmp_path / "b"), "--workers", "1",
                 "--no-progress", "--no-figures"]) == 0
    exudyn_std, batched_std = load_results(out / "pem").std, load_results(tmp_path / "b" / "pem").std
    assert np.allclose(batched_std, exudyn_std, rtol=0, atol=1e-6 * exudyn_std.max())
    assert main(["run", str(path), "--method", "mc", "--engine", "exudyn", "--samples", "4", "--seed", "7",
                 "--out", str(out), "--workers", "1", "--no-progress", "--no-figures"]) == 0
    assert load_results(out / "mc").n_samples == 4
    capsys.readouterr()
    assert main(["compare", str(out), str(out)]) == 0
    assert "car1.body.acc_z" in capsys.readouterr().out


def test_run_into_an_unwritable_folder_is_a_user_error(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert main(["run", "quick", "--out", str(blocker / "sub")]) == 2
    err = capsys.readouterr().err
    assert "not writable" in err and "Traceback" not in err


@pytest.mark.exudyn
def test_channel_pattern_matching_nothing_is_a_user_error(tmp_path, capsys):
    """A typo in analysis.channels is found when the model is built, before any run: exit 2, the key
    and the pattern in the message, no traceback."""
    import tomllib

    from tb_exudyn.scenario import model_files

    text = model_files("scenarios")["quick"].read_text().replace('"car1.body.*"', '"car1.boddy.*"')
    bad = tmp_path / "typo.toml"
    bad.write_text(text)
    assert "car1.boddy" in tomllib.loads(text)["analysis"]["channels"][1]
    assert main(["run", str(bad), "--method", "det", "--out", str(tmp_path / "o"), "--no-figures"]) == 2
    err = capsys.readouterr().err
    assert "analysis.channels[1]" in err and "car1.boddy.*" in err and "Traceback" not in err


def test_run_figures_all_with_no_figures_is_refused_before_any_work(tmp_path, capsys):
    """`--figures all` (the page with every car's PSD figures) and `--no-figures` contradict: exit 2,
    one line naming the option, nothing written."""
    out = tmp_path / "out"
    assert main(["run", "quick", "--out", str(out), "--figures", "all", "--no-figures"]) == 2
    err = capsys.readouterr().err
    assert "--figures" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
