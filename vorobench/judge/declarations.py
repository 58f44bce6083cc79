"""What an implementation declares about itself, read in a sandbox and pinned for a run.

The judge never imports an implementation's module (a plugin file, an entry point's package):
module-level code would run inside the judge and could replace the judge's own functions.
So the declarations the judge needs (``exact`` sets the standard a diagram is held to,
``weighted`` whether weighted cases are its to build) are read in a sandbox, once per run,
and every later sandbox of that run must declare the same or it is refused.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, Optional

__all__ = ["Declaration", "declaration_of", "declaration_from_data", "declare_here", "declare_in_sandbox",
           "resolve_declarations", "DeclarationError", "PluginError"]


class DeclarationError(ValueError):
    """A declaration that is not one: wrong types, or a name other than the one asked for."""


@dataclass(frozen=True)
class Declaration:
    """An implementation's declared identity: name, decision standard, weights, complexity,
    where it comes from (``kind``, ``origin``), what it is, and the version of its module."""

    name: str
    exact: bool
    weighted: bool
    complexity: str
    kind: str
    origin: str
    description: str
    version: str = ""
    #: The ``--plugin`` that defines it ("" for a built-in or an entry point): its sandbox
    #: loads that plugin alone, so no plugin's import-time code runs beside another's build.
    plugin: str = ""

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _module_version(impl: Any) -> str:
    """The version of the package whose module defines ``impl``'s build ("" if it has none)."""
    import sys

    module = getattr(impl.build, "__module__", "") or ""
    top = module.split(".")[0]
    for name in (module, top):
        version = getattr(sys.modules.get(name), "__version__", None)
        if isinstance(version, str):
            return version
    try:
        from importlib.metadata import PackageNotFoundError, version as dist_version

        return dist_version(top)
    except (PackageNotFoundError, ValueError, Exception):  # noqa: BLE001 - no distribution: no version
        return ""


def declaration_of(impl: Any, plugin: str = "") -> dict[str, Any]:
    """Runs in the sandbox: ``impl``'s declaration as plain data (``plugin``: the spec that
    defined it, if any)."""
    return {"name": str(impl.name), "exact": bool(impl.exact), "weighted": bool(impl.weighted),
            "complexity": str(impl.complexity), "kind": str(impl.kind), "origin": str(impl.origin),
            "description": str(impl.description), "version": _module_version(impl), "plugin": str(plugin)}


def declaration_from_data(data: Any, name: str) -> Declaration:
    """The judge's reading of a declaration a sandbox sent for ``name``: every field of its
    type, and the name the one asked for."""
    if not isinstance(data, dict):
        raise DeclarationError(f"{name}: the declaration is not an object")
    fields = {"exact": bool, "weighted": bool, "complexity": str, "kind": str, "origin": str,
              "description": str, "version": str, "plugin": str, "name": str}
    for key, kind in fields.items():
        if type(data.get(key)) is not kind:
            raise DeclarationError(f"{name}: the declaration's {key!r} is not a {kind.__name__}")
    if data["name"] != name:
        raise DeclarationError(f"{name}: the sandbox declared an implementation called {data['name']!r}")
    return Declaration(**{k: data[k] for k in fields})


def declare_here(names: Optional[list[str]], plugins: tuple[str, ...] = ()) -> tuple[dict, None]:
    """Runs in a sandbox: loads ``plugins`` one by one (noting which defines which name), then
    returns (``{"available": [...], "declared": {name: data}, "failed": {name: why}}``, no
    arrays) for ``names`` (None: every implementation available there)."""
    import impls
    from impls.plugins import load_plugin

    defined_by: dict[str, str] = {}
    for spec in plugins:
        for name in load_plugin(spec):
            defined_by.setdefault(name, spec)
    wanted = impls.available() if names is None else list(names)
    declared: dict[str, dict] = {}
    failed: dict[str, str] = {}
    for name in wanted:
        try:
            declared[name] = declaration_of(impls.get(name), defined_by.get(name, ""))
        except Exception as exc:  # noqa: BLE001 - an implementation that cannot load says why
            failed[name] = f"{type(exc).__name__}: {exc}"
    return {"available": impls.available(), "declared": declared, "failed": failed}, None


def declare_in_sandbox(names: Optional[list[str]], plugins: tuple[str, ...] = (), timeout: float = 120.0
                       ) -> tuple[list[str], dict[str, Declaration], dict[str, str]]:
    """(available names, declarations, why each other one failed) of ``names`` (None: all),
    read in one throwaway sandbox with ``plugins`` loaded there, never here."""
    from vorobench.judge.sandbox import Sandbox

    box = Sandbox(None, warmup_timeout=timeout)
    try:
        outcome = box.call(declare_here, names, tuple(plugins), timeout=timeout, step="reading the declarations")
    finally:
        box.close()
    if not outcome.ok:       # the plugins did not load (or the registry itself failed): nothing is declared
        return [], {}, {"*": outcome.message.replace(" (its worker could not start)", "")}
    data, _ = outcome.value
    if not isinstance(data, dict):
        return [], {}, {"*": "the declarations are not an object"}
    available = [str(n) for n in data.get("available") or [] if isinstance(n, str)]
    declared: dict[str, Declaration] = {}
    failed = {str(k): str(v) for k, v in (data.get("failed") or {}).items()}
    for name, item in (data.get("declared") or {}).items():
        try:
            declared[name] = declaration_from_data(item, name)
        except DeclarationError as exc:
            failed[name] = str(exc)
    return available, declared, failed


class PluginError(ValueError):
    """The run's plugins could not be loaded (in the sandbox that reads the declarations)."""


def resolve_declarations(names: Optional[list[str]], plugins: tuple[str, ...] = (), timeout: float = 120.0
                         ) -> dict[str, Declaration]:
    """The declarations of ``names`` (None or ``["all"]``: every implementation available with
    ``plugins``), read in a sandbox, in the order asked. Raises :class:`PluginError` when the
    plugins cannot be loaded and ``ValueError`` naming the available ones for an unknown or
    broken name: usage errors, said in one line."""
    every = not names or list(names) == ["all"]
    available, declared, failed = declare_in_sandbox(None if every else list(names), tuple(plugins), timeout)
    if "*" in failed:
        raise PluginError(failed["*"].split("\n")[0])
    wanted = available if every else list(dict.fromkeys(names))
    unknown = [n for n in wanted if n not in available]
    if unknown:
        raise ValueError(f"unknown implementation {unknown[0]!r}; available: {', '.join(available)}")
    broken = [n for n in wanted if n not in declared]
    if broken and not every:
        raise ValueError(f"implementation {broken[0]!r} could not be loaded: {failed.get(broken[0], '')}")
    return {n: declared[n] for n in wanted if n in declared}
