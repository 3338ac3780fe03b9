"""Hostile inputs of issue 27 ("model guards" and "Python API") as data, in the form of cases.py.

Sizes a user can type that made a run or ``tb-exudyn modes`` allocate without bound or fail inside a
library (a crawling speed, a huge lead-in, 1000 spans, 200 or 2000 vehicles, a degenerate bridge), and
Python calls that took wrong values silently (``Scenario.replace`` with a str, a bool, NaN, 8.5 or a
dict; ``bounds(k=nan)``). Every case ends in exit status 2 with one line naming the file (or the
function) and the key, no traceback, and nothing written (tests/reliability/test_guards.py).
The cases that would allocate without bound if their defence failed are ``isolate=True`` (a
subprocess with 2 GB of address space and 60 s).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from .cases import Case, Run, rr_arrays, rr_meta, write_result

GROUP = "guards"

#: the quick scenario's girder (models/bridges/single_span_32m.toml), inline
GIRDER = """[bridge.girder]
E = {E}
G = 1.4375e10
area = 8.8889
I_y = 10.947
I_z = 86.216
J = 22.650
mass_per_length = 33900.0
rot_mass_per_length = 383040.5
"""


def _scenario(d: Path, *, speed: float = 250.0, lead_in: float = 85.0, vehicles: int = 1, spans: str = "",
              E: str = "3.45e10", bridge: str = "single_span_32m") -> Path:
    """A scenario like quick (one ICE motor car, one 32 m span) with the given sizes; ``spans``: an
    inline bridge with these spans (TOML list) and girder modulus ``E``, else the ``bridge`` named."""
    bridge = f'bridge = "{bridge}"\n' if not spans else ""
    inline = (f'[bridge]\nkind = "simple_beam"\nname = "b"\nspans = {spans}\ndamping_ratio = 0.05\n'
              + GIRDER.format(E=E)) if spans else ""
    cars = ", ".join(['"ice_motor"'] * vehicles)
    text = (f'name = "guard"\nspeed_kmh = {speed!r}\n{bridge}\n{inline}\n[train]\nvehicles = [{cars}]\n\n'
            f'[track]\nirregularities = ["german_low.vertical"]\nlead_in = {lead_in!r}\nrun_out = 10.0\n\n'
            '[analysis]\nmode_max_frequency = 60.0\n')
    p = d / "sc.toml"
    p.write_text(text)
    return p


def _modes(p: Path) -> tuple[str, ...]:
    return ("modes", str(p))


def _run(p: Path, d: Path) -> tuple[str, ...]:
    return ("run", str(p), "--out", str(d / "out"), "--no-figures", "--no-progress")


# ------------------------------------------------------------------------------------ run length
def _modes_crawling(d: Path) -> Run:
    p = _scenario(d, speed=0.001)
    return Run(argv=_modes(p), expect=(str(p), "'speed_kmh'", "steps"), isolate=True)


def _run_crawling(d: Path) -> Run:
    p = _scenario(d, speed=0.001)
    return Run(argv=_run(p, d), expect=(str(p), "'speed_kmh'", "steps"), isolate=True)


def _modes_lead_in(d: Path) -> Run:
    p = _scenario(d, lead_in=1e9)
    return Run(argv=_modes(p), expect=(str(p), "'track.lead_in'"), isolate=True)


# ------------------------------------------------------------------------------------ model sizes
def _modes_1000_spans(d: Path) -> Run:
    p = _scenario(d, spans="[" + ", ".join(["32.0"] * 1000) + "]")
    return Run(argv=_modes(p), expect=(str(p), "'bridge.spans'", "1000 spans", "such spans at most"), isolate=True)


def _run_1000_spans(d: Path) -> Run:
    p = _scenario(d, spans="[" + ", ".join(["32.0"] * 1000) + "]")
    return Run(argv=_run(p, d), expect=(str(p), "'bridge.spans'"), isolate=True)


def _modes_200_vehicles(d: Path) -> Run:
    """200 cars: 8414 coordinates, 5.7 GB of linearised matrices, refused under the 2 GB limit."""
    p = _scenario(d, vehicles=200)
    return Run(argv=_modes(p), expect=(str(p), "'train.vehicles'", "such vehicles"), isolate=True)


def _run_2000_vehicles(d: Path) -> Run:
    """2000 cars: 84 000 coordinates, 565 GB: refused on any machine."""
    p = _scenario(d, vehicles=2000)
    return Run(argv=_run(p, d), expect=(str(p), "'train.vehicles'"), isolate=True)


# ------------------------------------------------------------------------------------ degenerate bridges
def _modes_micro_span(d: Path) -> Run:
    p = _scenario(d, spans="[1e-6]")
    return Run(argv=_modes(p), expect=(str(p), "'bridge.spans[0]'", "1 m <= span"))


def _run_soft_girder(d: Path) -> Run:
    p = _scenario(d, spans="[32.0]", E="1e-20")  # below the schema's lower bound: refused on loading
    return Run(argv=_run(p, d), expect=(str(p), "'bridge.girder.E'", "slip of units", ">= 1e+07"))


def _modes_soft_girder(d: Path) -> Run:
    p = _scenario(d, spans="[32.0]", E="1e-20")
    return Run(argv=_modes(p), expect=(str(p), "'bridge.girder.E'", "slip of units", ">= 1e+07"))


def _modes_overflowing_girder(d: Path) -> Run:
    p = _scenario(d, spans="[32.0]", E="1e308")
    return Run(argv=_modes(p), expect=(str(p), "'bridge.girder.E'", "overflow"))


def _bridge_file_soft_girder(d: Path) -> Run:
    """A bridge in its own file: the error names that file and the key inside it."""
    b = d / "soft.toml"
    b.write_text('kind = "simple_beam"\nname = "soft"\nspans = [32.0]\n' + GIRDER.format(E="1e-20").replace("[bridge.", "["))
    p = _scenario(d, bridge="soft.toml")
    return Run(argv=_modes(p), expect=(str(b), "'girder.E'", ">= 1e+07"))


# ------------------------------------------------------------------------------------ Python API
def _replace(change: str) -> str:
    return f"from tb_exudyn import load_scenario; load_scenario('quick').replace({change})"


def _replace_case(change: str, key: str, what: str = "Scenario.replace") -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        return Run(code=_replace(change), expect=(what, f"'{key}'"))
    return build


def _analysis_replace(change: str) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        code = f"from tb_exudyn import load_scenario; load_scenario('quick').analysis.replace({change})"
        return Run(code=code, expect=("Analysis.replace", "'n_freq'"))
    return build


def _bounds(k: str) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        f = write_result(d / "pem", rr_arrays(), rr_meta())
        code = f"from tb_exudyn.results import load_results; load_results({str(f)!r}).bounds(k={k})"
        return Run(code=code, expect=("RandomResponse.bounds", "'k'"))
    return build


CASES_GUARDS: list[Case] = [
    Case("modes at 0.001 km/h", GROUP, _modes_crawling),
    Case("run at 0.001 km/h", GROUP, _run_crawling),
    Case("modes with lead_in 1e9", GROUP, _modes_lead_in),
    Case("modes with 1000 spans", GROUP, _modes_1000_spans),
    Case("run with 1000 spans", GROUP, _run_1000_spans),
    Case("modes with 200 vehicles", GROUP, _modes_200_vehicles),
    Case("run with 2000 vehicles", GROUP, _run_2000_vehicles),
    Case("modes with a 1e-6 m span", GROUP, _modes_micro_span),
    Case("run with girder E 1e-20", GROUP, _run_soft_girder),
    Case("modes with girder E 1e-20", GROUP, _modes_soft_girder),
    Case("modes with girder E 1e308", GROUP, _modes_overflowing_girder),
    Case("bridge file with E 1e-20", GROUP, _bridge_file_soft_girder),
    Case("replace speed_kmh '300'", GROUP, _replace_case("speed_kmh='300'", "speed_kmh")),
    Case("replace speed_kmh True", GROUP, _replace_case("speed_kmh=True", "speed_kmh")),
    Case("replace speed_kmh None", GROUP, _replace_case("speed_kmh=None", "speed_kmh")),
    Case("replace speed_kmh complex", GROUP, _replace_case("speed_kmh=300j", "speed_kmh")),
    Case("replace speed_kmh NaN", GROUP, _replace_case("speed_kmh=float('nan')", "speed_kmh")),
    Case("replace speed_kmh array", GROUP, _replace_case("speed_kmh=__import__('numpy').array([300.0])", "speed_kmh")),
    Case("replace analysis dict", GROUP, _replace_case("analysis={'n_freq': 50}", "analysis")),
    Case("replace n_freq 8.5", GROUP, _analysis_replace("n_freq=8.5")),
    Case("bounds k NaN", GROUP, _bounds("float('nan')")),
    Case("bounds k -3", GROUP, _bounds("-3")),
]
