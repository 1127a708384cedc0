"""The obstacle shapes by name (SPEC §4.2): the blast-array rods, the wedge,
a polygon from its vertices, and a shape rebuilt from its ``to_dict()``.

:func:`circle`, :func:`square`, :func:`triangle_left`, :func:`triangle_right`
and :func:`diamond` (collected in :data:`SHAPES`) all take
``(cx, cy, size)`` and return a shape whose frontal extent across ``y`` (the
height seen by a blast travelling in ``+x``) equals ``size``, so an array of
any of them has the same blockage ratio.  The triangles are equilateral with
side ``size`` and a vertical flat side; by default they are centred on their
centroid (``anchor="centroid"``), ``anchor="bbox"`` centres the bounding box
instead.
"""

from __future__ import annotations

import math
from typing import Any, Mapping, Sequence

from partmesh.cases.shapes import Circle, Polygon, Shape
from partmesh.compare.checks import number, positive


def _centre(cx, cy) -> tuple[float, float]:
    return number("cx", cx), number("cy", cy)


def circle(cx: float, cy: float, size: float) -> Circle:
    """Circle of diameter ``size`` centred at ``(cx, cy)``."""
    cx, cy = _centre(cx, cy)
    return Circle(cx, cy, 0.5 * positive("size", size))


def square(cx: float, cy: float, size: float) -> Polygon:
    """Axis-aligned square of side ``size`` centred at ``(cx, cy)``."""
    cx, cy = _centre(cx, cy)
    h = 0.5 * positive("size", size)
    return Polygon(((cx - h, cy - h), (cx + h, cy - h), (cx + h, cy + h), (cx - h, cy + h)))


def _triangle(cx, cy, size, anchor, apex_left: bool) -> Polygon:
    cx, cy = _centre(cx, cy)
    a = positive("size", size)
    h = a * math.sqrt(3.0) / 2.0  # altitude along x
    if anchor == "centroid":
        off = h / 6.0  # centroid sits h/3 from the base, bbox centre h/2
    elif anchor == "bbox":
        off = 0.0
    else:
        raise ValueError(f"anchor must be 'centroid' or 'bbox', got {anchor!r}.")
    if apex_left:
        # x-extent relative to the bbox centre: apex at -h/2, base at +h/2;
        # the centroid lies at +h/6, so shift by -h/6 to put it at cx
        xa, xb = cx - h / 2 - off, cx + h / 2 - off
        return Polygon(((xa, cy), (xb, cy - a / 2), (xb, cy + a / 2)))
    xb, xa = cx - h / 2 + off, cx + h / 2 + off
    return Polygon(((xb, cy - a / 2), (xa, cy), (xb, cy + a / 2)))


def triangle_left(cx: float, cy: float, size: float, anchor: str = "centroid") -> Polygon:
    """Equilateral triangle of side ``size`` with its apex pointing upstream
    (toward -x) and its flat vertical base facing downstream (+x).

    Frontal extent (base height) = ``size``; x-extent = ``size * sqrt(3)/2``.
    ``anchor="centroid"`` (default) puts the centroid at ``(cx, cy)`` (apex at
    ``cx - size/sqrt(3)``, base at ``cx + size/(2 sqrt(3))``); ``"bbox"``
    centres the bounding box there instead.
    """
    return _triangle(cx, cy, size, anchor, apex_left=True)


def triangle_right(cx: float, cy: float, size: float, anchor: str = "centroid") -> Polygon:
    """Equilateral triangle of side ``size`` with its flat vertical base facing
    the blast (on the -x side) and its apex pointing downstream (toward +x).
    The mirror image of :func:`triangle_left` about ``x = cx``; same anchors."""
    return _triangle(cx, cy, size, anchor, apex_left=False)


def diamond(cx: float, cy: float, size: float) -> Polygon:
    """Square rotated by 45 degrees with diagonal ``size`` (both diagonals
    along the axes), centred at ``(cx, cy)``."""
    cx, cy = _centre(cx, cy)
    h = 0.5 * positive("size", size)
    return Polygon(((cx - h, cy), (cx, cy - h), (cx + h, cy), (cx, cy + h)))


def wedge(x_apex: float, y_wall: float, half_angle_deg: float, length: float) -> Polygon:
    """Upper half of a symmetric wedge standing on the wall ``y = y_wall``:
    the triangle ``(x_apex, y_wall), (x_apex + length, y_wall),
    (x_apex + length, y_wall + length tan(theta))``, apex pointing upstream."""
    x0 = number("x_apex", x_apex)
    y0 = number("y_wall", y_wall)
    theta = number("half_angle_deg", half_angle_deg)
    if not 0.0 < theta < 90.0:
        raise ValueError(f"half_angle_deg must lie in (0, 90) degrees, got {half_angle_deg!r}.")
    length = positive("length", length)
    top = length * math.tan(math.radians(theta))
    return Polygon(((x0, y0), (x0 + length, y0), (x0 + length, y0 + top)))


def polygon(vertices: Sequence[Sequence[float]]) -> Polygon:
    """Simple polygon from ``(x, y)`` vertices in either orientation."""
    return Polygon(vertices)


#: The blast-array shapes, all ``f(cx, cy, size)`` with frontal extent ``size``.
SHAPES = {
    "circle": circle,
    "square": square,
    "triangle_left": triangle_left,
    "triangle_right": triangle_right,
    "diamond": diamond,
}

_FACTORIES = {**SHAPES, "wedge": wedge}


def from_dict(d: Mapping[str, Any]) -> Shape:
    """Rebuild a shape from ``to_dict()`` output.

    Accepts ``{"shape": "circle", "cx", "cy", "radius"}``,
    ``{"shape": "polygon", "vertices": [[x, y], ...]}``, and the factory forms
    ``{"shape": <name in SHAPES>, "cx", "cy", "size"[, "anchor"]}`` and
    ``{"shape": "wedge", "x_apex", "y_wall", "half_angle_deg", "length"}``.
    """
    if not isinstance(d, Mapping) or "shape" not in d:
        raise ValueError("d must be a mapping with a 'shape' key naming the shape.")
    kind = d["shape"]
    params = {k: v for k, v in d.items() if k != "shape"}
    allowed = sorted({"circle", "polygon", *_FACTORIES})
    try:
        if kind == "circle" and "radius" in params:
            return Circle(**params)
        if kind == "polygon":
            return Polygon(tuple(tuple(p) for p in params["vertices"]))
        if kind in _FACTORIES:
            return _FACTORIES[kind](**params)
    except (TypeError, KeyError) as exc:
        raise ValueError(f"d has the wrong parameters for shape {kind!r}: {exc}.") from None
    raise ValueError(f"shape must be one of {allowed}, got {kind!r}.")
