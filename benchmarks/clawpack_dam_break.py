"""The bench problem of ``swe`` side by side with Clawpack's 2D shallow-water
solver: the dam break across a square basin (``dam_break --set dim=2``:
[0, 10]² m, h = 1 m for x < 5 m and 0.1 m beyond, outflow in x, walls in
y), N² cells, to t = 0.05 s, cell-updates per second with compile and
set-up time excluded.

Clawpack (``pip install clawpack``; PyClaw's classic Fortran solver,
Roe solver with entropy fix, MC limiter, Courant number 0.9) runs
dimensionally split (its faster mode; one step = an x and a y sweep) and
unsplit with transverse corrections. Run it on one thread, as Clawpack
runs by default::

    OMP_NUM_THREADS=1 python benchmarks/clawpack_dam_break.py [N]
"""

import sys
import time

import numpy as np
from clawpack import pyclaw, riemann

from partmesh.bench import throughput

T_END = 0.05


def clawpack_rate(n: int, split: bool) -> tuple[float, int]:
    """``(cell-updates per second, steps)`` of PyClaw on the square dam break."""
    solver = pyclaw.ClawSolver2D(riemann.shallow_roe_with_efix_2D)
    solver.limiters, solver.order, solver.cfl_desired, solver.cfl_max = pyclaw.limiters.tvd.MC, 2, 0.9, 1.0
    solver.dimensional_split = split
    if not split:
        solver.transverse_waves = 2
    solver.bc_lower[0] = solver.bc_upper[0] = pyclaw.BC.extrap
    solver.bc_lower[1] = solver.bc_upper[1] = pyclaw.BC.wall
    domain = pyclaw.Domain([pyclaw.Dimension(0.0, 10.0, n, name="x"), pyclaw.Dimension(0.0, 10.0, n, name="y")])
    state = pyclaw.State(domain, 3)
    state.problem_data["grav"] = 9.81
    x, _ = state.p_centers
    state.q[0] = np.where(x < 5.0, 1.0, 0.1)
    state.q[1:] = 0.0
    claw = pyclaw.Controller()
    claw.tfinal, claw.solution, claw.solver = T_END, pyclaw.Solution(state, domain), solver
    claw.num_output_times, claw.output_format, claw.keep_copy, claw.verbosity = 1, None, False, 0
    solver.dt_initial = 0.5 * (10.0 / n) / np.sqrt(9.81)
    solver.setup(claw.solution)
    t0 = time.perf_counter()
    claw.run()
    seconds = time.perf_counter() - t0
    steps = solver.status["numsteps"]
    return n * n * steps / seconds, steps


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    print(f"square dam break, {n}² cells, to t = {T_END} s: cell-updates per second")
    for precision in ("float64", "float32"):
        record = throughput("swe", n, T_END, precision=precision)[0]
        print(f"  partmesh swe (MUSCL-Hancock, HLLC), {precision}: {record['value']:.3g} ({record['n_steps']} steps)")
    for split in (True, False):
        rate, steps = clawpack_rate(n, split)
        print(f"  Clawpack classic, {'split' if split else 'unsplit'}: {rate:.3g} ({steps} steps)")
