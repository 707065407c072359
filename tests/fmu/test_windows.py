"""Window statistics (plateimpact_tools.windows), on hand-made records: no FMU runs."""

import math

import numpy as np

from plateimpact_tools import windows


def test_window_values_split_the_samples_and_the_counts():
    """Two windows of 2 steps of 0.5 s: each holds the samples after its own steps, the impacts of
    the steps ending in it, and the change of the cumulative losses across it."""
    reals = np.zeros((5, len(windows.REALS)))
    reals[:, 0] = [9.0, 3.0, -4.0, 1.0, 1.0]  # corner1: the first sample precedes the windows
    reals[:, 1] = [0.0, 0.0, 5.0, 0.0, -2.0]  # corner2
    reals[:, 2] = [7.0, 1.0, 3.0, 5.0, 5.0]  # energy.total
    reals[:, 3] = [0.0, 1.0, 2.0, 4.0, 8.0]  # energy.damping_loss
    reals[:, 4] = [1.0, 1.0, 1.0, 1.0, 3.0]  # energy.contact_loss
    reals[:, 5] = [0.0, 3.0, 4.0, 0.0, 0.0]  # base.mean_force
    impacts = np.array([5, 1, 0, 0, 2])
    w = windows.window_values(reals, impacts, 1.0, 2)
    assert w["mean_energy"] == [2.0, 5.0]
    assert w["rms_corner"] == [np.sqrt(12.5), 1.0]
    assert w["peak_corner"] == [5.0, 2.0]
    assert w["rms_base_force"] == [np.sqrt(12.5), 0.0]
    assert w["damping_loss_rate"] == [2.0, 6.0]
    assert w["contact_loss_rate"] == [0.0, 2.0]
    assert w["impact_rate"] == [1.0, 2.0]
    # The peak: the largest window's, spread of the window peaks; the others: the mean, σ/√K.
    assert windows.value_and_spread("peak_corner", [5.0, 2.0]) == (5.0, np.std([5, 2], ddof=1))
    assert windows.value_and_spread("impact_rate", [1.0, 2.0]) == (
        1.5,
        np.std([1, 2], ddof=1) / np.sqrt(2),
    )


def test_standard_error_is_the_spread_of_the_mean():
    assert windows.standard_error([1.0, 2.0, 3.0, 4.0]) == np.std([1, 2, 3, 4], ddof=1) / 2
    assert math.isnan(windows.standard_error([5.0]))


def test_the_sweep_window_is_the_last_whole_periods_of_the_last_half():
    """10 Hz over 1 s sampled every 1 ms: 5 whole periods, from 0.5 s (row 500); 0.7 s: 3 periods
    from 0.4 s; 1.5 Hz over 1 s has no whole period in the last half: the last half, N = 0."""
    assert windows.last_whole_periods(10.0, 1.0, 1e-3) == (500, 5)
    assert windows.last_whole_periods(10.0, 0.7, 1e-3) == (400, 3)
    assert windows.last_whole_periods(1.5, 1.0, 1e-3) == (500, 0)


def test_period_blocks_hold_whole_periods_to_the_nearest_step():
    """10 periods of 8 steps (f·h = 1/8) in 4 blocks: periods [0, 2), [2, 5), [5, 8), [8, 10)
    (Python rounds half to even: 2.5 → 2, 7.5 → 8), so 16, 24, 24 and 16 steps; a block past the
    recorded steps is cut short."""
    assert windows.period_blocks(10, 4, 1 / 8, 80) == [(0, 16), (16, 40), (40, 64), (64, 80)]
    assert windows.period_blocks(10, 4, 1 / 8, 50) == [(0, 16), (16, 40), (40, 50)]
