"""``python -m partmesh``: the command line (:mod:`partmesh.cli`)."""

import sys

from partmesh.cli import main

sys.exit(main())
