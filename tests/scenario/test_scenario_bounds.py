"""Physical bounds of a bridge's spans (tb_exudyn/scenario/bounds.py, issue 27): a span shorter than
1 m or longer than 2500 m is refused when the scenario is read or built, naming ``spans[i]``.

Reference: the stated bounds (SPAN_RANGE, with its reason); the limits themselves are accepted.
"""

from __future__ import annotations

import dataclasses

import pytest

from tb_exudyn.scenario import ScenarioError, load_scenario
from tb_exudyn.scenario.bounds import SPAN_RANGE


@pytest.mark.parametrize("spans, index", [((1e-6,), 0), ((32.0, 0.5), 1), ((32.0, 1e9), 1)])
def test_a_span_outside_the_physical_range_is_refused(spans, index):
    bridge = load_scenario("quick").bridge
    with pytest.raises(ScenarioError, match=rf"spans\[{index}\].*1 m <= span <= 2500 m"):
        dataclasses.replace(bridge, spans=spans)
    with pytest.raises(ScenarioError, match=rf"SimpleBeam.replace: key 'spans\[{index}\]'"):
        bridge.replace(spans=spans)


def test_the_bounds_themselves_are_spans():
    bridge = load_scenario("quick").bridge
    assert dataclasses.replace(bridge, spans=SPAN_RANGE).spans == SPAN_RANGE


def test_a_file_with_a_micro_span_names_file_and_key(tmp_path):
    text = load_scenario("quick").source_file
    data = open(text).read().replace('bridge = "single_span_32m"', "")
    data = data.replace("[train]", '[bridge]\nkind = "simple_beam"\nname = "b"\nspans = [32.0, 0.001]\n'
                        "[bridge.girder]\nE = 3e10\nG = 1e10\narea = 1.0\nI_y = 1.0\nI_z = 1.0\nJ = 1.0\n"
                        "mass_per_length = 1e4\nrot_mass_per_length = 1e4\n\n[train]")
    p = tmp_path / "micro.toml"
    p.write_text(data)
    with pytest.raises(ScenarioError) as err:
        load_scenario(p)
    assert str(err.value).startswith(f"{p}: key 'bridge.spans[1]' = 0.001")
