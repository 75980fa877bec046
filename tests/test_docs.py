"""Every code block of the README and of the documentation pages runs, and prints what the
page says it prints.

Python blocks of one page run in order in one namespace (a later block may use what an
earlier one defined), in a temporary folder (files they write land there), with
matplotlib's file-only back-end. Shell blocks: every line that calls the ``shellbvp``
command runs it, and must exit 0; lines that install the package, run the tests or build
these docs are what CI itself runs (``.ci/run``), so they are checked to be exactly those.
A page whose blocks take long carries ``<!-- docs-test: slow -->`` and runs with
``pytest -m slow``.

Stated outputs. What a page says a block prints is written as an ``output`` block (a fenced
block whose language is ``output``, shown as program output) after that code block: the
next fenced block of the page, with prose between them if need be. It is compared with
what the block printed (a python block's standard output; the standard output of a shell
block's ``shellbvp`` commands), never with a value computed here:

* text matches as written, any run of white space matching any other;
* ``...`` stands for any text, within a line or over lines (as in doctest), for what the
  page does not state;
* a number matches a printed number within one unit of its last stated digit
  (``4.2214291314`` within 1e-10, ``-0.50`` within 0.01, ``2e-10`` within 1e-10), so the
  page states as many digits as it vouches for; a number written without a decimal point
  or an exponent (``n = 3``) matches exactly;
* ``~x`` is an order of magnitude: a number of x's sign within a factor of 3 of x
  (``~1e-10`` for an error estimate).

A number is a whole token: digits inside a word (``R0``, ``h0``) are text. A page whose
claim cannot be written so (a relation between two printed numbers, a rate) prints the
relation instead, or states it in prose, unchecked.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest

from docs_blocks import PAGES, ROOT, blocks

SLOW = "<!-- docs-test: slow -->"
#: shell lines that CI runs itself (install, test, docs build), not this test
CI_LINES = re.compile(r"^(python -m pip install|python -m pytest|mkdocs build)")
PYTHON, SHELL, OUTPUT = ("python", "py"), ("bash", "sh", "console"), "output"
#: a number as a whole token: not inside a word or another number
_WHOLE = r"(?<![\w.\-]){}(?!\d|\.\d|[eE][-+]?\d)"
_NUMBER = r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?"
STATED_NUMBER = re.compile(_WHOLE.format(f"(~?)({_NUMBER})"))
PRINTED_NUMBER = _WHOLE.format(f"({_NUMBER})")


def _page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _params():
    out = []
    for page in PAGES:
        slow = SLOW in page.read_text()
        out.append(pytest.param(page, id=_page_id(page),
                                marks=[pytest.mark.slow] if slow else []))
    return out


def _text(text: str) -> str:
    """A regular expression for stated text: as written, any white space for white space."""
    return r"\s+".join(re.escape(word) for word in re.split(r"\s+", text))


def stated_pattern(stated: str):
    """(regular expression that the printed text must match in full, [(number as stated,
    whether it is an order of magnitude ~x)] in the order of the expression's groups)."""
    parts, numbers = [], []
    for k, piece in enumerate(re.split(r"\s*\.\.\.\s*", stated.strip())):
        if k:
            parts.append(".*?")
        at = 0
        for m in STATED_NUMBER.finditer(piece):
            parts += [_text(piece[at:m.start()]), PRINTED_NUMBER]
            numbers.append((m.group(2), m.group(1) == "~"))
            at = m.end()
        parts.append(_text(piece[at:]))
    return re.compile("".join(p for p in parts if p), re.S), numbers


def agrees(stated: str, approximate: bool, printed: str) -> bool:
    """Whether a printed number is a stated one, by the rules of the module docstring."""
    s, p = Decimal(stated), Decimal(printed)
    if approximate:
        return s != 0 and Decimal(1) / 3 <= p / s <= 3
    if not re.search(r"[.eE]", stated):
        return p == s
    return abs(p - s) <= Decimal(1).scaleb(s.as_tuple().exponent)


def output_mismatches(stated: str, printed: str) -> list[str]:
    """How ``printed`` differs from the stated output: [] where it reads as stated."""
    pattern, numbers = stated_pattern(stated)
    m = pattern.fullmatch(printed.strip())
    if m is None:
        return ["the printed text does not read as stated"]
    return [f"stated {s}{' (order of magnitude)' if approx else ''}, printed {p}"
            for (s, approx), p in zip(numbers, m.groups()) if not agrees(s, approx, p)]


def test_stated_output_rules():
    """The comparison of a stated output with a printed one, rule by rule, both ways."""
    ok = [("kappa_s R0 = 4.2214291314 +- ~1e-10", "kappa_s R0 = 4.2214291313606 +- 2.4e-10"),
          ("0.979494 2e-10 -0.50", "0.9794939398 1.6378e-10 -0.4987804"),
          ("n = 3, h0/R0 = 0.01", "n  =  3,\nh0/R0 = 0.010"),
          ("...\nfirst: n = 3 at ...\n...", "head 1\nfirst: n = 3 at 4.17 +- 1e-8\nlast"),
          ("a ... b", "a b"), ("0..20", "0..20"), ("x = 200", "x = 200.0")]
    not_ok = [("4.2214291314", "4.2214291316"), ("~1e-10", "4e-10"), ("~1e-10", "-1e-10"),
              ("n = 3", "n = 3.1"), ("2e-10", "3.2e-10"), ("-0.50", "-0.52"),
              ("kappa_s = 4.22", "kappa = 4.22"), ("R0 = 1", "R1 = 1"),
              ("4.22", "4.22 and more"), ("a ... b", "a c"), ("x = 1", "x = nan")]
    for stated, printed in ok:
        assert output_mismatches(stated, printed) == [], (stated, printed)
    for stated, printed in not_ok:
        assert output_mismatches(stated, printed), (stated, printed)


def test_every_page_has_its_blocks_found():
    """The fence pattern finds every block a page opens (an unmatched fence would hide a
    block from the tests below), and every output block follows a block that runs."""
    for page in PAGES:
        opened = sum(1 for line in page.read_text().splitlines()
                     if line.startswith("```") and line.strip() != "```")
        found = blocks(page)
        assert opened == len(found), page
        for k, (language, _) in enumerate(found):
            if language == OUTPUT:
                assert k > 0 and found[k - 1][0] in PYTHON + SHELL, \
                    f"{_page_id(page)}, block {k + 1}: an output block after no code block"


def _run_python(code: str, where: str, namespace: dict) -> str:
    """Run a python block; what it printed."""
    import matplotlib.pyplot as plt

    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, where, "exec"), namespace)
    plt.close("all")
    return printed.getvalue()


def _run_shell(code: str, where: str) -> str:
    """Run the ``shellbvp`` lines of a shell block (CI's own lines skipped); what they
    printed."""
    commands = [part.strip() for line in code.splitlines()
                for part in line.split("#", 1)[0].split("&&")]
    printed = ""
    for line in commands:
        if not line or CI_LINES.match(line):
            continue
        argv = shlex.split(line)
        assert argv[0] == "shellbvp", f"{where}: a shell line this test cannot run: {line}"
        env = dict(os.environ, MPLBACKEND="Agg")
        out = subprocess.run([sys.executable, "-m", "shellbvp.cli", *argv[1:]],
                             capture_output=True, text=True, env=env)
        assert out.returncode == 0, f"{where}: {line}\n{out.stderr[-2000:]}"
        printed += out.stdout
    return printed


@pytest.mark.parametrize("page", _params())
def test_code_blocks_run_and_print_what_the_page_states(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    found = blocks(page)
    for k, (language, code) in enumerate(found):
        where = f"{_page_id(page)}, block {k + 1}"
        if language in PYTHON:
            printed = _run_python(code, where, namespace)
        elif language in SHELL:
            printed = _run_shell(code, where)
        else:
            continue
        if k + 1 < len(found) and found[k + 1][0] == OUTPUT:
            stated = found[k + 1][1]
            wrong = output_mismatches(stated, printed)
            assert not wrong, (f"{where} does not print what block {k + 2} states: "
                               + "; ".join(wrong)
                               + f"\n--- stated\n{stated.rstrip()}\n--- printed\n{printed}")


def test_the_sites_scripts_are_served_with_it():
    """Equations are typeset by MathJax served with the site (no network): every
    ``extra_javascript`` of mkdocs.yml is a file under docs/, MathJax's fonts beside it."""
    text = (ROOT / "mkdocs.yml").read_text()
    block = re.match(r"((?:\n\s+-\s+\S+)+)", text.split("extra_javascript:", 1)[1]).group(1)
    scripts = re.findall(r"-\s+(\S+)", block)
    assert any("mathjax" in s for s in scripts)
    for s in scripts:
        assert "://" not in s and (ROOT / "docs" / s).is_file(), s
    assert list((ROOT / "docs/javascripts/mathjax/output/chtml/fonts/woff-v2").glob("*.woff*"))
