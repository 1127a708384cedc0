"""Numerical flux of the shallow-water equations through a face, dry states
included (Toro 2001, *Shock-Capturing Methods for Free-Surface Shallow
Flows*, Wiley, ch. 10).

With the normal velocity ``u``, the tangential ``v`` and ``c = sqrt(g h)``,
the physical flux is ``F = (h u, h u² + g h²/2, h u v)``. The HLL flux
(Harten, Lax & van Leer 1983) of the first two components is

    F = (s_R F_L − s_L F_R + s_L s_R (U_R − U_L)) / (s_R − s_L)

between the wave-speed bounds ``s_L = min(u_L − c_L, u_R − c_R)`` and
``s_R = max(u_L + c_L, u_R + c_R)`` (Davis 1988), replaced by the front
speeds of a dry side (``u_R − 2 c_R`` when ``h_L = 0``, ``u_L + 2 c_L`` when
``h_R = 0``; Toro 2001 §10.5); the flux is the left or right physical flux
where both bounds have one sign. The tangential momentum is carried by the
mass flux with the upwind tangential velocity: the HLLC flux for the
shear wave (Toro 2001 §10.4).
"""

from __future__ import annotations

import jax.numpy as jnp


def physical_flux(h, u, v, g):
    """``(h u, h u² + g h²/2, h u v)``."""
    hu = h * u
    return hu, hu * u + 0.5 * g * h * h, hu * v


def hllc(hL, uL, vL, hR, uR, vR, g):
    """The HLLC flux ``(mass, normal momentum, tangential momentum)``
    between the states left and right of a face; ``h ≥ 0`` (dry sides allowed)."""
    cL, cR = jnp.sqrt(g * hL), jnp.sqrt(g * hR)
    wetL, wetR = hL > 0.0, hR > 0.0
    sL = jnp.where(wetL, jnp.minimum(uL - cL, uR - cR), uR - 2.0 * cR)
    sR = jnp.where(wetR, jnp.maximum(uL + cL, uR + cR), uL + 2.0 * cL)
    sL = jnp.where(wetR, sL, uL - cL)  # a dry side: the wet state's own wave on the other edge
    sR = jnp.where(wetL, sR, uR + cR)
    fL, fR = physical_flux(hL, uL, vL, g), physical_flux(hR, uR, vR, g)
    width = jnp.where(sR > sL, sR - sL, 1.0)
    mass_star = (sR * fL[0] - sL * fR[0] + sL * sR * (hR - hL)) / width
    mom_star = (sR * fL[1] - sL * fR[1] + sL * sR * (hR * uR - hL * uL)) / width
    left, right = sL >= 0.0, sR <= 0.0
    mass = jnp.where(left, fL[0], jnp.where(right, fR[0], mass_star))
    mom = jnp.where(left, fL[1], jnp.where(right, fR[1], mom_star))
    both_dry = ~(wetL | wetR)
    mass, mom = jnp.where(both_dry, 0.0, mass), jnp.where(both_dry, 0.0, mom)
    return mass, mom, mass * jnp.where(mass >= 0.0, vL, vR)
