"""Every code block of the README and of the documentation pages runs.

Python blocks of one page run in order in one namespace (a later block may use what an
earlier one defined), in a temporary folder (files they write land there), with
matplotlib's file-only back-end. Shell blocks: every line that calls the ``shellbvp``
command runs it, and must exit 0; lines that install the package, run the tests or build
these docs are what CI itself runs (``.ci/run``), so they are checked to be exactly those.
A page whose blocks take long carries ``<!-- docs-test: slow -->`` and runs with
``pytest -m slow``.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from docs_blocks import PAGES, ROOT, blocks

SLOW = "<!-- docs-test: slow -->"
#: shell lines that CI runs itself (install, test, docs build), not this test
CI_LINES = re.compile(r"^(python -m pip install|python -m pytest|mkdocs build)")


def _page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _params():
    out = []
    for page in PAGES:
        slow = SLOW in page.read_text()
        out.append(pytest.param(page, id=_page_id(page),
                                marks=[pytest.mark.slow] if slow else []))
    return out


def test_every_page_has_its_blocks_found():
    """The fence pattern finds every block a page opens (an unmatched fence would hide a
    block from the tests below)."""
    for page in PAGES:
        opened = sum(1 for line in page.read_text().splitlines()
                     if line.startswith("```") and line.strip() != "```")
        assert opened == len(blocks(page)), page


@pytest.mark.parametrize("page", _params())
def test_code_blocks_run(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    for k, (language, code) in enumerate(blocks(page)):
        where = f"{_page_id(page)}, block {k + 1}"
        if language in ("python", "py"):
            exec(compile(code, where, "exec"), namespace)
            plt.close("all")
        elif language in ("bash", "sh", "console"):
            commands = [part.strip() for line in code.splitlines()
                        for part in line.split("#", 1)[0].split("&&")]
            for line in commands:
                if not line or CI_LINES.match(line):
                    continue
                argv = shlex.split(line)
                assert argv[0] == "shellbvp", f"{where}: a shell line this test cannot run: {line}"
                env = dict(os.environ, MPLBACKEND="Agg")
                out = subprocess.run([sys.executable, "-m", "shellbvp.cli", *argv[1:]],
                                     capture_output=True, text=True, env=env)
                assert out.returncode == 0, f"{where}: {line}\n{out.stderr[-2000:]}"
