"""The materials of gas SPH's particles (SPEC §3.10): air, an ideal gas of
the scene's γ, p = (γ − 1)ρu, and — where the scene holds a charge of
detonation products — the products, with the JWL equation of state of its
explosive (:class:`partmesh.compare.materials.JWL`),
p = A(1 − ω/(R₁V))e^{−R₁V} + B(1 − ω/(R₂V))e^{−R₂V} + ωρu, V = ρ₀/ρ
(Lee, Hornig & Kury 1968; Dobratz & Crawford 1985). A particle keeps its
material for the whole run: SPH is Lagrangian, so the interface between
the materials needs no indicator of its own. The momentum and energy
equations take the pressure of whichever material a particle holds; they
conserve momentum and energy for any equation of state (Price 2012,
J. Comput. Phys. 231, 759, §3.2), and the artificial conduction's signal
speed √(|p_i − p_j|/ρ̄) vanishes across a contact at one pressure, so the
two materials are not mixed by it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from partmesh.cases.errors import Unsupported
from partmesh.compare.materials import ProductsInAir


@dataclass(frozen=True)
class Materials:
    """Air of ``gamma`` and, with an ``explosive`` (a :class:`~partmesh.compare.materials.JWL`), its
    detonation products. ``products`` below is the boolean mask of the particles that hold them."""

    gamma: float
    explosive: object | None = None

    @classmethod
    def of(cls, scene) -> "Materials":
        """The materials of ``scene``: its air, and its charge's products where it holds one."""
        charge = getattr(scene, "detonation", None)
        return cls(scene.gamma, None if charge is None else charge.explosive)

    def holds_products(self, products) -> bool:
        """Whether any particle of the mask ``products`` holds detonation products."""
        return self.explosive is not None and bool(products.any())

    def pressure(self, rho, u, products) -> np.ndarray:
        """p [Pa] of particles of gas density ``rho`` and specific internal energy ``u``."""
        p = (self.gamma - 1.0) * rho * u
        if self.holds_products(products):
            p[products] = self.explosive.pressure(rho[products], u[products])
        return p

    def products_state(self, rho, u) -> tuple[np.ndarray, np.ndarray]:
        """``(p/ρ, c)`` of products particles of gas density ``rho`` and energy ``u``
        (c² = (∂p/∂ρ)_u + ωp/ρ, :meth:`~partmesh.compare.materials.JWL.sound_speed`; NaN where c² ≤ 0)."""
        return self.explosive.pressure(rho, u) / rho, self.explosive.sound_speed(rho, u)


def charged_state(scene, x, y, dx, rho_air, p) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(ρ, u, products)`` of lattice particles at ``(x, y)`` (spacing ``dx``) in a scene whose charge of
    burnt detonation products (:class:`~partmesh.cases.parts.Detonation`) fills the share α of each
    particle's cell, the air there at ``rho_air`` and the cell at pressure ``p``: each particle carries its
    cell's mass ρ = αρ₁ + (1 − α)ρ_air and internal energy ρu = ξp − αf₁(ρ₁)/ω
    (:class:`~partmesh.compare.materials.ProductsInAir`, the cell at one pressure), and is products where
    they are at least half its mass (a mixed cell becomes one particle of one material: the interface is
    placed to a particle spacing)."""
    charge = scene.detonation
    if not charge.burnt:
        raise Unsupported(f"scene {scene.name}: sph carries detonation products once burnt (surface_burst "
                          "charge=jwl starts from fv's detonated sphere), not a charge to detonate: run it with "
                          "method fv.")
    alpha = np.clip(np.broadcast_to(np.asarray(charge.fraction(x, y, dx), float), x.shape), 0.0, 1.0)
    density = charge.explosive.rho0 if charge.density is None else charge.density
    rho1 = np.broadcast_to(np.asarray(density(x, y, dx) if callable(density) else density, float), x.shape)
    rho_y = alpha * rho1
    rho = rho_y + (1.0 - alpha) * rho_air
    rho_e = ProductsInAir(charge.explosive, scene.gamma).internal_energy(rho, (rho_y, rho_y, alpha), p)
    return rho, rho_e / rho, rho_y >= 0.5 * rho
