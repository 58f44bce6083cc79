"""List the runs of a run store, one line each, oldest first.

    vorobench history DIR [--machine ID] [--json]

Each line: run id, date, vorobench's commit (``+`` if the tree was dirty), the machine
fingerprint, host, cases run and failed, and the implementations. ``--json`` prints the same
as a list of objects (the full metadata of each run under ``meta``).
"""

from __future__ import annotations

import argparse
import json

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("store", help="run store folder (filled by `vorobench bench --store DIR`)")
    p.add_argument("--machine", default=None, metavar="ID", help="only the runs of this machine fingerprint (prefix)")
    p.add_argument("--json", action="store_true", help="print the runs as JSON")


def _commit(run) -> str:
    if not run.commit:
        return "-"
    return str(run.commit)[:10] + ("+" if run.dirty else "")


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.store import Store

    runs = Store(args.store).runs(machine_id=args.machine)
    if args.json:
        records = []
        for r in runs.itertuples(index=False):
            record = {k: v for k, v in r._asdict().items() if k != "meta"}
            record["dirty"] = None if record["dirty"] is None else bool(record["dirty"])
            record["complete"] = bool(record["complete"])
            record["meta"] = json.loads(r.meta or "{}")
            records.append(record)
        print(json.dumps(records, indent=2, default=str))
        return 0
    if runs.empty:
        print(f"{args.store}: no runs" + (f" on machine {args.machine}" if args.machine else ""))
        return 0
    for r in runs.itertuples(index=False):
        meta = json.loads(r.meta or "{}")
        impls = ",".join(meta.get("impls") or [])
        print(f"{r.run_id}  {str(r.date or '-')[:19]}  {_commit(r):<11}  machine {r.machine_id or '-'}  "
              f"{r.hostname or '-'}  {r.cases} cases, {r.failed} failed"
              + ("" if r.complete else ", interrupted") + (f"  {impls}" if impls else ""))
    return 0
