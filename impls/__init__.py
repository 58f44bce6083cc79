"""Registry of Voronoi implementations: own ones by name, outside ones by entry point,
programs in any language by their TOML manifests (:mod:`impls.executable`).

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

import numpy as np
from numpy.typing import ArrayLike

from impls.base import Implementation, InputMutated, UnsupportedInput
from vorobench.core.diagram import Diagram

__all__ = ["Implementation", "UnsupportedInput", "InputMutated", "available", "get", "build", "register", "registered",
           "unregister", "of_kind", "weighted", "apollonius", "is_builtin", "builtin", "ENTRY_POINT_GROUP", "DEFAULT_REFERENCE"]

ENTRY_POINT_GROUP = "vorobench.impls"

#: The implementation a run judges the others against unless told otherwise: Qhull, the
#: library most users already trust (it decides in floating point and is certified per case).
DEFAULT_REFERENCE = "qhull"

# Built-in implementations: name -> ("module:ATTRIBUTE" of its Implementation, the outside
# library it needs or None). Modules are imported on first use (numba is slow to import and
# compile, and `vorobench impls` should stay quick); an adapter is listed only when its
# library is installed.
_BUILTIN: dict[str, tuple[str, Optional[str]]] = {
    "fortune": ("impls.fortune:IMPLEMENTATION", None),
    "halfplane": ("impls.halfplane:IMPLEMENTATION", None),
    "incremental": ("impls.incremental:IMPLEMENTATION", None),
    "qhull": ("impls.qhull:IMPLEMENTATION", None),
    "triangle": ("impls.external.triangle_lib:DIVIDE_AND_CONQUER", "triangle"),
    "triangle-sweep": ("impls.external.triangle_lib:SWEEP", "triangle"),
    "triangle-incremental": ("impls.external.triangle_lib:INCREMENTAL", "triangle"),
    "cgal": ("impls.external.cgal:IMPLEMENTATION", "CGAL"),
    "boost": ("impls.external.boost:IMPLEMENTATION", "pyvoronoi"),
    "geos": ("impls.external.geos:IMPLEMENTATION", "shapely"),
}

_registered: dict[str, Implementation] = {}
_loaded: dict[str, Implementation] = {}


def _module_exists(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def _runs_here(entry: tuple[str, Optional[str]]) -> bool:
    target, library = entry
    return (library is None or _module_exists(library)) and _module_exists(target.partition(":")[0])


def _entry_point_impls() -> dict[str, object]:
    return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}


def _resolve(target: str) -> object:
    """The object a ``module:attribute`` entry names."""
    module, _, attribute = target.partition(":")
    return getattr(importlib.import_module(module), attribute)


def _executables() -> dict[str, object]:
    """Executable implementations found without a ``--plugin``: the shipped references whose
    toolchain is here and the manifests of ``VOROBENCH_IMPLS_PATH`` (name -> manifest path)."""
    from impls.executable import discovered

    return discovered()


def available() -> list[str]:
    """Names of the implementations that can run here (built-in ones first, then the shipped
    executable references, then plugins)."""
    names = [name for name, entry in _BUILTIN.items() if _runs_here(entry)]
    names += [name for name in _executables() if name not in names]
    names += [name for name in _entry_point_impls() if name not in names]
    names += [name for name in _registered if name not in names]
    return names


def is_builtin(name: str) -> bool:
    """Whether ``name`` is one of vorobench's own implementations or adapters (not a plugin or
    an entry point) that can run here: code the judge may import."""
    return name in _BUILTIN and _runs_here(_BUILTIN[name])


def builtin(name: str) -> Implementation:
    """vorobench's own implementation or adapter ``name`` (never a plugin or an entry point of
    that name); ``KeyError`` when it is none, or cannot run here."""
    if not is_builtin(name):
        raise KeyError(f"{name!r} is not a built-in implementation that runs here")
    return _resolve(_BUILTIN[name][0])


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
    impl: object = None
    if name in _BUILTIN and _runs_here(_BUILTIN[name]):
        impl = _resolve(_BUILTIN[name][0])
    elif name in (executables := _executables()):
        from impls.executable import implementation_of, read_manifest

        impl = implementation_of(read_manifest(executables[name]))
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


def _declaring(test) -> list[str]:
    """The available implementations for which ``test(impl)`` holds; one that fails to load is
    left out (a broken plugin is reported where it is used, not here)."""
    out = []
    for name in available():
        try:
            if test(get(name)):
                out.append(name)
        except Exception:  # noqa: BLE001 - see above
            continue
    return out


def weighted() -> list[str]:
    """The available implementations that take weights (power diagrams)."""
    return _declaring(lambda impl: impl.weighted)


def of_kind(kind: str) -> list[str]:
    """The available implementations that declare ``kind`` ("own", "outside" or "plugin")."""
    return _declaring(lambda impl: impl.kind == kind)


def apollonius() -> list[str]:
    """The available implementations that take disks (docs/apollonius.md)."""
    return _declaring(lambda impl: impl.apollonius)


def build(name: str, points: ArrayLike, stats: Optional[dict] = None, *,
          weights: Optional[ArrayLike] = None, radii: Optional[ArrayLike] = None) -> Diagram:
    """Prepare ``points`` and build their Voronoi diagram with implementation ``name``.

    ``weights`` (one per point) asks for the power diagram: the power of x with respect to
    site i is |x - p_i|^2 - w_i; equal rows keep the largest of their weights; an
    implementation that does not take weights raises :class:`UnsupportedInput`.
    ``radii`` (one per point, >= 0) asks for the diagram of disks centred at the points
    (docs/apollonius.md): rows with one centre keep the largest radius, and an implementation
    that does not take disks raises :class:`UnsupportedInput`.
    Duplicate rows share one site; the diagram remembers the rows, so its scipy-style
    ``points`` and ``point_region`` have one entry per row. Raises :class:`UnsupportedInput`
    (a ``ValueError``) when the implementation declares it cannot take these points, and
    :class:`InputMutated` when it changed its input.
    """
    # Imported here, not at the top: prepare compiles with numba, which adds 0.3 s to every
    # import of the registry (measured); listing implementations does not need it.
    from vorobench.core.prepare import prepare, prepare_disks, prepare_weighted

    impl = get(name)
    if radii is not None:
        if weights is not None:
            raise ValueError("weights (power diagram) and radii (disks) go one at a time")
        if not impl.apollonius:
            raise UnsupportedInput(f"{name} does not take disks; implementations that do: "
                                   f"{', '.join(apollonius()) or 'none here'}")
        sites, site_radii, inverse = prepare_disks(points, radii)
        diagram = impl.run(sites, stats, radii=site_radii)
    elif weights is None:
        sites, inverse = prepare(points)
        diagram = impl.run(sites, stats)
    else:
        if not impl.weighted:
            raise UnsupportedInput(f"{name} does not support weighted sites; weighted implementations: "
                                   f"{', '.join(weighted()) or 'none here'}")
        sites, site_weights, inverse = prepare_weighted(points, weights)
        diagram = impl.run(sites, stats, weights=site_weights)
    if inverse.size == sites.shape[0]:
        return diagram                  # no duplicates: the sites are the input rows
    rows = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return diagram.with_input(rows, inverse)
