"""The ground gauges of a charge (partmesh.cases.charges.gauge_metrics) read
from synthetic records whose answers are known: a Friedlander wave with the
Kingery–Bulmash peak, arrival and duration, the same wave cut short or
smeared past fitting, and a quiet record."""

import math

import numpy as np
import pytest
import xarray as xr

from partmesh.cases.charges import GAUGE_QUANTITIES, gauge_metrics
from partmesh.compare.exact.kingery_bulmash import blast_parameters
from tests.test_metrics import friedlander_overpressure

P0, W, ALPHA = 101325.0, 1.0, 1.5
DT = 5e-6
T_END = 40e-3


def friedlander(Z, smear=0.0, end=T_END):
    """The Friedlander wave with the Kingery–Bulmash P, arrival and T at Z, its jump between samples, smeared
    by ``smear`` T, sampled every DT to ``end`` (NaN after)."""
    kb = blast_parameters(Z, W)
    t = np.arange(0.0, T_END, DT)
    wave = friedlander_overpressure(t, kb.incident_overpressure, kb.positive_duration, ALPHA,
                                    kb.arrival_time + 0.37 * DT, smear)
    return np.where(t <= end, P0 + wave, np.nan)


def gauges(records: dict) -> xr.Dataset:
    names = list(records)
    t = np.arange(0.0, T_END, DT)
    return xr.Dataset({"p_probe": (("t_probe", "probe"), np.stack([records[n] for n in names], axis=1))},
                      coords={"t_probe": t, "probe": names,
                              "probe_x": ("probe", [float(n[1:]) if n[0] == "Z" else 5.0 for n in names])})


def test_a_friedlander_gauge_reads_the_wave_it_was_made_of():
    m = gauge_metrics(gauges({"Z3": friedlander(3.0, smear=0.01)}), W, P0)
    kb = blast_parameters(3.0, W)
    P, T = kb.incident_overpressure, kb.positive_duration
    assert m["Z3_peak_overpressure_kb"] == P
    assert m["Z3_peak_overpressure"] < 0.97 * P  # the smeared front
    assert m["Z3_peak_overpressure_fitted"] == pytest.approx(P, rel=1e-3)
    assert m["Z3_arrival_time"] == pytest.approx(kb.arrival_time, abs=0.03 * T)
    # the phase starts at the smeared front's foot, 4–5 smear widths ahead of the jump (at 1e-6 of P)
    assert T < m["Z3_positive_duration"] < 1.05 * T
    impulse = P * T * (1 / ALPHA - (1 - math.exp(-ALPHA)) / ALPHA**2)
    assert m["Z3_positive_impulse"] == pytest.approx(impulse, rel=2e-3)


@pytest.mark.full
def test_a_gauge_that_cannot_be_fitted_keeps_what_can_be_read():
    kb5 = blast_parameters(5.0, W)
    m = gauge_metrics(gauges({"Z5": friedlander(5.0, end=kb5.arrival_time + 0.5 * kb5.positive_duration),
                              "Z8": friedlander(8.0, smear=0.3),
                              "Z2": np.full(int(round(T_END / DT)), P0)}), W, P0)
    assert set(m) == {f"{g}_{q}" for g in ("Z5", "Z8", "Z2") for q in GAUGE_QUANTITIES} | {
        f"{g}_{q}_kb" for g in ("Z5", "Z8", "Z2") for q in GAUGE_QUANTITIES if not q.endswith("_fitted")}
    # cut short inside its positive phase: no fit, the rest up to the end
    assert math.isnan(m["Z5_peak_overpressure_fitted"])
    assert m["Z5_positive_duration"] == pytest.approx(0.5 * kb5.positive_duration, rel=0.01)
    assert m["Z5_peak_overpressure"] == pytest.approx(kb5.incident_overpressure, rel=0.01)
    # a front smeared over a third of its phase: too wide to fit behind, the raw values stay
    assert math.isnan(m["Z8_peak_overpressure_fitted"])
    assert m["Z8_peak_overpressure"] > 0.0
    # a quiet record: nothing to read
    assert all(math.isnan(m[f"Z2_{q}"]) for q in GAUGE_QUANTITIES)
