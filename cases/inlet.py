"""The gas state on an inflow face (SPEC §3.1, §4.2): what a
finite-volume scheme puts on the face between an imposed state and the gas
inside (Toro 2009, "Riemann Solvers and Numerical Methods for Fluid
Dynamics", §6.3.3), for a method whose inflow boundary needs one state.

Where the imposed flow is supersonic the face takes the imposed state;
where it is subsonic, the waves travelling upstream from the domain leave
through the face instead of reflecting from a boundary that holds its
pressure and velocity fixed."""

from __future__ import annotations

from partmesh.compare.exact.riemann import sample


def inlet_face_state(imposed, adjacent, gamma: float) -> tuple[float, float, float, float]:
    """(ρ, u, v, p) on an inflow face normal to x, from the ``imposed``
    state upstream and the ``adjacent`` gas inside, each (ρ, u, v, p): the
    exact solution of their Riemann problem at x/t = 0 (Toro 2009, §4.5),
    with the tangential velocity v carried from the side the gas comes
    from."""
    rho, u, v, p = imposed
    rho_a, u_a, v_a, p_a = adjacent
    rho_b, u_b, p_b = (float(a) for a in sample((rho, u, p), (rho_a, u_a, p_a), gamma, 0.0))
    return rho_b, u_b, (v if u_b > 0.0 else v_a), p_b
