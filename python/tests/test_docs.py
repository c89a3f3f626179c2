"""Every `python` block of the README and of the user guide (docs/*.md) runs, from the
repository's root, as a reader would paste it (tests/docs.rs checks the `sh` blocks)."""

import contextlib
import io
import os
import re

import pytest

from conftest import REPO

FENCE = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.M | re.S)


def blocks():
    """(page:line, code) of every python block."""
    pages = [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md"))
    out = []
    for page in pages:
        text = page.read_text()
        for m in FENCE.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            out.append((f"{page.relative_to(REPO)}:{line}", m.group(1)))
    return out


def test_the_guide_has_python_blocks():
    assert len(blocks()) >= 2, blocks()


@pytest.mark.parametrize("where,code", blocks(), ids=[b[0] for b in blocks()])
def test_python_block_runs(where, code, monkeypatch):
    pytest.importorskip("critspeed")
    monkeypatch.chdir(REPO)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, where, "exec"), {"__name__": "__doc__"})
    # where every print line shows its output as a comment, the output must be that
    prints = [l for l in code.splitlines() if l.lstrip().startswith("print(")]
    shown = [l.split("#", 1)[1].strip() for l in prints if "#" in l]
    if prints and len(shown) == len(prints):
        assert printed.getvalue().splitlines() == shown, f"{where}: the comments are stale"
    elif prints:
        assert printed.getvalue().strip(), f"{where} printed nothing"
