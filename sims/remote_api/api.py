"""The ``sim`` module as scripts see it: every ``simx*`` function and ``sim*`` constant.

Unknown ``simx*`` names resolve (module ``__getattr__``) to a stub that returns
``simx_return_local_error_flag`` and says so once on stderr, instead of an AttributeError.
"""

from __future__ import annotations

from . import constants as _constants
from . import extras as _extras
from . import functions_objects as _objects
from . import functions_session as _session

for _module in (_constants, _session, _objects, _extras):
    for _name in dir(_module):
        if _name.startswith(("simx", "sim_")):
            globals()[_name] = getattr(_module, _name)
del _module, _name

__all__ = sorted(n for n in list(globals()) if n.startswith(("simx", "sim_")))


def __getattr__(name: str):
    return _extras.module_getattr(name)
