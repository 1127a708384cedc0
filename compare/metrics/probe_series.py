"""Measures of a probe series (SPEC §5): arrival time, positive phase
(duration and impulse), peak raw and fitted back to the arrival, the peak
of a captured blast wave fitted behind its shock, first crest, plateau."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from partmesh.compare.checks import number
from partmesh.compare.metrics.samples import crossings, fraction, pair, time_series, vertex


def _arrival(t, v, baseline, threshold_fraction) -> tuple[float, int]:
    """Arrival time and the index of the first sample of the rise: the
    last sample before the maximum to cross the level from below."""
    vmax = float(v.max())
    if not vmax > baseline:
        raise ValueError(f"baseline={baseline:g} must lie below the series maximum {vmax:g}.")
    level = baseline + threshold_fraction * (vmax - baseline)
    top = int(np.argmax(v))
    below = np.flatnonzero(v[: top + 1] <= level)
    if below.size == 0:
        return float(t[0]), 0
    i = int(below[-1]) + 1
    ta = t[i - 1] + (level - v[i - 1]) * (t[i] - t[i - 1]) / (v[i] - v[i - 1])
    return float(ta), i


def arrival_time(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05) -> float:
    """The time a probe series rises above baseline + f (max − baseline) for
    good: its last upward crossing of that level before its maximum, so a
    noise spike ahead of the front (a particle method's scatter) does not
    count; for a clean front, the first crossing.

    With level = baseline + f (max_t v − baseline), f = ``threshold_fraction``,
    and i the first sample after the last one at or below the level before
    the maximum,

        t_a = t_{i−1} + (level − v_{i−1}) (t_i − t_{i−1}) / (v_i − v_{i−1}),

    the linear-interpolated crossing (t_a = t_0 if the first sample is
    already above). The usual time-of-arrival of blast measurements
    (Kinney & Graham 1985, *Explosive Shocks in Air*, ch. 6).

    Parameters
    ----------
    series : 1D DataArray on a time coordinate (NaN samples are dropped).
    baseline : the undisturbed value (e.g. p0).
    threshold_fraction : f in (0, 1).

    Raises
    ------
    ValueError
        for a series that is not 1D with ≥ 2 finite samples, f outside
        (0, 1), or a baseline not below the series maximum.
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    f = fraction("threshold_fraction", threshold_fraction)
    return _arrival(t, v, baseline, f)[0]


#: ahead of the arrival, a sample is above the baseline when it exceeds it by more than this fraction of the
#: peak excess (:func:`positive_phase`)
QUIET = 1e-6


def _phase(t, v, baseline, threshold_fraction):
    ta, i = _arrival(t, v, baseline, threshold_fraction)
    above = v > baseline
    # start: the upward crossing of baseline just before the arrival (past the round-off of a quiet baseline)
    below_before = np.nonzero(~(v[:i] > baseline + QUIET * (float(v.max()) - baseline)))[0]
    if below_before.size:
        j = int(below_before[-1])  # (v[j] may lie a round-off above the baseline: the crossing stays in [t_j, t_j+1])
        start = t[j] + min(max((baseline - v[j]) / (v[j + 1] - v[j]), 0.0), 1.0) * (t[j + 1] - t[j])
    else:
        j = -1
        start = float(t[0])
    # end: the first return to baseline after the arrival
    below_after = np.nonzero(~above[i:])[0]
    if below_after.size:
        k = i + int(below_after[0])
        end = t[k - 1] + (v[k - 1] - baseline) * (t[k] - t[k - 1]) / (v[k - 1] - v[k])
        truncated = False
        tt = np.concatenate(([start], t[j + 1 : k], [end]))
        vv = np.concatenate(([0.0], v[j + 1 : k] - baseline, [0.0]))
    else:
        end = float(t[-1])
        truncated = True
        head_t = [start] if j >= 0 else []
        head_v = [0.0] if j >= 0 else []
        tt = np.concatenate((head_t, t[j + 1 :]))
        vv = np.concatenate((head_v, v[j + 1 :] - baseline))
    impulse = float(np.trapezoid(vv, tt))
    return dict(duration=float(end - start), impulse=impulse, start=float(start), end=float(end),
                arrival=ta, truncated=truncated)


def positive_phase(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05) -> dict:
    """Positive-phase duration and impulse of a probe series.

    The positive phase runs from the upward crossing of ``baseline`` just
    before the arrival (see :func:`arrival_time`) to the first return to
    ``baseline`` after it, both crossings linearly interpolated (before the
    arrival a sample counts as above the baseline when it exceeds it by
    more than :data:`QUIET` of the peak excess, so the round-off of a quiet
    baseline ahead of a computed front does not start the phase early);
    over it:

        I₊ = ∫ (v − baseline) dt     (trapezoid rule on the samples plus the
                                      two interpolated crossings),
        T₊ = t_end − t_start,

    as defined for blast waves by Baker 1973, *Explosions in Air*, §1 and
    Kinney & Graham 1985, ch. 6.

    Returns
    -------
    dict(duration=T₊, impulse=I₊, start=t_start, end=t_end, arrival=t_a,
    truncated=bool) — ``truncated`` is True when the series ends before it
    returns to baseline (then end = the last sample time).

    Raises
    ------
    ValueError
        as :func:`arrival_time`.
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    f = fraction("threshold_fraction", threshold_fraction)
    return _phase(t, v, baseline, f)


def peak(
    series: xr.DataArray,
    baseline: float,
    fit_window: tuple[float, float] | None = None,
    fit: str = "exponential",
    threshold_fraction: float = 0.05,
) -> dict:
    """Peak of a probe series: raw, and extrapolated back to the arrival.

    raw = max_t v. The raw maximum of a captured shock reflecting from a
    wall carries a start-up spike that does not shrink with resolution
    (SPEC §5; it differs from the physical peak by several per cent), so
    the peak is also read by a short least-squares fit just after the
    arrival t_a, skipping the first samples, and extrapolated back to t_a:

    * ``fit="exponential"`` (default): log(v − baseline) = c₀ + c₁ t,
      fitted = baseline + exp(c₀ + c₁ t_a). For a Friedlander wave
      v − baseline = P (1 − τ/T₊) e^{−α τ/T₊} the log is linear to first
      order in τ, so the default window's extrapolation bias is small: for
      α = 4 and the window 2–15 % of T₊ it is +0.33 % of P (log(1 − τ/T₊)
      is not linear), against −5.3 % for a linear fit of v itself.
    * ``fit="linear"``: v = c₀ + c₁ t, fitted = c₀ + c₁ t_a.

    Parameters
    ----------
    series : 1D DataArray on a time coordinate.
    baseline : the undisturbed value (e.g. p0).
    fit_window : (f0, f1), 0 ≤ f0 < f1 ≤ 1, default (0.02, 0.15)
        The fit uses the samples with t_a + f0 T₊ ≤ t ≤ t_a + f1 T₊,
        T₊ the positive-phase duration of :func:`positive_phase`.
    fit : "exponential" or "linear".
    threshold_fraction : passed to :func:`arrival_time`.

    Returns
    -------
    dict(raw=..., fitted=..., arrival=t_a, window=(t_lo, t_hi),
    n_fit=number of samples fitted).

    Raises
    ------
    ValueError
        for a bad window, an unknown fit, or fewer than 2 usable samples in
        the window ("widen fit_window or sample more often").
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    f = fraction("threshold_fraction", threshold_fraction)
    if fit not in ("exponential", "linear"):
        raise ValueError(f"fit must be 'exponential' or 'linear', got {fit!r}.")
    if fit_window is None:
        fit_window = (0.02, 0.15)
    f0, f1 = pair("fit_window", fit_window, "(f0, f1) with 0 <= f0 < f1 <= 1")
    if not 0.0 <= f0 < f1 <= 1.0:
        raise ValueError(f"fit_window must be a pair (f0, f1) with 0 <= f0 < f1 <= 1, got ({f0:g}, {f1:g}).")
    ph = _phase(t, v, baseline, f)
    ta, dur = ph["arrival"], ph["duration"]
    lo, hi = ta + f0 * dur, ta + f1 * dur
    sel = (t >= lo) & (t <= hi)
    if fit == "exponential":
        sel &= v > baseline
    ts, vs = t[sel], v[sel]
    if ts.size < 2:
        raise ValueError(
            f"fit_window=({f0:g}, {f1:g}) holds {ts.size} usable sample(s) (need 2); widen fit_window or sample more often."
        )
    y = np.log(vs - baseline) if fit == "exponential" else vs
    c1, c0 = np.polyfit(ts - ta, y, 1)
    fitted = baseline + math.exp(c0) if fit == "exponential" else c0
    return dict(raw=float(v.max()), fitted=float(fitted), arrival=ta, window=(float(lo), float(hi)), n_fit=int(ts.size))


#: Gauss–Legendre nodes and weights on [−1, 1] for the fitted wave's impulse (:func:`shock_fitted_peak`)
_GAUSS = np.polynomial.legendre.leggauss(16)


def shock_fitted_peak(series: xr.DataArray, baseline: float, lag: float = 1.0, width: float = 0.2,
                      threshold_fraction: float = 0.05) -> dict:
    """Peak of a captured blast wave, read from the flow behind its smeared
    shock and carried back to the shock by the equal-area rule.

    A shock-capturing scheme spreads a shock over a few cells, so the raw
    maximum of a gauge falls short of the jump by the wave's decay across
    that width, and a threshold arrival comes early by about half of it.
    Behind the shock the flow is resolved, and a conservative scheme keeps
    both the shock's speed and the impulse it carries; so:

    1. the positive phase [t₀, t_e] of duration T₊ (:func:`positive_phase`),
       its arrival t_a and its maximum at t_m;
    2. a Friedlander wave with its zero at the measured t_e (Friedlander
       1946; Baker 1973, *Explosions in Air*, §1):

           v − baseline = f(t) = (t_e − t) exp(c₀ + c₁ (t − t_a)),

       the form P (1 − τ/T) e^{−α τ/T} rewritten, fitted by least squares
       to log((v − baseline)/(t_e − t)) on the window from
       t_w = t_m + ``lag`` (t_m − t_a), past the smeared rise, to
       t_w + ``width`` T₊ (its samples before t_e);
    3. the shock time t_s by the equal-area rule of shock fitting (Whitham
       1974, *Linear and Nonlinear Waves*, §2.8): the fitted wave from t_s
       carries the impulse the series carries from t₀ to the window:

           ∫_{t_s}^{t_w} f dt = ∫_{t₀}^{t_w} (v − baseline) dt;

    4. peak = baseline + f(t_s).

    For a Friedlander wave the fit is exact on any window, and the error
    left is that of the smeared front's shape, some hundred times smaller
    than the raw maximum's deficit (on a Gaussian smear of 1 % of T₊:
    0.02 % against 12 %) and, like it, shrinking with the front's width.
    The reading rests on the Friedlander form and on t_e: a decay of
    two time scales reads low (the window sees the slow one), and a noisy
    record that returns to the baseline early moves t_e and with it the
    peak (at a scatter of 1 % of P, by about 1 %); ``fit_rms``, the rms
    residual of the log fit, shows how well the form holds.

    Parameters
    ----------
    series : 1D DataArray on a time coordinate: a blast wave whose positive phase ends within it.
    baseline : the undisturbed value (e.g. p0).
    lag : ≥ 0, the window's start past the maximum in rise times t_m − t_a.
    width : in (0, 1), the window's length in positive-phase durations T₊.
    threshold_fraction : passed to :func:`arrival_time`.

    Returns
    -------
    dict(peak=baseline + f(t_s), shock_time=t_s, raw=max v, arrival=t_a,
    window=(t_w, t_w + width T₊), n_fit=number of samples fitted,
    fit_rms=rms residual of the log fit).

    Raises
    ------
    ValueError
        for a lag or width out of range; a series whose positive phase does
        not end within it; a window that starts more than halfway into the
        positive phase (a lag too large, or a shock too wide to fit
        behind); fewer than 3 samples in the window; a rise whose impulse
        the fitted wave cannot carry (not a blast wave).
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    lag = number("lag", lag)
    if not lag >= 0.0:
        raise ValueError(f"lag must be >= 0 (rise times past the maximum), got {lag:g}.")
    width = fraction("width", width)
    ph = _phase(t, v, baseline, fraction("threshold_fraction", threshold_fraction))
    if ph["truncated"]:
        raise ValueError("series ends before its positive phase does; a fit behind the shock needs the whole phase.")
    t0, ta, te, duration = ph["start"], ph["arrival"], ph["end"], ph["duration"]
    phase = (t >= ta) & (t <= te)
    tm = float(t[phase][np.argmax(v[phase])])
    tw = tm + lag * (tm - ta)
    if tw > t0 + 0.5 * duration:
        raise ValueError(f"the fit window starts {(tw - t0) / duration:.0%} into the positive phase, more than half "
                         f"(lag={lag:g} rise times past the maximum): lower lag, or the shock is too wide to fit behind.")
    hi = tw + width * duration
    sel = (t >= tw) & (t <= hi) & (t < te) & (v > baseline)
    n_fit = int(np.count_nonzero(sel))
    if n_fit < 3:
        raise ValueError(f"the fit window [{tw:g}, {hi:g}] holds {n_fit} usable samples (need 3); "
                         f"widen width or sample more often.")
    y = np.log(v[sel] - baseline) - np.log(te - t[sel])
    c1, c0 = np.polyfit(t[sel] - ta, y, 1)
    fit_rms = float(np.sqrt(np.mean((y - c0 - c1 * (t[sel] - ta)) ** 2)))

    def wave(s):
        return (te - s) * np.exp(c0 + c1 * (s - ta))

    def impulse_from(s):
        x, w = _GAUSS
        half = 0.5 * (tw - s)
        return half * float(np.dot(w, wave(s + half * (x + 1.0))))

    before = (t > t0) & (t < tw)
    tt = np.concatenate(([t0], t[before], [tw]))
    impulse = float(np.trapezoid(np.interp(tt, t, v) - baseline, tt))
    earliest = t0 - (tw - t0)
    if not 0.0 < impulse < impulse_from(earliest):
        raise ValueError("the rise's impulse cannot be matched by the wave fitted behind it (equal-area rule); "
                         "the series is not a blast wave.")
    ts = brentq(lambda s: impulse_from(s) - impulse, earliest, tw)
    return dict(peak=baseline + float(wave(ts)), shock_time=float(ts), raw=float(v.max()), arrival=ta,
                window=(float(tw), float(hi)), n_fit=n_fit, fit_rms=fit_rms)


def first_crest(series: xr.DataArray, threshold_fraction: float = 0.1) -> dict:
    """The first crest of a wave record η(t): the first local maximum above
    ``threshold_fraction`` of the record's largest |η| (so the ripples of a
    quiet start do not count), refined by the parabola through it and its
    two neighbours, and its arrival: the last time before the crest at which
    η rises through half the crest's height (linear between samples; the
    front of a flat-topped wave, whose crest time means little). Returns
    ``{"height", "time", "arrival"}``; NaN for all if the record never rises
    above the threshold."""
    t, v = time_series("series", series)
    level = fraction("threshold_fraction", threshold_fraction) * float(np.max(np.abs(v)))
    rising = np.flatnonzero((v[1:-1] >= v[:-2]) & (v[1:-1] > v[2:]) & (v[1:-1] > level)) + 1
    if rising.size == 0 or level == 0.0:
        return {"height": float("nan"), "time": float("nan"), "arrival": float("nan")}
    k = int(rising[0])
    time, height = vertex(t, v, k)
    below = np.flatnonzero(v[: k + 1] < 0.5 * height)
    arrival = float(t[0]) if below.size == 0 else float(crossings(t[below[-1]:k + 1], v[below[-1]:k + 1],
                                                                   0.5 * height)[0])
    return {"height": height, "time": time, "arrival": arrival}


def plateau(series: xr.DataArray, t0: float, t1: float) -> float:
    """Time-mean of a series over [t0, t1] (e.g. a reflected-shock pressure).

        v̄ = (1/(t1 − t0)) ∫_{t0}^{t1} v(t) dt,

    with v the piecewise-linear interpolant of the samples (trapezoid rule,
    values at t0 and t1 interpolated), so a linear signal gives
    (v(t0) + v(t1))/2 exactly.

    Raises
    ------
    ValueError
        unless t_first ≤ t0 < t1 ≤ t_last of the series' finite samples.
    """
    t, v = time_series("series", series)
    t0, t1 = number("t0", t0), number("t1", t1)
    if not t0 < t1:
        raise ValueError(f"t0={t0:g} must be smaller than t1={t1:g}.")
    if t0 < t[0] or t1 > t[-1]:
        raise ValueError(f"the window [t0, t1] = [{t0:g}, {t1:g}] must lie within the series' times [{t[0]:g}, {t[-1]:g}].")
    inner = (t > t0) & (t < t1)
    tt = np.concatenate(([t0], t[inner], [t1]))
    vv = np.concatenate(([np.interp(t0, t, v)], v[inner], [np.interp(t1, t, v)]))
    return float(np.trapezoid(vv, tt) / (t1 - t0))
