"""CoppeliaSim's legacy remote API (``import sim`` / ``import vrep``) on sitegen's pybullet scenes.

Course scripts written for CoppeliaSim run unchanged: ``runner.run_script`` (or the CLI,
``sitegen remote-api run SCRIPT --scene 2w1a``) executes them with the ``shim`` directory first
on ``sys.path``, so ``import sim`` finds :mod:`sims.remote_api.api`. No socket is ever opened:
``simxStart`` only records the address. See docs/remote-api-legacy.md.

The ``script`` clip kind (``ClipSpec(kind="script", scenario="path/to/script.py")``) is
:mod:`sims.remote_api.script_clips`, declared in ``sims.sources.SOURCE_KINDS``.

The package root imports nothing: import from the modules (``from
sims.remote_api.runner import run_script``), so that the Lua layer, which uses
``commands`` and ``constants``, does not load the runner that loads it.
"""
