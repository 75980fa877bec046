"""The generated code shipped with the package (shellbvp/generated_code.json) is the
derivation's: its digest is that of the current derivation sources, and every shipped
function equals the one a fresh sympy derivation lambdifies (reference: that derivation,
with the disk cache off, evaluated at random arguments)."""

import numpy as np
import pytest

from shellbvp import codegen


def test_shipped_code_comes_from_the_current_derivation():
    """A stale file would be ignored at run time (every process derives again, ~3.5 s): it
    must be regenerated whenever the derivation changes."""
    import json

    data = json.loads(codegen.SHIPPED_PATH.read_text())
    assert data["digest"] == codegen.derivation_digest(), \
        "the derivation changed: regenerate with `python -m shellbvp.codegen`"
    assert codegen.shipped(), "the shipped code is not used"


def test_scenes_take_the_shipped_code_without_sympy(monkeypatch):
    """The default cap's functions come from the shipped file: building them is refused."""
    def refuse(*args):
        raise AssertionError("derived instead of shipped")

    monkeypatch.setattr(codegen, "_build_energy", refuse)
    monkeypatch.setattr(codegen, "_build_el", refuse)
    assert set(codegen.energy("relaxed", "cg", "default")) == {"W"}
    assert set(codegen.euler_lagrange(False)) == {"X", "G", "G_q", "G_y", "f", "f_y", "f_q"}


def _arguments(fn, rng, k=4):
    """k random argument tuples for a generated function: stretches near 1, the rest O(1)
    (lam, h positive)."""
    n = fn.__code__.co_argcount
    return [tuple(rng.uniform(0.8, 1.2) if i < 2 else rng.uniform(0.05, 1.0)
                  for i in range(n)) for _ in range(k)]


def _agree(shipped_fns, fresh_fns, rng):
    for name, fresh in fresh_fns.items():
        for args in _arguments(fresh, rng):
            a = np.asarray(shipped_fns[name](*args), dtype=float)
            b = np.asarray(fresh(*args), dtype=float)
            assert np.all(np.isfinite(b))
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * (1 + np.abs(b).max()),
                                       err_msg=name)


def _compare(label, build, args, monkeypatch, tmp_path):
    monkeypatch.setenv("SHELLBVP_CACHE_DIR", "off")
    fresh = build(*args)
    shipped = codegen._functions(label, lambda: pytest.fail(f"{label} not shipped"))
    assert set(shipped) == set(fresh)
    _agree(shipped, fresh, np.random.default_rng(len(label)))


def test_shipped_energy_and_equations_equal_a_fresh_derivation(monkeypatch, tmp_path):
    """The default cap's energy (relaxed, CG) and Euler-Lagrange system, derived afresh."""
    _compare("energy/relaxed/cg/default", codegen._build_energy, ("relaxed", "cg", "default"),
             monkeypatch, tmp_path)
    _compare("euler-lagrange/False", codegen._build_el, (False,), monkeypatch, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("label", sorted(
    ["energy/{}/{}/{}".format(m, a, st) for m in ("plane_strain", "relaxed")
     for a in ("cg", "nh", "koiter") for st in codegen.STIMULI]
    + ["general-energy/{}/{}".format(m, a) for m in ("plane_strain", "relaxed")
       for a in ("cg", "nh")]
    + ["euler-lagrange/True"]))
def test_every_shipped_function_equals_a_fresh_derivation(label, monkeypatch, tmp_path):
    kind, *parts = label.split("/")
    if kind == "energy":
        build, args = codegen._build_energy, (parts[0], parts[1], parts[2])
    elif kind == "general-energy":
        build, args = codegen._build_general_energy, tuple(parts)
    else:
        build, args = codegen._build_el, (parts[0] == "True",)
    _compare(label, build, args, monkeypatch, tmp_path)
