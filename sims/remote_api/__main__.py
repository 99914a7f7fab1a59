"""``python -m sims.remote_api run SCRIPT --scene NAME``: see sims.remote_api.cli."""

import sys

from .cli import main

sys.exit(main(prog="python -m sims.remote_api"))
