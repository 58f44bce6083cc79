"""Registry of Voronoi implementations: own ones by name, outside ones by entry point.

``available()`` lists what can run here; ``build(name, points)`` prepares the points and
returns the implementation's :class:`~vorobench.Diagram`. Third-party packages register an
:class:`Implementation` (or a zero-argument callable returning one) in the entry-point
group ``vorobench.impls``.
"""

from __future__ import annotations

import importlib
import importlib.util
from importlib.metadata import entry_points
from typing import Optional

from numpy.typing import ArrayLike

from impls.base import Implementation, InputMutated, UnsupportedInput
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare

__all__ = ["Implementation", "UnsupportedInput", "InputMutated", "available", "get", "build", "register", "registered",
           "unregister", "ENTRY_POINT_GROUP"]

ENTRY_POINT_GROUP = "vorobench.impls"

# Own implementations: name -> module defining IMPLEMENTATION (imported lazily: numba is slow
# to import and compile, and `vorobench impls` should stay quick).
_OWN = {
    "fortune": "impls.fortune",
    "halfplane": "impls.halfplane",
    "incremental": "impls.incremental",
    "qhull": "impls.qhull",
}
# Adapters to outside libraries: name -> (module, the library it needs).
_EXTERNAL: dict[str, tuple[str, str]] = {
    "triangle": ("impls.external.triangle_lib", "triangle"),
    "triangle-sweep": ("impls.external.triangle_sweep", "triangle"),
    "triangle-incremental": ("impls.external.triangle_incremental", "triangle"),
    "boost": ("impls.external.boost", "pyvoronoi"),
    "geos": ("impls.external.geos", "shapely"),
    "cgal": ("impls.external.cgal", "CGAL"),
}

_registered: dict[str, Implementation] = {}
_loaded: dict[str, Implementation] = {}


def _module_exists(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def _entry_point_impls() -> dict[str, object]:
    return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}


def available() -> list[str]:
    """Names of the implementations that can run here (own ones first, then outside ones)."""
    names = [name for name, mod in _OWN.items() if _module_exists(mod)]
    names += [name for name, (mod, lib) in _EXTERNAL.items() if _module_exists(lib) and _module_exists(mod)]
    names += [name for name in _entry_point_impls() if name not in names]
    names += [name for name in _registered if name not in names]
    return names


def register(impl: Implementation) -> None:
    """Register an implementation in this process (tests, plugins loaded by hand)."""
    _registered[impl.name] = impl


def registered() -> list[str]:
    """Names registered in this process with :func:`register` (plugins, test doubles)."""
    return list(_registered)


def unregister(name: str) -> None:
    """Remove an implementation added with :func:`register`."""
    _registered.pop(name, None)
    _loaded.pop(name, None)


def get(name: str) -> Implementation:
    """The implementation called ``name``; ``KeyError`` listing the available ones otherwise."""
    if name in _registered:
        return _registered[name]
    if name in _loaded:
        return _loaded[name]
    module = _OWN.get(name) or (_EXTERNAL[name][0] if name in _EXTERNAL else None)
    impl: Optional[Implementation] = None
    if module is not None and _module_exists(module):
        impl = importlib.import_module(module).IMPLEMENTATION
    else:
        ep = _entry_point_impls().get(name)
        if ep is not None:
            obj = ep.load()
            impl = obj if isinstance(obj, Implementation) else obj()
    if impl is None:
        raise KeyError(f"unknown implementation {name!r}; available: {', '.join(available())}")
    if not isinstance(impl, Implementation):
        raise TypeError(f"implementation {name!r} is a {type(impl).__name__}, not an Implementation")
    _loaded[name] = impl
    return impl


def build(name: str, points: ArrayLike, stats: Optional[dict] = None) -> Diagram:
    """Prepare ``points`` and build their Voronoi diagram with implementation ``name``.

    Raises :class:`UnsupportedInput` (a ``ValueError``) when the implementation declares it
    cannot take these points, and :class:`InputMutated` when it changed its input.
    """
    impl = get(name)
    sites, _ = prepare(points)
    return impl.run(sites, stats)
