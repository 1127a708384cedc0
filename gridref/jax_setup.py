"""JAX as the grid methods run it: double precision (every reference result
is float64; ``swe`` may ask for float32 arrays explicitly) and the
persistent compilation cache, so that a second run of the same problem
does not recompile. Set when a run starts (:func:`configure_jax`), not on
import."""

from __future__ import annotations

import ctypes
import os

import jax

#: where compiled programs are kept between runs (``PARTMESH_JAX_CACHE`` overrides it)
CACHE = os.environ.get("PARTMESH_JAX_CACHE", os.path.join(os.path.expanduser("~"), ".cache", "partmesh", "jax"))


def configure_jax() -> None:
    """Switch JAX to float64 and to the persistent compilation cache, and
    keep the grid's arrays in the process's heap (:func:`keep_freed_memory`)."""
    jax.config.update("jax_enable_x64", True)
    jax.config.update("jax_compilation_cache_dir", CACHE)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    keep_freed_memory()


#: glibc's mallopt parameters (malloc.h) and the thresholds tried, largest first: 256 MiB (glibc 2.36 takes it),
#: else 32 MiB, the largest older ones take on a 64-bit machine. A 2048² Sedov step's arrays are 32 MiB and more:
#: measured alone on two cores, interleaved, its rate 1.67, 1.72, 1.68e7 cell updates/s with 32 MiB, 1.72, 1.81,
#: 1.75e7 with 256 MiB, the 512² step's 2.1-2.3e7 either way
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD, _MMAP_THRESHOLDS = -1, -3, (256 * 1024 * 1024, 32 * 1024 * 1024)


def keep_freed_memory() -> bool:
    """Ask glibc's malloc to serve arrays up to 256 MiB (32 MiB where it
    takes no more) from its heap and to
    keep what is freed there, instead of mapping fresh pages for every
    array of a step and returning them when it is freed: a grid step's
    arrays are allocated and freed anew at every step, and each fresh page
    costs a page fault and its zeroing (a quarter of the run time of a
    1448² fv Sedov step, whose arrays are 17 MB; 3.8e6 cell updates/s, 6.7e6
    with this, against 1.0e7 at 512²). The memory a run has used stays
    with its process until it ends. Returns whether glibc took both
    settings; does nothing where the C library is not glibc."""
    try:
        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):
        return False
    mapped = any(mallopt(_M_MMAP_THRESHOLD, threshold) for threshold in _MMAP_THRESHOLDS)
    return mapped and bool(mallopt(_M_TRIM_THRESHOLD, 2 ** 31 - 1))
