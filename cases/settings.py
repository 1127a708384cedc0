"""The settings of a method: a frozen, typed dataclass per method (SPEC §1).

A method declares its settings as fields made with :func:`setting`: the
default and the check that converts what a user gives — a number, or the
text of the command line's ``--option key=value`` — and refuses a bad value
in one sentence naming the setting and its allowed range (SPEC §9).
:meth:`Settings.checked` applies every check once, before a run builds
anything, so the solver sees only typed, checked values::

    @dataclass(frozen=True)
    class FVSettings(Settings):
        method: ClassVar[str] = "fv"
        cfl: float = setting(0.8, within(0.0, 1.0, lo_open=True), "Courant number")

:meth:`Settings.record` is what a result and a checkpoint keep of them:
the settings that change what a run computes (not where it reports or
checkpoints), under ``method``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable, ClassVar

from partmesh.cases.errors import InputError
from partmesh.compare.checks import choice, flag, in_range, integer, positive

#: settings that say how a run reports and where it checkpoints, not what it computes
RUN_CONTROLS = ("progress", "checkpoint", "checkpoint_every", "resume", "particles")


def setting(default, check: Callable | None = None, doc: str = ""):
    """A settings field: its ``default``, ``check(name, value) -> value``
    (converts text, raises :class:`InputError`; not applied to None, which
    means "the method's default for the scene") and what it means."""
    return dataclasses.field(default=default, metadata={"check": check, "doc": doc})


def within(lo: float, hi: float, **ends) -> Callable:
    """The check of a number in [lo, hi] (``lo_open``/``hi_open`` open an end)."""
    return lambda name, value: in_range(name, value, lo, hi, **ends)


def one_of(options) -> Callable:
    """The check of a name among ``options``."""
    return lambda name, value: choice(name, value, tuple(options))


def at_least(lo: int, hi: int | None = None) -> Callable:
    """The check of an integer ≥ ``lo`` (and ≤ ``hi``)."""
    return lambda name, value: integer(name, value, lo, hi)


def optional_path(name: str, value):
    """A file path (text or path-like), or None."""
    if value is None or isinstance(value, str) or hasattr(value, "__fspath__"):
        return value
    raise InputError(f"{name} must be a file path, got {value!r}.")


@dataclass(frozen=True)
class Settings:
    """What every method takes: the resolution ``dx`` [m] (None: the
    scene's), the end time ``t_end`` [s] (None: the scene's), the progress
    bar, and the checkpoint file, its period and whether to resume from it
    (:mod:`partmesh.cases.checkpoint`)."""

    #: the method these settings belong to
    method: ClassVar[str] = ""

    dx: float | None = setting(None, positive, "resolution: cell width or particle spacing [m]")
    t_end: float | None = setting(None, positive, "end time [s]")
    progress: bool = setting(True, flag, "show a progress bar")
    checkpoint: str | None = setting(None, optional_path, "file the state is saved to")
    checkpoint_every: float = setting(600.0, positive, "seconds of wall time between checkpoints")
    resume: bool = setting(False, flag, "continue from the checkpoint file")

    @classmethod
    def checked(cls, scene, given: dict):
        """The settings ``given`` (name -> value or text) for a run of
        ``scene``, checked and converted; a setting not given (or given as
        None) takes its default, None defaults are filled in from the scene
        (:meth:`scene_defaults`) and :meth:`check_together` applies the
        rules that tie settings to each other or to the scene."""
        names = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(given) - set(names))
        if unknown:
            raise InputError(f"method {cls.method} has no setting {unknown[0]!r}; settings: {', '.join(names)}.")
        values = {}
        for f in dataclasses.fields(cls):
            value = given.get(f.name)
            value = f.default if value is None else value
            check = f.metadata.get("check")
            values[f.name] = value if value is None or check is None else check(f.name, value)
        settings = cls(**values)
        settings = dataclasses.replace(settings, **settings.scene_defaults(scene))
        settings.check_together(scene)
        return settings

    def scene_defaults(self, scene) -> dict:
        """The values of the settings left None that the scene sets."""
        return {"dx": scene.dx if self.dx is None else self.dx,
                "t_end": scene.t_end if self.t_end is None else self.t_end}

    def check_together(self, scene) -> None:
        """Rules between settings, or between a setting and the scene (here:
        the run ends after the scene starts); raise :class:`InputError`."""
        if not self.t_end > scene.t_start:
            raise InputError(f"t_end must be later than the time scene {scene.name} starts at, "
                             f"t_start = {scene.t_start:g} s, got {self.t_end:g} s.")

    def record(self) -> dict:
        """The settings a result and a checkpoint keep: ``method``, then
        every setting that changes what the run computes (``t_end`` last)."""
        names = [f.name for f in dataclasses.fields(self) if f.name not in (*RUN_CONTROLS, "t_end")]
        return {"method": self.method, **{name: getattr(self, name) for name in (*names, "t_end")}}
