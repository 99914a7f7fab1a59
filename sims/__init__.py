"""Headless pybullet ports of the course robots, scenarios and browser-playable clips.

Never imports sitegen. Public entry points: ``sims.world.World``, ``sims.scenarios``,
``sims.clips.render_clips`` and the CLI ``sims.cli.main``.
"""
