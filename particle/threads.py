"""How many numba threads a run's particle loops use.

A parallel loop (``prange``) pays a fork and a join on every call, tens of
microseconds on an idle machine and a whole scheduler time slice when
another process holds a core; a step calls a dozen such loops. Below
:data:`SERIAL_BELOW` particles the loops finish sooner on one thread:
measured here on ``sod`` with 400 sph particles while another run held a
core, 57 steps took 0.42 s on one thread and 8.9 s on two.
"""

from __future__ import annotations

from contextlib import contextmanager

import numba

#: runs with fewer particles than this step on one thread
SERIAL_BELOW = 20_000


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
