"""Plugins given by the user on the command line (``--plugin``): a module name or a ``.py``
file defining ``IMPLEMENTATIONS`` (a list of :class:`~impls.base.Implementation`) or
``IMPLEMENTATION``, or an executable's TOML manifest (:mod:`impls.executable`), registered for the duration of a run (in the parent and in every worker).
Installed packages use the entry-point group ``vorobench.impls`` instead (see :mod:`impls`)."""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import os
import sys
import zlib
from pathlib import Path
from typing import Iterator, Sequence

from impls import register, registered, unregister
from impls.base import Implementation

__all__ = ["load_plugin", "plugins_registered"]


def load_plugin(spec: str) -> list[str]:
    """Import a module (dotted name or ``.py`` path) and register its ``IMPLEMENTATIONS``.

    A plugin module defines ``IMPLEMENTATIONS`` (a list of :class:`impls.Implementation`) or
    ``IMPLEMENTATION``; nothing happens at its import time, the runner registers them here, in
    the parent and in every worker. Returns the registered names. A ``.toml`` file is an
    executable's manifest: read (no code runs) and registered as an implementation of kind
    ``executable`` (:mod:`impls.executable`).
    """
    if spec.endswith(".toml"):
        from impls.executable import implementation_of, read_manifest

        impl = implementation_of(read_manifest(spec))     # ManifestError (a ValueError) says what is wrong
        register(impl)
        return [impl.name]
    try:
        if spec.endswith(".py") or os.sep in spec:
            path = Path(spec).resolve()
            if not path.is_file():
                raise FileNotFoundError(f"plugin file not found: {spec}")
            name = f"vorobench_plugin_{zlib.crc32(str(path).encode()):08x}"
            module = sys.modules.get(name)
            if module is None:
                module_spec = importlib.util.spec_from_file_location(name, path)
                module = importlib.util.module_from_spec(module_spec)
                sys.modules[name] = module
                try:
                    module_spec.loader.exec_module(module)
                except BaseException:
                    del sys.modules[name]
                    raise
        else:
            module = importlib.import_module(spec)
    except FileNotFoundError:
        raise
    except Exception as exc:  # a plugin that cannot load is a usage error, said in one line
        raise ValueError(f"plugin {spec!r} could not be loaded: {type(exc).__name__}: {exc}") from None
    found = list(getattr(module, "IMPLEMENTATIONS", None) or [])
    single = getattr(module, "IMPLEMENTATION", None)
    if single is not None:
        found.append(single)
    if not found:
        raise ValueError(f"plugin {spec!r} defines neither IMPLEMENTATIONS nor IMPLEMENTATION")
    wrong = [type(impl).__name__ for impl in found if not isinstance(impl, Implementation)]
    if wrong:
        raise ValueError(f"plugin {spec!r}: IMPLEMENTATIONS must hold impls.Implementation objects, not {wrong[0]}")
    for impl in found:
        register(impl)
    return [impl.name for impl in found]


@contextlib.contextmanager
def plugins_registered(specs: Sequence[str]) -> Iterator[list[str]]:
    """Register plugin implementations for the duration of a run in this process, then remove
    them, so a test double never outlives the run that asked for it."""
    before = set(registered())          # a nested use leaves the outer registrations alone
    names: list[str] = []
    try:
        for spec in specs:
            names += load_plugin(spec)
        yield names
    finally:
        for name in names:
            if name not in before:
                unregister(name)
