"""The track's supports on a deck (tb_exudyn.system.track_model.track_on_deck): the lowest spring of every
sleeper on the deck ends on the deck's track-line mode shapes at that sleeper.

Problem: ballasted_uic60 (100 supports, 60 m, on rigid ground off the deck) over a simply supported deck
of 20 m from x = 20 m (EI = 1.58e10 N m^2, m = 10 000 kg/m: 5, 20, 45, 80, 125 Hz alone; 2 % damping);
a harmonic force on the rail at mid-span (x = 30 m, mid-bay), 1-30 Hz.

Reference, written here: below the track's own resonances (the sleepers on the ballast, about 140 Hz) the
track passes the force to the deck over a metre or two, so the rail's receptance is the track's on rigid
ground (the FE model of test_track_model.py, checked there) plus the deck's point receptance, the deck's
modes carrying the track's masses on it smeared (rail and sleeper: m_t = 60.21 + 170 / 0.6 = 343.5 kg/m per
rail; omega_j' = omega_j sqrt(m / (m + m_t)), phi_j' = phi_j sqrt(m / (m + m_t))):
alpha = alpha_track + sum_j phi_j'(x)^2 / (omega_j'^2 - omega^2 + 2 i zeta omega_j' omega).

Measured: the first resonance at 4.915 Hz against the reference's 4.916 Hz (0.03 %; without the track's
mass the deck alone has 5.00 Hz, 1.7 % off); away from it (|f / f1' - 1| > 0.1) the difference is within
1.2 % of |alpha_track| + |alpha_deck| (the scale of a sum whose terms cancel near 7.3 Hz, the
anti-resonance). Tolerances: 0.3 % on the resonance (the grid of 0.005 Hz is 0.1 %), 2 % on the rest
(the load's spread over the deck, of the order of (pi spread / L)^2 / 6 ~ 1 %).
"""

from __future__ import annotations

import numpy as np
import pytest

from tb_exudyn.scenario.track_structure import load_track_structure
from tb_exudyn.structure import simply_supported_modes
from tb_exudyn.system.track_model import modal_track, track_model, track_on_deck

L, M, ZETA, X_DECK, X = 20.0, 1.0e4, 0.02, 20.0, 30.0
EI = (2 * np.pi * 5.0 / (np.pi / L) ** 2) ** 2 * M


@pytest.fixture(scope="module")
def case():
    structure = load_track_structure("ballasted_uic60")
    deck = simply_supported_modes([L], EI, 1e3 * EI, 1e3 * EI, M, M, ZETA, 130.0)
    track = track_model(structure, 100, elements_per_bay=4)
    return structure, deck, track, track_on_deck(track, deck, X_DECK)


def _reference(structure, track, freqs: np.ndarray, with_track_mass: bool = True):
    m_t = structure.rail.mass_per_length + structure.chain("rigid")[0][2] / structure.spacing
    m = M + (m_t if with_track_mass else 0.0)
    j = np.arange(1, 6)
    wj = (j * np.pi / L) ** 2 * np.sqrt(EI / m)
    phi2 = 2.0 / (m * L) * np.sin(j * np.pi * (X - X_DECK) / L) ** 2
    w = 2 * np.pi * freqs
    alpha_deck = (phi2[None, :] / (wj[None, :] ** 2 - w[:, None] ** 2 + 2j * ZETA * wj[None, :] * w[:, None])).sum(1)
    return track.receptance(X, freqs), alpha_deck, wj[0] / (2 * np.pi)


def test_the_deck_modes_are_appended_and_off_deck_supports_stay_on_the_ground(case):
    structure, deck, track, on_deck = case
    assert on_deck.n_dof == track.n_dof + deck.n_modes and on_deck.deck_dofs.size == deck.n_modes
    with pytest.raises(ValueError):
        track_on_deck(on_deck, deck, X_DECK)
    with pytest.raises(ValueError, match="rigid"):  # the subgrade's spring must not end on the deck
        track_on_deck(track_model(structure, 10, ground="subgrade"), deck, X_DECK)


def test_rail_receptance_on_the_deck_against_track_plus_deck(case):
    structure, deck, track, on_deck = case
    freqs = np.concatenate([np.linspace(1.0, 12.0, 45), [15.0, 20.0, 30.0]])
    got = on_deck.receptance(X, freqs)
    alpha_t, alpha_d, f1 = _reference(structure, track, freqs)
    away = np.abs(freqs / f1 - 1.0) > 0.1
    err = np.abs(got - alpha_t - alpha_d) / (np.abs(alpha_t) + np.abs(alpha_d))
    assert err[away].max() < 0.02, err[away].max()
    fine = np.linspace(4.8, 5.05, 51)
    peak = fine[np.argmax(np.abs(on_deck.receptance(X, fine)))]
    assert abs(peak / f1 - 1.0) < 0.003, (peak, f1)
    f1_bare = _reference(structure, track, freqs[:1], with_track_mass=False)[2]
    assert abs(peak / f1_bare - 1.0) > 0.01  # the track's mass on the deck shows: the test can fail


def test_the_track_on_the_deck_in_the_couplings_form(case):
    """modal_track of the combined system: the contact's rail row is the rail's (the Hermite rows of the
    combined modes), the deck inside the modes; its static flexibility at x equals the FE's."""
    structure, deck, track, on_deck = case
    mt = modal_track(on_deck)
    z = mt.bridge.rail_shapes(np.array([X])).z[0]
    flex_modal = np.sum(z**2 / mt.bridge.omega**2)
    assert flex_modal == pytest.approx(abs(on_deck.receptance(X, np.array([1e-3]))[0]), rel=1e-6)
