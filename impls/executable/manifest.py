"""An executable implementation's TOML manifest: read, checked field by field, nothing run.

Reading a manifest runs no code (it is TOML), so the judge may read one; the program itself,
its ``setup`` and its ``version`` command run only in a sandbox (:mod:`impls.executable`).
vorobench adds three optional fields to the contract's: ``description``, ``origin`` and
``requires`` (programs looked up on PATH, or absolute paths, that must exist for the
implementation to be available here). ``{cache}`` (this manifest's cache folder) and
``{python}`` (the interpreter running vorobench) may appear in ``command``, ``setup`` and
``version``.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
import tomllib
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any, Optional

__all__ = ["Manifest", "ManifestError", "OutputKind", "InputFormat", "read_manifest", "cache_root", "file_digest",
           "MANIFEST_NAME"]

#: The file name of a manifest inside an implementation's folder (shipped references, and the
#: sub-folders of a ``VOROBENCH_IMPLS_PATH`` folder).
MANIFEST_NAME = "impl.toml"


class ManifestError(ValueError):
    """A manifest that cannot be read or says something the protocol does not allow."""


class OutputKind(str, Enum):
    """What the program prints: triangles of a Delaunay or regular triangulation, or the
    Voronoi (power) diagram's vertices and edges."""

    TRIANGLES = "triangles"
    VORONOI = "voronoi"

    def __str__(self) -> str:
        return self.value


class InputFormat(str, Enum):
    """How the sites reach the program's stdin."""

    TEXT = "text"
    BINARY = "binary"

    def __str__(self) -> str:
        return self.value


_FIELDS = {"name", "command", "output", "exact", "complexity", "weights", "setup", "version", "input",
           "description", "origin", "requires"}


@dataclass(frozen=True)
class Manifest:
    """One executable implementation as its manifest declares it. ``folder``: where relative
    paths resolve and ``setup`` runs."""

    path: Path
    name: str
    command: tuple[str, ...]
    output: OutputKind
    exact: bool
    complexity: str
    weighted: bool = False
    setup: tuple[str, ...] = ()
    version: tuple[str, ...] = ()
    input: InputFormat = InputFormat.TEXT
    description: str = ""
    origin: str = ""
    requires: tuple[str, ...] = ()
    #: It takes disks (``weights = "apollonius"``): text ``x y r`` rows, and its ``triangles`` are
    #: the faces of the Apollonius graph with their neighbours (docs/apollonius.md).
    apollonius: bool = False

    @property
    def folder(self) -> Path:
        return self.path.parent

    def missing(self) -> list[str]:
        """The ``requires`` entries this machine lacks (empty: it can run here)."""
        out = []
        for item in self.requires:
            if os.sep in item:
                if not Path(item).exists():
                    out.append(item)
            elif shutil.which(item) is None:
                out.append(item)
        return out

    def sources(self) -> dict[str, str]:
        """The files of the manifest's folder, by relative path, with a digest of each (contents
        up to ``_HASHED_BYTES``, size and modification time beyond): what ``setup`` built from.
        Folders that builds and tools fill (``.git``, ``node_modules``, ``build``, ...) are left out."""
        out = {}
        for file in sorted(self.folder.rglob("*")):
            if _generated(file, self.folder):
                continue
            try:
                if not file.is_file():
                    continue
                out[str(file.relative_to(self.folder))] = file_digest(file)
            except OSError:             # removed while we looked (a build's temporary file)
                continue
        return out

    def cache(self) -> Path:
        """This implementation's cache folder (not created here): one per manifest folder, so
        each checkout (a worktree of ``continuous``) has its own build."""
        key = hashlib.sha256(str(self.folder).encode()).hexdigest()[:12]
        return cache_root() / "executables" / f"{_safe(self.name)}-{key}"

    def argv(self, words: tuple[str, ...], cache: Optional[Path] = None) -> list[str]:
        """``words`` with the placeholders filled in and a relative program path (``./x``,
        ``bin/x``) resolved against the manifest's folder; a bare name is looked up on PATH."""
        cache = cache or self.cache()
        out = [w.replace("{cache}", str(cache)).replace("{python}", sys.executable) for w in words]
        if out and not os.path.isabs(out[0]) and os.sep in out[0]:
            out[0] = str((self.folder / out[0]).resolve())
        return out


#: Folders of a manifest's folder that hold what tools and builds make, not sources.
_NOT_SOURCES = {"__pycache__", "node_modules", ".git", ".hg", ".svn", ".venv", "venv", "build", "dist", "target",
                ".mypy_cache", ".pytest_cache"}
#: Files larger than this are known by their size and modification time, not read.
_HASHED_BYTES = 16 * 2 ** 20


def _generated(path: Path, folder: Path) -> bool:
    """Whether ``path`` is something tools and builds leave beside the sources."""
    parts = path.relative_to(folder).parts
    return any(p in _NOT_SOURCES for p in parts[:-1]) or parts[-1] in _NOT_SOURCES \
        or path.suffix in {".pyc", ".o", ".so", ".class"}


def file_digest(file: Path) -> str:
    """A file's contents hash, read in chunks (size and modification time for a large file)."""
    info = file.stat()
    if info.st_size > _HASHED_BYTES:
        return f"size {info.st_size} mtime {info.st_mtime_ns}"
    digest = hashlib.sha256()
    with open(file, "rb") as handle:
        for chunk in iter(lambda: handle.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def _safe(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)[:60] or "impl"


def cache_root() -> Path:
    """``VOROBENCH_CACHE_DIR``, else ``$XDG_CACHE_HOME/vorobench``, else ``~/.cache/vorobench``."""
    explicit = os.environ.get("VOROBENCH_CACHE_DIR")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "vorobench"


def _argv(data: dict, key: str, where: str, required: bool = False) -> tuple[str, ...]:
    value = data.get(key)
    if value is None:
        if required:
            raise ManifestError(f"{where}: [implementation] needs {key!r} (an argv list, e.g. [\"./my_program\"])")
        return ()
    if isinstance(value, str):
        raise ManifestError(f"{where}: {key!r} must be a list of words (argv), not the string {value!r}")
    if not isinstance(value, list) or not value or not all(isinstance(w, str) and w for w in value):
        raise ManifestError(f"{where}: {key!r} must be a non-empty list of non-empty strings")
    return tuple(value)


def _text(data: dict, key: str, where: str, default: Optional[str] = None) -> str:
    value = data.get(key, default)
    if not isinstance(value, str) or (default is None and not value.strip()):
        raise ManifestError(f"{where}: [implementation] needs {key!r} as a string" if key not in data
                            else f"{where}: {key!r} must be a string, not {value!r}")
    return value


def _choice(data: dict, key: str, enum: type[Enum], where: str, default: Optional[Enum] = None) -> Any:
    value = data.get(key, default.value if default is not None else None)
    try:
        return enum(value)
    except ValueError:
        allowed = ", ".join(f'"{e.value}"' for e in enum)
        raise ManifestError(f"{where}: {key!r} must be one of {allowed}, not {value!r}") from None


def read_manifest(path: str | Path) -> Manifest:
    """The manifest at ``path``; :class:`ManifestError` naming the file and the field at fault."""
    path = Path(path).resolve()
    where = str(path)
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ManifestError(f"manifest not found: {path}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ManifestError(f"{where}: cannot be read: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ManifestError(f"{where}: not valid TOML: {exc}") from None
    data = document.get("implementation")
    if not isinstance(data, dict):
        raise ManifestError(f"{where}: needs an [implementation] table")
    unknown = sorted(set(data) - _FIELDS)
    if unknown:
        raise ManifestError(f"{where}: unknown field {unknown[0]!r} in [implementation]; allowed: {', '.join(sorted(_FIELDS))}")
    exact = data.get("exact")
    if not isinstance(exact, bool):
        raise ManifestError(f"{where}: [implementation] needs 'exact = true' or 'exact = false'")
    weights = data.get("weights")
    kinds = [weights] if isinstance(weights, str) else weights if isinstance(weights, list) else None
    if weights is not None and (not kinds or not all(k in ("power", "apollonius") for k in kinds)
                                or len(set(kinds)) != len(kinds)):
        raise ManifestError(f"{where}: 'weights' may be \"power\" (weighted sites), \"apollonius\" (disks) or a "
                            f"list of both, not {weights!r}")
    kinds = kinds or []
    requires = data.get("requires", [])
    if not isinstance(requires, list) or not all(isinstance(r, str) and r for r in requires):
        raise ManifestError(f"{where}: 'requires' must be a list of program names or absolute paths")
    name = _text(data, "name", where)
    if name != name.strip() or "," in name or any(c.isspace() for c in name):
        raise ManifestError(f"{where}: the name {name!r} may not hold spaces or commas (it is used in --impls)")
    return Manifest(path=path, name=name, command=_argv(data, "command", where, required=True),
                    output=_choice(data, "output", OutputKind, where), exact=exact,
                    complexity=_text(data, "complexity", where), weighted="power" in kinds,
                    apollonius="apollonius" in kinds,
                    setup=_argv(data, "setup", where), version=_argv(data, "version", where),
                    input=_choice(data, "input", InputFormat, where, InputFormat.TEXT),
                    description=_text(data, "description", where, ""), origin=_text(data, "origin", where, ""),
                    requires=tuple(requires))
