"""The arrival of the first transmitted wave at a wall (the first crossing of
5 % of the peak overpressure) and the running-mean peak of a noisy wall
load, on synthetic records whose answers are known."""

import math

import numpy as np
import pytest
import xarray as xr

from partmesh.cases.blast import WALL_MEAN_WINDOW, wall_load_metrics
from partmesh.compare.metrics import arrival_time, peak, positive_phase, running_peak

P0 = 1e5
DT = 1e-6
T = np.arange(0.0, 3e-3 + 0.5 * DT, DT)
#: the first wave: a jump between two samples to P1, decaying with THETA; a later crest P2 > P1 at T2
T1, P1, THETA = 1.4705e-3, 1.0e5, 1.0e-4
T2, P2 = 2.25e-3, 1.5e5


def series(v, t=T):
    return xr.DataArray(np.asarray(v, float), dims="t_probe", coords={"t_probe": t})


def first_wave_then_higher_crest():
    """Overpressure of a wave train at a wall: a jump at T1 (between two
    samples) to P1, decaying to 0.04 % of P2 by T2, then a higher crest at
    T2 (on a sample); it never returns to ambient in between."""
    first = np.where(T >= T1, P1 * np.exp(-(T - T1) / THETA), 0.0)
    later = np.where(T >= T2, P2 * np.exp(-(T - T2) / THETA), 0.0)
    return first + later


def test_the_arrival_is_the_first_crossing_not_the_rise_of_a_later_higher_crest():
    over = first_wave_then_higher_crest()
    level = 0.05 * over.max()  # 5 % of the raw peak overpressure (the crest and the first wave's tail under it)
    k = int(np.ceil(T1 / DT))  # the first sample of the first wave
    expected = T[k - 1] + level / over[k] * DT  # linear between the last ambient sample and the first above
    assert over[int(round(T2 / DT)) - 1] < level  # the first wave has decayed below the level before the crest
    assert arrival_time(series(P0 + over), P0, crossing="first") == pytest.approx(expected, abs=1e-12)
    # the last crossing before the maximum reads the later crest
    assert arrival_time(series(P0 + over), P0) == pytest.approx(T2, abs=DT)


def test_the_fit_window_follows_the_first_arrival():
    over = first_wave_then_higher_crest()
    res = peak(series(P0 + over), P0, crossing="first")
    phase = positive_phase(series(P0 + over), P0, crossing="first")
    assert phase["truncated"] and phase["start"] == pytest.approx(T[int(np.ceil(T1 / DT)) - 1], abs=1e-12)
    lo, hi = res["window"]
    assert res["arrival"] < lo < hi < T2  # within the first wave, before the later crest
    assert lo == pytest.approx(res["arrival"] + 0.02 * phase["duration"], rel=1e-12)
    # the first wave is a pure exponential there: its fit is exact, carried back to the arrival
    assert res["fitted"] == pytest.approx(P0 + P1 * math.exp(-(res["arrival"] - T1) / THETA), rel=1e-9)
    assert res["raw"] == pytest.approx(P0 + over.max(), rel=1e-12)
    # after the last crossing the window lies on the later crest, and the fit reads it instead
    late = peak(series(P0 + over), P0)
    assert late["window"][0] > T2
    assert late["fitted"] > P0 + 1.4 * P1


def test_scatter_ahead_of_the_front_does_not_make_the_arrival():
    """A particle method's record: white scatter of 10 % of the peak on every
    sample, ahead of the front too, far above the 5 % level."""
    rng = np.random.default_rng(7)
    signal = np.where(T >= T1, P1 * np.exp(-(T - T1) / 1e-3), 0.0)
    noisy = P0 + signal + rng.normal(0.0, 0.1 * P1, T.size)
    level = P0 + 0.05 * (noisy.max() - P0)
    assert T[np.argmax(noisy > level)] < 1e-4  # the plain first crossing is scatter at the start
    ta = arrival_time(series(noisy), P0, crossing="first")
    assert abs(ta - T1) < 25 * DT  # (1 000 seeds: all within 22 samples, 99 % within 6)


def test_a_dip_of_the_scatter_at_the_foot_of_the_front_does_not_end_the_positive_phase():
    """A noisy record crosses the baseline at the foot of its front: with the
    first crossing the phase runs on to the first return after the maximum."""
    rng = np.random.default_rng(3)
    rise, t_end = 2e-4, 2.8e-3  # a front that rises over 0.2 ms, as dsmc's on the deep arrays, and its zero
    signal = np.where((T >= T1) & (T < t_end), P1 * np.minimum((T - T1) / rise, 1.0) * (t_end - T) / (t_end - T1),
                      0.0)
    noisy = P0 + signal + rng.normal(0.0, 0.1 * P1, T.size)
    phase = positive_phase(series(noisy), P0, crossing="first")
    top = T[np.argmax(noisy)]
    assert np.any((T > phase["arrival"]) & (T < top) & (noisy <= P0))  # the scatter dips below on the rise
    assert T1 - 25 * DT < phase["arrival"] < T1 + 0.1 * rise
    assert phase["end"] > top
    # the end is the first sample at or below the baseline after the maximum
    after = np.flatnonzero((T > top) & (noisy <= P0))[0]
    assert T[after - 1] <= phase["end"] <= T[after]


def test_the_wall_arrival_is_read_where_the_fit_cannot_be():
    over = first_wave_then_higher_crest()
    keep = T < T1 + 3 * DT  # the record ends three samples after the front: too short a phase for the fit
    t = T[keep]
    ds = xr.Dataset({"p_probe": (("t_probe", "probe"), (P0 + over[keep])[:, None]),
                     "wall_force": ("t_probe", over[keep] * 0.12), "wall_impulse": ("t_probe", np.zeros(t.size))},
                    coords={"t_probe": t, "probe": ["w"]})
    m = wall_load_metrics(ds, P0)
    assert math.isnan(m["wall_peak_pressure_fitted"]) and math.isnan(m["wall_force_peak_fitted"])
    k = int(np.ceil(T1 / DT))
    level = 0.05 * over[keep].max()
    assert m["wall_arrival_time"] == pytest.approx(T[k - 1] + level / over[k] * DT, abs=1e-12)


def test_the_arrival_rules_are_checked():
    s = series(P0 + first_wave_then_higher_crest())
    with pytest.raises(ValueError, match="crossing"):
        arrival_time(s, P0, crossing="middle")
    for samples in (0, 4, 2.0, True):
        with pytest.raises(ValueError, match="samples"):
            peak(s, P0, crossing="first", samples=samples)


def test_running_peak_of_a_sharp_apex_is_its_window_mean():
    # a triangle of slope s per sample about its apex P: the mean of 21 samples there is P - s (2 * 55) / 21
    k = np.arange(200)
    apex, slope = 120, 3.0
    v = 500.0 - slope * np.abs(k - apex)
    res = running_peak(series(v, k * DT), 21)
    assert res["peak"] == pytest.approx(500.0 - slope * 110.0 / 21.0, rel=1e-12)
    assert res["time"] == pytest.approx(apex * DT, abs=1e-15)
    assert res["samples"] == 21
    with pytest.raises(ValueError, match="samples"):
        running_peak(series(v[:10], k[:10] * DT), 21)


def test_running_peak_of_a_noisy_load_reads_its_mean_peak():
    """dsmc's wall force scatters by about 2 kN/m per sample around a load
    of about 15 kN/m on the deep arrays: the raw maximum is the scatter, the
    running mean of 21 samples follows the load."""
    rng = np.random.default_rng(11)
    load, sigma = 15e3, 2e3
    signal = np.where(T >= T1, load * np.exp(-(T - T1) / 1e-3), 0.0)
    noisy = signal + rng.normal(0.0, sigma, T.size)
    raw = float(noisy.max())
    res = running_peak(series(noisy), 21)
    assert raw > load + 1.5 * sigma  # the raw peak: the largest excursion of the scatter
    assert abs(res["peak"] - load) < 3.5 * sigma / math.sqrt(21)  # within the mean's own scatter
    assert T1 - 20 * DT < res["time"] < T1 + 3e-4


def _wall_record(over, force):
    impulse = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(T))])
    return xr.Dataset({"p_probe": (("t_probe", "probe"), (P0 + over)[:, None]), "wall_force": ("t_probe", force),
                       "wall_impulse": ("t_probe", impulse)}, coords={"t_probe": T, "probe": ["w"]})


def test_wall_loads_read_the_first_transmitted_wave():
    over = first_wave_then_higher_crest()
    height = 0.12
    m = wall_load_metrics(_wall_record(over, over * height), P0)
    k = int(np.ceil(T1 / DT))
    assert m["wall_arrival_time"] == pytest.approx(T[k - 1] + 0.05 * over.max() / over[k] * DT, abs=1e-12)
    ta = m["wall_arrival_time"]
    assert m["wall_peak_pressure_fitted"] == pytest.approx(P0 + P1 * math.exp(-(ta - T1) / THETA), rel=1e-9)
    assert m["wall_force_peak_fitted"] == pytest.approx(height * P1 * math.exp(-(ta - T1) / THETA), rel=1e-9)
    assert m["wall_force_peak_raw"] == pytest.approx(height * over.max(), rel=1e-12)
    # the running mean of WALL_MEAN_WINDOW (21 samples at 1 us) over the later crest's jump: the mean of its
    # first 11 samples after the jump (and the first wave's tail, 0.04 % of P2), less than the raw peak
    n = 2 * int(round(0.5 * WALL_MEAN_WINDOW / DT)) + 1
    assert n == 21
    j = int(round(T2 / DT))
    best = max(np.mean(over[c - 10:c + 11]) for c in range(j - 10, j + 11)) * height
    assert m["wall_force_peak_mean"] == pytest.approx(best, rel=1e-12)
    assert m["wall_force_peak_mean"] < m["wall_force_peak_raw"]
