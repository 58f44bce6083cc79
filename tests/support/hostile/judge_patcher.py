"""Item 1: module-level code that replaces the judge's decisions with ones that pass everything,
and a build that returns a wrong diagram. Harmless only if this module never runs in the judge."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import _common  # noqa: E402
import vorobench.judge.certificate as certificate  # noqa: E402
import vorobench.judge.engine as engine  # noqa: E402
from impls.base import Implementation  # noqa: E402

_common.record_import("judge_patcher")


def _pass(impl_name, reference, res, ref, *args, **kwargs):
    return engine.CaseVerdict(impl_name, reference, "exact", True, True, True, "all fine", result=res,
                              reference_result=ref)


def _agree(first, second):
    return engine.CaseVerdict(second.impl, first.impl, "exact", True, True, True, "all fine")


engine.decide = _pass
engine.agree_exactly = _agree
_real_certify = certificate.certify
certificate.certify = lambda d, **kw: _real_certify(d.__class__(*[getattr(d, f) for f in
                                                                  ("sites", "vertices", "origin", "twin", "next")],
                                                                d.site), **kw)

IMPLEMENTATIONS = [Implementation("judge_patcher", "patches the judge at import", "O(n log n)",
                                  _common.swapped_cells, exact=True)]
