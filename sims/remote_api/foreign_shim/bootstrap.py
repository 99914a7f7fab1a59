"""Runs a script in its own Python for ``sitegen remote-api run SCRIPT --python PATH``:
``PATH bootstrap.py SCRIPT ARGS...``. Standard library only, Python 3.8 compatible.

It puts the right client modules in front of the script and runs it as ``__main__``:
- legacy (``import sim`` / ``vrep``): the script's own CoppeliaSim ``sim.py`` when the native
  library it loads (``remoteApi.so``) sits beside it, talking to the legacy server over TCP;
  else the bridge module (legacy/), which asks the sitegen server (rpc.py);
- ZeroMQ: the real client when this Python has it (``coppeliasim_zmqremoteapi_client``,
  ``zmq``, ``cbor2``), talking to the ZeroMQ server; else the bridge client (zmq_client/);
- ``keyboard`` plays the run's key file (common/).
"""

import importlib.util
import os
import random
import runpy
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
LEGACY, ZMQ, COMMON = (os.path.join(HERE, d) for d in ("legacy", "zmq_client", "common"))


def _has_real_zmq_client():
    try:
        return all(
            importlib.util.find_spec(name) is not None
            for name in ("zmq", "cbor2", "coppeliasim_zmqremoteapi_client")
        )
    except (ImportError, ValueError):
        return False


def _seed_random(seed):
    real_seed = random.seed
    real_seed(seed)

    def seeded(a=None, version=2):
        real_seed(seed if a is None else a, version)

    random.seed = seeded


def main():
    if sys.path and os.path.abspath(sys.path[0] or ".") == HERE:
        del sys.path[0]  # this folder is not the script's: its subfolders are no packages
    if len(sys.argv) < 2:
        sys.exit("usage: bootstrap.py SCRIPT [ARGS...]")
    script = os.path.abspath(sys.argv[1])
    folder = os.path.dirname(script)
    real_legacy = os.path.exists(os.path.join(folder, "remoteApi.so"))
    paths = [COMMON]
    if not _has_real_zmq_client():
        paths.append(ZMQ)
    if real_legacy:
        paths = [folder, *paths]
    else:
        paths = [LEGACY, *paths, folder]
    sys.path[:0] = paths
    while sys.path.count(folder) > 1:
        sys.path.remove(folder)
    sys.argv = [script, *sys.argv[2:]]
    seed = os.environ.get("SITEGEN_REMOTE_API_SEED")
    if seed:
        _seed_random(int(seed))
    runpy.run_path(script, run_name="__main__")


if __name__ == "__main__":
    main()
