"""Scalar measures of results (partmesh.compare.metrics), checked against values
worked out by hand or known analytically."""

import math

import numpy as np
import pytest
import xarray as xr
from scipy.ndimage import gaussian_filter1d

from partmesh.compare import schema
from partmesh.compare.metrics import (
    arrival_time,
    conservation_drift,
    errors,
    field_error,
    first_crest,
    measured_unit,
    oblique_shock_angle,
    peak,
    plateau,
    positive_phase,
    shock_fitted_peak,
    shock_position,
    shock_radius,
)


def centres(x0, x1, n):
    h = (x1 - x0) / n
    return x0 + h * (np.arange(n) + 0.5)


def da1(v, x, dim="x"):
    return xr.DataArray(np.asarray(v, float), dims=dim, coords={dim: np.asarray(x, float)})


def da2(v, x, y):
    return xr.DataArray(np.asarray(v, float), dims=("y", "x"), coords={"x": x, "y": y})


def series(t, v):
    return xr.DataArray(np.asarray(v, float), dims="t_probe", coords={"t_probe": np.asarray(t, float)})


# --- field errors ------------------------------------------------------------


def test_field_error_1d_by_hand_with_nan_excluded():
    x = centres(0, 1, 4)
    a = da1([1.0, -2.0, 3.0, np.nan], x)
    b = da1([0.0, 0.0, 0.0, 5.0], x)
    assert field_error(a, b, "L1") == pytest.approx(2.0, abs=1e-15)  # (1 + 2 + 3)/3
    assert field_error(a, b, "L2") == pytest.approx(math.sqrt(14 / 3), abs=1e-15)
    assert field_error(a, b, "Linf") == 3.0
    assert field_error(a, b, "linf") == 3.0


def test_field_error_weights_cells_by_size():
    # centres 0.5, 1.5, 3.0: edges 0, 1, 2.25, 3.75 -> widths 1, 1.25, 1.5
    x = [0.5, 1.5, 3.0]
    a, b = da1([1.0, 2.0, 4.0], x), da1([0.0, 0.0, 0.0], x)
    assert field_error(a, b, "L1") == pytest.approx((1 + 2.5 + 6) / 3.75, abs=1e-15)
    assert field_error(a, b, "L2") == pytest.approx(math.sqrt((1 + 5 + 24) / 3.75), abs=1e-15)


def test_field_error_2d_region_and_mask():
    x, y = centres(0, 2, 2), centres(0, 3, 3)  # x = 0.5, 1.5; y = 0.5, 1.5, 2.5
    X, Y = np.meshgrid(x, y)
    a, b = da2(X + Y, x, y), da2(np.zeros((3, 2)), x, y)
    assert field_error(a, b, "L1") == pytest.approx(2.5, abs=1e-15)  # mean of 1, 2, 2, 3, 3, 4
    assert field_error(a, b, "Linf") == 4.0
    # region y in [1, 3] and x in [0, 1]: cells (0.5, 1.5), (0.5, 2.5) -> 2, 3
    assert field_error(a, b, "L1", region={"x": (0.0, 1.0), "y": (1.0, 3.0)}) == pytest.approx(2.5)
    assert field_error(a, b, "Linf", region={"y": (0.0, 1.0)}) == 2.0
    mask = np.array([[True, False], [False, False], [False, True]])  # values 1 and 4
    assert field_error(a, b, "L2", mask=mask) == pytest.approx(math.sqrt(17 / 2), abs=1e-15)
    # b with its dims in the other order is transposed, not refused
    assert field_error(a, b.transpose("x", "y"), "L1") == pytest.approx(2.5, abs=1e-15)


def test_field_error_refuses_different_grids_naming_the_coordinate():
    x = centres(0, 1, 10)
    a = da1(np.ones(10), x)
    with pytest.raises(ValueError, match="'x'"):
        field_error(a, da1(np.ones(10), x + 1e-9))
    with pytest.raises(ValueError, match="'x'"):
        field_error(a, da1(np.ones(9), x[:9]))
    y = centres(0, 1, 3)
    with pytest.raises(ValueError, match="'y'"):
        field_error(da2(np.ones((3, 10)), x, y), da2(np.ones((3, 10)), x, y * 1.01))
    with pytest.raises(ValueError, match="norm"):
        field_error(a, a, "L3")
    with pytest.raises(ValueError, match="region"):
        field_error(a, a, region={"z": (0, 1)})
    with pytest.raises(ValueError, match="mask"):
        field_error(a, a, mask=np.ones(3, bool))


def test_errors_at_the_last_common_time():
    x = centres(0, 1, 4)

    def run(times, rho, p, method):
        return schema.result(case="sod", method=method, scheme="t", x=x, times=times,
                             fields={"rho": rho, "p": p}, dx=0.25)

    ones = np.ones((3, 4))
    a = run([0.1, 0.2, 0.3], ones * [[1], [2], [3]], ones, "fv")
    ref = run([0.1, 0.2, 0.4], ones * 0.0, np.zeros((3, 4)), "exact")
    ref["p"][1, :] = [0.0, 1.0, 1.0, 1.0]  # at t = 0.2 run p - ref p = (1, 0, 0, 0)
    e = errors(a, ref)
    assert set(e) == {(f, n) for f in ("rho", "p") for n in ("L1", "L2", "Linf")}
    assert e[("rho", "L1")] == pytest.approx(2.0)  # t = 0.2 is the last common time
    assert e[("p", "L1")] == pytest.approx(0.25)
    assert e[("p", "L2")] == pytest.approx(0.5)
    assert e[("p", "Linf")] == pytest.approx(1.0)
    e = errors(a, ref, fields=["rho"], time=0.1, norms=("Linf",))
    assert e == {("rho", "Linf"): pytest.approx(1.0)}
    with pytest.raises(ValueError, match="time"):
        errors(a, ref, time=0.3)
    with pytest.raises(ValueError, match="fields"):
        errors(a, ref, fields=["u"])


# --- shock position and radius -----------------------------------------------


def test_shock_position_of_a_step_is_halfway_between_samples():
    x = centres(0, 1, 100)
    v = da1(np.where(x < 0.4, 3.0, 1.0), x)  # jump between x = 0.395 and 0.405
    assert shock_position(v, "gradient") == pytest.approx(0.4, abs=1e-12)
    assert shock_position(v, "threshold", level=2.0) == pytest.approx(0.4, abs=1e-12)
    assert shock_position(v, "threshold") == pytest.approx(0.4, abs=1e-12)  # default level = 2


def test_shock_position_threshold_is_exact_on_a_ramp_and_picks_the_outermost():
    x = centres(0, 1, 50)
    # a linear ramp from 1 (x <= 0.3) up to 4 (x >= 0.6): level 2 is crossed at 0.4 exactly
    v = da1(np.clip(1 + 10 * (x - 0.3), 1, 4), x)
    assert shock_position(v, "threshold", level=2.0) == pytest.approx(0.4, abs=1e-12)
    # a bump 1 -> 2 -> 1 with jumps at x = 0.3 and 0.7 (cell faces)
    bump = da1(np.where((x > 0.3) & (x < 0.7), 2.0, 1.0), x)
    assert shock_position(bump, "threshold", level=1.5) == pytest.approx(0.7, abs=1e-12)
    assert shock_position(bump, "threshold", level=1.5, direction=-1) == pytest.approx(0.3, abs=1e-12)


@pytest.mark.parametrize("x0", [0.4, 0.4013, 0.4037, 0.405, 0.4071])
@pytest.mark.parametrize("width", [1.0, 2.0, 3.0])
def test_shock_position_is_sub_cell_on_a_smooth_front(x0, width):
    dx = 0.01
    x = centres(0, 1, 100)
    v = da1(1 + np.tanh((x0 - x) / (width * dx)), x)  # steepest and mid-level at x0
    assert abs(shock_position(v, "gradient") - x0) < 0.1 * dx
    assert abs(shock_position(v, "threshold", level=1.0) - x0) < 0.1 * dx


def test_shock_position_along_a_radius_and_with_solids():
    r = centres(0, 2, 40)
    v = np.where(r < 1.2, 5.0, 1.0)
    v[5:8] = np.nan  # a solid: dropped
    assert shock_position(da1(v, r, dim="r")) == pytest.approx(1.2, abs=1e-12)
    with pytest.raises(ValueError, match="level"):
        shock_position(da1(v, r, dim="r"), "threshold", level=7.0)
    with pytest.raises(ValueError, match="method"):
        shock_position(da1(v, r, dim="r"), "fit")
    with pytest.raises(ValueError, match="direction"):
        shock_position(da1(v, r, dim="r"), "threshold", direction=0)


@pytest.mark.parametrize("R", [0.5, 0.5037, 0.5071])
def test_shock_radius_quarter_domain(R):
    n = 200
    dx = 1.0 / n
    x = y = centres(0, 1, n)
    X, Y = np.meshgrid(x, y)
    r = np.hypot(X, Y)
    smooth = da2(1.0 + 1.5 * (1 + np.tanh((R - r) / (1.5 * dx))), x, y)  # ambient 1, peak 4
    assert abs(shock_radius(smooth) - R) < 0.05 * dx
    assert abs(shock_radius(smooth, method="gradient") - R) < 0.1 * dx
    sharp = da2(np.where(r < R, 4.0, 1.0), x, y)
    assert abs(shock_radius(sharp) - R) < 0.25 * dx


def test_front_radius_finds_the_air_shock_ahead_of_a_hotter_driver():
    # a driver at 10 (edge 0.3) behind an air shock at 3 (front 0.7) over ambient 1:
    # the plain threshold (level 5.5) finds the driver's edge, "front" (level 2) the shock
    n = 200
    dx = 1.0 / n
    x = y = centres(0, 1, n)
    X, Y = np.meshgrid(x, y)
    r = np.hypot(X, Y)
    f = 1.0 + 1.0 * (1 + np.tanh((0.7 - r) / (1.5 * dx))) + 3.5 * (1 + np.tanh((0.3 - r) / (1.5 * dx)))
    assert abs(shock_radius(da2(f, x, y)) - 0.3) < 2 * dx
    assert abs(shock_radius(da2(f, x, y), method="front") - 0.7) < 0.1 * dx
    # on a single front both readings agree
    single = da2(1.0 + 1.5 * (1 + np.tanh((0.6 - r) / (1.5 * dx))), x, y)
    assert abs(shock_radius(single, method="front") - shock_radius(single)) < 1e-12


def test_shock_radius_full_domain_off_centre_with_a_solid():
    n = 160
    dx = 2.0 / n
    x = y = centres(-1, 1, n)
    X, Y = np.meshgrid(x, y)
    xc, yc, R = 0.1, -0.05, 0.6
    r = np.hypot(X - xc, Y - yc)
    f = 1.0 + 2.0 * (1 + np.tanh((R - r) / (2 * dx)))
    f[(np.abs(X + 0.6) < 0.05) & (np.abs(Y) < 0.05)] = np.nan
    assert abs(shock_radius(da2(f, x, y), centre=(xc, yc)) - R) < 0.05 * dx
    # an explicit level halfway between 1 and 5 gives the same front
    assert abs(shock_radius(da2(f, x, y), centre=(xc, yc), level=3.0) - R) < 0.05 * dx


# --- probe series ------------------------------------------------------------


def test_arrival_time_on_a_ramp():
    t = np.linspace(0, 3, 31)  # dt = 0.1
    v = 2.0 + 10.0 * np.clip(t - 1.0, 0.0, 1.0)  # rises from 2 at t = 1 to 12 at t = 2
    s = series(t, v)
    assert arrival_time(s, 2.0) == pytest.approx(1.05, abs=1e-12)  # level 2.5
    assert arrival_time(s, 2.0, threshold_fraction=0.5) == pytest.approx(1.5, abs=1e-12)
    with pytest.raises(ValueError, match="threshold_fraction"):
        arrival_time(s, 2.0, threshold_fraction=1.5)
    with pytest.raises(ValueError, match="baseline"):
        arrival_time(s, 20.0)
    with pytest.raises(ValueError, match="series"):
        arrival_time(xr.DataArray(np.ones((3, 2)), dims=("t_probe", "probe")), 0.0)


def test_arrival_time_ignores_a_noise_spike_ahead_of_the_front():
    # a step from 1 to 11 at t = 2.0 (crossing the 5 % level 1.5 between samples 2.0 and 2.1), with a spike to 3
    # at t = 0.5 and a dip behind the peak: the front's own crossing counts, not the spike's
    t = np.linspace(0, 3, 31)
    v = np.where(t > 2.05, 11.0, 1.0)
    v[5] = 3.0
    v[-3] = 1.2
    assert arrival_time(series(t, v), 1.0) == pytest.approx(2.0 + 0.5 / 10.0 * 0.1, abs=1e-12)


# A Friedlander overpressure P (1 - tau/T) exp(-alpha tau/T), tau = t - ta,
# sampled every dt with a sample exactly at the arrival (value P) and the one
# before it at the baseline.
P, T, ALPHA, P0, TA = 10.0, 1.0, 4.0, 1.0, 0.3
DT = T / 20000


def friedlander(extra=None):
    k = np.arange(-6000, 54000)
    tau = k * DT
    t = TA + tau
    v = np.where(k >= 0, P0 + P * (1 - tau / T) * np.exp(-ALPHA * tau / T), P0)
    if extra is not None:
        v = v + extra(tau)
    return t, v


def test_positive_phase_of_a_friedlander_wave():
    t, v = friedlander()
    ph = positive_phase(series(t, v), P0)
    assert not ph["truncated"]
    # starts at the last baseline sample (ta - dt), ends at the zero of (1 - tau/T)
    assert ph["start"] == pytest.approx(TA - DT, abs=1e-12)
    assert ph["end"] == pytest.approx(TA + T, abs=1e-9)
    assert ph["duration"] == pytest.approx(T + DT, abs=1e-9)
    # exact: I = P T [1/alpha - (1 - e^-alpha)/alpha^2]; the sampled jump adds the
    # trapezoid (0 + P) dt/2 on [ta - dt, ta]; the rest is O(dt^2)
    exact = P * T * (1 / ALPHA - (1 - math.exp(-ALPHA)) / ALPHA**2)
    assert ph["impulse"] == pytest.approx(exact + P * DT / 2, abs=1e-3 * P * DT)


def test_round_off_on_a_quiet_baseline_does_not_start_the_positive_phase_early():
    """A computed baseline a few ulps above ambient ahead of the front (p0 + 1e-11) reads as ambient."""
    t, v = friedlander()
    ph = positive_phase(series(t, np.where(t < TA, v + 1e-11 * P0, v)), P0)
    assert ph["start"] == pytest.approx(TA - DT, abs=1e-12)
    assert ph["duration"] == pytest.approx(T + DT, abs=1e-9)


def test_the_positive_phase_never_starts_before_the_sample_it_leaves_the_baseline_from():
    """A sample a round-off above the baseline, then the rise: the start lies between the two samples."""
    q = 1e-6 * 100.0
    t = np.arange(8) * 1e-5
    v = P0 + np.array([0.0, 0.5 * q, 0.95 * q, 1.02 * q, 100.0, 60.0, 20.0, -5.0])
    ph = positive_phase(series(t, v), P0)
    assert t[2] <= ph["start"] <= t[3]


def test_positive_phase_truncated_series():
    t, v = friedlander()
    keep = t < TA + 0.5 * T
    ph = positive_phase(series(t[keep], v[keep]), P0)
    assert ph["truncated"]
    assert ph["end"] == pytest.approx(t[keep][-1])


def test_peak_of_a_pure_exponential_is_recovered_exactly():
    theta = 0.2
    k = np.arange(-1000, 20000)
    t = TA + k * DT
    v = np.where(k >= 0, P0 + P * np.exp(-(t - TA) / theta), P0)
    res = peak(series(t, v), P0)
    # level 5 % of the jump across the last sample interval: t_a = ta - 0.95 dt
    assert res["arrival"] == pytest.approx(TA - 0.95 * DT, abs=1e-12)
    assert res["raw"] == pytest.approx(P0 + P, abs=1e-12)
    assert res["fitted"] == pytest.approx(P0 + P * math.exp(0.95 * DT / theta), rel=1e-10)


def test_peak_linear_fit_of_a_linear_decay():
    k = np.arange(-100, 2000)
    t = TA + k * DT
    rate = 3000.0
    v = np.where(k >= 0, P0 + P - rate * (t - TA), P0)
    res = peak(series(t, v), P0, fit="linear")
    assert res["fitted"] == pytest.approx(P0 + P + rate * 0.95 * DT, rel=1e-10)


def test_peak_skips_a_start_up_spike():
    # an 8 % spike over the first 1 % of the positive phase (what a captured
    # shock reflecting from a wall shows) must move the raw peak, not the fit
    def spike(tau):
        return np.where((tau >= 0) & (tau < 0.01 * T), 0.08 * P * (1 - tau / (0.01 * T)), 0.0)

    t, v = friedlander(spike)
    res = peak(series(t, v), P0)
    assert res["raw"] == pytest.approx(P0 + 1.08 * P, abs=1e-12)
    # bias of the log-linear fit over 2-15 % of T for alpha = 4 is +0.33 % of P;
    # extrapolating to ta - 0.95 dt adds 0.95 dt (1 + alpha)/T = 0.024 %
    assert abs(res["fitted"] - (P0 + P)) < 0.004 * P
    assert res["fitted"] > P0 + P
    # without the spike the fit is the same: it never sees the first 2 %
    t0, v0 = friedlander()
    assert peak(series(t0, v0), P0)["fitted"] == pytest.approx(res["fitted"], rel=1e-12)
    # a window too short for the sampling is refused
    with pytest.raises(ValueError, match="fit_window"):
        peak(series(t[::2000], v[::2000]), P0)
    with pytest.raises(ValueError, match="fit_window"):
        peak(series(t, v), P0, fit_window=(0.2, 0.1))


def friedlander_overpressure(t, P, T, alpha, jump, smear=0.0):
    """The Friedlander overpressure P (1 − τ/T) e^{−α τ/T}, τ = t − ``jump``
    (0 before it), convolved with a Gaussian of standard deviation ``smear``
    T (a captured shock: its impulse kept), at the evenly spaced times ``t``
    (worked out on a grid twenty times finer)."""
    fine = (t[1] - t[0]) / 20
    tf = np.arange(0.0, t[-1] + 20 * fine, fine)
    tau = tf - jump
    w = np.where(tau >= 0, P * (1 - tau / T) * np.exp(-alpha * tau / T), 0.0)
    if smear > 0:
        w = gaussian_filter1d(w, smear * T / fine, mode="nearest")
    return np.interp(t, tf, w)


TS = 0.30137


def smeared_friedlander(width, end=2.0, samples=400, jump=TS):
    """The Friedlander wave of the constants above, its jump at ``jump``
    (between samples), smeared by ``width`` T and sampled every
    T/``samples`` to t = ``end`` T."""
    t = np.arange(0.0, end * T, T / samples)
    return series(t, P0 + friedlander_overpressure(t, P, T, ALPHA, jump, width))


@pytest.mark.parametrize("width", [0.005, 0.01, 0.02, 0.04])
def test_shock_fitted_peak_reads_the_jump_under_a_smeared_shock(width):
    res = shock_fitted_peak(smeared_friedlander(width), P0)
    # the raw maximum falls short by the decay across the smeared front (12 % at width 0.01) ...
    assert res["raw"] < P0 + (1 - 5 * width) * P
    # ... the fitted peak by 0.05 % at most (measured +0.026 … −0.051 %), the shock time by a tenth of the width
    assert abs(res["peak"] - (P0 + P)) < 1e-3 * P
    assert res["shock_time"] == pytest.approx(TS, abs=0.15 * width * T)
    assert res["arrival"] < TS - width * T  # the threshold arrival comes early: the front's foot
    assert res["fit_rms"] < 1e-6  # the Friedlander form holds


@pytest.mark.parametrize("position", [0.0, 0.25, 0.5, 0.75, 0.99])
def test_shock_fitted_peak_of_a_sampled_jump_is_the_jump(position):
    """A jump between two samples: the trapezoid across it is off by up to half an interval of the wave, so
    the peak by (1 + α) dt/(2T) P = 0.6 %, wherever the jump falls; the shock time by half an interval."""
    dt = T / 400
    jump = 0.3 + position * dt
    res = shock_fitted_peak(smeared_friedlander(0.0, jump=jump), P0)
    assert abs(res["peak"] - (P0 + P)) < (1 + ALPHA) * dt / (2 * T) * P
    assert res["shock_time"] == pytest.approx(jump, abs=0.5 * dt)


def test_shock_fitted_peak_of_a_noisy_record_stays_within_its_scatter():
    """Noise of 0.5 % of P on every sample (20 seeded records): the peak within 1.5 % (measured ≤ 1.2 %)."""
    rng = np.random.default_rng(1)
    clean = smeared_friedlander(0.01)
    for _ in range(20):
        res = shock_fitted_peak(clean + rng.normal(0.0, 0.005 * P, clean.size), P0)
        assert abs(res["peak"] - (P0 + P)) < 0.015 * P


def test_shock_fitted_peak_refuses_a_wave_it_cannot_fit_behind():
    with pytest.raises(ValueError, match="too wide"):
        shock_fitted_peak(smeared_friedlander(0.3), P0)
    with pytest.raises(ValueError, match="ends before its positive phase"):
        shock_fitted_peak(smeared_friedlander(0.01, end=1.0), P0)
    with pytest.raises(ValueError, match="sample more often"):
        shock_fitted_peak(smeared_friedlander(0.01, samples=8), P0)
    with pytest.raises(ValueError, match="lag"):
        shock_fitted_peak(smeared_friedlander(0.01), P0, lag=-1)
    with pytest.raises(ValueError, match="width"):
        shock_fitted_peak(smeared_friedlander(0.01), P0, width=1.5)
    # a ramp to P, then a cliff to a slow tenth: no wave fitted behind the cliff carries the ramp's impulse
    t = np.arange(0.0, 2.0, 1 / 400)
    ramp = np.where((t > 0.3) & (t <= 0.6), P * (t - 0.3) / 0.3, 0.0)
    tail = np.where((t > 0.6) & (t < 1.3), 0.1 * P * (1.3 - t) / 0.7, 0.0)
    with pytest.raises(ValueError, match="not a blast wave"):
        shock_fitted_peak(series(t, P0 + ramp + tail), P0, lag=0.0)


def test_plateau_time_mean():
    t = np.linspace(0.0, 1.0, 11)
    s = series(t, 4.0 + 2.0 * t)
    assert plateau(s, 0.23, 0.77) == pytest.approx(4.0 + (0.23 + 0.77), abs=1e-12)
    assert plateau(series(t, np.full(11, 3.5)), 0.0, 1.0) == pytest.approx(3.5, abs=1e-15)
    # a step 1 -> 3 at t = 0.5 sampled: the interpolant ramps over [0.4, 0.5]
    step = series(t, np.where(t >= 0.5, 3.0, 1.0))
    assert plateau(step, 0.6, 0.9) == pytest.approx(3.0, abs=1e-15)
    with pytest.raises(ValueError, match="t0"):
        plateau(s, 0.5, 0.5)
    with pytest.raises(ValueError, match="window"):
        plateau(s, 0.5, 1.5)


# --- oblique shock -----------------------------------------------------------


def wedge_field(beta, theta, profile, n=160):
    h = 1.0 / n
    x, y = centres(0, 1, n), centres(0, 0.5, n // 2)
    X, Y = np.meshgrid(x, y)
    xa, ya = 0.2, 0.0
    ys = ya + math.tan(math.radians(beta)) * (X - xa)
    if profile == "ramp":  # linear in y across the shock: interpolation is exact
        rho = np.clip(2.0 - (Y - ys) / (3 * h), 1.0, 3.0)
    else:
        rho = 2.0 - np.tanh((Y - ys) / (1.5 * h))
    rho = np.where(X < xa, 1.0, rho)
    rho = np.where(Y < ya + math.tan(math.radians(theta)) * (X - xa), np.nan, rho)  # the wedge
    return da2(rho, x, y), (xa, ya)


@pytest.mark.parametrize("beta, theta", [(30.0, 10.0), (38.5, 20.0), (45.0, 20.0)])
def test_oblique_shock_angle(beta, theta):
    f, apex = wedge_field(beta, theta, "ramp")
    assert oblique_shock_angle(f, apex, (0.3, 0.6)) == pytest.approx(beta, abs=1e-9)
    assert oblique_shock_angle(f, apex, (0.3, 0.6), through_apex=True) == pytest.approx(beta, abs=1e-9)
    f, apex = wedge_field(beta, theta, "tanh")
    assert oblique_shock_angle(f, apex, (0.3, 0.6)) == pytest.approx(beta, abs=0.01)
    assert oblique_shock_angle(f, apex, (0.3, 0.6), rho_free=1.0, rho_post=3.0) == pytest.approx(beta, abs=0.01)


def test_oblique_shock_angle_bad_input():
    f, apex = wedge_field(30.0, 10.0, "ramp")
    with pytest.raises(ValueError, match="x_range"):
        oblique_shock_angle(f, apex, (0.1, 0.6))
    with pytest.raises(ValueError, match="x_range"):
        oblique_shock_angle(f, apex, (0.6, 0.3))
    with pytest.raises(ValueError, match="rho_post"):
        oblique_shock_angle(f, apex, (0.3, 0.6), rho_free=2.0, rho_post=2.0)


# --- conservation ------------------------------------------------------------


def test_conservation_drift():
    assert conservation_drift([2.0, 2.002, 1.997, 2.0]) == pytest.approx(0.0015, abs=1e-15)
    assert conservation_drift(np.full(5, 3.0)) == 0.0
    assert conservation_drift([-4.0, -4.4]) == pytest.approx(0.1, abs=1e-15)
    with pytest.raises(ValueError, match="totals"):
        conservation_drift([0.0, 1.0])
    with pytest.raises(ValueError, match="totals"):
        conservation_drift([1.0, np.nan])
    with pytest.raises(ValueError, match="totals"):
        conservation_drift([])


def test_schlieren_of_a_linear_ramp_and_a_kink_by_hand():
    from partmesh.compare.metrics import schlieren

    x, y = np.linspace(0.0, 1.0, 11), np.linspace(0.0, 0.5, 6)
    # ρ = 1 + 2x for x ≤ 0.5, then 2 + 4 (x − 0.5): |∇ρ| = 2 on the left, 4 on the right, 3 at the kink
    rho = np.where(x <= 0.5, 1.0 + 2.0 * x, 2.0 + 4.0 * (x - 0.5))
    field = xr.DataArray(np.tile(rho, (y.size, 1)), coords={"y": y, "x": x}, dims=("y", "x"))
    s = schlieren(field, k=2.0).values
    np.testing.assert_allclose(s[:, :5], np.exp(-2.0 * 2.0 / 4.0), rtol=1e-12)
    np.testing.assert_allclose(s[:, 5], np.exp(-2.0 * 3.0 / 4.0), rtol=1e-12)
    np.testing.assert_allclose(s[:, 6:], np.exp(-2.0), rtol=1e-12)
    field[2, 3] = np.nan  # a solid cell: NaN there and beside it, the rest unchanged
    assert np.isnan(schlieren(field, k=2.0).values[2, 3])
    with pytest.raises(ValueError, match="2D field on"):
        schlieren(field.isel(y=0))


def test_first_crest_is_the_first_maximum_above_the_threshold_refined_by_a_parabola():
    t = np.arange(0.0, 10.0, 0.05)
    # quiet ripples (1 % of the largest wave), a crest of 0.5 at t = 3.02 (between samples), a larger one at 6
    eta = 0.01 * np.sin(20 * t) * (t < 2) + 0.5 * np.exp(-((t - 3.02) / 0.4) ** 2) + np.exp(-((t - 6) / 0.4) ** 2)
    series = xr.DataArray(eta, coords={"t_probe": t}, dims="t_probe")
    crest = first_crest(series)
    # the parabola through three samples 0.05 s apart of a Gaussian of width 0.4 s: within 1e-3 s and 1e-3
    assert crest["time"] == pytest.approx(3.02, abs=1e-3)
    assert crest["height"] == pytest.approx(0.5, abs=1e-3)
    # arrival: where the Gaussian rises through half its height, 0.4 sqrt(ln 2) s before its top
    assert crest["arrival"] == pytest.approx(3.02 - 0.4 * math.sqrt(math.log(2.0)), abs=2e-3)
    # a flat-topped wave arrives with its front
    box = xr.DataArray(np.where((t > 2.0) & (t < 4.0), 1.0, 0.0) + 1e-3 * np.sin(7 * t), coords={"t_probe": t},
                       dims="t_probe")
    assert first_crest(box)["arrival"] == pytest.approx(2.025, abs=0.03)
    # a depression: the first crest is the one after the trough
    trough = xr.DataArray(-np.exp(-((t - 3) / 0.4) ** 2) + 0.3 * np.exp(-((t - 5) / 0.4) ** 2),
                          coords={"t_probe": t}, dims="t_probe")
    assert first_crest(trough)["time"] == pytest.approx(5.0, abs=1e-3)
    # no crest above a tenth of the largest |eta| (a record that only falls): NaN
    assert np.isnan(first_crest(xr.DataArray(-t, coords={"t_probe": t}, dims="t_probe"))["height"])
    assert measured_unit("first_crest_time_x4.57") == "s"
    assert measured_unit("wall_arrival_time") == "s" and measured_unit("nonsense") is None
