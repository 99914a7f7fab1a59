"""Scripted key presses for scripts that ``import keyboard`` (``--keys FILE``).

A keys file lists when each key is held down, on the script's clock (virtual seconds since the
script started), one event per line::

    # seconds  duration  key
    0.5        2.0       z      # hold "z" from 0.5 s to 2.5 s
    3          0.2       v
    8          end              # optional: the keyboard is "closed" at 8 s

``keyboard.is_pressed(key)`` is true while an event holds ``key``; each poll costs a little
virtual time (a poll loop lets the simulation run). Once the last event is over (or at ``end``)
``is_pressed`` raises KeyboardInterrupt, as if the user pressed Ctrl+C, so that a script's
polling loop ends the way it ends at a real keyboard. Without ``--keys`` no key is ever pressed
and the keyboard closes at once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

POLL_COST = 0.002  # virtual seconds one keyboard poll takes


class KeysEnded(KeyboardInterrupt):
    """The scripted keyboard has no more key presses: raised in the script like the Ctrl+C
    that ends it at a real keyboard. A run that ends this way ended as planned."""


class KeysFileError(ValueError):
    """A keys file that cannot be used: the message names the file, line and field."""


@dataclass(frozen=True)
class KeyEvent:
    start: float
    end: float
    key: str


@dataclass(frozen=True)
class KeyScript:
    events: tuple[KeyEvent, ...]
    closes_at: float

    def pressed(self, key: str, now: float) -> bool:
        key = key.lower()
        return any(e.key == key and e.start <= now < e.end for e in self.events)


def parse(text: str, label: str) -> KeyScript:
    events: list[KeyEvent] = []
    closes: float | None = None
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.split()
        where = f"{label}:{number}"
        try:
            start = float(parts[0])
        except ValueError:
            raise KeysFileError(f"{where}: seconds: not a number: {parts[0]!r}") from None
        if start < 0:
            raise KeysFileError(f"{where}: seconds: must not be negative")
        if len(parts) == 2 and parts[1] == "end":
            closes = start
            continue
        if len(parts) != 3:
            raise KeysFileError(f"{where}: expected 'seconds duration key' or 'seconds end'")
        try:
            duration = float(parts[1])
        except ValueError:
            raise KeysFileError(f"{where}: duration: not a number: {parts[1]!r}") from None
        if duration <= 0:
            raise KeysFileError(f"{where}: duration: must be positive")
        events.append(KeyEvent(start, start + duration, parts[2].lower()))
    last = max((e.end for e in events), default=0.0)
    return KeyScript(tuple(events), last if closes is None else closes)


def load(path: str | Path) -> KeyScript:
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise KeysFileError(f"{path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise KeysFileError(f"{path}: not a UTF-8 text file") from None
    return parse(text, str(path))


_current = KeyScript((), 0.0)


def configure(script: KeyScript | None) -> None:
    """The key script the ``keyboard`` shim plays (None: no key, closed at once)."""
    global _current
    _current = script or KeyScript((), 0.0)


def pressed_at(key: object, now: float) -> bool:
    """Whether ``key`` is held at ``now`` (the run's clock; ``keyboard.is_pressed`` in the shim
    advances it by ``POLL_COST`` first); raises KeysEnded once the key file has ended (also for
    a script in another Python, through sims/remote_api/rpc.py)."""
    if now >= _current.closes_at:
        raise KeysEnded("the scripted keyboard (--keys) has no more key presses")
    return _current.pressed(str(key), now)


def current() -> KeyScript:
    """The key script of the run (``--keys``): scene scripts read its presses through
    ``sim.getSimulatorMessage`` on the simulation's clock."""
    return _current


#: CoppeliaSim's key codes for keys that are not one character (sim.message_keypress)
SPECIAL_KEYS = {"up": 2007, "down": 2008, "left": 2009, "right": 2010, "enter": 13,
                "return": 13, "space": 32, "esc": 27, "escape": 27, "tab": 9,
                "backspace": 8, "delete": 127}  # fmt: skip


def key_code(key: str) -> int:
    """The code a key press carries: its character's code, or CoppeliaSim's for arrows..."""
    k = key.lower()
    if k in SPECIAL_KEYS:
        return SPECIAL_KEYS[k]
    return ord(key[0]) if key else 0
