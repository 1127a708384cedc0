"""The Kingery–Bulmash fits against Swisdak's (1994) own tables (scaled
to 1 kg: ms, kPa, kPa·ms per kg^(1/3)), their scaling with the charge
mass, and their refusals outside the fitted range."""

import numpy as np
import pytest

from partmesh.cases.errors import InputError
from partmesh.compare.exact import kingery_bulmash as kb
from partmesh.compare.exact.kingery_bulmash import blast_parameters, scaled_value

#: Z, arrival, incident p, reflected p, positive duration, incident impulse, reflected impulse, shock speed
#: (m/kg^1/3, ms, kPa, kPa, ms, kPa ms, kPa ms, km/s): Swisdak 1994, metric table
SWISDAK = [
    (0.2, 0.037, 17310.36, 185301, 0.243, 369.5, 10520, 3.962),
    (0.5, 0.143, 4888, 39422, 0.281, 166.2, 2371, 2.178),
    (1, 0.467, 1354, 8152, 1.72, 236.3, 884.7, 1.196),
    (1.5, 0.989, 551.4, 2511, 2.148, 177.4, 520.7, 0.808),
    (2, 1.693, 283.7, 1058, 2.053, 134.6, 363.8, 0.623),
    (3, 3.546, 115.7, 330.7, 2.819, 92.7, 224.3, 0.48),
    (5, 8.242, 43.23, 100.9, 3.793, 59.31, 125.6, 0.398),
    (8, 16.18, 20.42, 44.05, 4.445, 38.35, 75.25, 0.368),
    (12, 27.21, 11.67, 24.43, 5.074, 26.07, 48.93, 0.357),
    (20, 49.93, 6.102, 12.44, 5.94, 15.89, 28.67, 0.349),
    (40, 107.8, 2.375, 4.775, 7.162, 7.885, 13.85, 0.344),
]
SI = {"arrival_time": 1e-3, "incident_overpressure": 1e3, "reflected_overpressure": 1e3, "positive_duration": 1e-3,
      "incident_impulse": 1.0, "reflected_impulse": 1.0, "shock_speed": 1e3}


@pytest.mark.parametrize("row", SWISDAK, ids=[f"Z{r[0]:g}" for r in SWISDAK])
def test_the_fits_reproduce_swisdaks_table_to_one_percent(row):
    Z, *values = row
    got = blast_parameters(Z, W=1.0)
    for quantity, table in zip(SI, values):
        assert getattr(got, quantity) == pytest.approx(table * SI[quantity], rel=0.01), quantity


def test_times_and_impulses_scale_with_the_cube_root_of_the_charge_and_pressures_do_not():
    W = 1000.0
    one, big = blast_parameters(np.array([2.5, 5.0]), 1.0), blast_parameters(np.array([25.0, 50.0]), W)
    np.testing.assert_allclose(big.scaled_distance, one.scaled_distance, rtol=1e-14)
    for q in ("arrival_time", "positive_duration", "incident_impulse", "reflected_impulse"):
        np.testing.assert_allclose(getattr(big, q), 10.0 * getattr(one, q), rtol=1e-12)
    for q in ("incident_overpressure", "reflected_overpressure", "shock_speed"):
        np.testing.assert_allclose(getattr(big, q), getattr(one, q), rtol=1e-12)


def test_the_overpressure_falls_and_the_arrival_time_grows_with_distance():
    Z = np.geomspace(0.2, 40.0, 400)
    assert np.all(np.diff(scaled_value("incident_overpressure", Z)) < 0)
    assert np.all(np.diff(scaled_value("reflected_overpressure", Z)) < 0)
    assert np.all(np.diff(scaled_value("arrival_time", Z)) > 0)
    assert np.all(scaled_value("reflected_overpressure", Z) > 2.0 * scaled_value("incident_overpressure", Z))


def test_adjacent_ranges_of_a_fit_meet_within_two_and_a_half_percent():
    """(The largest step of Swisdak's fits is the incident impulse's at Z = 2.38, −2.4 %.)"""
    for quantity, (_, ranges) in kb.FITS.items():
        for (_, border, _), _next in zip(ranges, ranges[1:]):
            below, above = scaled_value(quantity, [border, border * (1 + 1e-9)])
            assert above == pytest.approx(below, rel=0.025), (quantity, border)


@pytest.mark.parametrize("distance, W, words", [
    (0.1, 1.0, "must lie in [0.2, 40]"), (50.0, 1.0, "must lie in [0.2, 40]"), (1.0, 0.0, "W must be"),
    (1.0, -2.0, "W must be"), (-1.0, 1.0, "must lie in"),
])
def test_a_distance_or_charge_outside_the_fits_is_refused_in_one_sentence(distance, W, words):
    with pytest.raises(InputError, match=None) as error:
        blast_parameters(distance, W)
    assert words in str(error.value) and str(error.value).count(". ") == 0


def test_a_single_quantity_answers_over_its_own_range():
    assert scaled_value("reflected_impulse", 0.06) > 0
    with pytest.raises(InputError, match=r"\[0.2, 2\.9|\[0.2, 198.5\]"):
        scaled_value("incident_overpressure", 0.1)
    with pytest.raises(InputError, match="quantity must be one of"):
        scaled_value("duration", 1.0)
