"""Item 10: replaces the sandbox's encoder (in its own process) so that its answers claim arrays
far larger than n sites allow, or carry bytes the wire does not define (a deflated blob)."""

from __future__ import annotations

import io
import json
import multiprocessing as mp
import sys
import zlib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import _common  # noqa: E402
try:
    import vorobench.judge.wire as wire  # noqa: E402
except ImportError:     # before the bounded wire, the sandbox module encoded its own answers
    import vorobench.judge.sandbox as wire  # noqa: E402
from impls.base import Implementation  # noqa: E402
from impls.qhull import build as qhull_build  # noqa: E402

_real_encode = wire.encode
_MODE = {"bomb_shape": "shape", "bomb_deflate": "deflate", "bomb_npz": "npz"}


def _evil_encode(kind, data=None, arrays=None):
    # Which double this sandbox serves: its process is named after it.
    mode = _MODE.get(mp.current_process().name.replace("vorobench-judge-", ""))
    if kind != "ok" or not arrays or mode is None:
        return _real_encode(kind, data, arrays)
    if mode == "shape":        # claims 2**31 vertices, sends a few bytes
        header = json.dumps({"kind": "ok", "data": data, "arrays": [
            {"name": "vertices", "dtype": "<f8", "shape": [2 ** 31, 2]}]}).encode()
        return len(header).to_bytes(8, "little") + header + b"\0" * 64
    blob = io.BytesIO()
    if mode == "npz":          # the old answer format: a deflated .npz
        np.savez_compressed(blob, vertices=np.zeros((1000, 2)))
        payload = blob.getvalue()
    else:
        payload = zlib.compress(b"\0" * 100_000_000, 9)   # 100 MB in about 100 kB
    header = json.dumps({"kind": "ok", "data": data, "arrays": []}).encode()
    return len(header).to_bytes(8, "little") + header + payload


wire.encode = _evil_encode


def _build(sites, stats=None):
    return qhull_build(sites, stats)


IMPLEMENTATIONS = [Implementation(name, f"answers a {mode} bomb", "O(n log n)", _build, exact=False)
                   for name, mode in _MODE.items()]
