"""Expressions of scene files (shellbvp.expressions): values against numpy written by hand,
traced through ``jax.jit`` and ``jax.grad``, every input outside the grammar refused with a
ValueError that names the key, and a canonical cache key."""

import ast
import inspect
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from shellbvp import expressions
from shellbvp.expressions import MAX_DEPTH, MAX_LENGTH, Expression, parse

SYMBOLS = ("p", "s", "r", "z", "k1_ref", "k2_ref")
KEY = "stimulus.kb1"
S = np.linspace(0.05, 0.95, 7)
R = np.linspace(0.9, 0.1, 7)
VALUES = dict(p=1.5, s=S, r=R, z=-0.3, k1_ref=2.0, k2_ref=-1.0)


def ev(text, **values):
    return parse(text, SYMBOLS, key=KEY)(**{**VALUES, **values})


@pytest.mark.parametrize("text, expected", [
    ("0.01*(1 - r**2)", 0.01 * (1 - R**2)),
    ("k1_ref + p*exp(-(s/0.2)**2)", 2.0 + 1.5 * np.exp(-(S / 0.2) ** 2)),
    ("sin(s) + cos(r) - tan(z)", np.sin(S) + np.cos(R) - np.tan(-0.3)),
    ("log(p) * sqrt(s) / abs(z)", np.log(1.5) * np.sqrt(S) / 0.3),
    ("tanh(s) + sinh(r) + cosh(z)", np.tanh(S) + np.sinh(R) + np.cosh(-0.3)),
    ("arcsin(s) + arccos(r) + arctan(z)", np.arcsin(S) + np.arccos(R) + np.arctan(-0.3)),
    ("arctan2(s, z)", np.arctan2(S, -0.3)),
    ("minimum(s, r) + maximum(s, r)", np.minimum(S, R) + np.maximum(S, R)),
    ("pi*e", np.full(7, np.pi * np.e)),
    ("-s**2", -(S**2)),
    ("2**-1", np.full(7, 0.5)),
    ("2**3**2", np.full(7, 512.0)),
    ("(2**3)**2", np.full(7, 64.0)),
    ("-2*s + +r - -z", -2 * S + R - 0.3),
    ("1 - s/2/r", 1 - S / 2 / R),
    ("where(s < 0.5, s, r)", np.where(S < 0.5, S, R)),
    ("where(0.2 <= s < 0.6, 1, 0)", np.where((0.2 <= S) & (S < 0.6), 1.0, 0.0)),
    ("where(r > s >= 0.2 > z, 1, 0)", np.where((R > S) & (S >= 0.2) & (0.2 > -0.3), 1.0, 0.0)),
    ("where((s < 0.2) | (s > 0.8) & (r < 1), -1, where(s < r, s, 2))",
     np.where((S < 0.2) | ((S > 0.8) & (R < 1)), -1.0, np.where(S < R, S, 2.0))),
    ("1e-3 + 0x10 + 1_000", np.full(7, 0.001 + 16 + 1000)),
])
def test_values_against_numpy(text, expected):
    out = ev(text)
    assert out.dtype == np.float64 and out.shape == S.shape
    np.testing.assert_allclose(out, expected, rtol=1e-14, atol=0)


def test_layout_and_several_lines():
    assert ev("  s *\t2 ")[0] == 2 * S[0]
    assert ev("\n(s +\n 1)\n")[0] == S[0] + 1


def test_numbers_as_scene_files_give_them():
    for value in (0.01, 2, np.float64(0.25)):
        e = parse(value, SYMBOLS, key=KEY)
        assert e.is_constant and e.symbols_used == ()
        assert e().shape == () and e() == float(value)
    assert parse(2, SYMBOLS, key=KEY).text == "2"
    assert parse(0.01, SYMBOLS, key=KEY).cache_key == parse("0.01", SYMBOLS, key=KEY).cache_key


def test_broadcasting_and_floats():
    """A constant is broadcast to the arrays given (a writable float array); integer inputs
    are floats before any arithmetic."""
    c = parse("0.01", SYMBOLS, key=KEY)
    assert c().shape == () and c().dtype == np.float64
    out = c(s=np.zeros((2, 3)), p=1.0)
    assert out.shape == (2, 3) and out.flags.writeable
    e = parse("s**-1 + p", SYMBOLS, key=KEY)
    np.testing.assert_array_equal(e(s=np.arange(1, 4), p=np.ones((2, 1), dtype=int)),
                                  1.0 / np.arange(1, 4) + np.ones((2, 3)))
    assert e(s=2, p=1).dtype == np.float64 and e(s=2, p=1) == 1.5


def test_nesting_up_to_the_bound():
    """MAX_DEPTH levels of parentheses, of operations and of chained comparisons are
    accepted and evaluated."""
    assert ev("(" * MAX_DEPTH + "s" + ")" * MAX_DEPTH)[0] == S[0]
    assert ev("-" * (MAX_DEPTH - 1) + "s")[0] == -S[0]
    chain = "where(" + " <= ".join(["s"] * (MAX_DEPTH - 1)) + ", 1, 0)"
    assert ev(chain)[0] == 1.0


def test_literals_are_floats_before_arithmetic():
    """``9**9**9`` as Python integers would run for hours; as floats it overflows at once."""
    with np.errstate(over="ignore"):
        assert ev("9**9**9")[0] == np.inf


def test_used_symbols_and_missing_values():
    e = parse("k1_ref + p*exp(-(s/0.2)**2) + pi", SYMBOLS, key=KEY)
    assert e.symbols_used == ("k1_ref", "p", "s") and not e.is_constant
    with pytest.raises(ValueError, match=r"^stimulus\.kb1: no value for k1_ref, s \("):
        e(p=1.0, r=R)


def test_traceable_by_jax():
    e = parse("k1_ref + p*exp(-(s/0.2)**2) + where(s < 0.5, s**2, 0.25)", SYMBOLS, key=KEY)
    f = jax.jit(lambda s, p: e(jnp, s=s, p=p, k1_ref=2.0))
    out = f(jnp.asarray(S), 1.5)
    assert out.dtype == jnp.float64
    np.testing.assert_allclose(out, e(s=S, p=1.5, k1_ref=2.0), rtol=1e-14)

    def d_ds(s):
        return -2 * s / 0.04 * 1.5 * np.exp(-(s / 0.2) ** 2) + np.where(s < 0.5, 2 * s, 0.0)

    g = jax.jit(jax.grad(lambda s: e(xp=jnp, s=s, p=1.5, k1_ref=2.0)))
    for s in (0.1, 0.3, 0.7):
        np.testing.assert_allclose(g(s), d_ds(s), rtol=1e-13)
    dp = jax.grad(lambda p: e(jnp, s=0.1, p=p, k1_ref=2.0))(1.5)
    np.testing.assert_allclose(dp, np.exp(-0.25), rtol=1e-14)
    c = parse("0.01", SYMBOLS, key=KEY)
    assert jax.jit(lambda s: c(jnp, s=s))(jnp.ones(3)).shape == (3,)


@pytest.mark.parametrize("text, says", [
    ("__import__('os').system('x')", "attribute access"),
    ("().__class__", "attribute access '().__class__' at column 1"),
    ("s.real", "attribute access 's.real' at column 1"),
    ("[1][0]", "subscript"),
    ("lambda: 1", "lambda"),
    ("(x:=1)", "assignment expression 'x:=1' at column 2"),
    ('f"{s}"', "f-string"),
    ("'a'", "string"),
    ("True", "boolean 'True'"),
    ("None", "None"),
    ("1j", "complex number '1j'"),
    ("1e999", "number '1e999'"),
    ("sin(x=1)", "keyword argument 'x=1' at column 5"),
    ("sin(*s)", "starred argument"),
    ("sin(1, 2)", "sin given 2 arguments"),
    ("arctan2(s)", "arctan2 takes 2 arguments"),
    ("s < 1", "comparison 's < 1' at column 1"),
    ("where(s < 1, s < 2, 1)", "comparison 's < 2' at column 14"),
    ("where(s, 1, 2)", "condition 's' at column 7"),
    ("where(s == 1, 1, 2)", "comparison '=='"),
    ("where(s > 0 and s < 1, 1, 2)", "condition"),
    ("s & r", "operator '&'"),
    ("s % 2", "operator '%'"),
    ("not s", "operator 'not'"),
    ("a if s else b", "conditional expression"),
    ("open('f')", "unknown function 'open' at column 1"),
    ("s(1)", "symbol called as a function"),
    ("exp", "function 'exp' at column 1"),
    ("k1_ref + foo", "unknown name 'foo' at column 10 (allowed names: p, s, r, z, k1_ref, "
                     "k2_ref, pi, e; functions: sin, cos,"),
    ("(1 +\n foo)", "unknown name 'foo' at line 2, column 2"),
    ("1 # comment", "comment '# comment' at column 3"),
    ("1\0", "control character"),
    ("1 + * 2", "syntax error at '*' at column 5"),
    ("sin(", "syntax error"),
    ("1 +", "syntax error at the end"),
    ("(" * 200 + "9" + ")" * 200, f"nested deeper than {MAX_DEPTH} levels"),
    ("+".join(["s"] * 100), f"nested deeper than {MAX_DEPTH} levels"),
    ("-" * 1999 + "1", f"nested deeper than {MAX_DEPTH} levels"),
    ("where(" + " < ".join(["s"] * 100) + ", 1, 0)", f"nested deeper than {MAX_DEPTH} levels"),
    ("1+" * 1500 + "1", f"at most {MAX_LENGTH} are allowed"),
    ("", "empty expression"),
    ("  \n ", "empty expression"),
])
def test_refused(text, says):
    with pytest.raises(ValueError) as info:
        parse(text, SYMBOLS, key=KEY)
    message = str(info.value)
    assert message.startswith(f"{KEY}: ") and "\n" not in message, message
    assert says in message, message
    assert info.value.__cause__ is None and info.value.__suppress_context__


@pytest.mark.parametrize("value", [True, None, [1.0], float("nan"), float("inf"), 10**400])
def test_refused_values(value):
    with pytest.raises(ValueError, match=r"^stimulus\.kb1: "):
        parse(value, SYMBOLS, key=KEY)


@pytest.mark.parametrize("symbols", ["s", ("s", "sin"), ("pi",), ("xp",), ("a b",), ("if",)])
def test_refused_symbols(symbols):
    with pytest.raises(ValueError, match=r"^stimulus\.kb1: "):
        parse("1", symbols, key=KEY)


def test_nothing_runs_user_text():
    """The module has no way to run text: no eval, exec, compile or sympify, by name."""
    source = inspect.getsource(expressions)
    tree = ast.parse(source)
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    for forbidden in ("eval", "exec", "compile", "sympify", "__import__", "sympy"):
        assert forbidden not in names, forbidden
    code = "\n".join(line.split("#")[0] for line in source.splitlines())
    for forbidden in ("eval(", "exec(", "compile(", "sympify", "import sympy", "import jax"):
        assert forbidden not in code, forbidden


def test_refused_text_is_not_run(tmp_path, monkeypatch):
    """A refused call with side effects has none."""
    target = tmp_path / "touched"
    monkeypatch.chdir(tmp_path)
    for text in (f"open('{target.name}', 'w')", "__import__('os').mkdir('d')"):
        with pytest.raises(ValueError):
            parse(text, SYMBOLS, key=KEY)
    assert list(tmp_path.iterdir()) == []


def test_cache_key():
    a = parse("0.01*(1 - r**2)", SYMBOLS, key=KEY)
    b = parse(" 0.01 * ( (1) - r ** 2.0 ) ", SYMBOLS, key="geometry.thickness")
    assert a.cache_key == b.cache_key and a.text != b.text
    assert parse("where(0 < s < 1, 1, 0)", SYMBOLS, key=KEY).cache_key == \
        parse("where((0 < s) & (s < 1), 1, 0)", SYMBOLS, key=KEY).cache_key
    others = ["0.01*(1 - r**2)", "0.01*(1 - r**3)", "0.01*(1 + r**2)", "0.01*1 - r**2",
              "0.01*(1 - s**2)", "2**3**2", "(2**3)**2", "-s**2", "(-s)**2", "pi", "e",
              "where(s < 1, 1, 0)", "where(s <= 1, 1, 0)", "minimum(s, r)", "minimum(r, s)"]
    keys = [parse(t, SYMBOLS, key=KEY).cache_key for t in others]
    assert len(set(keys)) == len(keys), keys
    assert all("0x" not in k and " at " not in k for k in keys)


def test_cache_key_is_the_same_in_another_process():
    text = "k1_ref + p*exp(-(s/0.2)**2) + where(0 < s < 1, sin(s), 2**-1)"
    code = (f"from shellbvp.expressions import parse; "
            f"print(parse({text!r}, {SYMBOLS!r}, key='k').cache_key)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == parse(text, SYMBOLS, key=KEY).cache_key


def test_expression_is_a_frozen_hashable_value():
    a = parse("s + 1", SYMBOLS, key=KEY)
    assert isinstance(a, Expression)
    assert a == parse("s + 1", SYMBOLS, key=KEY) and hash(a) == hash(parse("s + 1", SYMBOLS,
                                                                             key=KEY))
    assert len({a, parse("s + 1", SYMBOLS, key=KEY), parse("s + 2", SYMBOLS, key=KEY)}) == 2
    with pytest.raises(AttributeError):
        a.text = "s"
    assert set(expressions.__all__) <= set(dir(expressions))
