"""What an implementation declares about itself, read in a sandbox and pinned for a run.

The judge never imports an implementation's module (a plugin file, an entry point's package):
module-level code would run inside the judge and could replace the judge's own functions.
So the declarations the judge needs (``exact`` sets the standard a diagram is held to,
``weighted`` and ``apollonius`` whether weighted cases and disks are its to build) are read in a sandbox, once per run,
and every later sandbox of that run must declare the same or it is refused
(:mod:`vorobench.judge.pinning` reads them).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, Optional

__all__ = ["Declaration", "declaration_of", "declaration_from_data", "declare_here", "DeclarationError"]


class DeclarationError(ValueError):
    """A declaration that is not one: wrong types, or a name other than the one asked for."""


@dataclass(frozen=True)
class Declaration:
    """An implementation's declared identity: name, decision standard, weights, complexity,
    where it comes from (``kind``, ``origin``), what it is, the version of its module, and
    whether it builds diagrams of disks (``apollonius``)."""

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
    apollonius: bool = False

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _module_version(impl: Any) -> str:
    """The version ``impl`` reads of itself, else that of the package whose module defines its
    build ("" if it has none)."""
    import sys

    if getattr(impl, "version", None) is not None:
        try:
            return str(impl.version())[:200]
        except Exception:  # noqa: BLE001 - a version that cannot be read is unknown, not a failure
            return ""

    module = getattr(impl.build, "__module__", "") or ""
    top = module.split(".")[0]
    for name in (module, top):
        version = getattr(sys.modules.get(name), "__version__", None)
        if isinstance(version, str):
            return version
    try:
        from importlib.metadata import version as dist_version

        return dist_version(top)
    except Exception:  # noqa: BLE001 - no distribution (PackageNotFoundError, or a bad name): no version
        return ""


def declaration_of(impl: Any, plugin: str = "") -> dict[str, Any]:
    """Runs in the sandbox: ``impl``'s declaration as plain data (``plugin``: the spec that
    defined it, if any)."""
    return {"name": str(impl.name), "exact": bool(impl.exact), "weighted": bool(impl.weighted),
            "apollonius": bool(getattr(impl, "apollonius", False)),
            "complexity": str(impl.complexity), "kind": str(impl.kind), "origin": str(impl.origin),
            "description": str(impl.description), "version": _module_version(impl), "plugin": str(plugin)}


def declaration_from_data(data: Any, name: str) -> Declaration:
    """The judge's reading of a declaration a sandbox sent for ``name``: every field of its
    type, and the name the one asked for."""
    if not isinstance(data, dict):
        raise DeclarationError(f"{name}: the declaration is not an object")
    fields = {"exact": bool, "weighted": bool, "complexity": str, "kind": str, "origin": str,
              "description": str, "version": str, "plugin": str, "name": str, "apollonius": bool}
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
        defined_by.update(dict.fromkeys(load_plugin(spec), spec))     # the last one registered wins, as in the registry
    wanted = impls.available() if names is None else list(names)
    declared: dict[str, dict] = {}
    failed: dict[str, str] = {}
    for name in wanted:
        try:
            declared[name] = declaration_of(impls.get(name), defined_by.get(name, ""))
        except Exception as exc:  # noqa: BLE001 - an implementation that cannot load says why
            failed[name] = f"{type(exc).__name__}: {exc}"
    return {"available": impls.available(), "declared": declared, "failed": failed}, None
