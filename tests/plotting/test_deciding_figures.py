"""The report's bridge verdict rows link to a figure of their deciding location (issue 26 review,
finding 2: the deck acceleration that decided had no figure). Exact problem: a result whose checks'
worst rows are a deck acceleration (OK), a twist (NOT EVALUATED) and a car-body acceleration (OK).
Reference: the rule itself: bridge channels of evaluated deciding rows, in order; no channel when the
checks cannot be computed (a broken limits file is the run's error, not the figures')."""

from types import SimpleNamespace

from tb_exudyn.errors import ScenarioError
from tb_exudyn.plotting.data import deciding_bridge_channels


def _result(rows=None, error=None):
    def checks():
        if error is not None:
            raise error
        return SimpleNamespace(worst=lambda: [SimpleNamespace(channel=c, verdict=v) for c, v in rows])
    return SimpleNamespace(checks=checks)


def test_the_deciding_bridge_channels_are_drawn():
    rows = [("bridge.span1.q1.acc_z_en1990", "OK"), ("bridge.span2.mid.twist_3m", "NOT EVALUATED"),
            ("car1.body.acc_z", "OK"), ("bridge.span1.q1.acc_z_en1990", "EXCEEDS")]
    assert deciding_bridge_channels(_result(rows)) == ["bridge.span1.q1.acc_z_en1990"]


def test_no_checks_no_extra_figures():
    assert deciding_bridge_channels(_result(error=ScenarioError("limits.toml", "criteria", [], "a criterion"))) == []
    assert deciding_bridge_channels(SimpleNamespace()) == []
