"""What a run shows while its method compiles, and how long that took.

A method's first run compiles its kernels (numba) or its step (JAX)
before the first step: up to a minute of silence where the progress bar
has not started. :class:`compiling` says so on the terminal while it
lasts, with the seconds so far, and keeps the seconds for the result's
``compile_seconds``; later runs load the compiled code from disk and the
line flashes by.
"""

from __future__ import annotations

import threading
import time as _time

from tqdm.auto import tqdm

#: how often the line's seconds are redrawn [s]
REDRAW = 0.5
#: the ``when`` of a grid method, whose compiled step is kept per grid size
GRID_SIZE = "first run at this grid size only"


class compiling:
    """``with compiling("sph", progress) as c: ...`` shows ``compiling sph
    kernels (first run only)`` (or ``when`` in place of ``first run only``)
    with the elapsed seconds while the block runs, where ``progress`` is
    true and the output is a terminal (as the run's progress bar), and
    clears it after; ``c.seconds`` is the block's wall time. ``file``: where
    the line goes (tqdm's default, standard error, when None)."""

    def __init__(self, method: str, progress: bool = True, when: str = "first run only", file=None):
        self.text = f"compiling {method} kernels ({when})"
        self.progress, self.file = progress, file
        self.seconds = 0.0

    def __enter__(self) -> compiling:
        self._line = tqdm(total=None, desc=self.text, bar_format="{desc} [{elapsed}]", leave=False,
                          disable=None if self.progress else True, file=self.file)
        self._done = threading.Event()
        self._redraw = None if self._line.disable else threading.Thread(target=self._redrawn, daemon=True)
        if self._redraw is not None:
            self._redraw.start()
        self._started = _time.perf_counter()
        return self

    def _redrawn(self) -> None:
        while not self._done.wait(REDRAW):
            self._line.refresh()

    def __exit__(self, *exc) -> None:
        self.seconds = _time.perf_counter() - self._started
        self._done.set()
        if self._redraw is not None:
            self._redraw.join()
        self._line.close()
