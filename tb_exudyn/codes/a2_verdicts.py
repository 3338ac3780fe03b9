"""One verdict per criterion of EN 1990 Annex A2.4.4 for `tb-exudyn check`: the deck acceleration of the
moving-force rows, and the static and modal criteria of models/criteria/en1990_a2.toml computed on the bridge
(:mod:`.deformation`, :mod:`.comfort_deflection`).

:func:`a2_verdicts` takes what the check already has (its rows, responses, nominal modes and settings) and
returns :class:`.criteria.CriterionVerdict` records, deck acceleration first. The classified-load factor alpha
is 1.0 unless given (a national annex's choice: the verdicts say so); Phi is Phi_2 for a carefully maintained
track and Phi_3 for standard maintenance (the check's ``maintenance``), with L_Phi of Table 6.2.
"""

from __future__ import annotations

import math
import re
from typing import Mapping, Sequence

import numpy as np

from ..errors import SettingError
from ..results.check_records import CheckRecord
from ..results.checks_table import format_value
from ..scenario.model import Continuous
from .comfort_deflection import comfort_limit
from .criteria import CriterionVerdict, DECK_ACCELERATION_CRITERIA, DECK_LIMIT_SET, load_criteria
from .deformation import (LM71, NOSING_FORCE, StaticDeformations, dynamic_factor, first_lateral_frequency,
                          static_deformations)


#: the classified-load factors of EN 1991-2 6.3.2(3) [recalled, check]
ALPHA_VALUES = (0.75, 0.83, 0.91, 1.00, 1.10, 1.21, 1.33, 1.46)


_STATION = re.compile(r"span(\d+)\.x(\d+)/(\d+)")


def place_words(station: str) -> str:
    """A station name in words: 'span1.x4/8 (16 m)' -> 'span 1, mid-span (16 m)', 'span2.x3/8' -> 'span 2 at 3/8'."""
    def said(m: re.Match) -> str:
        i, n = int(m.group(2)), int(m.group(3))
        return f"span {m.group(1)}, mid-span" if 2 * i == n else f"span {m.group(1)} at {i}/{n}"
    return _STATION.sub(said, station)


def check_alpha(alpha, where: str, key: str = "alpha") -> float:  # noqa: ANN001
    """alpha as given (one of :data:`ALPHA_VALUES`), or 1.0 for None; SettingError naming ``where`` and ``key``."""
    if alpha is None:
        return 1.0
    ok = isinstance(alpha, (int, float)) and not isinstance(alpha, bool) and any(
        abs(float(alpha) - a) < 1e-9 for a in ALPHA_VALUES)
    if not ok:
        raise SettingError(where, key, alpha, "one of " + ", ".join(f"{a:g}" for a in ALPHA_VALUES)
                           + " (EN 1991-2 6.3.2(3)), or none for 1")
    return float(alpha)


def _verdict(crit, value: float, limit: float, case: str, location: str, caveats: str = "",  # noqa: ANN001
             bound: str | None = None) -> CriterionVerdict:
    return CriterionVerdict(criterion=crit.id, title=crit.title, clause=crit.clause.replace("EN 1990:2002+A1:2005 ", "EN 1990 "),
                            load_model=crit.load_model, value=float(value), limit=float(limit), unit=crit.unit,
                            bound=bound or crit.bound, case=case, location=location, caveats=caveats, check=crit.check)


def deck_acceleration_verdict(rows: Sequence[CheckRecord], limit: float, track: str) -> CriterionVerdict:
    """The moving-force rows' largest peak deck acceleration against the limit (EN 1990 A2.4.4.2.1)."""
    r = max(rows, key=lambda x: x.value)
    return CriterionVerdict(
        criterion=f"deck_acceleration ({DECK_LIMIT_SET}/{DECK_ACCELERATION_CRITERIA[track]})",
        title=f"peak deck vertical acceleration, {track} track", clause="EN 1990 Annex A2, A2.4.4.2.1(4)",
        load_model="HSLM / real trains as moving forces", value=float(r.value), limit=float(limit),
        unit="m/s^2", bound="upper", case=f"{r.train} at {r.speed_kmh:.1f} km/h ({r.case} case)",
        location=place_words(str(r.location)), check=True)


def _largest(per_track: Sequence[np.ndarray], limits: Sequence[float] | None = None) -> tuple[int, int, float]:
    """(track, index, value) of the largest value / limit over the tracks' arrays."""
    best = (0, 0, -math.inf, -math.inf)
    for t, arr in enumerate(per_track):
        for i, v in enumerate(np.ravel(arr)):
            u = v / limits[i] if limits is not None else v
            if u > best[3]:
                best = (t, i, float(v), u)
    return best[:3]


def a2_verdicts(bridge, line_speed_kmh: float, track: str, maintenance: str, modal, rows: Sequence[CheckRecord],  # noqa: ANN001
                responses: Sequence, cases: Sequence[str], train_names: Sequence[str], limit: float,
                alpha: float = 1.0, alpha_given: bool = False,
                static: Mapping[tuple[str, ...], StaticDeformations] | None = None) -> tuple[CriterionVerdict, ...]:
    """Every criterion's verdict (see the module docstring). ``modal``: the nominal case's ModalBridge;
    ``responses``: the MovingForceResponse of each (case, train) in that order; ``static``: the static
    deformations already computed (:func:`static_deformations` by its vertical load models' names: () the
    default set, ('LM71',) LM71 alone; the check's tasks), the others computed here."""
    crits = load_criteria()
    phi, phi_basis = dynamic_factor(bridge, maintenance)
    static = dict(static or {})
    sd = static[()] if () in static else static_deformations(bridge)
    spans = np.array(sd.spans)
    a_note = f"alpha = {alpha:g}" + ("" if alpha_given else " (not given: the national annex's classified-load factor)")
    load = f"{' and '.join(sd.loads)} x alpha {alpha:g} x {phi_basis.split(' (')[0]}"
    out = [deck_acceleration_verdict(rows, limit, track)]

    def on(t: int) -> str:  # the loaded track, named on a deck of two tracks or more
        return f" on track {t + 1}" if len(sd.deflection) > 1 else ""

    c = crits.criterion("vertical_deflection")
    t, i, v = _largest(sd.deflection, [c.limit_value(span=s) for s in spans])
    out.append(_verdict(c, alpha * phi * v, c.limit_value(span=spans[i]), f"{load}{on(t)}",
                        f"span {i + 1} at {sd.deflection_x[t][i]:.3g} m", a_note))
    c = crits.criterion("deck_twist_3m")
    t, _, v = _largest([np.array([x]) for x in sd.twist])
    twist_at = f"from x = {sd.twist_x[t]:.3g} m"
    out.append(_verdict(c, alpha * phi * v, c.limit_value(speed_kmh=line_speed_kmh), f"{load}{on(t)}",
                        twist_at, f"the limit of line speed {line_speed_kmh:g} km/h; " + a_note))
    out.append(_dynamic_twist_verdict(crits.criterion("deck_twist_3m_dynamic"), responses, cases, train_names,
                                      line_speed_kmh))
    c = crits.criterion("deck_twist_3m_total")
    out.append(_verdict(c, alpha * phi * v, c.limit_value(), f"{load}{on(t)}", twist_at,
                        "the track's own twist taken as 0 (no cant transition in the bridge data); " + a_note))
    c = crits.criterion("deck_end_rotation")
    t, i, v = _largest(sd.end_rotation)
    out.append(_verdict(c, alpha * phi * v, c.limit_value(), f"{load}{on(t)}",
                        f"{'start' if i == 0 else 'end'} of the bridge",
                        "ENV 1991-3 value: EN 1990 A2 leaves the limit to the national annex; " + a_note))
    c = crits.criterion("deck_end_rotation_between_decks")
    if any(j.size for j in sd.joint_rotation):
        t, i, v = _largest(sd.joint_rotation)
        out.append(_verdict(c, alpha * phi * v, c.limit_value(), f"{load}{on(t)}",
                            f"joint after span {i + 1}", "ENV 1991-3 value; " + a_note))
    else:
        out.append(_verdict(c, math.nan, c.limit_value(), "-", "-", "no joint between simply supported spans"))
    lateral_note = ("nosing force only (EN 1991-2 6.5.2, 100 kN x alpha): wind, centrifugal forces (straight track) "
                    "and a transverse temperature difference not applied; " + a_note)
    c = crits.criterion("horizontal_rotation")
    t, i, v = _largest(sd.horizontal_rotation)
    out.append(_verdict(c, alpha * v, c.limit_value(speed_kmh=line_speed_kmh),
                        f"nosing force {alpha * NOSING_FORCE / 1e3:g} kN{on(t)}",
                        f"span {i // 2 + 1} {'start' if i % 2 == 0 else 'end'}", lateral_note))
    c = crits.criterion("horizontal_radius_single_deck" if spans.size == 1 else "horizontal_radius_multi_deck")
    t, i, v = _largest(sd.lateral, list(spans**2))  # the smallest radius: the largest delta / L^2
    radius = spans[i] ** 2 / (8.0 * alpha * v) if v > 0 else math.inf
    out.append(_verdict(c, radius, c.limit_value(speed_kmh=line_speed_kmh),
                        f"nosing force {alpha * NOSING_FORCE / 1e3:g} kN{on(t)}",
                        f"span {i + 1}", f"r = L^2 / (8 delta_h), delta_h = {format_value(alpha * v, 'm')}; "
                        + lateral_note))
    c = crits.criterion("lateral_frequency")
    f_lat = first_lateral_frequency(modal.frequencies, modal.mode_types)
    out.append(_verdict(c, f_lat, c.limit_value(), "modes of the nominal mass case", "the bridge's first lateral mode",
                        "" if math.isfinite(f_lat) else f"no lateral mode among the {modal.n_modes} computed"))
    c = crits.criterion("comfort_deflection")
    n_spans, cont = spans.size, isinstance(bridge, Continuous)
    lims = [comfort_limit(s, line_speed_kmh, n_spans, cont) for s in spans]
    comfort_sd = sd if sd.loads == (LM71.name,) else static.get((LM71.name,)) or static_deformations(bridge, (LM71,))
    # (LM71 only: A2.4.4.3.2)
    comfort_load = f"LM71 x {phi_basis.split(' (')[0]} (alpha = 1), one track"
    if all(math.isfinite(x) for x in lims):
        t, i, v = _largest(comfort_sd.deflection, lims)
        out.append(_verdict(c, phi * v, lims[i], f"{comfort_load.split(' (')[0]}{on(t)}", f"span {i + 1}",
                            f"{comfort_load}; b_v = 1.0 m/s^2 (very good comfort) at {line_speed_kmh:g} km/h"))
    else:
        beyond = [f"line speed {line_speed_kmh:g} km/h: Figure A2.3's curves above 220 km/h are not digitised"
                  ] if line_speed_kmh > 220.0 else []
        beyond += [f"span {s:g} m beyond the figure's 120 m" for s in spans if s > 120.0]
        out.append(_verdict(c, math.nan, math.nan, comfort_load, "-",
                            "; ".join(beyond or ["outside Figure A2.3 as digitised"]) + ": A2.4.4.3.3 asks a dynamic "
                            "vehicle-bridge analysis of the car-body acceleration instead"))
    out.append(_envelope_verdict(crits.criterion("dynamic_factor_envelope"), rows, responses, cases, train_names,
                                 alpha * phi * np.max([d.max() for d in sd.deflection[:1]]), load))
    return tuple(out)


def _dynamic_twist_verdict(c, responses, cases, train_names, line_speed_kmh: float) -> CriterionVerdict:  # noqa: ANN001
    """The largest twist peak of the moving-force responses (every train, speed and mass case)."""
    best, where = -1.0, None
    k = 0
    for case in cases:
        for name in train_names:
            resp = responses[k]
            k += 1
            if resp.max_twist.size and resp.max_twist.max() > best:
                s, j = np.unravel_index(int(np.argmax(resp.max_twist)), resp.max_twist.shape)
                best, where = float(resp.max_twist[s, j]), (name, case, float(resp.speeds_kmh[j]), float(resp.twist_x[s]))
    if where is None:
        return _verdict(c, math.nan, math.nan, "-", "-", "no twist station computed")
    name, case, v, x = where
    return _verdict(c, best, c.limit_value(speed_kmh=line_speed_kmh), f"{name} at {v:.1f} km/h ({case} case)",
                    f"from x = {x:.3g} m", "track 1; moving forces on the modes up to the cut-off")


def _envelope_verdict(c, rows, responses, cases, train_names, lm71_phi: float, load: str) -> CriterionVerdict:  # noqa: ANN001
    """6.4.6.5(3): the largest (1 + phi'_dyn + k phi'') y_stat,train over the rows against Phi alpha LM71's
    deflection of the check's track (the track of the moving-force rows: track 1)."""
    static = {}
    k = 0
    for case in cases:
        for name in train_names:
            resp = responses[k]
            static[(case, name)] = float(resp.static_disp[resp.mid_stations].max())
            k += 1
    best = max(rows, key=lambda r: r.enhancement * static[(r.case, r.train)])
    value = best.enhancement * static[(best.case, best.train)] / lm71_phi if lm71_phi > 0 else math.nan
    word = "the dynamic analysis governs" if value > 1.0 else "LM71 x Phi governs"
    return _verdict(c, value, 1.0, f"{best.train} at {best.speed_kmh:.1f} km/h ({best.case} case)",
                    "mid-span deflection, track 1", f"{word}; a comparison, not a limit; 1 + phi'_dyn + k phi'' = "
                    f"{best.enhancement:.3f}, against {load}", bound="compare")


__all__ = ["a2_verdicts", "deck_acceleration_verdict", "place_words"]
