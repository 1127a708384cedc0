"""Refuse, before anything is allocated, a run larger than the memory this
machine has free (SPEC §9): a run of 10⁹ cells is a typing mistake to be
told about in one sentence, not a process the kernel kills minutes later.

Each method states how many elements a run has (cells, particles) and
roughly how many bytes each needs while it steps (its state, the
intermediate arrays of one step, neighbour lists, the frames it keeps);
the estimate only has to tell a run that fits from one that cannot.
"""

from __future__ import annotations

import math
import os

from partmesh.cases.errors import InputError

#: bytes in a GiB
GIB = 2.0**30


def available_bytes() -> float:
    """Memory this machine can give a new allocation now: ``MemAvailable``
    of ``/proc/meminfo`` where there is one, else the free physical pages."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))


def elements_in(domain, spacing: float) -> float:
    """Cells (or lattice sites) of size ``spacing`` in ``domain``
    (``((lo, hi), ...)``), as a float (it may be far too many to hold)."""
    return math.prod(max(hi - lo, 0.0) / spacing for lo, hi in domain)


def check_fits(method: str, elements: float, bytes_each: float, what: str, setting: str = "dx") -> None:
    """Refuse a run of ``method`` with ``elements`` ``what`` (cells,
    particles) of ``bytes_each`` bytes each if it would need more than the
    memory free now, naming the ``setting`` to change."""
    need, free = elements * bytes_each, available_bytes()
    if need > free:
        raise InputError(f"{method} would need about {need / GIB:.3g} GiB for {elements:.3g} {what}, and "
                         f"{free / GIB:.3g} GiB are free: raise {setting}.")


def grid_cell_bytes(variables: int, scene) -> float:
    """Bytes per cell of a grid method with ``variables`` conserved
    variables: its state and about fifteen arrays like it for one step's
    ghost cells, slopes, predictor, fluxes and update, and the frames of
    ``scene``'s fields it keeps on its grid until the run ends."""
    return 8.0 * (15 * variables + len(scene.fields) * (len(scene.output.times) + 1))


def particle_bytes(dim: int, support: float) -> float:
    """Bytes per particle of an SPH method whose neighbour lists reach
    ``support`` spacings (8 bytes per neighbour, as many as lattice sites
    within it), beside about fifty numbers of its own."""
    neighbours = (2.0 * support, math.pi * support**2, 4.0 / 3.0 * math.pi * support**3)[dim - 1]
    return 8.0 * (50 + neighbours)
