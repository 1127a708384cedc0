"""The time loop of a particle method: :func:`partmesh.cases.march.march` one host
step at a time (:class:`partmesh.cases.march.single_steps`), on the numba threads
that suit the run's size (:func:`partmesh.particle.threads.threads_for`), writing
the particles of the last good state where the settings ask for them."""

from __future__ import annotations

from partmesh.cases.march import Start, Stepping, march, single_steps
from partmesh.compare.io import write_particles
from partmesh.particle.threads import threads_for


def march_particles(run, state, t: float, step, ckpt, saved_state, settings, particles: int, snapshot=None):
    """Advance ``state`` from ``t`` to ``settings.t_end`` by ``step(state,
    t, dt_cfl, t_out)`` (:class:`~partmesh.cases.march.single_steps`) and return the
    run's Dataset; ``particles`` is the particle count the threads are
    chosen for. However the run ends, ``snapshot(state, t)`` (the particle
    Dataset of SPEC §2) of the last good state is written to
    ``settings.particles`` if that names a file."""
    try:
        with threads_for(particles):
            return march(run, Start(state, t), Stepping(single_steps(step), saved_state), ckpt, settings)
    finally:
        if getattr(settings, "particles", None) is not None and run.state is not None:
            write_particles(snapshot(run.state, run.t), settings.particles)
