"""``import vrepConst``: V-REP's name for the constants module."""

from sims.remote_api.constants import *  # noqa: F403
from sims.remote_api.constants import __all__  # noqa: F401
