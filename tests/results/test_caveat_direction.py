"""A caveat that can only raise the estimate (a ratio's second order) is a condition of an OK row whose
margin it can cover, never of an EXCEEDS row (issue 26: "conditional" only where a caveat can turn the
verdict by its own numbers).

Exact problem: estimates 0.55 / 0.604 / 0.62 against a limit of 0.6 with a relative effect of 13 %
(the second order of li_zhu_2011_creep's wheel unloading, 4.5 cv^2 with cv = 0.17). Reference: the
rule written here: a two-sided caveat turns the verdict when |estimate| x effect >= |limit - estimate|;
one that only raises |estimate| turns it only from below the limit. Exact comparisons of floats chosen
away from the boundary (margins of 9 %, 0.7 %, 3 % against 13 %)."""

import pytest

from tb_exudyn.results.caveats import can_turn, judged
from tb_exudyn.results.checks_table import Caveat


@pytest.mark.parametrize("estimate, two_sided, raising", [(0.55, True, True), (0.604, True, False), (0.62, True, False),
                                                           (0.40, False, False)])
def test_direction_decides_which_verdicts_a_caveat_can_turn(estimate, two_sided, raising):
    assert can_turn(estimate, 0.6, 0.13) is two_sided
    assert can_turn(estimate, 0.6, 0.13, raises_only=True) is raising


def test_a_raising_caveat_on_an_exceeding_estimate_is_a_note_that_says_why():
    c = judged(Caveat("linear_model", "second order", True), 0.13, 0.604, 0.6, raises_only=True)
    assert not c.changes_verdict
    assert "can only raise the estimate (by up to 13 %)" in c.text and "cannot turn the verdict" in c.text
    below = judged(Caveat("linear_model", "second order", True), 0.13, 0.55, 0.6, raises_only=True)
    assert below.changes_verdict and "more than the 9.1 %" in below.text


def test_a_caveat_without_finite_numbers_keeps_its_own_judgement():
    assert can_turn(float("nan"), 0.6, 0.13, raises_only=True) is None
    assert judged(Caveat("x", "t", True), 0.13, float("nan"), 0.6, raises_only=True).changes_verdict
