r"""Detonation products and air in one cell of the fv grid: the pressure-equilibrium mixture of the
five-equation model (Allaire, Clerc & Kokh 2002, J. Comput. Phys. 181, 577), whose equation of state is
:class:`partmesh.compare.materials.ProductsInAir`, with a programmed burn.

A contact between the two materials moving at constant speed keeps its pressure and velocity exactly: the
partial densities are advected conservatively and α by :math:`\alpha_t + u\cdot\nabla\alpha = 0` with the
HLLC solver's volume flux (Johnsen & Colonius 2006, J. Comput. Phys. 219, 715),
:math:`\alpha^{n+1} = \alpha - \Delta t\,[\nabla\cdot(\alpha u) - \alpha\nabla\cdot u]`, clipped to
[0, 1]; face states are kept within the materials' bounds (0 ≤ ρY ≤ ρ, 0 ≤ ρYλ ≤ ρY, 0 ≤ α ≤ 1), which the
limited slopes of ρ and ρY taken apart may leave. Where the contact is smeared, a trace of products carried
into the air keeps the density ratio to the mixture it had when it was mixed (the model's equal strain of
both materials), denser than any products can be at the cell's pressure once the fireball has expanded;
after every step the burnt products' density is therefore bounded by the principal isentrope's at the
cell's pressure, :math:`\rho_1 \le \rho_s(p)` (products leave the CJ state on that isentrope and
only gain entropy in shocks, so at a given pressure none is denser), raising α where it is exceeded.
:mod:`partmesh.gridref.euler.state` lays the state out, :mod:`partmesh.gridref.euler.riemann` fluxes it.

The programmed burn (Mader 2008, *Numerical Modeling of Explosives and Propellants*, §2.2): a cell of the
charge lights at :math:`t_l = |x - x_i|/D` and burns over 1.5 cells of front travel,
:math:`\lambda = \min(1, \tfrac{2}{3} D (t - t_l)/\Delta x)` (as in LS-DYNA's programmed burn), the
chemical energy :math:`e_0` released into the pressure as λ rises.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import jax.numpy as jnp
import numpy as np

from partmesh.compare.materials import ProductsInAir
from partmesh.gridref.euler.state import parts, primitive

#: how many cells of front travel a programmed burn takes to complete in a cell
BURN_CELLS = 1.5


@dataclass(frozen=True)
class Mixture(ProductsInAir):
    """Detonation products and air (:class:`~partmesh.compare.materials.ProductsInAir`) in the fv state
    tuples: after its velocities a cell carries the explosive's partial density ρY, its burnt part ρYλ and
    its volume fraction α; the programmed burn runs at ``burn_speed`` (the explosive's Chapman–Jouguet
    speed)."""

    burn_speed: float

    #: the scalars a cell carries after its velocities, in the state tuples (ρY, ρYλ, α)
    scalars = 3
    #: of these, the ones advected like a density (conserved, compressed with the flow)
    densities = 2

    @cached_property
    def _isentrope(self):
        """``(ln p_s, ln ρ)`` on the principal isentrope, from 10⁻⁶ to 2 times the unreacted density (NumPy
        arrays: constants of any program that reads them, never values of one trace kept for another)."""
        x = self.explosive
        cj = x.cj_state()
        rho = np.geomspace(1e-6, 2.0, 600) * x.rho0
        return np.log(x.isentrope_pressure(rho, x.isentrope(cj.rho, cj.p))), np.log(rho)

    def admissible(self, U):
        """The conservative state ``U`` with α raised where the burnt products would be denser than the
        principal isentrope allows at the cell's pressure (module docstring): α ≥ ρY/ρ_s(p)."""
        rho, _, scalars, p = parts(primitive(U, self), self)
        log_p, log_rho = self._isentrope
        densest = jnp.exp(jnp.interp(jnp.log(jnp.maximum(p, 1e-300)), log_p, log_rho))
        burnt = scalars[1] >= scalars[0]
        alpha = jnp.where(burnt, jnp.clip(jnp.maximum(U[-2], scalars[0] / densest), 0.0, 1.0), U[-2])
        return (*U[:-2], alpha, U[-1])

    def bounded(self, W):
        """The primitive state ``W`` with its scalars within the materials' bounds: 0 ≤ ρY ≤ ρ,
        0 ≤ ρYλ ≤ ρY, 0 ≤ α ≤ 1."""
        rho, rho_y, burnt, alpha = W[0], W[-4], W[-3], W[-2]
        rho_y = jnp.clip(rho_y, 0.0, rho)
        return (*W[:-4], rho_y, jnp.clip(burnt, 0.0, rho_y), jnp.clip(alpha, 0.0, 1.0), W[-1])


def burn_fraction(t, lighting, dx, D):
    """λ of the programmed burn at time ``t`` in cells lit at ``lighting`` [s] (−∞ outside the charge)."""
    return jnp.clip((t - lighting) * (D / (BURN_CELLS * dx)), 0.0, 1.0)


def burnt(U, lighting, t, dx, D):
    """The conservative state ``U`` of a mixture with its explosive burnt as far as the programmed burn has
    reached at time ``t``: ``ρYλ = min(ρY, max(ρYλ, ρY λ(t)))`` (mass, momentum and energy unchanged: the
    energy it releases is the reactant's pressure becoming the products'; burnt, the products' ρYλ is ρY)."""
    burnt_part = jnp.minimum(U[-4], jnp.maximum(U[-3], U[-4] * burn_fraction(t, lighting, dx, D)))
    return (*U[:-3], burnt_part, *U[-2:])


def lighting_times(points, fraction, initiation, D):
    """The time [s] each cell of the charge (``fraction`` > 0) is reached by a detonation front run at ``D``
    from ``initiation``, −∞ in the cells without explosive (NumPy; ``points`` the cells' centres)."""
    distance = np.sqrt(sum((np.asarray(x, float) - x0) ** 2 for x, x0 in zip(points, initiation)))
    return np.where(np.asarray(fraction) > 0.0, distance / D, -np.inf)
