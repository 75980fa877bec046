"""The fenced code blocks of the README and the documentation pages (for tests/test_docs.py,
which runs them all, and for the tests that check what a page's example computes)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("**/*.md"))]
FENCE = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```", re.S | re.M)


def blocks(page: Path):
    """(language, code) of every fenced block of ``page``, in order."""
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(page.read_text())]


def python_block(containing: str) -> str:
    """The first python block of the README or a page whose code contains ``containing``."""
    return next(code for page in PAGES for language, code in blocks(page)
                if language == "python" and containing in code)
