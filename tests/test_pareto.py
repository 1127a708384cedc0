"""The Pareto front of a speed-versus-error study (partmesh.compare.pareto.pareto_front)."""

import numpy as np
import pytest

from partmesh.compare.pareto import pareto_front


def test_front_by_hand():
    # (seconds, error): a is fastest, d most accurate; b beats c in both; e ties b's time with a larger error;
    # f ties d exactly (neither beats the other: both on the front); g has no error
    seconds = [1.0, 2.0, 3.0, 8.0, 2.0, 8.0, 0.5]
    errors = [0.10, 0.05, 0.06, 0.01, 0.07, 0.01, np.nan]
    np.testing.assert_array_equal(pareto_front(seconds, errors), [True, True, False, True, False, True, False])


def test_front_is_the_running_minimum_of_error_over_time():
    rng = np.random.default_rng(3)
    seconds, errors = rng.uniform(1, 100, 200), rng.uniform(1e-3, 1, 200)
    front = pareto_front(seconds, errors)
    order = np.argsort(seconds)
    running = np.minimum.accumulate(errors[order])
    expected = np.zeros(200, dtype=bool)
    expected[order] = np.concatenate([[True], running[1:] < running[:-1]])
    np.testing.assert_array_equal(front, expected)


def test_front_refuses_mismatched_arrays():
    with pytest.raises(ValueError, match="1D arrays of one length"):
        pareto_front([1.0, 2.0], [0.1])
