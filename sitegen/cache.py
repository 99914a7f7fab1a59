"""The build cache: what the last build made, keyed by content hashes, never by mtimes.

Two files: a small ``state.json`` (input fingerprint and output manifest) that a no-op
rebuild reads and stops at, and ``fragments.pickle`` (rendered Markdown per source hash and
the context hash of every page) that a partial rebuild needs. A cache that cannot be read
(other version, truncated file) is simply ignored: the build is then a cold one.
"""

from __future__ import annotations

import json
import os
import pickle
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sitegen import __version__

FORMAT = f"sitegen-cache-2-{__version__}"


@dataclass
class State:
    fingerprint: str = ""
    output: str = ""
    manifest: dict[str, list] = field(default_factory=dict)
    rosters: dict[str, Any] = field(default_factory=dict)


@dataclass
class Fragments:
    markdown: dict[str, Any] = field(default_factory=dict)  # source key -> Rendered
    pages: dict[str, tuple[str, str]] = field(
        default_factory=dict
    )  # url -> (context hash, output digest)


class Cache:
    def __init__(self, directory: Path):
        self.dir = directory

    def load_state(self) -> State:
        try:
            raw = json.loads((self.dir / "state.json").read_text(encoding="utf-8"))
            if raw.get("format") != FORMAT:
                return State()
            return State(raw["fingerprint"], raw["output"], raw["manifest"], raw.get("rosters", {}))
        except (OSError, ValueError, KeyError, TypeError):
            return State()

    def save_state(self, state: State) -> None:
        data = {
            "format": FORMAT,
            "fingerprint": state.fingerprint,
            "output": state.output,
            "manifest": state.manifest,
            "rosters": state.rosters,
        }
        self._write(
            self.dir / "state.json", json.dumps(data, ensure_ascii=False, sort_keys=True).encode()
        )

    def load_fragments(self) -> Fragments:
        try:
            with open(self.dir / "fragments.pickle", "rb") as fh:
                fmt, frag = pickle.load(fh)
            return frag if fmt == FORMAT and isinstance(frag, Fragments) else Fragments()
        except (OSError, pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError):
            return Fragments()

    def save_fragments(self, frag: Fragments) -> None:
        self._write(
            self.dir / "fragments.pickle",
            pickle.dumps((FORMAT, frag), protocol=pickle.HIGHEST_PROTOCOL),
        )

    def _write(self, path: Path, data: bytes) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
