"""Hostile inputs of issue 27 as data (group "bounds"): sweep sizes without bounds, messages that
blamed the wrong thing, and refused runs that left an empty --out folder.

Each case must end as every case of cases.py does: exit status 2, one line naming "command line" and
the option (or the file and the key, or the function and the argument), no traceback, and nothing
under the scratch folder written, moved or deleted: a sweep refused for its settings is refused
before its --out is created (the sweep's checks, tb_exudyn.methods.sweep.check_sweep, come first),
and an --out that existed is left as it was. Cases that would allocate without end if their defence
failed (a series of 1e6 or 1e12 speeds, a line speed of 1e300 km/h in 10 km/h steps, a step of 1e-6
km/h, 1e9 speeds given to run_sweep, 1001 PEM runs) are ``isolate=True``.
"""

from __future__ import annotations

from pathlib import Path

from .cases import Case, Run

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = 'name = "x"\nspeed_kmh = 100.0\nbridge = "single_span_32m"\n[train]\nvehicles = ["car.toml"]\n'


def _sweep(d: Path, *options: str) -> tuple[str, ...]:
    return ("sweep", "quick", *options, "--out", str(d / "out"), "--no-progress", "--no-figures")


def _option(option: str) -> tuple[str, str]:
    return ("command line", f"'{option}'")


# ------------------------------------------------------------------------------------ sweep sizes
def _speeds_million(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "1:1000:0.001"), expect=(*_option("--speeds-kmh"), "speeds"),
               isolate=True)


def _speeds_1e12(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "1:1e12:1"), expect=_option("--speeds-kmh"), isolate=True)


def _speeds_to_inf(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "1:inf:1"), expect=_option("--speeds-kmh"), isolate=True)


def _speeds_step_zero(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "100:200:0"), expect=_option("--speeds-kmh"), isolate=True)


def _speeds_list_too_long(d: Path) -> Run:
    text = ",".join(str(100 + 0.1 * i) for i in range(1001))
    return Run(argv=_sweep(d, "--speeds-kmh", text), expect=(*_option("--speeds-kmh"), "1001 speeds"), isolate=True)


def _line_speed_1e300(d: Path) -> Run:
    return Run(argv=_sweep(d, "--line-speed-kmh", "1e300"), expect=_option("--line-speed-kmh"), isolate=True)


def _line_speed_inf(d: Path) -> Run:
    return Run(argv=_sweep(d, "--line-speed-kmh", "inf"), expect=_option("--line-speed-kmh"), isolate=True)


def _step_tiny(d: Path) -> Run:
    return Run(argv=_sweep(d, "--line-speed-kmh", "300", "--speed-step-kmh", "1e-6"),
               expect=_option("--speed-step-kmh"), isolate=True)


def _step(value: str):  # noqa: ANN202
    def build(d: Path) -> Run:
        return Run(argv=_sweep(d, "--line-speed-kmh", "300", "--speed-step-kmh", value),
                   expect=(*_option("--speed-step-kmh"), value), isolate=True)
    return build


def _speeds_same_key(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "100,100.0000001"),
               expect=(*_option("--speeds-kmh"), "100.0", "100.0000001", "same speed"))


def _n_freq_huge(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "200", "--n-freq", "1000000000"), expect=_option("--n-freq"),
               isolate=True)


def _run_sweep_many(d: Path) -> Run:
    code = ("from tb_exudyn.scenario import load_scenario; from tb_exudyn.methods.sweep import run_sweep; "
            "run_sweep(load_scenario('quick'), range(1, 10**9))")
    return Run(code=code, expect=("run_sweep", "'speeds_kmh'"), isolate=True)


def _en1991_library(d: Path) -> Run:
    code = "from tb_exudyn.methods.sweep import en1991_speeds; en1991_speeds(300.0, 1e-9)"
    return Run(code=code, expect=("en1991_speeds", "'step_kmh'"), isolate=True)


def _speed_too_slow(d: Path) -> Run:
    """0.01 km/h: quick's crossing of 146.9 m takes 5.3e7 steps of 1 ms, above the 1e7 of MAX_STEPS; was
    refused in the speed's task (naming quick.toml's speed_kmh) after checkpoint-sweep/ was written."""
    return Run(argv=_sweep(d, "--speeds-kmh", "0.01,200"), expect=(*_option("--speeds-kmh"), "0.01 km/h", "steps"))


# ------------------------------------------------------------------------------------ what the message names
def _speeds_nan(d: Path) -> Run:
    return Run(argv=_sweep(d, "--speeds-kmh", "nan"), expect=(*_option("--speeds-kmh"), "nan"))


def _run_sweep_nan(d: Path) -> Run:
    code = ("from tb_exudyn.scenario import load_scenario; from tb_exudyn.methods.sweep import run_sweep; "
            "run_sweep(load_scenario('quick'), [200.0, float('nan')])")
    return Run(code=code, expect=("run_sweep", "'speeds_kmh'", "nan"))


def _position_nan(d: Path) -> Run:
    return Run(argv=("modes", "quick", "--position", "nan"), expect=(*_option("--position"), "nan"))


def _speed_1e300(d: Path) -> Run:
    return Run(argv=("run", "quick", "--method", "det", "--speed-kmh", "1e300", "--out", str(d / "out"),
                     "--no-figures"), expect=_option("--speed-kmh"))


def _car_file(d: Path, old: str, new: str) -> Path:
    text = (ROOT / "models" / "vehicles" / "ice_motor.toml").read_text()
    assert text.count(old) == 1, old
    (d / "car.toml").write_text(text.replace(old, new))
    (d / "sc.toml").write_text(SCENARIO)
    return d / "car.toml"


def _secondary_c_z(d: Path) -> Run:
    stage = "[secondary]\nk_z = 4.0e5\nk_y = 4.8e5\n"
    car = _car_file(d, stage + "c_z = 6.0e4", stage + "c_z = 1e30")
    return Run(argv=("run", str(d / "sc.toml"), "--out", str(d / "out"), "--no-figures", "--no-progress"),
               expect=(str(car), "'secondary.c_z'", "1e+30"))


def _primary_k_z(d: Path) -> Run:
    car = _car_file(d, "[primary]\nk_z = 1.04e6", "[primary]\nk_z = 1e30")
    return Run(argv=("run", str(d / "sc.toml"), "--out", str(d / "out"), "--no-figures", "--no-progress"),
               expect=(str(car), "'primary.k_z'"))


def _body_mass(d: Path) -> Run:
    car = _car_file(d, "[body]\nmass = 48000.0", "[body]\nmass = 1e30")
    return Run(argv=("run", str(d / "sc.toml"), "--out", str(d / "out"), "--no-figures", "--no-progress"),
               expect=(str(car), "'body.mass'"))


def _sprung_mass_damping(d: Path) -> Run:
    (d / "car.toml").write_text('kind = "sprung_mass"\nname = "sm"\nmass = 5750.0\nstiffness = 1.595e6\n'
                                'damping = 1e30\nlength = 10.0\n')
    (d / "sc.toml").write_text(SCENARIO)
    return Run(argv=("show", str(d / "sc.toml")), expect=(str(d / "car.toml"), "'damping'"))


# ------------------------------------------------------------------------------------ no empty --out left
def _sweep_refused_in_new_folders(d: Path) -> Run:
    """A key quantity that matches no channel, in an --out whose two parents are missing too: refused by
    the sweep's checks (check_sweep) before any of them is created; was refused by run_sweep after."""
    argv = ("sweep", "quick", "--speeds-kmh", "200", "--channels", "nomatch.*", "--out", str(d / "a" / "b" / "out"),
            "--no-progress", "--no-figures")
    return Run(argv=argv, expect=_option("--channels"))


def _sweep_refused_in_existing_folder(d: Path) -> Run:
    """The same refusal in an --out that existed (empty): kept."""
    (d / "out").mkdir()
    return Run(argv=_sweep(d, "--speeds-kmh", "200", "--channels", "nomatch.*"), expect=_option("--channels"))


def run_refused_in_new_folder(d: Path) -> Run:
    """PEM of a scenario without track irregularities (fryba_moving_force), refused by run_pem after the
    command created --out and its missing parent: not a case of the list, for the folders are removed
    again but the scratch folder's modification time has changed (tests/reliability/test_bounds.py
    compares the names)."""
    return Run(argv=("run", "fryba_moving_force", "--out", str(d / "new" / "out"), "--no-figures", "--no-progress"),
               expect=("fryba_moving_force.toml", "'track.irregularities'"))


def run_refused_by_memory_in_new_folder(d: Path) -> Run:
    """PEM of quick with --max-memory 1KB, refused when its tasks are set up, after the run wrote
    --out/checkpoint/manifest.json (no task finished): not a case of the list, as above."""
    return Run(argv=("run", "quick", "--max-memory", "1KB", "--out", str(d / "new" / "out"), "--no-figures",
                     "--no-progress"), expect=_option("--max-memory"))


CASES_BOUNDS: list[Case] = [
    Case("sweep --speeds-kmh 1:1000:0.001", "bounds", _speeds_million),
    Case("sweep --speeds-kmh 1:1e12:1", "bounds", _speeds_1e12),
    Case("sweep --speeds-kmh 1:inf:1", "bounds", _speeds_to_inf),
    Case("sweep --speeds-kmh 100:200:0", "bounds", _speeds_step_zero),
    Case("sweep --speeds-kmh 1001 speeds", "bounds", _speeds_list_too_long),
    Case("sweep --line-speed-kmh 1e300", "bounds", _line_speed_1e300),
    Case("sweep --line-speed-kmh inf", "bounds", _line_speed_inf),
    Case("sweep --speed-step-kmh 1e-6", "bounds", _step_tiny),
    Case("sweep --speed-step-kmh 0", "bounds", _step("0")),
    Case("sweep --speed-step-kmh -10", "bounds", _step("-10")),
    Case("sweep --speed-step-kmh nan", "bounds", _step("nan")),
    Case("sweep --speeds-kmh 100,100.0000001", "bounds", _speeds_same_key),
    Case("sweep --n-freq 1e9", "bounds", _n_freq_huge),
    Case("sweep --speeds-kmh 0.01 (too many steps)", "bounds", _speed_too_slow),
    Case("run_sweep over 1e9 speeds", "bounds", _run_sweep_many),
    Case("en1991_speeds step 1e-9", "bounds", _en1991_library),
    Case("sweep --speeds-kmh nan", "bounds", _speeds_nan),
    Case("run_sweep NaN speed", "bounds", _run_sweep_nan),
    Case("modes --position nan", "bounds", _position_nan),
    Case("run --speed-kmh 1e300", "bounds", _speed_1e300),
    Case("vehicle secondary.c_z = 1e30", "bounds", _secondary_c_z),
    Case("vehicle primary.k_z = 1e30", "bounds", _primary_k_z),
    Case("vehicle body.mass = 1e30", "bounds", _body_mass),
    Case("sprung mass damping = 1e30", "bounds", _sprung_mass_damping),
    Case("sweep refused: no new empty --out", "bounds", _sweep_refused_in_new_folders),
    Case("sweep refused: existing --out kept", "bounds", _sweep_refused_in_existing_folder),
]
