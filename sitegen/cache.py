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

FORMAT = f"sitegen-cache-5-{__version__}"


@dataclass
class State:
    fingerprint: str = ""
    output: str = ""
    manifest: dict[str, list] = field(default_factory=dict)
    rosters: dict[str, Any] = field(default_factory=dict)


@dataclass
class Fragments:
    #: source key -> (ids, toc, directives); the HTML is in fragments.sqlite (fragment_store)
    markdown: dict[str, Any] = field(default_factory=dict)
    #: url -> (input key, context hash, output digest, diagnostics): see sitegen/page_jobs.py
    pages: dict[str, tuple] = field(default_factory=dict)
    #: name -> (inputs hash, {output path: digest}) for the site-wide files (build.SiteWide)
    site_wide: dict[str, tuple] = field(default_factory=dict)


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
        """Pickled straight to the file: never a second copy of every fragment in memory."""
        path = self.dir / "fragments.pickle"
        self.dir.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        with open(tmp, "wb") as fh:
            pickle.dump((FORMAT, frag), fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, path)

    def _write(self, path: Path, data: bytes) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
