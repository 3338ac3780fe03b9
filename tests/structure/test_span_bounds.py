"""Physical bounds of a bridge's spans (SPAN_RANGE in tb_exudyn/structure/assembly.py, issue 27): a span
shorter than 1 m or longer than 2500 m gives no bridge model; it is refused with one line naming
``spans[i]`` when the bridge is solved, and by ``tb-exudyn run`` and ``modes`` before any work, in
the scenario's file as ``bridge.spans[i]``.

Reference: the stated bounds (SPAN_RANGE, with its reason); the limits themselves are accepted.
"""

from __future__ import annotations

import dataclasses

import pytest

from tb_exudyn.cli import main
from tb_exudyn.scenario import load_scenario
from tb_exudyn.structure import StructureError, modal_bridge
from tb_exudyn.structure.assembly import SPAN_RANGE, validate_bridge


@pytest.mark.parametrize("spans, index", [((1e-6,), 0), ((32.0, 0.5), 1), ((32.0, 1e9), 1)])
def test_a_span_outside_the_physical_range_is_refused(spans, index):
    bridge = dataclasses.replace(load_scenario("quick").bridge, spans=spans)
    with pytest.raises(StructureError, match=rf"key 'spans\[{index}\]'.*1 m <= span <= 2500 m"):
        modal_bridge(bridge, 60.0)


def test_the_bounds_themselves_are_spans():
    validate_bridge(dataclasses.replace(load_scenario("quick").bridge, spans=SPAN_RANGE))


@pytest.mark.parametrize("span", ["0.001", "1e9"])
def test_a_file_with_a_span_out_of_range_names_file_and_key(tmp_path, capsys, span):
    """A 1e9 m span is named as the bridge's, not as a run too long (its crossing would take 1e10 steps)."""
    data = open(load_scenario("quick").source_file).read().replace('bridge = "single_span_32m"', "")
    data = data.replace("[train]", f'[bridge]\nkind = "simple_beam"\nname = "b"\nspans = [32.0, {span}]\n'
                        "[bridge.girder]\nE = 3e10\nG = 1e10\narea = 1.0\nI_y = 1.0\nI_z = 1.0\nJ = 1.0\n"
                        "mass_per_length = 1e4\nrot_mass_per_length = 1e4\n\n[train]")
    p = tmp_path / "span.toml"
    p.write_text(data)
    assert main(["modes", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"tb-exudyn: error: {p}: key 'bridge.spans[1]' = ") and len(err.splitlines()) == 1, err
