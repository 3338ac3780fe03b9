"""Hostile continuous girders (issue 29, bridge kind ``continuous``) as data, in the form of cases.py.

Bridge files of kind ``continuous`` that give no structural model: a continuous girder without
supports (none, too few, of an unknown kind, the key missing), piers without pier data, girder
sections not one per span (too few, both ``girder`` and ``girders``, none), a fixed bearing at no
support, one span, every bearing free vertically, a span's section far too soft; and the same data
built in Python. Every case ends in exit status 2 with one line naming the bridge file (or the
class) and the key, no traceback, and nothing written (tests/reliability/test_cont.py).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from .cases import Case, Run

GROUP = "continuous"

SECTION = """E = {E}
G = 1.4375e10
area = 8.8889
I_y = 10.947
I_z = 86.216
J = 22.650
mass_per_length = 33900.0
rot_mass_per_length = 383040.5
"""

PIER = """[pier]
height = 15.0

[pier.section]
E = 3.25e10
G = 1.3542e10
area = 19.069
I_y = 12.976
I_z = 66.250
J = 41.0
mass_per_length = 47672.5
rot_mass_per_length = 198065.0
"""


def _bridge(d: Path, *, spans: str = "[32.0, 32.0, 32.0]", supports: str | None = '["pier", "rigid"]',
            girder: bool = True, girders: tuple[str, ...] = (), pier: bool = True, bearings: str = "") -> Path:
    """A continuous bridge file (the quick girder) with the given keys; ``girders``: the moduli E of
    one [[girders]] table each; ``supports`` None: the key left out."""
    text = 'kind = "continuous"\nname = "cont"\nsource = "test"\n'
    text += f"spans = {spans}\n" + (f"supports = {supports}\n" if supports is not None else "")
    text += "damping_ratio = 0.02\n\n"
    if girder:
        text += "[girder]\n" + SECTION.format(E="3.45e10") + "\n"
    for e in girders:
        text += "[[girders]]\n" + SECTION.format(E=e) + "\n"
    if pier:
        text += PIER + "\n"
    if bearings:
        text += "[bearings]\n" + bearings + "\n"
    p = d / "cont.toml"
    p.write_text(text)
    return p


def _scenario(d: Path, bridge: Path) -> Path:
    p = d / "sc.toml"
    p.write_text(f'name = "cont"\nspeed_kmh = 250.0\nbridge = "{bridge.name}"\n\n[train]\nvehicles = ["ice_motor"]\n\n'
                 '[track]\nirregularities = ["german_low.vertical"]\nlead_in = 85.0\nrun_out = 10.0\n\n'
                 '[analysis]\nmode_max_frequency = 40.0\n')
    return p


def _modes_case(expect: tuple[str, ...], **bridge) -> Callable[[Path], Run]:
    def build(d: Path) -> Run:
        b = _bridge(d, **bridge)
        return Run(argv=("modes", str(_scenario(d, b))), expect=(str(b.resolve()),) + expect)
    return build


def _check_without_supports(d: Path) -> Run:
    b = _bridge(d, supports="[]")
    return Run(argv=("check", str(b), "--line-speed-kmh", "300", "--trains", "HSLM-A1", "--out", str(d / "out")),
               expect=(str(b), "'supports'", "without supports"))


def _python_without_supports(d: Path) -> Run:
    code = ("from tb_exudyn.scenario.model import BeamSection, Continuous\n"
            "g = BeamSection(E=3.45e10, G=1.4375e10, area=8.8889, I_y=10.947, I_z=86.216, J=22.65, "
            "mass_per_length=33900.0, rot_mass_per_length=383040.5)\n"
            "Continuous(name='c', spans=(32.0, 32.0), girder=g, supports=())\n")
    return Run(code=code, expect=("'supports'", "without supports", "1 entry 'pier' or 'rigid'"))


def _python_replace_spans(d: Path) -> Run:
    """A third span added by replace without a support for it."""
    code = ("from tb_exudyn.scenario import load_bridge\n"
            "b = load_bridge('continuous_3x32m')\n"
            "b.replace(spans=(32.0, 32.0, 32.0, 32.0))\n")
    return Run(code=code, expect=("Continuous.replace", "'supports'", "3 entries"))


CASES_CONT: list[Case] = [
    Case("continuous girder without supports", GROUP,
         _modes_case(("'supports'", "without supports", "2 entries 'pier' or 'rigid'"), supports="[]")),
    Case("continuous girder, supports key missing", GROUP,
         _modes_case(("'supports'", "missing key"), supports=None)),
    Case("continuous girder, one support for three spans", GROUP,
         _modes_case(("'supports'", "2 entries", "one support per span joint"), supports='["pier"]')),
    Case("continuous girder, support kind 'roller'", GROUP,
         _modes_case(("'supports[1]'", "'pier', 'rigid'"), supports='["pier", "roller"]')),
    Case("continuous girder, piers without pier data", GROUP,
         _modes_case(("'pier'", "no pier data"), pier=False)),
    Case("continuous girder of one span", GROUP,
         _modes_case(("'spans'", "at least two", "'frame'"), spans="[32.0]", supports="[]")),
    Case("continuous girder without a section", GROUP,
         _modes_case(("'girder'", "no girder section"), girder=False)),
    Case("continuous girder, two sections for three spans", GROUP,
         _modes_case(("'girders'", "3 sections, one per span"), girder=False, girders=("3.45e10", "3.45e10"))),
    Case("continuous girder, girder and girders", GROUP,
         _modes_case(("'girders'", "not both"), girders=("3.45e10",) * 3)),
    Case("continuous girder, fixed bearing at support 7", GROUP,
         _modes_case(("'bearings.fixed_support'", "0 ... 3"), bearings="fixed_support = 7")),
    Case("continuous girder, every bearing free vertically", GROUP,
         _modes_case(("'bearings.k_z'", "mechanism"), bearings="k_z = 0.0")),
    Case("continuous girder, span 2's section E 1e-20", GROUP,
         _modes_case(("'girders[1].E'", ">= 1e+07"), girder=False, girders=("3.45e10", "1e-20", "3.45e10"))),
    Case("check of a continuous girder without supports", GROUP, _check_without_supports),
    Case("Continuous() without supports", GROUP, _python_without_supports),
    Case("Continuous.replace with a span more", GROUP, _python_replace_spans),
]
