"""The rolling body's exact kernel and its tracks (stability.rolling.methods): switches between
slipping and rolling keep the energy, a slip friction cannot stop goes on, a track is described
in order."""

import math

import numpy as np
import pytest

from stability.rolling.methods import HEAT, MODE, SWITCHES, T_ROLL, X_ROLL, V, track_row
from stability.rolling.model import SHAPES, G, rolling_acceleration, rolls, start_states

from .test_model import SCENE, run


def test_a_member_switches_twice_on_a_track_and_keeps_its_energy():
    """Rolling down a gentle slope, slipping down a steep one (static friction cannot hold it),
    rolling again on the floor: two switches, the first where the steep section starts, at the
    time the rolling acceleration gives; the energy with the heat added back is kept."""
    k, R, mu_s, mu_k = SHAPES["sphere"], 0.1, 0.3, 0.25
    row = track_row(k, R, mu_s, mu_k, angles=(0.2, 1.0, 0.0), starts=(0.5, 1.5))
    assert rolls(0.2, mu_s, k) and not rolls(1.0, mu_s, k)
    x0 = start_states(0.0, 0.0, row[None])
    t_switch = math.sqrt(2 * 0.5 / rolling_acceleration(0.2, k))
    h = 0.0137  # steps never land on an event
    out = run(row, x0, h, 400, save_every=1)
    samples = np.concatenate([x0, out.saved[0]])
    assert out.x_final[0, SWITCHES] == 2 and out.x_final[0, MODE] == 0
    energy = SCENE.invariants["energy"](samples, row)
    assert np.abs(energy).max() < 1e-13 * np.abs(0.5 * samples[:, V] ** 2).max()
    slipping = samples[:, MODE] != 0
    t = np.arange(samples.shape[0]) * h
    assert t[slipping].min() == pytest.approx(t_switch, abs=h)
    assert out.x_final[0, X_ROLL] > 1.5  # rolls again on the floor


def test_a_slip_started_where_kinetic_friction_cannot_stop_it_never_ends():
    """Hysteresis: with mu_k (1 + 1/k) < tan(theta) <= mu_s (1 + 1/k) a body released at rest
    rolls, a body nudged into a forward slip slips for ever; below that band the slip ends at
    t = u0 / (mu_k g cos (1 + 1/k) - g sin)."""
    k, R, mu_s, mu_k = SHAPES["cylinder"], 0.05, 0.3, 0.2
    band = math.atan(0.5 * (mu_k + mu_s) * (1 + 1 / k))
    below = math.atan(0.5 * mu_k * (1 + 1 / k))
    rows = np.array([track_row(k, R, mu_s, mu_k, angles=(a,)) for a in (band, band, below)])
    x0 = start_states(np.array([0.0, 0.1, 0.1]), 0.0, rows)
    out = run(rows, x0, 2.0, 3).x_final
    assert out[0, HEAT] == 0.0 and out[0, MODE] == 0  # at rest: rolls
    assert out[1, MODE] == 1 and out[1, SWITCHES] == 0  # nudged: slips on
    rate = G * (mu_k * math.cos(below) * (1 + 1 / k) - math.sin(below))
    assert out[2, T_ROLL] == pytest.approx(0.1 / rate, rel=1e-14)


def test_a_track_must_be_described_in_order():
    with pytest.raises(ValueError, match="must ascend"):
        track_row(0.4, 0.1, 0.3, 0.2, angles=(0.1, 0.2, 0.3), starts=(2.0, 1.0))
    with pytest.raises(ValueError, match="one start fewer"):
        track_row(0.4, 0.1, 0.3, 0.2, angles=(0.1, 0.2), starts=())
