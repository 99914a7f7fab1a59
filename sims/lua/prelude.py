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
io.open = function(path, mode)
    if inside_tmp(path) then return io_open(path, mode) end
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
debug = {traceback = traceback, getinfo = getinfo}
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
RT.switch_due = false
local function hook()
    count = count + HOOK_EVERY
    if count >= soft then RT.switch_due = true end
    if count >= hard then
        local info = getinfo(2, "Sl") or {}
        error(sformat("%s:%s: stopped: ran %d virtual steps' worth of Lua instructions (%d) " ..
            "without returning or yielding (an endless loop?)", tostring(info.short_src),
            tostring(info.currentline), PY.max_steps, count), 0)
    end
end
local function arm(co)
    count = 0
    RT.switch_due = false
    if co then sethook(co, hook, "", HOOK_EVERY) else sethook(hook, "", HOOK_EVERY) end
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
