"""One fv run of ``sedov_3d`` at N³ cells (``python studies/sedov_3d/run.py 256``): its figures land in
``fv_N.json``. It checkpoints every 10 minutes beside the record and resumes from there when started again."""

import json
import sys
import time
from pathlib import Path

import partmesh as pm

n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
here = Path(__file__).parent
checkpoint = here / f"fv_{n}.checkpoint"
start = time.time()
ds = pm.run(pm.scene("sedov_3d", n_out=n), "fv", dx=2 / n, progress=True,
            checkpoint=checkpoint, resume=checkpoint.exists(), checkpoint_every=600)
keys = ("shock_radius", "shock_radius_exact", "shock_radius_error", "shock_radius_spread", "mass_drift",
        "energy_drift", "n_steps", "wall_seconds", "compile_seconds")
record = {k: float(ds.attrs[k]) for k in keys if k in ds.attrs}
record["script_wall_seconds"] = time.time() - start
(here / f"fv_{n}.json").write_text(json.dumps(record, indent=1) + "\n")
checkpoint.unlink(missing_ok=True)
print(record)
