"""Hostile inputs of `tb-exudyn check` (issue 25) as data, in the form of tests/reliability/cases.py:
each case builds its files in a scratch folder and must end in exit status 2 with one line naming the
option (or the file and key), no traceback, and nothing written. Group: "check"."""

from __future__ import annotations

import os
from pathlib import Path

from .cases import Case, Run

GROUP = "check"


def _argv(d: Path, *more: str, line_speed: str = "250", trains: tuple[str, ...] = ("HSLM-A1",)) -> tuple[str, ...]:
    return ("check", "single_span_32m", "--line-speed-kmh", line_speed, "--trains", *trains,
            "--out", str(d / "out"), "--no-figures", *more)


def _line_speed(value: str):
    def build(d: Path) -> Run:
        return Run(argv=_argv(d, line_speed=value), expect=("command line", "--line-speed-kmh", "[1, 600] km/h"))
    return build


def _line_speed_not_a_number(d: Path) -> Run:
    return Run(argv=_argv(d, line_speed="fast"), expect=("--line-speed-kmh", "'fast'", "not a number"))


def _earlier_figure_in_out(d: Path) -> Run:
    (d / "out").mkdir()
    (d / "out" / "check.png").write_bytes(b"png")
    return Run(argv=_argv(d), expect=(str(d / "out"), "check.png", "--overwrite"))


def _line_speed_too_low_for_the_steps(d: Path) -> Run:
    return Run(argv=_argv(d, line_speed="1"), expect=("--line-speed-kmh", "steps"))


def _unknown_train(d: Path) -> Run:
    return Run(argv=_argv(d, trains=("HSLM-A11",)), expect=("--trains", "HSLM-A11", "unknown train", "ice_mttm"))


def _unknown_bridge(d: Path) -> Run:
    return Run(argv=("check", "no_such_bridge", "--line-speed-kmh", "250", "--out", str(d / "out")),
               expect=("BRIDGE", "no_such_bridge", "single_span_32m"))


def _bad_track(d: Path) -> Run:
    return Run(argv=_argv(d, "--track", "gravel"), expect=("--track", "ballasted or direct"))


def _bad_construction(d: Path) -> Run:
    return Run(argv=_argv(d, "--construction", "timber"), expect=("--construction", "prestressed_concrete"))


def _train_file_bad_key(d: Path) -> Run:
    p = d / "train.toml"
    p.write_text('name = "t"\n[[cars]]\nvehicle = "ice_motor"\nwheels = 4\n')
    return Run(argv=_argv(d, trains=(str(p),)), expect=(str(p), "cars[0].wheels", "unknown key"))


def _train_file_unknown_vehicle(d: Path) -> Run:
    p = d / "train.toml"
    p.write_text('name = "t"\n[[cars]]\nvehicle = "no_such_car"\n')
    return Run(argv=_argv(d, trains=(str(p),)), expect=(str(p), "cars[0].vehicle", "no_such_car"))


def _train_file_too_long(d: Path) -> Run:
    p = d / "train.toml"
    p.write_text('name = "t"\n[[cars]]\nvehicle = "ice_motor"\ncount = 100\n')
    return Run(argv=_argv(d, trains=(str(p),)), expect=(str(p), "cars", "1000 m"))


def _train_file_fifo(d: Path) -> Run:
    p = d / "fifo.toml"
    os.mkfifo(p)
    return Run(argv=_argv(d, trains=(str(p),)), expect=(str(p), "FIFO"), isolate=True)


def _train_file_missing(d: Path) -> Run:
    p = d / "missing.toml"
    return Run(argv=_argv(d, trains=(str(p),)), expect=(str(p), "file not found"))


def _hslm_on_a_5_m_span(d: Path) -> Run:
    """A continuous girder with 5 m spans: HSLM-A is for spans from 7 m and HSLM-B for simply supported spans
    (a simply supported 5 m span gets HSLM-B, tests/codes/test_check.py)."""
    p = d / "short.toml"
    text = (Path(__file__).resolve().parents[2] / "models" / "bridges" / "continuous_3x32m.toml").read_text()
    assert "spans = [32.0, 32.0, 32.0]" in text
    p.write_text(text.replace("spans = [32.0, 32.0, 32.0]", "spans = [5.0, 5.0, 5.0]"))
    return Run(argv=("check", str(p), "--line-speed-kmh", "160", "--out", str(d / "out"), "--no-figures"),
               expect=("--trains", "HSLM-B", "7 m"))


def _earlier_check_in_out(d: Path) -> Run:
    (d / "out").mkdir()
    (d / "out" / "check.csv").write_text("train\n")
    return Run(argv=_argv(d), expect=(str(d / "out"), "check.csv", "--overwrite"))


def _out_is_a_file(d: Path) -> Run:
    (d / "out").write_text("not a folder\n")
    return Run(argv=_argv(d), expect=(str(d / "out"), "not writable"))


#: a train of axle loads (four 170 kN axles over a 20 m car), named ``name``
TRAIN = 'name = "{name}"\n[[cars]]\naxles = [0.0, 2.5, 17.5, 20.0]\naxle_load = 170e3\nlength = 25.0\n'


def _two_train_files_with_one_name(d: Path) -> Run:
    a, b = d / "a.toml", d / "b.toml"
    a.write_text(TRAIN.format(name="t"))
    b.write_text(TRAIN.format(name="t").replace("170e3", "190e3"))
    return Run(argv=_argv(d, trains=(str(a), str(b))), expect=("--trains", "two trains named 't'", str(a), str(b)))


def _train_file_named_like_hslm(d: Path) -> Run:
    a = d / "mine.toml"
    a.write_text(TRAIN.format(name="HSLM-A1"))
    return Run(argv=_argv(d, trains=("hslm_a", str(a))), expect=("--trains", "'HSLM-A1'", str(a), "EN 1991-2's"))


def _folder_named_like_an_output(name: str, overwrite: bool):
    def build(d: Path) -> Run:
        (d / "out").mkdir()
        (d / "out" / "check.csv").write_text("train\n")  # an earlier table, left as it is
        (d / "out" / name).mkdir(exist_ok=True)
        return Run(argv=_argv(d, *(("--overwrite",) if overwrite else ())),
                   expect=(str(d / "out"), name, "a directory", "another --out"))
    return build


def _fifo_named_like_an_output(d: Path) -> Run:
    (d / "out").mkdir()
    os.mkfifo(d / "out" / "check.png")
    return Run(argv=_argv(d, "--overwrite"), expect=(str(d / "out"), "check.png", "FIFO", "another --out"),
               isolate=True)


def _out_is_a_fifo(d: Path) -> Run:
    os.mkfifo(d / "out")
    return Run(argv=_argv(d), expect=(str(d / "out"), "FIFO", "allowed: a folder"), isolate=True)


def _out_under_a_file(d: Path) -> Run:
    (d / "file").write_text("x\n")
    return Run(argv=("check", "single_span_32m", "--line-speed-kmh", "250", "--out", str(d / "file" / "out")),
               expect=(str(d / "file" / "out"), str(d / "file"), "not a folder", "allowed: a folder"))


def _out_in_proc(d: Path) -> Run:
    return Run(argv=("check", "single_span_32m", "--line-speed-kmh", "250", "--out", "/proc"),
               expect=("'/proc'", "not writable", "allowed: a folder"))


def _out_in_a_result_folder(sub: str):
    def build(d: Path) -> Run:
        (d / "pem").mkdir()
        for name in ("arrays.npz", "meta.json"):
            (d / "pem" / name).write_bytes(b"{}")
        out = d / "pem" / sub
        return Run(argv=_argv(d)[:-3] + ("--out", str(out), "--no-figures"),
                   expect=(str(out), "inside the result folder", "another --out"))
    return build


def _edited_copy_of_a_shipped_bridge(d: Path) -> Run:
    """single_span_32m's file copied (its name kept) with a 1 m span: no mode below the check's 480 Hz;
    the message names the file given, not 'single_span_32m'."""
    p = d / "edited.toml"
    text = (Path(__file__).resolve().parents[2] / "models" / "bridges" / "single_span_32m.toml").read_text()
    p.write_text(text.replace("spans = [32.0]", "spans = [1.0]"))
    given = f"../{d.name}/edited.toml"  # as typed, relative to the command's folder (the case runs in d/../cwd)
    return Run(argv=("check", given, "--line-speed-kmh", "160", "--trains", "ice_mttm", "--out", str(d / "out")),
               expect=(f"key 'BRIDGE' = {given!r}", "480 Hz", "a longer or more flexible span"))


CASES_EN1991: list[Case] = [
    Case("check: line speed 0", GROUP, _line_speed("0")),
    Case("check: line speed negative", GROUP, _line_speed("-100")),
    Case("check: line speed 601 km/h", GROUP, _line_speed("601")),
    Case("check: line speed nan", GROUP, _line_speed("nan")),
    Case("check: line speed inf", GROUP, _line_speed("inf")),
    Case("check: line speed not a number", GROUP, _line_speed_not_a_number),
    Case("check: line speed too low for the steps", GROUP, _line_speed_too_low_for_the_steps),
    Case("check: unknown train", GROUP, _unknown_train),
    Case("check: unknown bridge", GROUP, _unknown_bridge),
    Case("check: unknown track form", GROUP, _bad_track),
    Case("check: unknown construction type", GROUP, _bad_construction),
    Case("check: train file with an unknown key", GROUP, _train_file_bad_key),
    Case("check: train file naming no vehicle", GROUP, _train_file_unknown_vehicle),
    Case("check: train file 2.5 km long", GROUP, _train_file_too_long),
    Case("check: train file is a FIFO", GROUP, _train_file_fifo),
    Case("check: train file missing", GROUP, _train_file_missing),
    Case("check: HSLM-A on a continuous girder of 5 m spans", GROUP, _hslm_on_a_5_m_span),
    Case("check: an earlier check.csv in --out", GROUP, _earlier_check_in_out),
    Case("check: an earlier check.png in --out", GROUP, _earlier_figure_in_out),
    Case("check: --out is a file", GROUP, _out_is_a_file),
    Case("check: line speed 1e-300", GROUP, _line_speed("1e-300")),
    Case("check: two train files with one name", GROUP, _two_train_files_with_one_name),
    Case("check: a train file named HSLM-A1", GROUP, _train_file_named_like_hslm),
    Case("check: --overwrite onto a folder named check.html", GROUP, _folder_named_like_an_output("check.html", True)),
    Case("check: a folder named check.png in --out", GROUP, _folder_named_like_an_output("check.png", False)),
    Case("check: --overwrite onto a FIFO named check.png", GROUP, _fifo_named_like_an_output),
    Case("check: --out is a FIFO", GROUP, _out_is_a_fifo),
    Case("check: --out under a file", GROUP, _out_under_a_file),
    Case("check: --out is /proc", GROUP, _out_in_proc),
    Case("check: --out is a result folder", GROUP, _out_in_a_result_folder("")),
    Case("check: --out a new folder inside a result folder", GROUP, _out_in_a_result_folder("new")),
    Case("check: an edited copy of a shipped bridge, no mode below 480 Hz", GROUP, _edited_copy_of_a_shipped_bridge),
]
