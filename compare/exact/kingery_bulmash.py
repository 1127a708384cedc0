"""The Kingery–Bulmash blast parameters of a hemispherical TNT surface
burst, from the simplified fits of M. M. Swisdak, *Simplified Kingery
Airblast Calculations*, NSWC Indian Head, 1994 (DTIC ADA526744), the
curves of C. N. Kingery & G. Bulmash (1984) that UFC 3-340-02 prints.

Each quantity is a polynomial in ln Z over a few ranges of the scaled
distance Z = R / W^(1/3) [m/kg^(1/3)]:

    Y = exp(A + B ln Z + C (ln Z)² + D (ln Z)³ + E (ln Z)⁴ + F (ln Z)⁵ + G (ln Z)⁶),

in kPa (pressures), ms/kg^(1/3) (times) and kPa·ms/kg^(1/3) (impulses),
and km/s (shock speed); times and impulses scale with W^(1/3) (Hopkinson–
Cranz). The functions here take SI and return SI (Pa, s, Pa·s, m/s), and
refuse a scaled distance outside the fits' range.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from partmesh.compare.checks import InputError, positive

__all__ = ["COMMON_RANGE", "FITS", "QUANTITIES", "KingeryBulmash", "blast_parameters", "scaled_value", "validity"]

#: quantity -> (SI factor of the fit's unit, [(Z_lo, Z_hi, (A, B, C, D, E, F, G)), ...]) (Swisdak 1994, metric)
FITS = {
    "arrival_time": (1e-3, [
        (0.06, 1.50, (-0.7604, 1.8058, 0.1257, -0.0437, -0.0310, -0.00669, 0.0)),
        (1.50, 40.0, (-0.7137, 1.5732, 0.5561, -0.4213, 0.1054, -0.00929, 0.0)),
    ]),
    "incident_overpressure": (1e3, [
        (0.2, 2.9, (7.2106, -2.1069, -0.3229, 0.1117, 0.0685, 0.0, 0.0)),
        (2.9, 23.8, (7.5938, -3.0523, 0.40977, 0.0261, -0.01267, 0.0, 0.0)),
        (23.8, 198.5, (6.0536, -1.4066, 0.0, 0.0, 0.0, 0.0, 0.0)),
    ]),
    "reflected_overpressure": (1e3, [
        (0.06, 2.00, (9.006, -2.6893, -0.6295, 0.1011, 0.29255, 0.13505, 0.019736)),
        (2.00, 40.0, (8.8396, -1.733, -2.64, 2.293, -0.8232, 0.14247, -0.0099)),
    ]),
    "positive_duration": (1e-3, [
        (0.2, 1.02, (0.5426, 3.2299, -1.5931, -5.9667, -4.0815, -0.9149, 0.0)),
        (1.02, 2.8, (0.5440, 2.7082, -9.7354, 14.3425, -9.7791, 2.8535, 0.0)),
        (2.8, 40.0, (-2.4608, 7.1639, -5.6215, 2.2711, -0.44994, 0.03486, 0.0)),
    ]),
    "incident_impulse": (1.0, [  # kPa·ms = Pa·s
        (0.2, 0.96, (5.522, 1.117, 0.6, -0.292, -0.087, 0.0, 0.0)),
        (0.96, 2.38, (5.465, -0.308, -1.464, 1.362, -0.432, 0.0, 0.0)),
        (2.38, 33.7, (5.2749, -0.4677, -0.2499, 0.0588, -0.00554, 0.0, 0.0)),
        (33.7, 158.7, (5.9825, -1.062, 0.0, 0.0, 0.0, 0.0, 0.0)),
    ]),
    "reflected_impulse": (1.0, [
        (0.06, 40.0, (6.7853, -1.3466, 0.101, -0.01123, 0.0, 0.0, 0.0)),
    ]),
    "shock_speed": (1e3, [
        (0.06, 1.50, (0.1794, -0.956, -0.0866, 0.109, 0.0699, 0.01218, 0.0)),
        (1.50, 40.0, (0.2597, -1.326, 0.3767, 0.0396, -0.0351, 0.00432, 0.0)),
    ]),
}
QUANTITIES = tuple(FITS)
#: the scaled distances every fit covers [m/kg^(1/3)]
COMMON_RANGE = (0.2, 40.0)
#: the quantities that scale with W^(1/3) (Hopkinson–Cranz: times and impulses)
_CUBE_ROOT_SCALED = ("arrival_time", "positive_duration", "incident_impulse", "reflected_impulse")


def validity(quantity: str) -> tuple[float, float]:
    """The range of scaled distance Z [m/kg^(1/3)] the fit of ``quantity`` covers."""
    ranges = FITS[_known(quantity)][1]
    return ranges[0][0], ranges[-1][1]


def _known(quantity: str) -> str:
    if quantity not in FITS:
        raise InputError(f"quantity must be one of {', '.join(QUANTITIES)}, got {quantity!r}.")
    return quantity


def scaled_value(quantity: str, Z):
    """``quantity`` at the scaled distances ``Z`` [m/kg^(1/3)] for a 1 kg
    charge, in SI (s, Pa, Pa·s or m/s); a Z on a border between two
    ranges takes the lower range's fit, as Swisdak's tables do."""
    factor, ranges = FITS[_known(quantity)]
    Z = np.asarray(Z, float)
    lo, hi = validity(quantity)
    outside = ~((Z >= lo) & (Z <= hi))
    if np.any(outside):
        bad = Z[outside].flat[0]
        raise InputError(f"the scaled distance Z must lie in [{lo:g}, {hi:g}] m/kg^(1/3) for the Kingery-Bulmash "
                         f"{quantity.replace('_', ' ')}, got {bad:g}.")
    x = np.log(Z)
    out = np.zeros_like(Z)
    for k, (z_lo, z_hi, coefficients) in enumerate(ranges):
        here = (Z <= z_hi) & ((Z > z_lo) if k else (Z >= z_lo))
        out[here] = np.exp(np.polyval(coefficients[::-1], x[here]))
    return out * factor


class KingeryBulmash(NamedTuple):
    """The Kingery–Bulmash blast parameters at one or more distances, in SI."""

    scaled_distance: np.ndarray  # Z [m/kg^(1/3)]
    arrival_time: np.ndarray  # [s]
    incident_overpressure: np.ndarray  # [Pa]
    reflected_overpressure: np.ndarray  # [Pa]
    positive_duration: np.ndarray  # [s]
    incident_impulse: np.ndarray  # positive phase [Pa s]
    reflected_impulse: np.ndarray  # [Pa s]
    shock_speed: np.ndarray  # [m/s]


def blast_parameters(distance, W: float = 1.0) -> KingeryBulmash:
    """The blast parameters of a hemispherical surface burst of ``W`` kg TNT
    at ground ``distance`` [m] from the charge (Swisdak 1994), times and
    impulses scaled by W^(1/3). Every distance must fall in the range all
    fits cover, Z = R / W^(1/3) in [0.2, 40] m/kg^(1/3)."""
    W = positive("W", W)
    Z = np.asarray(distance, float) / W ** (1.0 / 3.0)
    lo, hi = COMMON_RANGE
    if not np.all((Z >= lo) & (Z <= hi)):
        bad = Z[~((Z >= lo) & (Z <= hi))].flat[0] if Z.ndim else Z
        raise InputError(f"the scaled distance R / W^(1/3) must lie in [{lo:g}, {hi:g}] m/kg^(1/3), the range every "
                         f"Kingery-Bulmash fit covers, got {bad:g} (R = distance, W = {W:g} kg).")
    scale = W ** (1.0 / 3.0)
    values = {q: scaled_value(q, Z) * (scale if q in _CUBE_ROOT_SCALED else 1.0) for q in QUANTITIES}
    return KingeryBulmash(scaled_distance=Z, **values)
