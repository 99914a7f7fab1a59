"""``python -m sims.sweeps.worker``: a local sweep worker, one run at a time.

The protocol is sims/clip_pool.py's (the pool that starts, feeds and replaces these workers):
a ``{"ready": true}`` line once imported, then one JSON job per line on stdin and one JSON line
``{"id", "ok", "result"}`` per run on stdout. Output the C level writes to stdout (pybullet's
banner) goes to the worker's log instead, so it cannot corrupt the channel.
"""

from __future__ import annotations

import json
import os
import sys
from typing import Any

# One BLAS thread per worker, set before NumPy loads OpenBLAS: a run is one core's work, and
# OpenBLAS's own threads (one per core, spinning while they wait) in every worker and every
# forked run made two workers slower than one on two cores. Ray does the same for a task of
# one CPU (OMP_NUM_THREADS=1).
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = "1"


def serve() -> None:
    channel = os.fdopen(os.dup(1), "w", buffering=1, encoding="utf-8")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    from .one_run import execute, warm

    warm(None)

    def send(message: dict[str, Any]) -> None:
        channel.write(json.dumps(message) + "\n")

    send({"ready": True})
    for line in sys.stdin:
        if not line.strip():
            continue
        job = json.loads(line)
        send({"id": job["id"], "ok": True, "result": execute(job)})


if __name__ == "__main__":  # pragma: no cover (a subprocess; tested through the local executor)
    serve()
