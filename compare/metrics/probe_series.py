"""Measures of a probe series (SPEC §5): arrival time, positive phase
(duration and impulse), peak raw and fitted back to the arrival, the peak
of its running mean, the peak of a captured blast wave fitted behind its
shock, first crest, plateau."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from partmesh.compare.checks import number
from partmesh.compare.metrics.samples import crossings, fraction, pair, time_series, vertex


#: ahead of the arrival, a sample is above the baseline when it exceeds it by more than this fraction of the
#: peak excess (:func:`positive_phase`; and the running mean stands at ambient within it, :func:`arrival_time`)
QUIET = 1e-6


#: the arrival's crossing rules (:func:`arrival_time`)
CROSSINGS = ("last", "first")
#: samples of the centred running mean that tells where a record last stood at ambient (``crossing="first"``)
GUARD_SAMPLES = 21


def _odd_samples(name: str, samples) -> int:
    """``samples`` as a positive odd integer, or a ValueError naming ``name``."""
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1 or samples % 2 == 0:
        raise ValueError(f"{name} must be a positive odd number of samples, got {samples!r}.")
    return int(samples)


def _running(v: np.ndarray, samples: int) -> np.ndarray:
    """The centred running mean of ``v`` over ``samples`` (odd) samples, its
    window cut short at the ends of the record (there it averages the
    samples it holds)."""
    kernel = np.ones(samples)
    return np.convolve(v, kernel, mode="same") / np.convolve(np.ones(v.size), kernel, mode="same")


def _scatter(v: np.ndarray) -> float:
    """The sample-to-sample scatter σ of a record, robustly: 1.4826 × the
    median absolute difference of successive samples, / √2 (σ of white
    noise; zero where most successive samples are equal, as ahead of a
    grid method's front)."""
    return 1.4826 * float(np.median(np.abs(np.diff(v)))) / math.sqrt(2.0)


def _arrival(t, v, baseline, threshold_fraction, crossing="last", samples=GUARD_SAMPLES) -> tuple[float, int]:
    """Arrival time and the index of the first sample past it (see
    :func:`arrival_time` for the two ``crossing`` rules)."""
    vmax = float(v.max())
    if not vmax > baseline:
        raise ValueError(f"baseline={baseline:g} must lie below the series maximum {vmax:g}.")
    level = baseline + threshold_fraction * (vmax - baseline)
    if crossing == "last":
        top = int(np.argmax(v))
        below = np.flatnonzero(v[: top + 1] <= level)
        if below.size == 0:
            return float(t[0]), 0
        i = int(below[-1]) + 1
    else:
        # where the record last stood at ambient before the running mean's maximum: its running mean within
        # round-off of the baseline, or within twice the mean's scatter of it on a noisy record
        mean = _running(v - baseline, samples)
        top = int(np.argmax(mean))
        ambient = np.flatnonzero(mean[: top + 1] <= max(QUIET * (vmax - baseline),
                                                        2.0 * _scatter(v) / math.sqrt(samples)))
        up = np.flatnonzero((v[1:] > level) & (v[:-1] <= level)) + 1  # the upward crossings of the level
        if ambient.size == 0:  # never at ambient before its maximum: the record's first crossing
            i = 0 if v[0] > level else int(up[0])
        else:
            # the running mean at j averages samples j - h ... j + h: the wave reaches the record after j + h
            j = int(ambient[-1])
            s = min(j + samples // 2 + 1, top)
            if v[s] > level:  # the crossing at or just before s (scatter may have crossed between j and s)
                near = up[(up > j) & (up <= s)]
                i = int(near[-1]) if near.size else int(up[up <= s][-1]) if np.any(up <= s) else 0
            else:  # the first crossing after s
                later = up[up > s]
                i = int(later[0]) if later.size else int(up[-1])
        if i == 0:
            return float(t[0]), 0
    ta = t[i - 1] + (level - v[i - 1]) * (t[i] - t[i - 1]) / (v[i] - v[i - 1])
    return float(ta), i


def _crossing(crossing: str) -> str:
    if crossing not in CROSSINGS:
        raise ValueError(f"crossing must be 'last' or 'first', got {crossing!r}.")
    return crossing


def arrival_time(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05, crossing: str = "last",
                 samples: int = GUARD_SAMPLES) -> float:
    """The time a probe series rises through baseline + f (max − baseline).

    With level = baseline + f (max_t v − baseline), f = ``threshold_fraction``,
    and i the first sample past the crossing,

        t_a = t_{i−1} + (level − v_{i−1}) (t_i − t_{i−1}) / (v_i − v_{i−1}),

    the linear-interpolated crossing (t_a = t_0 if the first sample is
    already above). The usual time-of-arrival of blast measurements
    (Kinney & Graham 1985, *Explosive Shocks in Air*, ch. 6). Which
    crossing:

    * ``crossing="last"`` (default): the last upward crossing before the
      maximum, so a noise spike ahead of the front (a particle method's
      scatter) does not count. It is the first crossing only while the
      record stays above the level from its front to its maximum: where a
      first wave decays below the level before a later, higher crest (a
      wave re-reflected inside an array), it reads the later crest.
    * ``crossing="first"``: the first upward crossing of the wave that
      carries the maximum: the first since the record last stood at
      ambient before the maximum of its centred running mean over
      ``samples`` samples. Ambient: that mean within 2σ/√n of the baseline
      (n = ``samples``, σ the sample-to-sample scatter, 1.4826 × the median
      absolute difference of successive samples / √2; at least
      :data:`QUIET` of the peak excess, for round-off). On a record that
      is quiet ahead of its front (a grid method's: σ = 0), and does not
      return to ambient between its first wave and its maximum, this is
      the first crossing of the record, the arrival of the first wave
      however much higher a later crest. On a noisy record (a particle
      method's scatter crosses a 5 % level many times ahead of the front)
      the running mean's last visit to ambient marks the foot of the front:
      the crossing taken is the last one within the half window after it
      (n//2 samples, where the mean's window first reaches the wave), or
      the first one past there; the scatter ahead does not count, and the
      arrival is uncertain by the scatter near the foot (1 000 records of
      white scatter of 10 % of the peak ahead of and behind a step, n = 21:
      99 % within 6 samples of the step, all within 22).

    Parameters
    ----------
    series : 1D DataArray on a time coordinate (NaN samples are dropped).
    baseline : the undisturbed value (e.g. p0).
    threshold_fraction : f in (0, 1).
    crossing : "last" or "first".
    samples : the running mean's window for ``crossing="first"``, a positive odd number of samples.

    Raises
    ------
    ValueError
        for a series that is not 1D with ≥ 2 finite samples, f outside
        (0, 1), a baseline not below the series maximum, an unknown
        crossing or a window that is not a positive odd number.
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    f = fraction("threshold_fraction", threshold_fraction)
    return _arrival(t, v, baseline, f, _crossing(crossing), _odd_samples("samples", samples))[0]


def _phase(t, v, baseline, threshold_fraction, crossing="last", samples=GUARD_SAMPLES):
    ta, i = _arrival(t, v, baseline, threshold_fraction, crossing, samples)
    above = v > baseline
    # start: the upward crossing of baseline just before the arrival (past the round-off of a quiet baseline)
    below_before = np.nonzero(~(v[:i] > baseline + QUIET * (float(v.max()) - baseline)))[0]
    if below_before.size:
        j = int(below_before[-1])  # (v[j] may lie a round-off above the baseline: the crossing stays in [t_j, t_j+1])
        start = t[j] + min(max((baseline - v[j]) / (v[j + 1] - v[j]), 0.0), 1.0) * (t[j + 1] - t[j])
    else:
        j = -1
        start = float(t[0])
    # end: the first return to baseline after the arrival (with the first crossing: after the maximum too)
    after = i if crossing == "last" else max(i, int(np.argmax(v)))
    below_after = np.nonzero(~above[after:])[0]
    if below_after.size:
        k = after + int(below_after[0])
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


def positive_phase(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05, crossing: str = "last",
                   samples: int = GUARD_SAMPLES) -> dict:
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

    ``threshold_fraction``, ``crossing`` and ``samples`` choose the
    arrival as in :func:`arrival_time`. With ``crossing="first"`` the phase
    ends at the first return to baseline after both the arrival and the
    maximum: a train of waves that stays above the baseline up to its
    peak is one positive phase (as with the last crossing), and on a noisy
    record a dip of the scatter below the baseline at the foot of the front
    does not end it.

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
    return _phase(t, v, baseline, f, _crossing(crossing), _odd_samples("samples", samples))


def peak(
    series: xr.DataArray,
    baseline: float,
    fit_window: tuple[float, float] | None = None,
    fit: str = "exponential",
    threshold_fraction: float = 0.05,
    crossing: str = "last",
    samples: int = GUARD_SAMPLES,
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
    threshold_fraction, crossing, samples : passed to :func:`arrival_time`.
        With ``crossing="first"`` the window follows the first wave even
        where a later crest is higher; with ``"last"`` it follows the last
        rise through the level before the maximum (which is the later crest
        where the first wave decays below the level before it).

    Returns
    -------
    dict(raw=..., fitted=..., arrival=t_a, window=(t_lo, t_hi),
    n_fit=number of samples fitted).

    Raises
    ------
    ValueError
        for a bad window, an unknown fit, or fewer than 2 usable samples in
        the window ("widen fit_window or sample more often"); as
        :func:`arrival_time` for the arrival's arguments.
    """
    t, v = time_series("series", series)
    baseline = number("baseline", baseline)
    f = fraction("threshold_fraction", threshold_fraction)
    crossing, samples = _crossing(crossing), _odd_samples("samples", samples)
    if fit not in ("exponential", "linear"):
        raise ValueError(f"fit must be 'exponential' or 'linear', got {fit!r}.")
    if fit_window is None:
        fit_window = (0.02, 0.15)
    f0, f1 = pair("fit_window", fit_window, "(f0, f1) with 0 <= f0 < f1 <= 1")
    if not 0.0 <= f0 < f1 <= 1.0:
        raise ValueError(f"fit_window must be a pair (f0, f1) with 0 <= f0 < f1 <= 1, got ({f0:g}, {f1:g}).")
    ph = _phase(t, v, baseline, f, crossing, samples)
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


def running_peak(series: xr.DataArray, samples: int) -> dict:
    """The largest value of the centred running mean of a probe series
    over ``samples`` samples, and its time (the window's centre):

        m_k = (1/n) Σ_{j=k−h}^{k+h} v_j,   n = ``samples`` = 2h + 1,
        peak = max_k m_k over the windows the record holds whole.

    The raw maximum of a record with scatter (a particle method's per-sample
    noise σ) is its largest excursion, a few σ above the signal and at a
    time set by the noise; the running mean's scatter is σ/√n for
    uncorrelated samples, so its maximum follows the signal. The window
    should be short against the rise and decay of the wave it reads (a
    running mean of n samples lowers a sharp peak by about the decay over
    n/2 samples) and long against the sampling interval; say which window.

    Returns
    -------
    dict(peak=max m, time=t of its window's centre, samples=n).

    Raises
    ------
    ValueError
        for a series that is not 1D, ``samples`` that is not a positive odd
        number, or a record shorter than one window.
    """
    t, v = time_series("series", series)
    n = _odd_samples("samples", samples)
    if v.size < n:
        raise ValueError(f"the series holds {v.size} samples, fewer than one window of samples={n}.")
    whole = np.convolve(v, np.ones(n), mode="valid") / n
    k = int(np.argmax(whole))
    return dict(peak=float(whole[k]), time=float(t[k + n // 2]), samples=n)


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
