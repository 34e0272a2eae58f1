"""The shared time grids."""

import numpy as np

from armkit._time import even_time_grid, rate_time_grid


def test_even_time_grid_steps_at_most_max_step_and_ends_on_duration():
    np.testing.assert_array_equal(even_time_grid(1.0, 0.3), [0.0, 0.25, 0.5, 0.75, 1.0])
    assert len(even_time_grid(3.0, 0.1)) == 31  # 3.0 / 0.1 = 30.000000000000004 counts as 30 steps
    assert len(even_time_grid(2.0, 1.0 / 50)) == 101
    np.testing.assert_array_equal(even_time_grid(0.001, 1.0), [0.0, 0.001])


def test_rate_time_grid_appends_a_missed_end():
    np.testing.assert_array_equal(rate_time_grid(1.0, 4.0, 1e-9), [0.0, 0.25, 0.5, 0.75, 1.0])
    np.testing.assert_array_equal(rate_time_grid(0.6, 4.0, 1e-9), [0.0, 0.25, 0.5, 0.6])
    assert len(rate_time_grid(3.0, 10.0, 1e-9)) == 31
