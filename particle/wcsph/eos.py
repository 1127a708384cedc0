"""The equation of state of weakly compressible water (SPEC §3.2): Tait's,
with the sound speed, the energy a compression stores and the pressure of
water at rest (Monaghan 1994, J. Comput. Phys. 110, 399)."""

from __future__ import annotations

from dataclasses import dataclass

#: the exponent of the Tait equation of state
TAIT_GAMMA = 7.0


@dataclass(frozen=True)
class Tait:
    """The Tait equation of state P = B[(ρ/ρ0)^γ − 1], B = c0² ρ0/γ, γ = 7
    (Monaghan 1994), and the sound speed c = c0 (ρ/ρ0)^((γ−1)/2)."""

    rho0: float
    c0: float

    @property
    def B(self) -> float:
        return self.c0 * self.c0 * self.rho0 / TAIT_GAMMA

    def pressure(self, rho):
        return self.B * ((rho / self.rho0) ** TAIT_GAMMA - 1.0)

    def density(self, p):
        """The density at pressure ``p`` (the inverse of :meth:`pressure`)."""
        return self.rho0 * (1.0 + p / self.B) ** (1.0 / TAIT_GAMMA)

    def sound_speed(self, rho):
        return self.c0 * (rho / self.rho0) ** (0.5 * (TAIT_GAMMA - 1.0))

    def internal_energy(self, rho):
        """The specific energy the compression stores,
        e(ρ) = ∫_{ρ0}^{ρ} P/ρ'² dρ' = B[((ρ/ρ0)^(γ−1) − 1)/((γ−1) ρ0) + 1/ρ − 1/ρ0]."""
        gm1 = TAIT_GAMMA - 1.0
        return self.B * (((rho / self.rho0) ** gm1 - 1.0) / (gm1 * self.rho0) + 1.0 / rho - 1.0 / self.rho0)

    def hydrostatic_pressure(self, depth, g: float):
        """The pressure ``depth`` below the surface of water at rest,
        dP/dz = −ρ(P) g with P = 0 at the surface: with s = 1 + P/B,
        s^(−1/γ) ds = −(ρ0 g/B) dz, so
        s = [1 + (1 − 1/γ) ρ0 g depth/B]^(γ/(γ−1))."""
        k = 1.0 - 1.0 / TAIT_GAMMA
        return self.B * ((1.0 + k * self.rho0 * g * depth / self.B) ** (1.0 / k) - 1.0)
