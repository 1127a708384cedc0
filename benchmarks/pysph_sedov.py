"""The SPH bench problem (2D Sedov, ``sedov`` scene: [-1, 1]² of gas at
rest, ρ = 1, p = 1e-5, γ = 1.4, energy E = 1 per metre put into the disc
r < 0.03; 448² = 200 704 particles) in PySPH, for the side-by-side rate of
``partmesh bench``: particle-steps per second of PySPH's stepping loop
(the setup, code generation and the first acceleration excluded).

PySPH 1.0b2's own gas-dynamics Sedov example is kept as it is (scheme
``mpm`` by default: cubic spline with h = 1.2 Δx, Hopkins' pressure-energy
adaptive h, PEC integrator); only its particles are replaced, since the
example reads a fixed 104² lattice, and it steps at a fixed Δt = 1e-6 s
(the blast barely moves: PySPH's adaptive-h iteration converges at once,
so this is its fastest rate; ``partmesh bench`` takes the CFL step, about
1e-4 s). Install PySPH in an environment of its
own (it needs numpy < 2: ``pip install "numpy<2" cython mako compyle
cyarray`` then ``pip install pysph==1.0b2 --no-build-isolation``) and run::

    python benchmarks/pysph_sedov.py --openmp --max-steps 25 --disable-output
"""

import time

import numpy as np
from pysph.base.kernels import WendlandQuinticC6
from pysph.base.utils import get_particle_array
from pysph.examples.gas_dynamics import sedov

N, HALF_WIDTH, E, R_INIT, P0 = 448, 1.0, 1.0, 0.03, 1e-5


class SedovBench(sedov.SedovPointExplosion):
    """The example with the ``sedov`` scene's particles, timing its steps."""

    def add_user_options(self, group):
        group.add_argument("--same-kernel", action="store_true",
                           help="Wendland C6 with support 4 dx (h = 2 dx), as partmesh sph uses")

    def consume_user_options(self):
        self.hdx = 2.0 if self.options.same_kernel else sedov.kernel_factor

    def create_particles(self):
        dx = 2.0 * HALF_WIDTH / N
        c = -HALF_WIDTH + (np.arange(N) + 0.5) * dx
        x, y = (a.ravel() for a in np.meshgrid(c, c, indexing="ij"))
        m = np.full(x.size, dx * dx)
        hot = np.hypot(x, y) < max(R_INIT, 2.0 * dx)
        e = P0 / (sedov.gamma1 * 1.0) + np.where(hot, E / m[hot].sum(), 0.0)
        fluid = get_particle_array(name="fluid", x=x, y=y, rho=np.ones_like(x), p=sedov.gamma1 * e, e=e,
                                   h=self.hdx * dx, m=m)
        self.scheme.setup_properties([fluid])
        self.steps = []
        return [fluid]

    def configure_scheme(self):
        kernel = None
        if self.options.same_kernel:
            self.scheme.scheme.kernel_factor = self.hdx
            kernel = WendlandQuinticC6(dim=2)
        self.scheme.configure_solver(kernel=kernel, dt=1e-6, tf=1.0, adaptive_timestep=False,
                                     pfreq=10**9)

    def pre_step(self, solver):
        if not self.steps:
            self.steps.append(time.perf_counter())

    def post_step(self, solver):
        self.steps.append(time.perf_counter())


if __name__ == "__main__":
    app = SedovBench()
    app.run()
    n, seconds = len(app.steps) - 1, app.steps[-1] - app.steps[0]
    count = app.particles[0].get_number_of_particles()
    print(f"PySPH {app.options.scheme}: {count} particles, {n} steps in {seconds:.2f} s: "
          f"{count * n / seconds:.3g} particle-steps/s")
