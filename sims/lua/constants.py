"""The constants a scene script reads, as ``sim.name`` (4.x) and ``sim_name`` (V-REP 3.x).

The legacy remote API's table (``sims.remote_api.constants``) supplies most values; this adds
the script-side ones: call types of child/customization scripts (V-REP 3.x: initialization 0,
cleanup 1, actuation 2, sensing 3; CoppeliaSim 4.x ``sim.syscb_*``), script attributes, object
special properties, dialog styles and parameters the course scenes read.
"""

from __future__ import annotations

from functools import lru_cache

from sims.simapi.constants import named

#: V-REP 3.x ``sim_call_type`` values (an old-style script compares against these).
CHILD_CALLS = {"initialization": 0, "cleanup": 1, "actuation": 2, "sensing": 3, "threaded": 4}
CUSTOMIZATION_CALLS = {
    "initialization": 0,
    "cleanup": 1,
    "nonsimulation": 2,
    "lastbeforesimulation": 3,
    "firstaftersimulation": 4,
    "simulationactuation": 5,
    "simulationsensing": 6,
    "simulationpause": 7,
}
#: CoppeliaSim 4.x callback numbers (``sim.syscb_*``); an old-style 4.x script gets these.
SYSCB = {
    "init": 0,
    "cleanup": 1,
    "nonsimulation": 2,
    "beforesimulation": 3,
    "aftersimulation": 4,
    "actuation": 5,
    "sensing": 6,
    "suspend": 7,
    "suspended": 8,
    "resume": 9,
}


@lru_cache(maxsize=2)
def constants(new_style: bool) -> dict[str, int]:
    """Every constant by its 4.x name without the ``sim.`` prefix (``handle_self`` -> -4).
    Shared (cached): do not modify the returned dict."""
    out = dict(named())  # the one table's constants (sims/simapi/constants.py)
    for k, v in SYSCB.items():
        out["syscb_" + k] = v
    if new_style:  # CoppeliaSim 4.x maps the old call types onto its callbacks
        child = {
            "initialization": 0,
            "cleanup": 1,
            "actuation": SYSCB["actuation"],
            "sensing": SYSCB["sensing"],
            "threaded": 10,
        }
        custom = {
            "initialization": 0,
            "cleanup": 1,
            "nonsimulation": 2,
            "lastbeforesimulation": 3,
            "firstaftersimulation": 4,
            "simulationactuation": SYSCB["actuation"],
            "simulationsensing": SYSCB["sensing"],
            "simulationpause": 11,
        }
    else:
        child, custom = CHILD_CALLS, CUSTOMIZATION_CALLS
    for k, v in child.items():
        out["childscriptcall_" + k] = v
    for k, v in custom.items():
        out["customizationscriptcall_" + k] = v
    return out
