"""The ``sim`` module as scripts see it: every ``simx*`` function and ``sim*`` constant.

Unknown ``simx*`` names resolve (module ``__getattr__``) to a stub that returns
``simx_return_local_error_flag`` and says so once on stderr, instead of an AttributeError.
"""

from __future__ import annotations

import sims.quiet as _quiet  # noqa: F401  (pybullet's banner silenced before the modules load it)

from . import constants as _constants
from . import extras as _extras
from . import functions_objects as _objects
from . import functions_params as _params
from . import functions_scene as _scene
from . import functions_session as _session

for _module in (_constants, _session, _objects, _extras, _scene, _params):
    for _name in dir(_module):
        if _name.startswith(("simx", "sim_")):
            globals()[_name] = getattr(_module, _name)
del _module, _name

__all__ = sorted(n for n in list(globals()) if n.startswith(("simx", "sim_")))


def __getattr__(name: str):
    return _extras.module_getattr(name)


#: The names CoppeliaSim 4.x's sim.py added for the same functions (its regular API's names).
ALIASES = {
    "simxClearInt32Signal": "simxClearIntegerSignal",
    "simxGetInt32Signal": "simxGetIntegerSignal",
    "simxSetInt32Signal": "simxSetIntegerSignal",
    "simxGetArrayParam": "simxGetArrayParameter",
    "simxGetBoolParam": "simxGetBooleanParameter",
    "simxGetFloatParam": "simxGetFloatingParameter",
    "simxGetInt32Param": "simxGetIntegerParameter",
    "simxGetStringParam": "simxGetStringParameter",
    "simxSetArrayParam": "simxSetArrayParameter",
    "simxSetBoolParam": "simxSetBooleanParameter",
    "simxSetFloatParam": "simxSetFloatingParameter",
    "simxSetInt32Param": "simxSetIntegerParameter",
    "simxGetObjectFloatParam": "simxGetObjectFloatParameter",
    "simxGetObjectInt32Param": "simxGetObjectIntParameter",
    "simxSetObjectFloatParam": "simxSetObjectFloatParameter",
    "simxSetObjectInt32Param": "simxSetObjectIntParameter",
}
for _alias, _name in ALIASES.items():
    globals()[_alias] = globals()[_name]
del _alias, _name
__all__ = sorted(n for n in list(globals()) if n.startswith(("simx", "sim_")))
