"""The Python snippets of the README's scipy section and docs/scipy.md run as written, and say
what the text around them says they say."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent


def _python_blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S)


@pytest.mark.parametrize("page", ["README.md", "docs/scipy.md"])
def test_scipy_snippet_runs_and_agrees(page):
    import matplotlib.pyplot as plt

    blocks = [b for b in _python_blocks(ROOT / page) if "from_scipy" in b]
    assert blocks, f"{page} has no from_scipy snippet"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], page, "exec"), {})
    plt.close("all")
    assert "EQUAL (exact)" in out.getvalue()
    if page == "README.md":
        assert len(blocks[0].strip().splitlines()) <= 5, "the README promises five lines"


@pytest.mark.parametrize("folder, language", [("c", "c"), ("js", "javascript")])
def test_the_executables_page_shows_the_examples_as_they_are(folder, language):
    """docs/executables.md's complete examples are the files the tests run (no drift)."""
    page = (ROOT / "docs" / "executables.md").read_text()
    example = ROOT / "examples" / "executable" / folder
    source = next(p for p in example.iterdir() if p.suffix in (".c", ".mjs"))
    for text, fence in ((example / "impl.toml").read_text(), "toml"), (source.read_text(), language):
        assert f"```{fence}\n{text}```" in page, f"{example.name}: the page's {fence} block is not the file"
