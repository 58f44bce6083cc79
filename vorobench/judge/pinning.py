"""Reading the declarations of a run's implementations in a throwaway sandbox, and pinning them.

The sandbox loads the run's plugins (never this process); what comes back is checked field by
field (:func:`~vorobench.judge.declarations.declaration_from_data`).
"""

from __future__ import annotations

from typing import Optional

from vorobench.judge.declarations import Declaration, DeclarationError, declaration_from_data, declare_here
from vorobench.judge.sandbox import Sandbox

__all__ = ["declare_in_sandbox", "resolve_declarations", "PluginError"]


def declare_in_sandbox(names: Optional[list[str]], plugins: tuple[str, ...] = (), timeout: float = 120.0
                       ) -> tuple[list[str], dict[str, Declaration], dict[str, str]]:
    """(available names, declarations, why each other one failed) of ``names`` (None: all),
    read in one throwaway sandbox with ``plugins`` loaded there, never here."""
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


def resolve_declarations(names: Optional[list[str]], plugins: tuple[str, ...] = (), timeout: float = 120.0,
                         also: tuple[str, ...] = ()) -> dict[str, Declaration]:
    """The declarations of ``names`` (None or ``["all"]``: every implementation available with
    ``plugins``, one that fails to load left out) and of ``also`` (the reference: always
    required), read in one sandbox, in the order asked. Raises :class:`PluginError` when the
    plugins cannot be loaded and ``ValueError`` naming the available ones for an unknown or
    broken name: usage errors, said in one line."""
    every = not names or list(names) == ["all"]
    asked = None if every else list(dict.fromkeys([*names, *also]))
    available, declared, failed = declare_in_sandbox(asked, tuple(plugins), timeout)
    if "*" in failed:
        raise PluginError(failed["*"].split("\n")[0])
    wanted = list(dict.fromkeys([*available, *also])) if every else asked
    unknown = [n for n in wanted if n not in available]
    if unknown:
        raise ValueError(f"unknown implementation {unknown[0]!r}; available: {', '.join(available)}")
    required = list(also) if every else wanted
    broken = [n for n in required if n not in declared]
    if broken:
        raise ValueError(f"implementation {broken[0]!r} could not be loaded: {failed.get(broken[0], '')}")
    return {n: declared[n] for n in wanted if n in declared}
