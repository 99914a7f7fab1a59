"""Small shared helpers that keep line numbers ("located" values) for every package.

``roster/``, ``sims/`` and ``sitegen/`` may all import this package; it imports none of them.
"""
