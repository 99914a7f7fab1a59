"""Sweeps: the same remote API script run many times, each run isolated, on local worker
processes or on a Ray cluster (docs/sweeps.md).

``plan.py`` turns seeds, grids and argument files into numbered runs with their own seeds;
``one_run.py`` runs one (own process, no network, time limit) and collects what it reports;
``local.py`` and ``ray_runs.py`` are the two executors; ``results.py`` writes results.csv and
results.jsonl; ``progress.py`` shows a sweep on a terminal; ``cli.py`` is ``sitegen remote-api
sweep``. The Python entry point for optimisers is :func:`sims.runs.evaluate`. The package
re-exports nothing: import from its modules.
"""
