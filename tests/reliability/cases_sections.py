"""Hostile sections per span (issue 29: ``[[girders]]`` of a ``simple_beam`` or ``frame``) as data, in the
form of cases.py: sections not one per span, both ``girder`` and ``girders``, none, a span's section far
too soft (a mechanism that names that span's section), and the same built in Python. Every case ends in
exit status 2 with one line naming the bridge file (or the class) and the key, no traceback, and nothing
written (tests/reliability/test_sections.py).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from .cases import Case, Run
from .cases_cont import PIER, SECTION

GROUP = "sections"


def _bridge(d: Path, kind: str, *, spans: str = "[32.0, 24.0]", girder: bool = False,
            girders: tuple[str, ...] = ("3.45e10", "3.45e10")) -> Path:
    text = f'kind = "{kind}"\nname = "sections"\nsource = "test"\nspans = {spans}\ndamping_ratio = 0.02\n\n'
    if girder:
        text += "[girder]\n" + SECTION.format(E="3.45e10") + "\n"
    for e in girders:
        text += "[[girders]]\n" + SECTION.format(E=e) + "\n"
    if kind == "frame":
        text += PIER + "\n[bearings]\nheight = 2.3\n"
    p = d / "sections.toml"
    p.write_text(text)
    return p


def _scenario(d: Path, bridge: Path) -> Path:
    p = d / "sc.toml"
    p.write_text(f'name = "sections"\nspeed_kmh = 250.0\nbridge = "{bridge.name}"\n\n[train]\nvehicles = ["ice_motor"]\n\n'
                 '[track]\nirregularities = ["german_low.vertical"]\nlead_in = 85.0\nrun_out = 10.0\n\n'
                 '[analysis]\nmode_max_frequency = 40.0\n')
    return p


def _modes_case(expect: tuple[str, ...], kind: str, **bridge) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        b = _bridge(d, kind, **bridge)
        return Run(argv=("modes", str(_scenario(d, b))), expect=(str(b.resolve()),) + expect)
    return build


def _python_one_for_two(d: Path) -> Run:
    code = ("from tb_exudyn.scenario.model import BeamSection, SimpleBeam\n"
            "g = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.65, "
            "mass_per_length=33900.0, rot_mass_per_length=383040.5)\n"
            "SimpleBeam(name='b', spans=(32.0, 24.0), girders=(g,))\n")
    return Run(code=code, expect=("'girders'", "2 sections, one per span"))


CASES_SECTIONS: list[Case] = [
    Case("frame, two sections for three spans", GROUP,
         _modes_case(("'girders'", "3 sections, one per span"), "frame", spans="[32.0, 32.0, 32.0]")),
    Case("simple_beam, girder and girders", GROUP,
         _modes_case(("'girders'", "not both"), "simple_beam", girder=True)),
    Case("simple_beam without a section", GROUP,
         _modes_case(("'girder'", "no girder section"), "simple_beam", girders=())),
    Case("frame, span 2's section E 1e-20", GROUP,
         _modes_case(("'girders[1].E'",), "frame", girders=("3.45e10", "1e-20"))),
    Case("simple_beam, span 1's section E 1e-20", GROUP,
         _modes_case(("'girders[0].E'",), "simple_beam", girders=("1e-20", "3.45e10"))),
    Case("SimpleBeam() with one section for two spans", GROUP, _python_one_for_two),
]
