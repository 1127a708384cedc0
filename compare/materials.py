r"""Detonation products: the Jones–Wilkins–Lee (JWL) equation of state, the explosives' constants, and
the products sharing a cell with air at one pressure (:class:`ProductsInAir`) (SPEC §3.10).

With the relative volume :math:`V = \rho_0/\rho` and the specific internal energy :math:`e`,

.. math::  p(\rho, e) = A\Big(1 - \frac{\omega}{R_1 V}\Big) e^{-R_1 V} + B\Big(1 - \frac{\omega}{R_2 V}\Big) e^{-R_2 V}
           + \omega \rho e

(Lee, Hornig & Kury 1968, UCRL-50422; Dobratz & Crawford 1985, *LLNL Explosives Handbook*, UCRL-52997
Change 2, §8.3). Its sound speed is :math:`c^2 = (\partial p/\partial\rho)_e + (p/\rho^2)(\partial p/\partial e)_\rho`,
and the isentropes are closed forms,

.. math::  p_s(V) = A e^{-R_1 V} + B e^{-R_2 V} + C V^{-(1+\omega)},\qquad
           \rho_0 e_s(V) = \frac{A}{R_1} e^{-R_1 V} + \frac{B}{R_2} e^{-R_2 V} + \frac{C}{\omega} V^{-\omega},

one per constant :math:`C` (the principal isentrope passes through the Chapman–Jouguet state). The CJ state of
a charge of detonation energy :math:`e_0` (per unit mass) is where the Rayleigh line
:math:`p = \rho_0 D^2 (1 - V)` touches the products' Hugoniot
:math:`\rho_0 e = \rho_0 e_0 + \tfrac12 p (1 - V)` (Fickett & Davis 1979, *Detonation*, §2A): the least
detonation speed D on the Hugoniot.

TNT (:data:`TNT`): Dobratz & Crawford's constants, with their detonation energy
:math:`E_0 = \rho_0 e_0 = 7.0` GPa (4.29 MJ/kg). Published energies for TNT's products differ by up to 44 %
(4.2 to 6 MJ/kg, with or without afterburning in air); 7.0 GPa is the one this fit of A, B, R₁, R₂ and ω was
made with, and with it the fit's own CJ point is the handbook's: D 6 929 m/s against 6 930, p 21.00 GPa
against 21.0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from partmesh.compare.checks import InputError

#: below this volume fraction a material's own density is not formed (its share of every sum is nil)
TRACE = 1e-12


@dataclass(frozen=True)
class CJState:
    """The Chapman–Jouguet state: detonation speed ``D`` [m/s], pressure ``p`` [Pa], density ``rho``
    [kg/m³], particle speed ``u`` [m/s] and specific internal energy ``e`` [J/kg] behind the front."""

    D: float
    p: float
    rho: float
    u: float
    e: float


@dataclass(frozen=True)
class JWL:
    """An explosive's detonation products: the JWL constants ``A``, ``B`` [Pa], ``R1``, ``R2``, ``omega``, the
    unreacted density ``rho0`` [kg/m³], the detonation energy ``e0`` [J/kg], the unreacted explosive's bulk
    sound speed ``c_reactant`` [m/s] (the intercept of its shock Hugoniot U_s = c + s u_p: the stiffness of
    the reactant a programmed burn holds until the front reaches it), and where they come from."""

    name: str
    A: float
    B: float
    R1: float
    R2: float
    omega: float
    rho0: float
    e0: float
    c_reactant: float
    source: str = ""

    def __post_init__(self):
        for key in ("A", "B", "R1", "R2", "omega", "rho0", "e0", "c_reactant"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise InputError(f"JWL constant {key} of {self.name} must be a finite number > 0; got {value!r}.")
        p = float(self.pressure(self.rho0, self.e0))
        if not p > 0.0:
            raise InputError(f"the JWL constants of {self.name} give a pressure of {p:.4g} Pa at the initial state "
                             f"(rho0 = {self.rho0:g} kg/m³, e0 = {self.e0:g} J/kg); it must be > 0.")

    def reference_terms(self, rho, xp=np):
        """``(V, f, df/dV)``: the relative volume V = ρ₀/ρ, the pressure's two exponential terms
        f = A(1 − ω/(R₁V)) e^{−R₁V} + B(1 − ω/(R₂V)) e^{−R₂V} (p = f + ωρe) and their derivative in V;
        ``xp`` the array namespace (NumPy, or JAX's inside a compiled solver)."""
        V = self.rho0 / xp.asarray(rho, dtype=float)
        x1, x2 = xp.exp(-self.R1 * V), xp.exp(-self.R2 * V)
        w = self.omega
        terms = self.A * (1.0 - w / (self.R1 * V)) * x1 + self.B * (1.0 - w / (self.R2 * V)) * x2
        slopes = (self.A * x1 * (w / (self.R1 * V * V) + w / V - self.R1)
                  + self.B * x2 * (w / (self.R2 * V * V) + w / V - self.R2))
        return V, terms, slopes

    def pressure(self, rho, e):
        """p(ρ, e) [Pa] (arrays broadcast)."""
        _, terms, _ = self.reference_terms(rho)
        return terms + self.omega * np.asarray(rho, dtype=float) * np.asarray(e, dtype=float)

    def sound_speed(self, rho, e):
        """c = √((∂p/∂ρ)_e + p ω/ρ) [m/s]; NaN where c² ≤ 0."""
        rho = np.asarray(rho, dtype=float)
        V, terms, slopes = self.reference_terms(rho)
        p = terms + self.omega * rho * np.asarray(e, dtype=float)
        c2 = -slopes * V / rho + self.omega * np.asarray(e, dtype=float) + self.omega * p / rho
        return np.sqrt(np.where(c2 > 0.0, c2, np.nan))

    def isentrope(self, rho, p):
        """The constant C of the isentrope through (ρ, p)."""
        V = self.rho0 / float(rho)
        return (float(p) - self.A * math.exp(-self.R1 * V) - self.B * math.exp(-self.R2 * V)) * V ** (1.0 + self.omega)

    def isentrope_pressure(self, rho, C):
        """p_s [Pa] on the isentrope of constant ``C`` at the densities ``rho``."""
        V = self.rho0 / np.asarray(rho, dtype=float)
        return self.A * np.exp(-self.R1 * V) + self.B * np.exp(-self.R2 * V) + C * V ** (-(1.0 + self.omega))

    def isentrope_energy(self, rho, C):
        """e_s [J/kg] on the isentrope of constant ``C`` at the densities ``rho``."""
        V = self.rho0 / np.asarray(rho, dtype=float)
        return (self.A / self.R1 * np.exp(-self.R1 * V) + self.B / self.R2 * np.exp(-self.R2 * V)
                + C / self.omega * V ** (-self.omega)) / self.rho0

    def hugoniot_pressure(self, V):
        """p [Pa] on the products' Hugoniot from the unreacted state (p₀ ≈ 0, energy e₀) at the relative
        volumes ``V``: p = (Σ terms + ω ρ₀ e₀/V) / (1 − ω (1 − V)/(2V))."""
        V = np.asarray(V, dtype=float)
        _, terms, _ = self.reference_terms(self.rho0 / V)
        return (terms + self.omega * self.rho0 * self.e0 / V) / (1.0 - self.omega * (1.0 - V) / (2.0 * V))

    def cj_state(self) -> CJState:
        """The Chapman–Jouguet state: the least D² = p_H(V)/(ρ₀ (1 − V)) over the Hugoniot's V < 1."""
        from scipy.optimize import minimize_scalar  # (SciPy: the CJ solve only, not the equation of state)

        # below V = ω/(2 + ω) the Hugoniot's denominator vanishes; the tangent point lies above it
        lowest = self.omega / (2.0 + self.omega)
        found = minimize_scalar(lambda V: self.hugoniot_pressure(V) / (self.rho0 * (1.0 - V)),
                                bounds=(lowest + 1e-9, 1.0 - 1e-9), method="bounded", options={"xatol": 1e-13})
        V = float(found.x)
        p = float(self.hugoniot_pressure(V))
        D = math.sqrt(p / (self.rho0 * (1.0 - V)))
        return CJState(D=D, p=p, rho=self.rho0 / V, u=D * (1.0 - V), e=self.e0 + 0.5 * p * (1.0 - V) / self.rho0)


@dataclass(frozen=True)
class ProductsInAir:
    r"""An explosive (``explosive``, a :class:`JWL`) and air (an ideal gas of ``gamma``) sharing a cell at
    one pressure: the thermodynamics of the cell from its density ρ, its ``scalars`` — the explosive's
    partial density ρY, its burnt part ρYλ (λ the burnt fraction), its volume fraction α — and its internal
    energy or pressure. Both materials are of Mie–Grüneisen form :math:`p = \Gamma_k\rho_k e_k + f_k(\rho_k)`:
    air with Γ = γ − 1 and f = 0, the explosive with Γ = ω and

    .. math::  f_1(\rho_1) = \lambda f_{\rm JWL}(\rho_1)
               + (1-\lambda)\big[K(1 - \rho_0/\rho_1) - \omega\rho_1 e_0\big],\qquad K = \rho_0 c_r^2

    (:meth:`JWL.reference_terms`; the reactant the linear limit of the unreacted Hugoniot, at rest at zero
    pressure holding e₀). The mixture's :math:`\rho e = \sum_k \alpha_k(p - f_k)/\Gamma_k` gives the
    pressure in closed form (Shyue 2001, J. Comput. Phys. 171, 678),

    .. math::  p = \frac{\rho e + \alpha f_1(\rho_1)/\omega}{\xi},\qquad
               \xi = \frac{\alpha}{\omega} + \frac{1-\alpha}{\gamma-1},

    and its sound speed is the frozen mixture's, :math:`\xi c^2 = \sum_k Y_k c_k^2/\Gamma_k` (Allaire, Clerc
    & Kokh 2002, J. Comput. Phys. 181, 577), :math:`c_k^2 = ((1+\Gamma_k)p - f_k)/\rho_k + f_k'(\rho_k)`.
    Every method takes the array namespace ``xp`` (NumPy, or JAX's inside a compiled solver)."""

    explosive: JWL
    gamma: float

    def parts(self, rho, scalars, xp=np):
        """``(ρ₁, ρ₂, Y, λ, α)``: each material's own density, the explosive's mass fraction, burnt fraction
        and volume fraction (clipped to [0, 1]; a material under :data:`TRACE` gets a stand-in density
        that every sum weighs by zero)."""
        rho_y, burnt, alpha = scalars
        alpha = xp.clip(alpha, 0.0, 1.0)
        present, air = alpha > TRACE, alpha < 1.0 - TRACE
        rho1 = xp.where(present, rho_y / xp.where(present, alpha, 1.0), self.explosive.rho0)
        rho2 = xp.where(air, xp.maximum(rho - rho_y, TRACE * rho) / xp.where(air, 1.0 - alpha, 1.0), rho)
        lam = xp.where(rho_y > 0.0, xp.clip(burnt / xp.where(rho_y > 0.0, rho_y, 1.0), 0.0, 1.0), 1.0)
        return rho1, rho2, xp.clip(rho_y / rho, 0.0, 1.0), lam, alpha

    def explosive_terms(self, rho1, lam, xp=np):
        """``(f₁, f₁')``: the explosive's reference pressure and its derivative in ρ₁ (class docstring)."""
        x = self.explosive
        V, f_jwl, slope = x.reference_terms(rho1, xp)
        K = x.rho0 * x.c_reactant ** 2
        f_reactant = K * (1.0 - V) - x.omega * rho1 * x.e0
        df_reactant = K * V / rho1 - x.omega * x.e0
        return lam * f_jwl + (1.0 - lam) * f_reactant, lam * (-slope * V / rho1) + (1.0 - lam) * df_reactant

    def xi(self, alpha):
        """ξ = α/ω + (1 − α)/(γ − 1): ∂(ρe)/∂p at fixed partial densities."""
        return alpha / self.explosive.omega + (1.0 - alpha) / (self.gamma - 1.0)

    def pressure(self, rho, scalars, rho_e, xp=np):
        """p = (ρe + α f₁/ω)/ξ [Pa]."""
        rho1, _, _, lam, alpha = self.parts(rho, scalars, xp)
        f1, _ = self.explosive_terms(rho1, lam, xp)
        return (rho_e + alpha * f1 / self.explosive.omega) / self.xi(alpha)

    def internal_energy(self, rho, scalars, p, xp=np):
        """ρe = ξ p − α f₁/ω [J/m³]: the internal energy per volume at pressure ``p``."""
        rho1, _, _, lam, alpha = self.parts(rho, scalars, xp)
        f1, _ = self.explosive_terms(rho1, lam, xp)
        return self.xi(alpha) * p - alpha * f1 / self.explosive.omega

    def energy_per_pressure(self, scalars, xp=np):
        """∂(ρe)/∂p at fixed partial densities: ξ."""
        return self.xi(xp.clip(scalars[2], 0.0, 1.0))

    def stiffness(self, rho, scalars, p, xp=np):
        """ρc² [Pa]: the frozen mixture's (class docstring)."""
        rho1, rho2, Y, lam, alpha = self.parts(rho, scalars, xp)
        f1, df1 = self.explosive_terms(rho1, lam, xp)
        c1 = ((1.0 + self.explosive.omega) * p - f1) / rho1 + df1
        c2 = self.gamma * p / rho2
        return rho * (Y * c1 / self.explosive.omega + (1.0 - Y) * c2 / (self.gamma - 1.0)) / self.xi(alpha)


#: TNT (Dobratz & Crawford 1985, LLNL Explosives Handbook UCRL-52997 Change 2, Table 8-5): ρ₀ 1.630 g/cm³,
#: D 0.693 cm/µs, p_CJ 0.210 Mbar, A 3.712 Mbar, B 0.03231 Mbar, R₁ 4.15, R₂ 0.95, ω 0.30, E₀ 0.070 Mbar;
#: the unreacted bulk sound speed 2.39 km/s of cast TNT's Hugoniot U_s = 2.39 + 2.05 u_p km/s (Marsh 1980,
#: LASL Shock Hugoniot Data, ρ₀ 1.614 g/cm³)
TNT = JWL("TNT", A=371.2e9, B=3.231e9, R1=4.15, R2=0.95, omega=0.30, rho0=1630.0, e0=7.0e9 / 1630.0,
          c_reactant=2390.0,
          source="Dobratz & Crawford 1985, LLNL Explosives Handbook (UCRL-52997 Change 2), Table 8-5; "
                 "reactant: Marsh 1980, LASL Shock Hugoniot Data")
