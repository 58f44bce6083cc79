"""What the exact topology check adds to certify() at 10^6 sites (issue 22's cost bound: 1.5x).

    .venv/bin/python benchmarks/topology_cost.py

The other checks are unchanged code, so the certificate's own per-check seconds of one run
give the ratio with / without it (repeated, to see the noise).
"""

import numpy as np, impls, time
from vorobench.judge.certificate import certify
if __name__ == "__main__":
    pts = np.random.default_rng(0).random((1_000_000, 2))
    d = impls.build("incremental", pts)
    certify(impls.build("incremental", pts[:1000]))        # compile
    for rep in range(2):
        c = certify(d)
        secs = {ch.name: ch.seconds for ch in c.checks}
        total = sum(secs.values())
        print(f"rep {rep}: certify {total:.2f} s, topology {secs['topology']:.2f} s, "
              f"ratio with/without {total / (total - secs['topology']):.3f}", c.ok)
