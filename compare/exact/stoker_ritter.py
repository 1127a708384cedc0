"""The ideal shallow-water dam break: Stoker's wet bed and Ritter's dry bed.

1D shallow-water equations, flat frictionless bed, water at rest with depth
h_l for x < x0 and h_r for x > x0 (Stoker 1957, "Water Waves"; Ritter
1892; Toro 2001, "Shock-Capturing Methods for Free-Surface Shallow Flows",
ch. 5; Delestre et al. 2013, "SWASHES: a compilation of shallow water
analytic solutions", Int. J. Numer. Meth. Fluids 72, §4.1.1 wet bed and
§4.1.2 dry bed). See :func:`dam_break_state` and :func:`dam_break_profile`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from partmesh.compare.checks import number
from partmesh.compare.exact._inputs import axis, non_negative, output_times, positive
from partmesh.compare.exact.water import GRAVITY
from partmesh.compare.schema import result


class DamBreakState(NamedTuple):
    """Wave structure of a dam break: rarefaction head and tail speeds, middle state, bore (front) speed."""

    head_speed: float   # left edge of the rarefaction, -sqrt(g h_l)
    tail_speed: float   # right edge of the rarefaction, u_m - sqrt(g h_m)
    h_middle: float     # depth between rarefaction and bore (0 on a dry bed)
    u_middle: float     # velocity there (the front speed 2 sqrt(g h_l) on a dry bed)
    front_speed: float  # bore speed (wet bed) or dry front speed 2 sqrt(g h_l)


def _depths(h_left, h_right):
    h_left, h_right = non_negative("h_left", h_left), non_negative("h_right", h_right)
    if h_left == 0.0 and h_right == 0.0:
        raise ValueError("h_left and h_right cannot both be 0: there is no water to release.")
    return h_left, h_right


def _state(h_left, h_right, g):
    """The dam-break structure for h_left >= h_right (Toro 2001, ch. 5)."""
    c_l = math.sqrt(g * h_left)
    if h_right == 0.0:
        return DamBreakState(-c_l, 2.0 * c_l, 0.0, 2.0 * c_l, 2.0 * c_l)
    if h_right == h_left:
        return DamBreakState(-c_l, -c_l, h_left, 0.0, c_l)

    def velocity_jump(h):  # u_m from the left rarefaction minus u_m from the right bore
        return 2.0 * (math.sqrt(g * h) - c_l) + (h - h_right) * math.sqrt(0.5 * g * (h + h_right) / (h * h_right))

    h_m = brentq(velocity_jump, h_right, h_left, xtol=1e-15 * h_left, rtol=4.0 * np.finfo(float).eps, maxiter=200)
    c_m = math.sqrt(g * h_m)
    u_m = 2.0 * (c_l - c_m)
    return DamBreakState(-c_l, u_m - c_m, h_m, u_m, h_m * u_m / (h_m - h_right))


def dam_break_state(h_left, h_right, g: float = GRAVITY) -> DamBreakState:
    """Middle state and wave speeds of the dam break (Stoker 1957; Toro 2001 ch. 5; SWASHES §4.1.1).

    For h_l > h_r > 0: a left rarefaction from -sqrt(g h_l) to u_m - c_m,
    a middle state (h_m, u_m) and a bore. The left Riemann invariant gives
    u_m = 2 (sqrt(g h_l) - c_m), c_m = sqrt(g h_m); the Rankine-Hugoniot
    conditions across the bore give u_m = (h_m - h_r) sqrt(g (h_m + h_r)/(2 h_m h_r))
    and the bore speed s = h_m u_m/(h_m - h_r). h_m is the root of the
    difference of the two u_m on (h_r, h_l) (brentq to 1e-15 h_l). It
    satisfies the relation of SWASHES (Delestre et al. 2013, §4.1.1)
    -8 g h_r c_m^2 (sqrt(g h_l) - c_m)^2 + (c_m^2 - g h_r)^2 (c_m^2 + g h_r) = 0.
    h_r = 0 is Ritter's dry bed (h_m = 0, front 2 sqrt(g h_l)); h_r = h_l
    is water at rest. h_r > h_l is the mirror image (speeds change sign and
    left/right swap roles: ``head_speed`` is then that of the right-going
    rarefaction head, etc.).
    """
    h_left, h_right = _depths(h_left, h_right)
    g = positive("g", g)
    if h_right > h_left:
        s = _state(h_right, h_left, g)
        return DamBreakState(-s.head_speed, -s.tail_speed, s.h_middle, -s.u_middle, -s.front_speed)
    return _state(h_left, h_right, g)


def _profile(xi, h_left, h_right, g):
    """(h, u) at xi = (x - x0)/t for h_left >= h_right."""
    s = _state(h_left, h_right, g)
    c_l = math.sqrt(g * h_left)
    fan_h = (2.0 * c_l - xi) ** 2 / (9.0 * g)
    fan_u = 2.0 / 3.0 * (xi + c_l)
    h = np.select([xi <= s.head_speed, xi <= s.tail_speed, xi < s.front_speed],
                  [h_left, fan_h, s.h_middle], h_right)
    u = np.select([xi <= s.head_speed, xi <= s.tail_speed, xi < s.front_speed],
                  [0.0, fan_u, s.u_middle], 0.0)
    return h, u


def dam_break_profile(x, t, h_left, h_right, x0: float = 0.0, g: float = GRAVITY):
    """Depth h and velocity u of the ideal dam break at positions ``x`` and time ``t`` (>= 0).

    Water at rest, depth h_l for x < x0 and h_r for x > x0, flat frictionless
    bed (Stoker 1957; Ritter 1892; SWASHES §4.1.1-4.1.2). With
    xi = (x - x0)/t, c_l = sqrt(g h_l) and the state of :func:`dam_break_state`:
    h = h_l, u = 0 for xi <= -c_l; the rarefaction
    h = (2 c_l - xi)^2/(9 g), u = 2 (xi + c_l)/3 for -c_l <= xi <= u_m - c_m;
    h = h_m, u = u_m up to the bore at xi = s; h = h_r, u = 0 beyond. On a
    dry bed (h_r = 0) the rarefaction reaches the front xi = 2 c_l (Ritter's
    parabola) and beyond it h = 0 and u = 0 (no water). h_r > h_l is the
    mirror image. At t = 0 the initial step (h_l for x < x0, h_r for
    x >= x0). Vectorised over ``x``.
    """
    h_left, h_right = _depths(h_left, h_right)
    g, t, x0 = positive("g", g), non_negative("t", t), number("x0", x0)
    x = np.asarray(x, dtype=float)
    if not np.all(np.isfinite(x)):
        raise ValueError("x must be finite.")
    if t == 0.0:
        return np.where(x < x0, h_left, h_right), np.zeros_like(x)
    if h_right > h_left:
        h, u = _profile(-(x - x0) / t, h_right, h_left, g)
        return h, -u
    return _profile((x - x0) / t, h_left, h_right, g)


def dam_break(x, times, h_left, h_right, x0: float = 0.0, g: float = GRAVITY, case: str = "dam_break") -> xr.Dataset:
    """The ideal dam break (Stoker 1957 wet bed, Ritter 1892 dry bed) as a partmesh result Dataset.

    Fields on (time, x) from :func:`dam_break_profile`: ``h`` the depth,
    ``u`` the depth-averaged velocity and ``eta = h - h_right``, the
    elevation above the still level downstream of the dam (on a dry bed,
    h_right = 0, that is h itself). ``x`` strictly increasing; ``times``
    increasing, >= 0.
    """
    h_left, h_right = _depths(h_left, h_right)
    x, times = axis("x", x), output_times(times)
    rows = [dam_break_profile(x, t, h_left, h_right, x0, g) for t in times]
    h = np.stack([row[0] for row in rows])
    u = np.stack([row[1] for row in rows])
    bed = "wet bed (Stoker 1957)" if h_right > 0.0 and h_left > 0.0 else "dry bed (Ritter 1892)"
    return result(
        case=case, method="exact", scheme=f"ideal dam break, {bed}, shallow-water equations",
        x=x, times=times, dx=float(np.mean(np.diff(x))),
        fields={"eta": h - h_right, "u": u, "h": h},
        parameters={"h_left": h_left, "h_right": h_right, "x0": float(x0), "g": float(g)},
        long_names={"eta": "free-surface elevation above the initial downstream level h_right",
                    "u": "depth-averaged x velocity"},
    )
