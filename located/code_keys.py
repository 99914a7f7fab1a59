"""The one way to key a cache by code: the digest of the code that runs when a stage runs.

A cache entry is stale when the code that made it changes. Hand-bumped version strings and
hand-kept file lists drift (an edit of ``sitegen/slugs.py`` once kept old heading ids in the
Markdown cache; an edit of ``sims/lua/`` kept a Lua clip's key), so every cache of the project
asks :func:`code_key` instead, naming the module(s) its stage starts from:

- **our modules** (``located``, ``roster``, ``sims``, ``sitegen``): the static import closure
  of the roots, every ``import`` statement counted wherever it stands (inside functions and
  under ``TYPE_CHECKING`` too), plus modules named in string constants (``"pkg.mod:function"``
  plugin tables), a module's parent packages, and every module of a package that lists its own
  modules (``pkgutil.iter_modules``); each by its path inside the package and its bytes;
- **data our code reads**: the files of every package in the closure that are not modules
  (its folder and its non-package subfolders: bundled scenes, URDF models, the remote API's
  shim scripts), by path and bytes;
- **third-party code**: the version of every distribution the closure imports (Markdown,
  Pygments, pybullet, ...), from ``importlib.metadata``.

The closure is found with :mod:`ast` (nothing is imported). Parsing every module costs a few
hundred milliseconds, which a no-op build must not pay, so the imports found in a file are kept
by the file's content digest in a small memo file (``$XDG_CACHE_HOME/sitegen/code-imports.json``,
``SITEGEN_CODE_MEMO`` to move it, ``off`` to keep none); a key then costs one read and hash of
each file. This module lives in ``located`` because it is the one package every other imports.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import json
import os
import re
import sys
from pathlib import Path

OURS = ("located", "roster", "sims", "sitegen")
#: a string constant that names one of our modules ("sims.sources:scenario_plan")
_MODULE_STRING = re.compile(r"^(?:" + "|".join(OURS) + r")(?:\.[A-Za-z_]\w*)+(?::[A-Za-z_]\w*)?$")
#: import names whose distribution is not named after them
_DISTRIBUTIONS = {
    "cv2": "opencv-python-headless",
    "yaml": "PyYAML",
    "pymdownx": "pymdown-extensions",
}
_SKIP_DIRS = {"__pycache__"}
#: files remembered in the memo (about 4 versions of every module of the project)
MEMO_ENTRIES = 2000


@functools.cache
def _package_root(top: str) -> Path | None:
    spec = importlib.util.find_spec(top)
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations))).resolve()


@functools.cache
def _modules(top: str) -> dict[str, Path]:
    """Every module file of our package ``top`` by module name (one walk of its folder)."""
    root = _package_root(top)
    found: dict[str, Path] = {}
    if root is None:
        return found
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in _SKIP_DIRS and not d.startswith("."))
        rel = os.path.relpath(folder, root)
        prefix = top if rel == "." else top + "." + rel.replace(os.sep, ".")
        for name in files:
            if name.endswith(".py"):
                module = prefix if name == "__init__.py" else f"{prefix}.{name[:-3]}"
                found[module] = Path(folder, name)
    return found


def _file_of(module: str) -> Path | None:
    top = module.partition(".")[0]
    return _modules(top).get(module) if top in OURS else None


def _memo_path() -> Path | None:
    chosen = os.environ.get("SITEGEN_CODE_MEMO", "").strip()
    if chosen == "off":
        return None
    if chosen:
        return Path(chosen).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", "").strip()
    try:
        root = Path(base) if base else Path.home() / ".cache"
    except RuntimeError:
        return None
    return root / "sitegen" / "code-imports.json"


class _Memo:
    """Imports found in a file, by the file's content digest (see the module docstring);
    read once per process."""

    def __init__(self) -> None:
        self.path = _memo_path()
        self.found: dict[str, list[str]] = {}
        self.dirty = False
        if self.path is not None:
            try:
                data = json.loads(self.path.read_text(encoding="utf-8"))
                if isinstance(data, dict):
                    self.found = {k: v for k, v in data.items() if isinstance(v, list)}
            except (OSError, ValueError):
                pass

    def imports(self, module: str, is_package: bool, text: bytes, digest: str) -> list[str]:
        # relative imports depend on the name; what is found, on this module's own code
        key = f"{digest}:{module}:{int(is_package)}:{_own_digest()}"
        if key not in self.found:
            self.found[key] = _imports(module, is_package, text)
            self.dirty = True
        return self.found[key]

    def save(self) -> None:
        if not self.dirty or self.path is None:
            return
        for stale in list(self.found)[: max(0, len(self.found) - MEMO_ENTRIES)]:
            del self.found[stale]  # the oldest first: files long since edited
        import tempfile

        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=self.path.parent, prefix=".code-imports-")
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                json.dump(self.found, f, sort_keys=True)
            os.replace(tmp, self.path)
            self.dirty = False
        except OSError:
            pass  # a memo that cannot be written only costs time


@functools.cache
def _own_digest() -> str:
    return hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:12]


@functools.cache
def _memo() -> _Memo:
    return _Memo()


def _imports(module: str, is_package: bool, text: bytes) -> list[str]:
    """Every module name the file may import: absolute names, ``pkg.name`` for each
    ``from pkg import name`` (a name may be a module), our module strings, and ``*`` when the
    package lists its own modules."""
    import ast  # only when a file is new to the memo

    package = module if is_package else module.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                parts = parts[: len(parts) - (node.level - 1)] if node.level > 1 else parts
                base = ".".join(parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            out.add(base)
            out.update(f"{base}.{alias.name}" for alias in node.names if alias.name != "*")
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            if _MODULE_STRING.match(node.value):
                out.add(node.value.partition(":")[0])
        elif isinstance(node, ast.Attribute) and node.attr == "iter_modules" and is_package:
            out.add(f"{module}.*")
    return sorted(out)


def _data_files(package_dir: Path) -> list[Path]:
    """Files of a package that are not its modules: its own folder's other files and every
    file of its subfolders that are not packages."""
    found: list[Path] = []
    for entry in sorted(package_dir.iterdir()):
        if entry.name in _SKIP_DIRS or entry.name.startswith("."):
            continue
        if entry.is_file() and entry.suffix not in (".py", ".pyc"):
            found.append(entry)
        elif entry.is_dir() and not (entry / "__init__.py").is_file():
            found += [
                f
                for f in sorted(entry.rglob("*"))
                if f.is_file() and not _SKIP_DIRS.intersection(f.parts) and f.suffix != ".pyc"
            ]
    return found


def _normal(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


@functools.cache
def _installed() -> dict[str, str]:
    """Normalised distribution name -> version, from the ``*.dist-info`` folder names on
    ``sys.path`` (one directory listing each; reading every METADATA file costs far more)."""
    found: dict[str, str] = {}
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except OSError:
            continue
        for name in names:
            if name.endswith(".dist-info"):
                dist, _, version = name[: -len(".dist-info")].partition("-")
                found.setdefault(_normal(dist), version)
    return found


def _version(top: str) -> str:
    name = _DISTRIBUTIONS.get(top, top)
    version = _installed().get(_normal(name))
    if version:
        return version
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        spec = importlib.util.find_spec(top)
        origin = spec.origin if spec is not None else None
        if origin and Path(origin).is_file():  # not installed as a distribution: its bytes
            return hashlib.sha256(Path(origin).read_bytes()).hexdigest()[:16]
        return "absent"


def _portable(path: Path) -> str:
    """``sims/scene/bundled/2w1a.scene.json``: the path from our package's parent folder."""
    for top in OURS:
        root = _package_root(top)
        if root is not None and path.is_relative_to(root):
            return path.relative_to(root.parent).as_posix()
    return path.name


@functools.cache
def _walk(roots: tuple[str, ...]) -> tuple[dict[str, tuple[Path, str]], frozenset[str]]:
    """Our modules reached from ``roots`` (name -> file, content digest) and the third-party
    top-level names they import."""
    memo = _memo()
    seen: dict[str, tuple[Path, str]] = {}
    tops: set[str] = set()
    todo = list(roots)
    while todo:
        module = todo.pop()
        if module in seen:
            continue
        if module.endswith(".*"):
            package = module[:-2]
            init = _file_of(package)
            if init is not None:
                todo += [
                    f"{package}.{f.stem}"
                    for f in sorted(init.parent.glob("*.py"))
                    if f.name != "__init__.py"
                ]
            continue
        path = _file_of(module)
        if path is None:
            continue
        text = path.read_bytes()
        digest = hashlib.sha256(text).hexdigest()
        seen[module] = (path, digest)
        parts = module.split(".")
        todo += [".".join(parts[:i]) for i in range(1, len(parts))]
        for name in memo.imports(module, path.name == "__init__.py", text, digest):
            top = name.split(".")[0]
            if top in OURS:
                todo.append(name)
            elif top and top not in sys.stdlib_module_names:
                tops.add(top)
    memo.save()
    return seen, frozenset(tops)


def closure(*roots: str) -> list[tuple[str, Path]]:
    """``(module, file)`` of every module of ours that running ``roots`` may run, sorted."""
    return sorted((module, path) for module, (path, _d) in _walk(roots)[0].items())


def third_party(*roots: str) -> list[tuple[str, str]]:
    """``(import name, version)`` of every third-party top-level module the closure imports."""
    return [(top, _version(top)) for top in sorted(_walk(roots)[1])]


@functools.cache
def code_key(*roots: str) -> str:
    """The key of the code that runs when ``roots`` (module names) run; see the module
    docstring. Stable across machines and install locations (paths are package-relative)."""
    modules, _tops = _walk(roots)
    h = hashlib.sha256(f"code-key-1\0{sys.version_info[:2]}\0".encode())
    for module in sorted(modules):
        h.update(f"{module}\0{modules[module][1]}\0".encode())
    for folder in sorted({path.parent for path, _d in modules.values()}):
        for f in _data_files(folder):
            h.update(f"{_portable(f)}\0".encode() + f.read_bytes() + b"\0")
    for top, version in third_party(*roots):
        h.update(f"{top}=={version}\0".encode())
    return h.hexdigest()
