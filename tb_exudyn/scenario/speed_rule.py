"""The one rule for a run at a speed: ``run --speed-kmh``, every speed of a sweep, the EN check's
stochastic rows (:func:`at_speed`).

A scenario states its band, grid and approach for its own speed v0. At another speed v the same
train runs over the same track, so the rule keeps what the scenario states about the track and
scales what depends on time by r = v / v0:

- **band**: the scenario's ``freq_min`` and ``freq_max`` times r, i.e. the same irregularity
  wavelengths v0 / freq_max .. v0 / freq_min at every speed (the PEM input is a spatial spectrum: a
  band fixed in Hz would analyse other wavelengths at each speed, a band set from the track's whole
  wavelength band would not be the scenario's own band at v0). ``freq_max`` is capped at
  0.1 / ``analysis.time_step`` (ten steps per period, what ``Analysis`` requires): above the speed
  where the cap acts, the shortest wavelengths are left out, and the rule's statement says so. A
  band that keeps no wavelength of the track's band is refused (``freq_min``, "empty frequency band");
- **grid**: the scenario's ``n_freq`` and ``freq_spacing`` (linear nodes land on the same
  wavelengths); an adaptive grid gets at least what its rules need at that speed (its modes, the run's
  length and the train's spread change with the speed: ``analysis_setup(least_count=True)``, done by
  the sweep's runs and by ``run --speed-kmh``);
- **approach**: ``track.lead_in`` kept in seconds above v0 (times r) and in metres below it, so that a
  run started at rest has had as long to settle as at v0, and at least as many metres. The builder's
  warning asks for one period of the slowest vehicle mode on the approach (lead_in >= v / f_min);
  with the approach's time kept, a scenario that meets it at v0 meets it at every speed, and one that
  does not is fixed in the scenario (``--set track.lead_in=...``, then scaled by the same rule).

At v = v0 the rule returns the scenario itself: ``run`` and ``run --speed-kmh v0`` and a sweep's row
at v0 are the same computation, and a row of a sweep at v is ``run --speed-kmh v`` (to round-off of
the column slices, tests/methods/test_sweep.py). The derived scenario's ``notes`` end with
:func:`statement` (it goes with the result); the command line prints it.
"""

from __future__ import annotations

from .errors import ScenarioError
from .model import KMH, Scenario

#: the rule in one line (terminal, report, provenance)
RULE = ("band x v / v0 (the same wavelengths, at most 0.1 / time_step), lead_in x max(1, v / v0), n_freq and "
        "spacing kept (adaptive: at least what v needs)")
#: what the derived scenario's notes start the rule's statement with
NOTE_HEAD = "Speed rule (tb_exudyn.scenario.speed_rule): "


def cap_hz(scenario: Scenario) -> float:
    """The highest band frequency the scenario's time step allows [Hz]."""
    return 0.1 / scenario.analysis.time_step


def at_speed(base: Scenario, speed_kmh: float) -> Scenario:
    """The scenario of a run of ``base`` at ``speed_kmh`` (the module docstring: band and approach
    scaled by v / v0, grid kept); ``base`` itself at its own speed (its band checked as at any other).
    ScenarioError (naming ``base``'s file) for a speed the schema refuses (key ``speed_kmh``), a band
    the time step leaves empty or one that keeps no wavelength of the track's band (key ``freq_min``)."""
    v = float(speed_kmh)
    sc = base if v == base.speed_kmh else base.replace(speed_kmh=v)  # the speed checked first (its key)
    an, tr = base.analysis, base.track
    r = v / base.speed_kmh
    f_min, f_max = an.freq_min * r, min(an.freq_max * r, cap_hz(base))
    ms = v * KMH
    lo, hi = ms / tr.wavelength_max, ms / tr.wavelength_min  # the track's band at v [Hz]
    if not (f_min < f_max and f_min <= hi and f_max >= lo):
        raise ScenarioError(base.where, "freq_min", f_min,
                            f"a band ({an.freq_min:g}-{an.freq_max:g} Hz x {r:.4g}, <= {cap_hz(base):g} Hz) in "
                            f"{lo:.4g}-{hi:.4g} Hz",
                            f"empty frequency band {f_min:.4g}-{f_max:.4g} Hz")
    if sc is base:
        return base
    sc = sc.replace(track=tr.replace(lead_in=max(tr.lead_in, tr.lead_in * r)),
                    analysis=an.replace(freq_min=f_min, freq_max=f_max))
    note = NOTE_HEAD + statement(base, sc, grid=False)
    return sc.replace(notes=f"{base.notes}\n{note}" if base.notes else note)


def statement(base: Scenario, sc: Scenario, grid: bool = True) -> str:
    """What the rule made of ``base`` at ``sc``'s speed, in one sentence: "at 300 km/h from li_zhu_2011
    at 220 km/h: band 0.3-60 Hz x 1.364 = 0.409-81.8 Hz (wavelengths 1.02-204 m), 200 linear
    frequencies, approach 100 m -> 136 m (1.64 s)" (and the cap, where it acts; ``grid``: with the
    grid of ``sc``)."""
    v, v0 = sc.speed_kmh, base.speed_kmh
    a, b = base.analysis, sc.analysis
    head = f"at {v:g} km/h from {base.name} at {v0:g} km/h"
    if v == v0:
        return f"{head}: the scenario as it is"
    r = v / v0
    nodes = f"{b.n_freq} {b.freq_spacing} frequencies, " if grid else ""
    band = (f"band {a.freq_min:g}-{a.freq_max:g} Hz x {r:.4g} = {b.freq_min:.3g}-{b.freq_max:.3g} Hz "
            f"(wavelengths {sc.speed / b.freq_max:.3g}-{sc.speed / b.freq_min:.3g} m)")
    if capped(base, sc):
        band += (f", capped at 0.1 / analysis.time_step: wavelengths {base.speed / a.freq_max:.3g}-"
                 f"{sc.speed / b.freq_max:.3g} m left out")
    t_in = sc.track.lead_in / sc.speed
    approach = f"approach {base.track.lead_in:g} m -> {sc.track.lead_in:.4g} m ({t_in:.3g} s)"
    return f"{head}: {band}, {nodes}{approach}"


def capped(base: Scenario, sc: Scenario) -> bool:
    """Whether the rule cut ``sc``'s band at 0.1 / time_step (shorter wavelengths than ``base``'s left out)."""
    r = sc.speed_kmh / base.speed_kmh
    return sc.analysis.freq_max < base.analysis.freq_max * r * (1 - 1e-12)


__all__ = ["NOTE_HEAD", "RULE", "at_speed", "cap_hz", "capped", "statement"]
