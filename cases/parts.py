"""The parts a scene is made of: an imposed inflow state, a probe, the
target wall, the output grid and a charge of detonation products
(:mod:`partmesh.cases.scene` puts them together)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Inflow:
    """An imposed, possibly time-dependent, gas state on a boundary.

    ``state(t)`` returns ``(rho, u, v, p)`` at time ``t`` [s]; velocities are
    Cartesian components (an inflow through ``x_lo`` has ``u > 0``).
    ``state(t, xp=jax.numpy)`` evaluates it on a traced ``t``, inside a
    compiled time loop: a time-dependent state is written with the array
    namespace ``xp`` (a constant one may ignore it).
    """

    state: Callable[[float], tuple[float, float, float, float]]
    description: str


@dataclass(frozen=True)
class Detonation:
    """A charge of high explosive in a gas scene, detonated by a programmed
    burn (SPEC §3.10): its ``explosive`` (a
    :class:`~partmesh.compare.materials.JWL`: the products' equation of state,
    the unreacted density and the detonation energy), ``fraction(x, y, dx)``
    the share of every cell's volume it fills at the points ``(x, y)``
    (``y`` None in 1D) of spacing ``dx``, and the ``initiation`` point where
    the burn starts, from which it runs at the Chapman–Jouguet speed. The
    charge is unreacted at the explosive's density, or with ``burnt`` its
    products from the start at ``density`` (default the explosive's; a
    number, or ``density(x, y, dx)`` per cell), in either case at the
    pressure and velocity ``initial`` gives, whose density is then the air's."""

    explosive: object
    fraction: Callable
    initiation: tuple[float, ...]
    density: float | Callable | None = None
    burnt: bool = False


@dataclass(frozen=True)
class Probe:
    """A named point where a time series is recorded.

    ``shell``: the flow is symmetric about the origin (a sphere in r–z, a
    circle in planar 2D), so the probe stands for every point at its
    distance from the origin. A method whose one-cell reading scatters
    (``dsmc``) then reads the mean over that shell; ``fv`` and ``sph``
    read the point, which in such a flow holds the same value.
    """

    name: str
    x: float
    y: float = 0.0
    shell: bool = False
    z: float = 0.0

    def at(self, dim: int) -> tuple[float, ...]:
        """The probe's position in ``dim`` dimensions: ``(x,)``, ``(x, y)`` or ``(x, y, z)``."""
        return (self.x, self.y, self.z)[:dim]


@dataclass(frozen=True)
class Wall:
    """The target wall whose load is reported as ``wall_force``/``wall_impulse``.

    ``height`` [m] is the wall's extent across the flow; in a 1D run the force
    per metre depth is ``(p_wall - p0) * height`` so 1D and 2D results of the
    same scene compare directly.
    """

    side: str
    p0: float
    height: float


@dataclass(frozen=True)
class OutputGrid:
    """The scene's output grid: uniform cell centres over the domain, output
    times, and the probe sampling interval."""

    domain: tuple[tuple[float, float], ...]
    shape: tuple[int, ...]  # (nx,), (nx, ny) or (nx, ny, nz)
    times: tuple[float, ...]
    dt_probe: float

    @property
    def spacing(self) -> tuple[float, ...]:
        return tuple((hi - lo) / n for (lo, hi), n in zip(self.domain, self.shape))

    def centres(self, axis: int) -> np.ndarray:
        """Cell-centre coordinates along ``axis`` (0: x, 1: y, 2: z)."""
        (lo, hi), n = self.domain[axis], self.shape[axis]
        return lo + (np.arange(n) + 0.5) * (hi - lo) / n

    @property
    def x(self) -> np.ndarray:
        return self.centres(0)

    @property
    def y(self) -> np.ndarray | None:
        return self.centres(1) if len(self.shape) >= 2 else None

    @property
    def z(self) -> np.ndarray | None:
        return self.centres(2) if len(self.shape) == 3 else None

    def probe_times(self, t_end: float, t_start: float = 0.0) -> np.ndarray:
        """Sampling times t_start, t_start + dt_probe, ... up to and including ``t_end``."""
        n = int(np.floor((t_end - t_start) / self.dt_probe + 1e-9))
        t = t_start + np.arange(n + 1) * self.dt_probe
        return t if np.isclose(t[-1], t_end) else np.append(t, t_end)
