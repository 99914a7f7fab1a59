"""Scene scripts come alive: a scene's embedded Lua child and customization scripts run in a
sandboxed Lua 5.4 interpreter (lupa) against an emulation of CoppeliaSim's ``sim.*`` API over
the same World the remote API drives. See docs/lua.md."""

from .host import ScriptHost, Unemulated

__all__ = ["ScriptHost", "Unemulated"]
