"""Numbers as people read them in reports: seconds, sizes, factors and percentages."""

from __future__ import annotations

import math

__all__ = ["seconds_text", "factor_text", "percent_text", "size_text"]


def seconds_text(seconds: float) -> str:
    if seconds is None or not math.isfinite(seconds):
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.3g} µs"
    if seconds < 1:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s"


def factor_text(x: float) -> str:
    """2.3, 15, 150: a ratio with two significant digits, never in exponent notation."""
    return f"{x:.2g}" if x < 100 else f"{x:.0f}"


def percent_text(x: float) -> str:
    """0.034 -> 3.4%, 0.25 -> 25%."""
    return f"{x * 100:.2g}%" if abs(x) < 0.1 else f"{x * 100:.0f}%"


def size_text(n: float) -> str:
    n = int(n)
    if n >= 1_000_000:
        return f"{n / 1e6:.3g}M"
    if n >= 1000:
        return f"{n / 1e3:.3g}k"
    return str(n)
