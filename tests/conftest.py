"""Shared test settings: strict JAX (float64), the tests folder importable, seeded states."""

import os
import sys

import numpy as np
import pytest

os.environ.setdefault("JAX_ENABLE_X64", "1")
# the test process compiles hundreds of programs: no JAX disk cache here, even where the CLI
# (tested in-process) would turn it on (see shellbvp.jaxsetup)
os.environ["SHELLBVP_JAX_CACHE"] = "off"
sys.path.insert(0, os.path.dirname(__file__))  # for the paper transcriptions in paper_formulas.py


def random_states(seed, n=6, *, stretch=(0.8, 1.25), curv=2.0):
    """Random admissible principal states (lam1, lam2, k1, k2, kb1, kb2), curvatures in 1/R0."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        l1, l2 = rng.uniform(*stretch, 2)
        k = rng.uniform(-curv, curv, 4)
        out.append((l1, l2, *k))
    return out


@pytest.fixture
def states():
    return random_states(2024)


def pytest_terminal_summary(terminalreporter):
    """The outcomes of the property-based cases that ran (tests/test_property_solvers.py)."""
    module = next((m for name, m in list(sys.modules.items())
                   if name.endswith("test_property_solvers")), None)
    outcomes = getattr(module, "OUTCOMES", None)
    if outcomes:
        terminalreporter.section("property-based cases")
        for outcome, count in sorted(outcomes.items()):
            terminalreporter.write_line(f"{count:5d}  {outcome}")
