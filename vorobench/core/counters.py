"""The counters rule: what an implementation may put into ``stats``.

Counters are machine-independent integers (events, predicate calls): the same code on the same
input gives the same counters, so they gate exactly. Durations are not counters; they go
through :func:`impls.base.record_timing`. :func:`check_counters` is applied at every build.
"""

from __future__ import annotations

import numbers
import re
from typing import Any, Mapping

__all__ = ["CounterError", "check_counters", "DURATION_NAME"]

class CounterError(TypeError):
    """An implementation put something other than a machine-independent integer into ``stats``."""


#: Names that say "a duration": such a value is a timing whatever its type.
DURATION_NAME = re.compile(r"(^|_)(s|ms|us|ns|sec|secs|seconds|time|elapsed|duration)$", re.IGNORECASE)


def check_counters(stats: Mapping[str, Any], who: str = "the implementation") -> dict[str, int]:
    """``stats`` as {name: int}, or :class:`CounterError` naming the first value that is not a
    counter: a non-integer, or a name that says it is a duration (``library_s``)."""
    out: dict[str, int] = {}
    for key, value in stats.items():
        name = str(key)
        if DURATION_NAME.search(name):
            raise CounterError(f"{who} put {name}={value!r} into its counters, but its name says it is a "
                               "duration: counters are machine-independent integers; report times with "
                               "impls.base.record_timing")
        if isinstance(value, bool) or isinstance(value, numbers.Integral):
            out[name] = int(value)
        elif isinstance(value, numbers.Real) and float(value).is_integer():
            out[name] = int(value)
        else:
            raise CounterError(f"{who} put {name}={value!r} into its counters: counters are machine-independent "
                               "integers; report times with impls.base.record_timing")
    return out
