"""Every ``vorobench`` command the README shows is accepted by today's parser: an option renamed
or dropped fails here, not on a reader's machine. (What the commands do is tested where each
command is: the README's examples run there, shrunk.)"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

from vorobench.cli import build_parser

README = Path(__file__).resolve().parents[2] / "README.md"


def _readme_commands() -> list[list[str]]:
    """The argument lists of the ``vorobench ...`` lines of the README's shell blocks
    (continuation lines joined, comments and the shell's pipes left out, a usage line's
    optional ``[--option value]`` given)."""
    blocks, block, language = [], None, ""
    for line in README.read_text().splitlines():
        if line.startswith("```"):
            if block is None:
                block, language = [], line[3:].strip()
            else:
                if language in ("", "bash", "sh", "console"):
                    blocks.append("\n".join(block) + "\n")
                block = None
        elif block is not None:
            block.append(line)
    found = []
    for block in blocks:
        for line in block.replace("\\\n", " ").splitlines():
            line = line.strip().removeprefix("$ ")
            if line.startswith("vorobench "):
                line = re.split(r"\s(?:\|\|?|&&|>|#)\s", line)[0]
                line = re.sub(r"\[([^\]]*)\]", r"\1", line)        # a usage line's [--option value]
                found.append(shlex.split(line)[1:])
    return found


def test_every_readme_command_parses():
    commands = _readme_commands()
    assert len(commands) >= 10 and {"bench", "validate", "fuzz", "report"} <= {c[0] for c in commands}
    parser = build_parser()
    for cmd in commands:
        args = parser.parse_args(cmd)          # an unknown option exits 2 (SystemExit): the test fails
        assert args.func is not None, cmd
