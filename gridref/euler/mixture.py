r"""Detonation products and air in one cell: the pressure-equilibrium mixture of the five-equation model
(Allaire, Clerc & Kokh 2002, J. Comput. Phys. 181, 577), with a programmed burn.

A cell holds the explosive (volume fraction :math:`\alpha`, partial density :math:`\alpha\rho_1 = \rho Y`)
and air (:math:`1-\alpha`, :math:`\rho(1-Y)`) at one pressure and one velocity. Both materials are of
Mie–Grüneisen form :math:`p = \Gamma_k\rho_k e_k + f_k(\rho_k)`: air an ideal gas (Γ = γ − 1, f = 0), the
explosive its burnt fraction :math:`\lambda` of JWL products and the rest reactant, at one Γ = ω,

.. math::  f_1(\rho_1) = \lambda f_{\rm JWL}(\rho_1) + (1-\lambda)\big[K(1 - \rho_0/\rho_1) - \omega\rho_1 e_0\big],
           \qquad K = \rho_0 c_r^2

(:meth:`partmesh.compare.materials.JWL.reference_terms`; the reactant is the linear limit of the unreacted
Hugoniot, at rest and ambient pressure until the burn reaches it). The mixture's internal energy
:math:`\rho e = \sum_k \alpha_k(p - f_k)/\Gamma_k` gives the pressure in closed form (Shyue 2001,
J. Comput. Phys. 171, 678, for Mie–Grüneisen mixtures):

.. math::  p = \frac{\rho e + \alpha f_1(\rho_1)/\omega}{\xi},\qquad
           \xi = \frac{\alpha}{\omega} + \frac{1-\alpha}{\gamma-1},

and its sound speed is the frozen mixture's, :math:`\xi c^2 = \sum_k Y_k c_k^2/\Gamma_k` (Allaire et al.
2002, eq. 3.5), with :math:`c_k^2 = ((1+\Gamma_k)p - f_k)/\rho_k + f_k'(\rho_k)`.

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

from partmesh.compare.materials import JWL
from partmesh.gridref.euler.state import parts, primitive

#: how many cells of front travel a programmed burn takes to complete in a cell
BURN_CELLS = 1.5
#: below this volume fraction a material's own density is not formed (its share of every sum is nil)
TRACE = 1e-12


@dataclass(frozen=True)
class Mixture:
    """Detonation products (``explosive``, a :class:`~partmesh.compare.materials.JWL`) and air (``gamma``):
    the thermodynamics of a cell from its density, its three scalars (the explosive's partial density ρY, its
    burnt part ρYλ, its volume fraction α) and its internal energy or pressure; the programmed burn runs at
    ``burn_speed`` (the explosive's Chapman–Jouguet speed)."""

    explosive: JWL
    gamma: float
    burn_speed: float

    #: the scalars a cell carries after its velocities, in the state tuples (ρY, ρYλ, α)
    scalars = 3
    #: of these, the ones advected like a density (conserved, compressed with the flow)
    densities = 2

    def _parts(self, rho, scalars):
        """``(ρ₁, ρ₂, Y, λ, α)``: each material's own density, the explosive's mass fraction, burnt fraction
        and volume fraction (clipped to [0, 1]; a material under :data:`TRACE` gets a stand-in density
        that every sum weighs by zero)."""
        rho_y, burnt, alpha = scalars
        alpha = jnp.clip(alpha, 0.0, 1.0)
        present, air = alpha > TRACE, alpha < 1.0 - TRACE
        rho1 = jnp.where(present, rho_y / jnp.where(present, alpha, 1.0), self.explosive.rho0)
        rho2 = jnp.where(air, jnp.maximum(rho - rho_y, TRACE * rho) / jnp.where(air, 1.0 - alpha, 1.0), rho)
        lam = jnp.where(rho_y > 0.0, jnp.clip(burnt / jnp.where(rho_y > 0.0, rho_y, 1.0), 0.0, 1.0), 1.0)
        return rho1, rho2, jnp.clip(rho_y / rho, 0.0, 1.0), lam, alpha

    def _explosive_terms(self, rho1, lam):
        """``(f₁, f₁')``: the explosive's reference pressure and its derivative in ρ₁ (module docstring)."""
        x = self.explosive
        V, f_jwl, slope = x.reference_terms(rho1, jnp)
        K = x.rho0 * x.c_reactant ** 2
        f_reactant = K * (1.0 - V) - x.omega * rho1 * x.e0
        df_reactant = K * V / rho1 - x.omega * x.e0
        return lam * f_jwl + (1.0 - lam) * f_reactant, lam * (-slope * V / rho1) + (1.0 - lam) * df_reactant

    def _xi(self, alpha):
        return alpha / self.explosive.omega + (1.0 - alpha) / (self.gamma - 1.0)

    def pressure(self, rho, scalars, rho_e):
        """p = (ρe + α f₁/ω)/ξ [Pa]."""
        rho1, _, _, lam, alpha = self._parts(rho, scalars)
        f1, _ = self._explosive_terms(rho1, lam)
        return (rho_e + alpha * f1 / self.explosive.omega) / self._xi(alpha)

    def internal_energy(self, rho, scalars, p):
        """ρe = ξ p − α f₁/ω [J/m³]: the internal energy per volume at pressure ``p``."""
        rho1, _, _, lam, alpha = self._parts(rho, scalars)
        f1, _ = self._explosive_terms(rho1, lam)
        return self._xi(alpha) * p - alpha * f1 / self.explosive.omega

    def energy_per_pressure(self, scalars):
        """∂(ρe)/∂p at fixed partial densities: ξ."""
        return self._xi(jnp.clip(scalars[2], 0.0, 1.0))

    def stiffness(self, rho, scalars, p):
        """ρc² [Pa]: the frozen mixture's (module docstring)."""
        rho1, rho2, Y, lam, alpha = self._parts(rho, scalars)
        f1, df1 = self._explosive_terms(rho1, lam)
        c1 = ((1.0 + self.explosive.omega) * p - f1) / rho1 + df1
        c2 = self.gamma * p / rho2
        return rho * (Y * c1 / self.explosive.omega + (1.0 - Y) * c2 / (self.gamma - 1.0)) / self._xi(alpha)

    @cached_property
    def _isentrope(self):
        """``(ln p_s, ln ρ)`` on the principal isentrope, from 10⁻⁶ to 2 times the unreacted density."""
        x = self.explosive
        cj = x.cj_state()
        rho = np.geomspace(1e-6, 2.0, 600) * x.rho0
        return (jnp.asarray(np.log(x.isentrope_pressure(rho, x.isentrope(cj.rho, cj.p)))),
                jnp.asarray(np.log(rho)))

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
