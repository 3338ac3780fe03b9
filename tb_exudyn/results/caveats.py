"""What a model can answer and when a caveat is a condition (used by :mod:`tb_exudyn.results.checks`).

A criterion on a quantity the result's vehicle model cannot give is NOT EVALUATED
(:data:`MODEL_REQUIREMENTS`, :func:`unmet_requirement`). A caveat whose effect on the estimate is a
number is a condition only where that number can carry the estimate across the limit
(:func:`can_turn`, :func:`judged`; a loss of contact by its probability, :func:`contact_judged`);
docs/verdicts.md gives the rules with measured numbers.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from .checks_table import Caveat

_CAR_ANY = re.compile(r"car(\d+)\.")


@dataclass(frozen=True)
class ModelRequirement:
    """What a vehicle model must be to answer criteria on some quantities.

    quantities : the quantities (tb_exudyn.scenario.limits.QUANTITIES) it concerns
    vehicle_kinds : the vehicle kinds whose channels can answer them
    reason : why another kind cannot (``{kind}`` is replaced by the vehicle's kind)
    instead : what to run instead
    """

    quantities: tuple[str, ...]
    vehicle_kinds: tuple[str, ...]
    reason: str
    instead: str


#: Running safety (Q/P, dP/P, H) is decided by the wheel-rail forces of wheelsets that creep forces
#: guide across the rail. In car15 the wheelsets follow the rail laterally, and in the ICE data no
#: primary lateral damping acts on the bogie yaw: its lateral wheel forces are those of an undamped
#: yaw mode held by the rail (on li_zhu_2011 Q/P 4.05 and H 295 kN against the creep cars' 4.4 kN
#: sigma, docs/findings.md section 6). Such a row is NOT EVALUATED, not a verdict.
MODEL_REQUIREMENTS: tuple[ModelRequirement, ...] = (
    ModelRequirement(
        ("derailment_coefficient", "wheel_unloading", "axle_force_y"), ("creep_car",),
        "running safety needs creep-guided wheelsets; {kind} holds them to the rail (bogie yaw undamped)",
        "use creep cars (ice_motor_creep, ice_trailer_creep), e.g. scenario li_zhu_2011_creep"),
)


#: a vehicle kind in a reason's words (the kind's name is what a file's ``kind`` holds)
_KIND_WORDS = {"car15": "the 15-DOF car", "sprung_mass": "a sprung mass", "moving_force": "a moving force",
               "articulated": "the articulated set"}


def unmet_requirement(result: Any, quantity_name: str, channel: str) -> str | None:
    """Why the result's model cannot answer a criterion on ``quantity_name`` at ``channel`` (one
    line: the reason and what to run instead), or None when it can or when the result carries no
    scenario to tell (:data:`MODEL_REQUIREMENTS`)."""
    sc = getattr(result, "scenario", None)
    m = _CAR_ANY.match(channel)
    if sc is None or m is None or not 1 <= int(m.group(1)) <= len(sc.train.vehicles):
        return None
    kind = getattr(sc.train.vehicles[int(m.group(1)) - 1], "kind", "?")
    for req in MODEL_REQUIREMENTS:
        if quantity_name in req.quantities and kind not in req.vehicle_kinds:
            return f"{req.reason.format(kind=_KIND_WORDS.get(kind, kind))}: {req.instead}"
    return None


# ============================================================================================ conditional or a note
def can_turn(estimate: float, limit: float, effect: float, raises_only: bool = False) -> bool | None:
    """Whether a relative change ``effect`` of the estimate (a grid error of sigma, a response still
    growing) could carry it across the limit: |estimate| x effect >= |limit - estimate|. With
    ``raises_only`` (a caveat that can only raise |estimate|, e.g. a ratio's second order) it can turn
    only an estimate below the limit. None when either number is not finite (the caveat then keeps its
    own judgement)."""
    if not (math.isfinite(estimate) and math.isfinite(limit) and math.isfinite(effect)):
        return None
    if raises_only and abs(estimate) >= abs(limit):
        return False
    return abs(estimate) * abs(effect) >= abs(limit - estimate)


def judged(c: Caveat, effect: float | None, estimate: float, limit: float, raises_only: bool = False) -> Caveat:
    """A caveat whose effect on the estimate is known, made conditional only where that effect could
    turn the verdict, with the margin it is compared with in its text (``raises_only``: the caveat can
    only raise |estimate|, so it cannot turn an estimate already beyond the limit)."""
    if effect is None:
        return c
    turn = can_turn(estimate, limit, effect, raises_only)
    if turn is None:
        return c
    margin = abs(limit - estimate) / abs(estimate) if estimate else math.inf
    if raises_only and not turn and abs(estimate) >= abs(limit):
        tail = (f"; it can only raise the estimate (by up to {100 * abs(effect):.2g} %), which is already beyond the "
                "limit: it cannot turn the verdict")
    elif turn:
        tail = (f"; it moves the estimate by up to {100 * abs(effect):.2g} %, more than the {100 * margin:.2g} % "
                "between the estimate and the limit")
    else:
        tail = (f"; it moves the estimate by up to {100 * abs(effect):.2g} %, less than the {100 * margin:.2g} % "
                "between the estimate and the limit: it cannot turn the verdict")
    return Caveat(c.kind, c.text + tail, turn)


#: the Sperling index grows as the acceleration's 0.3 power (W = 0.896 (a^3 F(f) / f)^(1/10),
#: tb_exudyn.system.comfort): a relative change e of sigma changes the index by (1 + e)^0.3 - 1
SPERLING_EXPONENT = 0.3


def effect_on_estimate(quantity_name: str, effect: float | None) -> float | None:
    """A relative change of the channel's sigma as a relative change of the criterion's estimate:
    the same for a level of a Gaussian process (mean + k sigma changes by at most that fraction), the
    0.3 power for a Sperling index (:data:`SPERLING_EXPONENT`)."""
    if effect is None or not quantity_name.startswith("sperling"):
        return effect
    return (1.0 + abs(effect)) ** SPERLING_EXPONENT - 1.0


def contact_judged(c: Caveat, p_loss: float | None, verdict: str, p: float | None, target: float) -> Caveat:
    """A PEM loss-of-contact caveat judged by its probability: the passages past the loss (probability
    p_loss) are not physical, so the true probability of exceeding lies within P -+ p_loss. It can
    turn OK when P + p_loss > target, EXCEEDS when P - p_loss <= target."""
    if p_loss is None or p is None or not c.changes_verdict:
        return c
    turn = (p + p_loss > target) if verdict == "OK" else (p - p_loss <= target)
    tail = (f"; P {p:.2g} -+ {p_loss:.2g} spans the target" if turn else
            f"; P {p:.2g} -+ {p_loss:.2g} stays on one side of the target: it cannot turn the verdict")
    return Caveat(c.kind, c.text + tail, turn)


def window_effect(c: Caveat, result: Any, channel: str) -> tuple[Caveat, float | None]:
    """A Sperling index over a window shorter than the criterion's, with a bound of its effect: a
    longer window averages the same car's acceleration power over more of a run like this one, so the
    index (the power's 0.15 power, the acceleration's 0.3) moves by at most (max sigma^2 / mean
    sigma^2)^0.15 - 1 of the acceleration (``car<k>.body.acc_<d>``) over the run. No bound (None) when
    the acceleration is not in the result."""
    m = re.match(r"(car\d+\.body)\.sperling_([yz])\Z", channel)
    acc = f"{m.group(1)}.acc_{m.group(2)}" if m else ""
    if acc not in result.channels:
        return c, None
    power = np.asarray(result.std[result.index(acc)], dtype=float) ** 2
    mean = float(np.mean(power))
    if not (mean > 0 and np.all(np.isfinite(power))):
        return c, None
    rise = math.sqrt(float(np.max(power)) / mean) - 1.0  # of sigma: effect_on_estimate's 0.3 power makes it the index's
    text = (c.text + f"; the acceleration's power over the run peaks at {float(np.max(power)) / mean:.3g} x its mean"
            f" (unweighted), which bounds the window's effect")
    return Caveat(c.kind, text, c.changes_verdict), effect_on_estimate("sperling", rise)


__all__ = ["MODEL_REQUIREMENTS", "SPERLING_EXPONENT", "ModelRequirement", "can_turn", "contact_judged", "effect_on_estimate",
           "judged", "unmet_requirement", "window_effect"]
