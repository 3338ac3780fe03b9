"""The damping guard: the modes inside the analysed band that decay slower than the run lasts.

Such a mode makes sigma near it grow through the run instead of settling, and PEM peaks there depend
on the frequency grid (docs/findings.md, section 4, measures it on the reference study).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from .modes import ModeTable

#: a mode warns when its decay time 1 / (zeta omega_n) exceeds this multiple of the run's duration
DECAY_FRACTION = 1.0
#: kinds of mode the guard never warns about: weak-spring coordinates no irregularity reaches, and
#: zero-frequency motions (below every band)
GUARD_EXEMPT: tuple[str, ...] = ("decoupled", "rigid")


@dataclass(frozen=True)
class RunTimes:
    """The times of a run that the damping guard compares decay times with [s].

    duration : the whole run (first axle at -lead_in until the last is run_out past the bridge)
    bridge_entry, bridge_exit : the first axle reaches the bridge, the last axle leaves it
    """

    duration: float
    bridge_entry: float
    bridge_exit: float

    @property
    def on_bridge(self) -> float:
        """Time the vehicles spend on the bridge (first axle on until last axle off) [s]."""
        return self.bridge_exit - self.bridge_entry


@dataclass(frozen=True)
class DampingWarning:
    """A mode inside the analysed band whose damping is too small for the run.

    mode : its row in the :class:`ModeTable`; label, kind : what moves
    frequency : undamped natural frequency [Hz]; damping_ratio : zeta
    decay_time : 1 / (zeta omega_n) [s] (inf if undamped)
    growth_on_bridge : relative growth of the mode's sigma from the first axle on the bridge to
        the last axle off it, by the envelope (:func:`envelope_growth`)
    channels : channel patterns it affects (:meth:`ModeTable.affected_channels`)
    message : the warning in words, with its consequence
    """

    mode: int
    label: str
    kind: str
    frequency: float
    damping_ratio: float
    decay_time: float
    growth_on_bridge: float
    channels: tuple[str, ...]
    message: str

    def __str__(self) -> str:
        return self.message


def envelope_growth(decay_time: float, t0: float, t1: float) -> float:
    """sigma(t1) / sigma(t0) - 1 of a mode excited from rest at t = 0 by a stationary broadband
    input, by the envelope sigma^2(t) = sigma_inf^2 (1 - exp(-2 t / tau)) (Caughey & Stumpf 1961,
    the oscillating terms of order zeta dropped); tau = inf: sqrt(t1 / t0) - 1 (a random walk)."""
    if t0 <= 0.0:
        return math.inf
    if not math.isfinite(decay_time):
        return math.sqrt(t1 / t0) - 1.0
    return math.sqrt(math.expm1(-2.0 * t1 / decay_time) / math.expm1(-2.0 * t0 / decay_time)) - 1.0


def damping_warnings(
    table: ModeTable,
    band: tuple[float, float],
    run: RunTimes,
    *,
    excited: NDArray[np.bool_] | Sequence[bool] | None = None,
    inputs: Sequence[str] | None = None,
    fraction: float = DECAY_FRACTION,
) -> list[DampingWarning]:
    """Every mode with f_min <= f_n <= f_max whose decay time 1 / (zeta omega_n) is longer than
    ``fraction`` x the run's duration (kinds in :data:`GUARD_EXEMPT` excepted; with ``excited``, a
    bool per coordinate, only modes holding most of their energy on excited coordinates; with
    ``inputs`` and a table with reach, only vehicle modes an input of those groups reaches,
    :meth:`ModeTable.reached`: e.g. not the undamped antisymmetric longitudinal wheelset mode of a
    creep car without longitudinal primary damping, which no irregularity can excite).

    Why this criterion. Under a broadband input starting at rest, a mode's response variance rises
    as sigma^2(t) = sigma_inf^2 (1 - exp(-2 t / tau)) (:func:`envelope_growth`), tau = 1 / (zeta
    omega_n). With tau longer than the run the response never settles: at the end sigma is below
    sqrt(1 - e^-2) = 93 % of its settled value and still rising; for tau >> T it is a random walk
    (variance in proportion to t), so every sigma the mode reaches depends on the run's length (the
    approach), and the PEM response near the mode is as narrow as 1 / T in frequency, so its peaks
    depend on the frequency grid. Measured on li_zhu_2011 (batched PEM, 800 frequencies; the ICE
    bogie yaw modes with test yaw dampers giving tau = 0.25 ... 16 s, and without: 194 s):
    fitting sigma^2(t) = a + b (1 - exp(-2 t / tau_fit)) to car1.axle1.force_y (t >= 0.6 s) gives
    tau_fit = 1.02, 1.99, 3.93, 7.69, 14.8, 191 s for tau = 0.995, 1.98, 3.92, 7.68, 14.8, 194 s, and
    its sigma grows between the first axle on and the last axle off the bridge by 2.0, 10.8, 26.6,
    42.5, 53.8, 68.1 % (envelope: 1.9, 10.8, 26.9, 43.0, 54.5, 69.0 %); see ``docs/findings.md``
    section 4. So the decay time says how much a mode's response grows during a run; a run no
    longer than tau is the point where it has not settled at all. Modes with tau between about a
    fifth of the run and the run still grow on the bridge (by the envelope), but a well-damped mode
    of low frequency (ICE car body roll, 0.45 Hz, zeta 0.18, tau 2 s) is slow because of its
    frequency, not its damping: that is a matter of the approach's length, not of this guard;
    ``fraction`` < 1 makes the guard stricter (each warning states the envelope's growth).

    Contact modes (wheelsets on the stiff contact, ~150-200 Hz, zeta ~0.5) have tau of a few
    milliseconds and the weak springs' modes (0.1 Hz, "decoupled") are never excited: neither warns.
    """
    f_min, f_max = float(band[0]), float(band[1])
    tau = table.decay_time
    limit = fraction * run.duration
    reached = np.ones(len(table), dtype=bool)
    if excited is not None:
        reached = table.shares @ np.asarray(excited, dtype=float) > 0.5
    if inputs is not None and table.reach is not None:
        # the reach is that of the table's train position: a bridge mode with no axle on the bridge
        # is reached later in the run (``excited`` covers the run), a vehicle mode's is the same
        reached &= table.reached(inputs) | np.array([k == "bridge" for k in table.kind])
    out = []
    for i in range(len(table)):
        f = float(table.frequency[i])
        if table.kind[i] in GUARD_EXEMPT or not reached[i] or not (f_min <= f <= f_max) or not tau[i] > limit:
            continue
        z = float(table.damping_ratio[i]) + 0.0  # no "-0"
        channels = table.affected_channels(i)
        growth = envelope_growth(float(tau[i]), run.bridge_entry, run.bridge_exit)
        t_text = "infinite (undamped)" if not math.isfinite(tau[i]) else f"{tau[i]:.3g} s"
        message = (  # what decides first (a terminal shows two lines of it): the mode, its damping, the effect
            f"lightly damped mode at {f:.4g} Hz, damping ratio {z:.2g}: sigma of {', '.join(channels)} grows "
            f"through the run (about {100 * growth:.0f} % on the bridge) instead of settling, as the decay time "
            f"1 / (zeta omega) = {t_text} is longer than the run ({run.duration:.3g} s); it depends on the run's "
            f"length, and PEM peaks near {f:.4g} Hz on the frequency grid (spacing finer than about "
            f"{1.0 / (4.0 * run.duration):.2g} Hz there). The mode: {table.label[i]}"
        )
        out.append(DampingWarning(i, table.label[i], table.kind[i], f, z, float(tau[i]), growth, channels, message))
    return out


def merged_messages(warnings: Sequence[DampingWarning]) -> list[str]:
    """One line per set of equal modes (same frequency and damping to 4 digits, e.g. the same
    bogie mode of identical cars), naming every mode's label and the union of their channels."""
    groups: dict[tuple[str, str], list[DampingWarning]] = {}
    for w in warnings:
        groups.setdefault((f"{w.frequency:.4g}", f"{w.damping_ratio:.4g}"), []).append(w)
    out = []
    for ws in groups.values():
        if len(ws) == 1:
            out.append(ws[0].message)
            continue
        w = ws[0]
        channels = list(dict.fromkeys(c for x in ws for c in x.channels))
        t_text = "infinite (undamped)" if not math.isfinite(w.decay_time) else f"{w.decay_time:.3g} s"
        out.append(
            f"{len(ws)} lightly damped modes at {w.frequency:.4g} Hz, damping ratio {w.damping_ratio:.2g}: sigma "
            f"of {', '.join(channels)} grows through the run (about {100 * w.growth_on_bridge:.0f} % on the "
            f"bridge) instead of settling, as the decay time 1 / (zeta omega) = {t_text} is longer than the run; "
            f"PEM peaks near {w.frequency:.4g} Hz depend on the frequency grid. The modes: "
            f"{'; '.join(x.label for x in ws)}"
        )
    return out


__all__ = ["DECAY_FRACTION", "GUARD_EXEMPT", "DampingWarning", "RunTimes", "damping_warnings", "envelope_growth",
           "merged_messages"]
