"""What a fuzz campaign covers and how long it runs, in a module that imports nothing heavy
(the command line parses ``--budget`` with it before loading the harness)."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Optional

__all__ = ["Budget", "parse_budget", "INT_BOX", "LOG_NAME"]

#: The generator of small integer boxes with lattice points of one circle mixed in.
INT_BOX = "int_box"
#: The campaign's log, one JSON record per checked case, in its folder.
LOG_NAME = "cases.jsonl"


@dataclass(frozen=True)
class Budget:
    """How much to check: ``cases`` cases in all, or ``seconds`` of checking in this run."""

    cases: Optional[int] = None
    seconds: Optional[float] = None

    def __str__(self) -> str:
        return f"{self.cases} cases" if self.cases is not None else f"{self.seconds:g} s"


def parse_budget(text: str) -> Budget:
    """``100000`` -> 100000 cases; ``90s``, ``10m``, ``2h`` -> a duration."""
    text = text.strip().lower()
    units = {"s": 1.0, "m": 60.0, "h": 3600.0}
    try:
        if text and text[-1] in units:
            seconds = float(text[:-1]) * units[text[-1]]
            if not 0 < seconds < float("inf"):
                raise ValueError
            return Budget(seconds=seconds)
        cases = int(float(text))
        if cases < 1:
            raise ValueError
        return Budget(cases=cases)
    except (ValueError, OverflowError):
        raise argparse.ArgumentTypeError(f"budget {text!r}: a case count (100000) or a duration (90s, 10m, 2h)") from None
