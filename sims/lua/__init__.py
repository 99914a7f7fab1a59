"""Scene scripts come alive: a scene's embedded Lua child and customization scripts run in a
sandboxed Lua 5.4 interpreter (lupa) against the one ``sim.*`` table (``sims.simapi``) over the
same World the remote API drives. See docs/lua.md. Import from the modules
(``sims.lua.host.ScriptHost``): the package re-exports nothing."""
