"""Keep a study's finished runs in this record, slimmed to what its report reads.

    python studies/blast_array/keep.py study/runs studies/blast_array/sph/runs

Each finished run in the first folder is written to the second with its time
series whole (probes, wall force and impulse), its density only at the
snapshot time of the report (1.7 ms, for the schlieren figures; single
precision) and its solid mask, compressed: about 0.5 MB instead of 30 MB. A
slim copy is a complete partmesh result, so putting it back in a study's
``runs/`` folder makes ``partmesh study`` skip that run and report it.
"""

from __future__ import annotations

import sys
from pathlib import Path

from partmesh.blast_study import SNAPSHOT_TIME
from partmesh.compare.io import read
from partmesh.sweeps import finished


def slim(ds):
    """``ds`` with every field dropped but ``rho`` at the snapshot time."""
    fields = [name for name in ("u", "v", "p", "e") if name in ds]
    return ds.drop_vars(fields).sel(time=[SNAPSHOT_TIME], method="nearest")


def main(source: str, target: str) -> None:
    target = Path(target)
    target.mkdir(parents=True, exist_ok=True)
    for path in sorted(Path(source).glob("*.nc")):
        if not finished(path):
            continue
        ds = slim(read(path))
        encoding = {name: {"zlib": True, "complevel": 6} for name in ds.data_vars}
        if "rho" in ds:
            encoding["rho"]["dtype"] = "float32"
        ds.to_netcdf(target / path.name, engine="netcdf4", encoding=encoding)
        print(f"{path.name}: {(target / path.name).stat().st_size / 1e6:.2f} MB")


if __name__ == "__main__":
    main(*sys.argv[1:3])
