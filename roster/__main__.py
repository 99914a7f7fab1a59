"""`python -m roster ...`: the same CLI as `sitegen roster ...`."""

import sys

from .cli import main

sys.exit(main(prog="python -m roster"))
