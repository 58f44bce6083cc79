"""The example CI workflow stays in step with the command line: it parses, and every vorobench
command in it is accepted by today's parser."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from vorobench.cli import build_parser

WORKFLOW = Path(__file__).resolve().parents[2] / "examples" / "ci" / "vorobench.yml"


def _commands(script: str) -> list[list[str]]:
    joined = script.replace("\\\n", " ")
    found = []
    for line in joined.splitlines():
        line = line.strip()
        if line.startswith("$VOROBENCH "):
            line = re.split(r"\s\|\|?\s", line)[0]          # the shell's pipes and fallbacks are not ours
            line = line.replace("$STORE_ARG", "--store S").replace('"$STORE', '"S').replace("$STORE", "S")
            found.append(shlex.split(line)[1:])
    return found


def test_every_vorobench_command_of_the_workflow_parses():
    yaml = pytest.importorskip("yaml")
    doc = yaml.safe_load(WORKFLOW.read_text())
    steps = doc["jobs"]["vorobench"]["steps"]
    commands = [cmd for step in steps if "run" in step for cmd in _commands(step["run"])]
    names = {cmd[0] for cmd in commands}
    assert {"validate", "bench", "history", "compare", "report"} <= names
    parser = build_parser()
    for cmd in commands:
        args = parser.parse_args(cmd)          # an unknown option exits 2 (SystemExit): the test fails
        assert args.func is not None
