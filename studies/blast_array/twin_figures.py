"""Wall force and impulse of dsmc beside fv and dsmc's deterministic twin.

    python studies/blast_array/twin_figures.py OUT fv=study/runs twin=twin/runs dsmc=study/runs ...

For every configuration of the study, one figure per quantity
(``OUT/wall_force_<label>.png``, ``OUT/wall_impulse_<label>.png``) with
the runs of each ``name=folder`` pair that hold it, at the scene's spacing
or at ``name=folder@dx``: e.g. ``twin=twin/runs`` for fv with Pullin's
equilibrium flux and no reconstruction (the limit of equilibrium DSMC with
many particles per cell on the same cells) and ``dsmc@2mm=dsmc2/runs@2e-3``.
The twin's runs are fv runs, so each set lives in its own folder and the
method the file names is read from the set's name before any ``@``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from partmesh.blast_study import PARTS, configurations, file_stem
from partmesh.compare import plots
from partmesh.compare.io import read
from partmesh.sweeps import finished

#: the method whose runs each set's name stands for, when it is not a method itself
METHOD_OF = {"twin": "fv"}


def run_sets(arguments: list[str]) -> list[tuple[str, Path, float | None]]:
    """``(name, folder, dx)`` from ``name=folder`` or ``name=folder@dx``."""
    sets = []
    for argument in arguments:
        name, _, where = argument.partition("=")
        folder, _, dx = where.partition("@")
        sets.append((name, Path(folder), float(dx) if dx else None))
    return sets


def main(output: str, *arguments: str) -> None:
    output = Path(output)
    for config in configurations(PARTS):
        runs, names = [], []
        for name, folder, dx in run_sets(list(arguments)):
            method = METHOD_OF.get(name.split("@")[0], name.split("@")[0])
            path = folder / f"{config.run(method, dx).name}.nc"
            if finished(path):
                runs.append(read(path))
                names.append(name)
        if len(runs) < 2:
            continue
        for var in ("wall_force", "wall_impulse"):
            print(plots.series(runs, var, output / f"{var}_{file_stem(config.label)}.png", names=names, scale=1e3,
                               unit="ms", title=config.label))


if __name__ == "__main__":
    main(*sys.argv[1:])
