"""The Lua text every script state runs first: the sandbox, the step budget and thread switching.

It runs with Lua's full standard library, keeps private references to what the emulation needs
(``debug.sethook``, ``coroutine``), then removes from the script's reach everything that could
leave the simulation: processes (``os.execute``, ``io.popen``), native modules (``require`` of
C libraries, ``package.loadlib``), bytecode (``string.dump``, binary chunks) and files outside the
run's temporary folder. Why Lua code and not Python: the instruction-count hook, the yields of
threaded scripts and the error positions all have to happen inside Lua to be cheap and exact.
"""

PRELUDE = r"""
local PY, ERR, TMP, COMPAT51 = ...
local sethook, getinfo, traceback = debug.sethook, debug.getinfo, debug.traceback
local co_create, co_resume, co_yield, co_status, co_running =
    coroutine.create, coroutine.resume, coroutine.yield, coroutine.status, coroutine.running
local select, error, type, pcall, xpcall, tostring = select, error, type, pcall, xpcall, tostring
local sfind, ssub, sformat = string.find, string.sub, string.format
local io_open, os_remove, os_rename = io.open, os.remove, os.rename
local table_unpack = table.unpack
local RT = {}
local real_pcall, real_xpcall, real_setmetatable = pcall, xpcall, setmetatable
local sgsub, srep, slen = string.gsub, string.rep, string.len

-- 5.1 names the V-REP 3.x scripts use (Lua 5.4 runs every scene; see docs/lua.md)
unpack = unpack or table_unpack
loadstring = loadstring or function(s, name) return load(s, name, "t") end
table.getn = table.getn or function(t) return #t end
math.pow = math.pow or function(a, b) return a ^ b end
math.ldexp = math.ldexp or function(m, e) return m * 2.0 ^ e end
string.gfind = string.gfind or string.gmatch

-- sandbox ------------------------------------------------------------------------------------
python = nil
local function inside_tmp(path)
    if type(path) ~= "string" or sfind(path, "..", 1, true) then return false end
    return ssub(path, 1, #TMP + 1) == TMP .. "/"
end
local function refuse(what)
    return function() error(what .. " is not available to scene scripts (sandbox)", 2) end
end
os.execute = refuse("os.execute")
os.exit = refuse("os.exit")
os.getenv = function() return nil end
local tmp_count = 0
os.tmpname = function() tmp_count = tmp_count + 1; return TMP .. "/lua_" .. tmp_count end
os.remove = function(p)
  if inside_tmp(p) then return os_remove(p) end
  return nil, "sandbox: outside the temporary folder"
end
os.rename = function(a, b)
  if inside_tmp(a) and inside_tmp(b) then return os_rename(a, b) end
  return nil, "sandbox: outside the temporary folder"
end
io.popen = refuse("io.popen")
-- what a run writes counts against its temporary folder's quota (PY.take_disk, runtime.py)
local function quota_write(f, proxy)
    return function(_, ...)
        local n = 0
        for i = 1, select("#", ...) do
            local a = select(i, ...)
            n = n + (type(a) == "string" and #a or #tostring(a))
        end
        if not PY.take_disk(n) then
            return nil, "sandbox: the run's temporary folder is full (quota)"
        end
        local ok, err = f:write(...)
        if not ok then return nil, err end
        return proxy
    end
end
local function counted(f)
    local proxy = {}
    return real_setmetatable(proxy, {__index = function(_, k)
        if k == "write" then return quota_write(f, proxy) end
        local v = f[k]
        if type(v) == "function" then return function(_, ...) return v(f, ...) end end
        return v
    end, __name = "FILE*", __close = function() f:close() end})
end
io.open = function(path, mode)
    if inside_tmp(path) then
        local f, err = io_open(path, mode)
        if f and type(mode) == "string" and sfind(mode, "[wa+]") then return counted(f) end
        return f, err
    end
    return nil, tostring(path) .. ": sandbox: files live in the run's temporary folder only"
end
io.lines = function(path, ...)
    if path == nil then return refuse("io.lines on standard input")() end
    local f, e = io.open(path, "r")
    if not f then error(e, 2) end
    return f:lines(...)
end
io.input, io.output = refuse("io.input"), refuse("io.output")
dofile, loadfile = refuse("dofile"), refuse("loadfile")
string.dump = refuse("string.dump")
local real_load = load
load = function(chunk, name, mode, env)
    if type(chunk) == "string" and ssub(chunk, 1, 1) == "\27" then
        return nil, "sandbox: binary chunks are not loaded"
    end
    if env ~= nil then return real_load(chunk, name, "t", env) end
    return real_load(chunk, name, "t")
end
loadstring = function(s, name) return load(s, name) end
local builtin = {
  string=string, table=table, math=math, coroutine=coroutine, os=os, io=io, utf8=utf8
}
-- what CoppeliaSim ships and scenes require: its API modules (the emulation's tables) and the
-- scene's own Lua files beside the scene file (nothing else: the sandbox stays closed)
local API = {sim=1, simUI=1, simIK=1, simRemoteApi=1, simOMPL=1, simVision=1, simAssimp=1,
  simZMQ=1, simBubble=1, simSurfRec=1, simQHull=1, simICP=1, simWS=1}
local loaded = {}
require = function(name)
    if type(name) ~= "string" then error("require: module name expected", 2) end
    if builtin[name] then return builtin[name] end
    if API[name] then return _G[name] end
    local base = sfind(name, "-", 1, true) and ssub(name, 1, sfind(name, "-", 1, true) - 1)
    if base and API[base] then return _G[base] end
    if loaded[name] ~= nil then return loaded[name] end
    local text, chunkname = PY.module_text(name)
    if not text then
        error("require '" .. name .. "': " .. tostring(chunkname) ..
            " (scene scripts may require only Lua files beside the scene file)", 2)
    end
    local fn, err = real_load(text, chunkname, "t")
    if not fn then error(err, 2) end
    local value = fn(name)
    if value == nil then value = true end
    loaded[name] = value
    return value
end
if package then
    package.loadlib = nil
    package.cpath, package.path = "", ""
    package.searchers = {}
    package.loaded = {}
end
-- debug.getinfo without functions ("f"): a script must not reach the runner's own functions
-- (calling one would take its hook away); levels count from the caller as the real one does
debug = {traceback = traceback, getinfo = function(what, opts, ...)
    if type(opts) == "string" then opts = sgsub(opts, "[fL]", "") end
    if type(what) == "number" then
        if what < 0 then return nil end
        what = what + 1
    elseif type(what) ~= "function" then
        return nil
    end
    local info = getinfo(what, opts or "nSlu")
    if info and info.source == "=prelude" then return nil end
    return info
end}
collectgarbage = function(opt) if opt == "count" then return 0 end return 0 end

-- budget: instructions run without returning or yielding, in virtual steps' worth ----------
local HOOK_EVERY = 1000
local count, soft, hard = 0, PY.step_budget, PY.step_budget * PY.max_steps
-- sim.setThreadSwitchTiming(ms): CoppeliaSim switches a thread after ms of its time (default
-- 2 ms); here a virtual step's worth of instructions stands for the default
local mmax, mfloor = math.max, math.floor
function RT.switch_timing(ms)
    soft = mmax(HOOK_EVERY, mfloor(PY.step_budget * mmax(ms, 1) / 2))
end
local STOPPED = nil  -- the budget's message once it ran out: nothing may catch it
RT.switch_due = false
local function hook()
    count = count + HOOK_EVERY
    if count >= soft then RT.switch_due = true end
    if STOPPED then  -- raised again in the script's code, never in the runner's own
        local info = getinfo(2, "S")
        if info and info.source ~= "=prelude" then error(STOPPED, 0) end
        return
    end
    if count >= hard then
        local info = getinfo(2, "Sl") or {}
        STOPPED = sformat("%s:%s: stopped: ran %d virtual steps' worth of Lua instructions " ..
            "(%d) without returning or yielding (an endless loop?)", tostring(info.short_src),
            tostring(info.currentline), PY.max_steps, count)
        error(STOPPED, 0)
    end
end
local function arm(co)
    count = 0
    STOPPED = nil
    RT.switch_due = false
    if co then sethook(co, hook, "", HOOK_EVERY) else sethook(hook, "", HOOK_EVERY) end
end

-- the budget cannot be escaped (issue 33) ----------------------------------------------------
-- a hook belongs to one coroutine: every coroutine a script makes gets it
local function hooked(fn)
    local co = co_create(fn)
    sethook(co, hook, "", HOOK_EVERY)
    return co
end
-- once the budget ran out, catching the error does not help: it is raised again
local function again(ok, ...)
    if STOPPED then error(STOPPED, 0) end
    return ok, ...
end
coroutine.create = hooked
coroutine.resume = function(co, ...) return again(co_resume(co, ...)) end
coroutine.wrap = function(fn)
    local co = hooked(fn)
    return function(...)
        local r = pack(again(co_resume(co, ...)))
        if not r[1] then error(r[2], type(r[2]) == "string" and 2 or 0) end
        return table_unpack(r, 2, r.n)
    end
end
_G.pcall = function(...) return again(real_pcall(...)) end  -- the global: "pcall" is a local
-- a message handler runs under the same budget, and not again once it ran out
_G.xpcall = function(fn, handler, ...)
    return again(real_xpcall(fn, function(e)
        if STOPPED then return STOPPED end
        return handler(e)
    end, ...))
end
-- finalizers run with hooks off (Lua stops them during collection): not run, and reported
setmetatable = function(t, mt)
    if type(mt) == "table" and rawget(mt, "__gc") ~= nil then
        rawset(mt, "__gc", nil)
        local info = getinfo(2, "Sl") or {}
        PY.missing("__gc finalizer (not run in scene scripts)", info.currentline or -1)
    end
    return real_setmetatable(t, mt)
end
-- pattern matching runs in C, out of the hook's reach: a pattern whose backtracking could
-- take more than PATTERN_STEPS steps on its subject is refused (quantifiers nest: each
-- *, + or - can try every length of the subject)
local PATTERN_STEPS = 1e10
local function pattern_cost(subject, pattern, plain)
    if plain or type(pattern) ~= "string" or type(subject) ~= "string" then return 0 end
    local p = sgsub(sgsub(pattern, "%%.", "x"), "%[.-%]", "x")  -- escapes and sets: one item
    local _, k = sgsub(p, "[%*%+%-]", "")
    local n = slen(subject) + 1
    local starts = ssub(pattern, 1, 1) == "^" and 1 or n
    return starts * n ^ k
end
local function guarded(real, name)
    return function(s, pattern, a, b)
        if type(s) == "number" then s = tostring(s) end
        local cost = pattern_cost(s, pattern, name == "find" and b)
        if cost > PATTERN_STEPS then
            error(sformat("string.%s: pattern %q on %d characters could take %.0e steps of " ..
                "backtracking (at most %.0e in a scene script)", name, tostring(pattern),
                slen(s), cost, PATTERN_STEPS), 2)
        end
        return real(s, pattern, a, b)
    end
end
for _, name in ipairs({"find", "match", "gmatch", "gsub"}) do
    string[name] = guarded(string[name], name)
end

local function pack(...) return {n = select("#", ...), ...} end
local function on_error(e)
    if type(e) == "string" then return traceback(e, 2) end
    return e
end

function RT.compile(text, name)
    return real_load(text, "=" .. name, "t")
end

function RT.call(fn, ...)
    arm(nil)
    local r = pack(xpcall(fn, on_error, ...))
    sethook()
    return table_unpack(r, 1, r.n)
end

local THREADS, next_thread = {}, 0
-- an old-style script: the whole chunk runs with sim_call_type set (one call from Python)
function RT.section(fn, call_type)
    sim_call_type = call_type
    return RT.call(fn)
end

function RT.thread(fn)
    next_thread = next_thread + 1
    THREADS[next_thread] = co_create(fn)
    return next_thread
end

function RT.resume(id)
    local co = THREADS[id]
    arm(co)
    local ok, err = co_resume(co)
    sethook(co)
    if not ok then
        THREADS[id] = nil
        return false, traceback(co, tostring(err))
    end
    local status = co_status(co)
    if status == "dead" then THREADS[id] = nil end
    return true, status
end

local function in_thread()
    local co, main = co_running()
    return co ~= nil and not main
end
RT.in_thread = in_thread

function RT.switch()
    if in_thread() then co_yield() end
end

-- a Python function as a sim.* function: errors raised at the script's line, auto switches
-- (no table per call: the results pass through ``finish``, which a tail call enters, so that
-- level 2 of its error is the script's line)
local function finish(name, threaded, first, ...)
    if first == ERR then error(name .. ": " .. tostring((...)), 2) end
    if threaded and RT.switch_due and RT.auto_switch and in_thread() then
        RT.switch_due = false
        co_yield()
    end
    return first, ...
end
function RT.wrap(fn, name, threaded)
    return function(...)
        return finish(name, threaded, fn(...))
    end
end

-- a blocking sim.* function (sim.wait, sim.rmlMoveToJointPositions...): Python answers
-- (true, results...) when done, or (false, id) to be stepped again at the next pass; a thread
-- yields in between, anything else steps on at once (CoppeliaSim's switchThread does nothing
-- outside a thread)
local function done(name, r)
    if r[1] == ERR then error(name .. ": " .. tostring(r[2]), 3) end
    return r[1] == true
end
function RT.blocking(start, step, name)
    return function(...)
        local r = pack(start(...))
        while not done(name, r) do
            if in_thread() then
                RT.switch_due = false
                co_yield()
            end
            r = pack(step(r[2]))
        end
        return table_unpack(r, 2, r.n)
    end
end

-- what the emulation lacks: reported once per (name, line) at the end of the run -------------
local function stub(name)
    return function(...)
        local info = getinfo(2, "Sl") or {}
        PY.missing(name, info.currentline or -1)
    end
end
RT.stub = stub
local MODULES = {simUI=1, simIK=1, simOMPL=1, simRemoteApi=1, simVision=1, simROS=1, simROS2=1,
    simZMQ=1, simB0=1, simAssimp=1, simQHull=1, simSurfRec=1, simICP=1, simWS=1, simBubble=1}
-- members are bound on first use: ``resolve(k)`` (Python) gives the function or constant
function RT.module(prefix, t, resolve)
    return setmetatable(t or {}, {__index = function(tab, k)
        if type(k) ~= "string" then return nil end
        if resolve then
            local v, fn, step = resolve(k)
            if step then
                v = RT.blocking(v, step, prefix .. "." .. k)
            elseif fn then
                v = RT.wrap(v, prefix .. "." .. k, RT.threaded)
            end
            if v ~= nil then rawset(tab, k, v) return v end
        end
        if sfind(k, "^%l[%w]*_") or sfind(k, "^%u") then
            local info = getinfo(2, "Sl") or {}
            PY.missing(prefix .. "." .. k .. " (constant)", info.currentline or -1)
            return nil
        end
        local f = stub(prefix .. "." .. k)
        rawset(tab, k, f)
        return f
    end})
end
setmetatable(_G, {__index = function(t, k)
    if type(k) ~= "string" or ssub(k, 1, 3) ~= "sim" then return nil end
    if RT.resolve_global then  -- 3.x names (simGetObjectHandle, sim_handle_self), on first use
        local v, member = RT.resolve_global(k)  -- a constant, or a module and member name
        if member then
            v = rawget(t, v)
            if v then v = v[member] end
        end
        if v ~= nil then rawset(t, k, v) return v end
    end
    if MODULES[k] then
        local m = RT.module(k)
        rawset(t, k, m)
        return m
    end
    if sfind(k, "^sim_") then
        local info = getinfo(2, "Sl") or {}
        PY.missing(k .. " (constant)", info.currentline or -1)
        return nil
    end
    if sfind(k, "^sim%u") then return stub(k) end
    return nil
end})

return RT
"""
