"""How many numba threads a run's particle loops use.

A parallel loop (``prange``) pays a fork and a join on every call, tens of
microseconds on an idle machine and a whole scheduler time slice when
another process holds a core; a step calls a dozen such loops. Below
:data:`SERIAL_BELOW` particles the loops finish sooner on one thread:
measured here on ``sod`` with 400 sph particles while another run held a
core, 57 steps took 0.42 s on one thread and 8.9 s on two.

Above it, the threads that wait at a join must sleep rather than spin:
numba's OpenMP layer (libgomp) spins by default, and a spinning thread holds
the core that the thread it waits for needs when another process runs
beside. Measured here (2 cores, 2 threads, dsmc beside a 2-thread run):
``blast_wall`` at dx 0.004 took 102.9 s spinning and 0.81 s sleeping (0.89 s
on one thread), ``sod`` at 0.005 18.6 s and 0.24 s; alone the two policies
are within 0-10 % (0.72 / 0.70 s, 0.17 / 0.21 s).
"""

from __future__ import annotations

import os
from contextlib import contextmanager

import numba

#: runs with fewer particles than this step on one thread
SERIAL_BELOW = 20_000

#: numba's ``parallel`` options of every particle kernel: only the explicit
#: ``prange`` loops run on the threads. With ``parallel=True`` numba also makes
#: a parallel loop of every ``np.zeros``, whole-array expression and reduction,
#: and compiles each as a function of its own (about a second apiece here);
#: none of them is where a step spends its time.
#: Each ``prange`` loop also compiles as a function of its own, at a cost that
#: grows with its body: the long bodies are functions of their own that the
#: loop calls once per chunk of its range (``error_model="numpy"``, as numba
#: compiles a loop body: a division by zero gives inf or NaN, no exception).
PRANGE_ONLY = dict(prange=True, comprehension=False, reduction=False, inplace_binop=False, setitem=False,
                   numpy=False, stencil=False, fusion=False)

#: how idle OpenMP threads wait, unless ``OMP_WAIT_POLICY`` is set already
WAIT_POLICY = "PASSIVE"


def passive_waits() -> str:
    """The ``OMP_WAIT_POLICY`` in force: :data:`WAIT_POLICY` unless the
    environment named one. OpenMP reads it when its threads first start,
    so this runs before any parallel loop (at import of the package)."""
    return os.environ.setdefault("OMP_WAIT_POLICY", WAIT_POLICY)


@contextmanager
def threads_for(particles: int):
    """Inside, the numba threads a run of ``particles`` particles uses: one
    below :data:`SERIAL_BELOW`, else as many as were set (the sweep's
    share of the cores, or all)."""
    before = numba.get_num_threads()
    numba.set_num_threads(1 if particles < SERIAL_BELOW else before)
    try:
        yield
    finally:
        numba.set_num_threads(before)
