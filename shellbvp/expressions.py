"""Expressions in scene files, parsed against a whitelist and evaluated by walking their tree.

A scene file is data: a value such as ``thickness = "0.01*(1 - r**2)"`` or
``kb1 = "k1_ref + kappa*exp(-(s/0.2)**2)"`` is never run as Python. :func:`parse` uses
``ast.parse`` only to obtain a syntax tree, accepts the tree only if every node belongs to the
grammar below, and keeps it as a small tree of its own; :class:`Expression` evaluates that tree
with an array module (numpy, or ``jax.numpy`` so that the value can be traced, jitted and
differentiated by JAX). The grammar, with ``symbol`` one of the names the caller allows::

    expression := number | symbol | "pi" | "e"
                | ("+" | "-") expression
                | expression ("+" | "-" | "*" | "/" | "**") expression
                | "(" expression ")"
                | function "(" expression {"," expression} ")"
                | "where" "(" condition "," expression "," expression ")"
    function   := sin | cos | tan | exp | log | sqrt | abs | tanh | sinh | cosh
                | arcsin | arccos | arctan                 (one argument)
                | arctan2(y, x) | minimum(a, b) | maximum(a, b)
    condition  := comparison | condition ("&" | "|") condition | "(" condition ")"
    comparison := expression compare expression {compare expression}
    compare    := "<" | "<=" | ">" | ">="

Operators bind as in Python (``-x**2`` is ``-(x**2)``, ``2**-1`` is 0.5, ``**`` is
right-associative, ``&`` binds tighter than ``|`` and both tighter than a comparison, so the
comparisons they join are parenthesised: ``(s < 0.2) | (s > 0.8)``), and a chained
comparison ``0 < s < 1`` means ``(0 < s) & (s < 1)``. A number is an int or float literal;
strings, booleans, complex numbers and ``None`` are not. A function takes positional
arguments only, exactly as many as listed. Comparisons, ``&`` and ``|`` occur only in the
condition of ``where``. Nothing else is accepted: no attributes, subscripts, lambdas,
comprehensions, keyword arguments, conditional or assignment expressions, f-strings or
comments. The input is bounded: at most :data:`MAX_LENGTH` characters, and at most
:data:`MAX_DEPTH` levels both of parentheses and of the expression tree (each operator, sign,
call or comparison is a level), so that neither parsing nor evaluation can hang or exhaust
the stack.

Evaluation uses only functions of the array module on floats: every literal is a float before
any arithmetic (``9**9**9`` gives inf, not hours of integer arithmetic), and integer inputs are
converted to floats. ``jax.grad`` through ``where`` differentiates both branches, so a branch
that is not finite where it is not taken (``where(s > 0, sqrt(s), 0)`` at s < 0) gives a nan
gradient, as in JAX itself. Every refusal is a one-line :class:`ValueError` that names the
scene-file key, quotes the offending piece with its position and says what is allowed.
"""

from __future__ import annotations

import ast
import functools
import keyword
import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["parse", "Expression", "FUNCTIONS", "CONSTANTS", "MAX_LENGTH", "MAX_DEPTH"]

#: the longest expression accepted, in characters
MAX_LENGTH = 2000
#: the deepest nesting accepted, of parentheses and of the expression tree alike
MAX_DEPTH = 64
#: the named constants every expression may use, besides the caller's symbols
CONSTANTS = {"pi": math.pi, "e": math.e}
#: the functions an expression may call, with the number of arguments each takes
FUNCTIONS = {**dict.fromkeys(("sin", "cos", "tan", "exp", "log", "sqrt", "abs", "tanh",
                              "sinh", "cosh", "arcsin", "arccos", "arctan"), 1),
             "arctan2": 2, "minimum": 2, "maximum": 2, "where": 3}

_UNARY = {ast.UAdd: None, ast.USub: "negative"}
_BINARY = {ast.Add: "add", ast.Sub: "subtract", ast.Mult: "multiply", ast.Div: "divide",
           ast.Pow: "power"}
_COMPARE = {ast.Lt: "less", ast.LtE: "less_equal", ast.Gt: "greater",
            ast.GtE: "greater_equal"}
_LOGICAL = {ast.BitAnd: "logical_and", ast.BitOr: "logical_or"}
#: every operation of the internal tree: the array-module function that evaluates it
_OPERATIONS = frozenset({"negative", *_BINARY.values(), *_COMPARE.values(),
                         *_LOGICAL.values(), *FUNCTIONS})
_SYMBOLS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**",
            ast.FloorDiv: "//", ast.Mod: "%", ast.MatMult: "@", ast.LShift: "<<",
            ast.RShift: ">>", ast.BitAnd: "&", ast.BitOr: "|", ast.BitXor: "^",
            ast.Invert: "~", ast.Not: "not", ast.And: "and", ast.Or: "or", ast.Eq: "==",
            ast.NotEq: "!=", ast.Is: "is", ast.IsNot: "is not", ast.In: "in",
            ast.NotIn: "not in", ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">="}
_KINDS = {ast.Attribute: "attribute access", ast.Subscript: "subscript",
          ast.Lambda: "lambda", ast.ListComp: "comprehension", ast.SetComp: "comprehension",
          ast.DictComp: "comprehension", ast.GeneratorExp: "comprehension",
          ast.NamedExpr: "assignment expression", ast.JoinedStr: "f-string",
          ast.FormattedValue: "f-string", ast.IfExp: "conditional expression",
          ast.List: "list", ast.Tuple: "tuple", ast.Set: "set", ast.Dict: "dict",
          ast.Starred: "starred argument", ast.Await: "await", ast.Yield: "yield",
          ast.YieldFrom: "yield", ast.Slice: "slice"}
_EXCERPT = 40


@dataclass(frozen=True)
class Expression:
    """A validated expression: its text, where it came from, and a tree to evaluate.

    Made by :func:`parse`. Equal expressions (same text, key and tree) hash alike; two texts
    that differ only in layout, in redundant parentheses or in how a number is written
    (``1`` and ``1.0``) share one :attr:`cache_key`, the string to key compiled programs by.

    Attributes:
        text: the expression as given (a number given as such is kept as its ``repr``).
        key: the scene-file key it was read from, e.g. ``"stimulus.kb1"``, for messages.
        symbols_used: the free symbols the expression uses, sorted.
        cache_key: a canonical form of the tree, e.g. ``multiply(0.01, r)``: the same in
            every process and every Python version, free of memory addresses.
    """

    text: str
    key: str
    symbols_used: tuple[str, ...]
    cache_key: str
    _tree: tuple = field(repr=False)

    @property
    def is_constant(self) -> bool:
        """True when the expression uses none of its symbols."""
        return not self.symbols_used

    def __call__(self, /, xp=np, **values):
        """The value of the expression for the given symbol values.

        Arguments:
            xp: the array module, ``numpy`` (default) or ``jax.numpy`` (then the value is
                traceable: ``jax.jit`` and ``jax.grad`` pass through it).
            values: a value (number or array) for each used symbol; values of other names
                are allowed and only take part in broadcasting.

        Returns:
            A float array of the broadcast shape of the result and every value given (a
            constant expression called with an array of shape (n,) gives shape (n,); called
            with no arrays, shape ()).

        Raises:
            ValueError: a used symbol has no value (the message names them).
        """
        missing = [name for name in self.symbols_used if name not in values]
        if missing:
            raise ValueError(f"{self.key}: no value for {', '.join(missing)} (the expression "
                             f"{_excerpt(self.text)!r} uses {', '.join(self.symbols_used)})")
        env = {name: _as_float(xp, value) for name, value in values.items()}
        result = xp.asarray(_evaluate(self._tree, xp, env))
        shape = np.broadcast_shapes(result.shape, *(np.shape(v) for v in env.values()))
        if result.shape != shape:
            result = xp.broadcast_to(result, shape)
            if isinstance(result, np.ndarray):
                result = result.copy()  # numpy's broadcast is a read-only view
        return result


def parse(text: str | float, symbols: Iterable[str], *, key: str) -> Expression:
    """Parse a scene-file value against the grammar of this module (never running it).

    Arguments:
        text: the expression, a string (e.g. ``"0.01*(1 - r**2)"``), or a number as a scene
            file gives it (an int or a float, not a boolean).
        symbols: the names the expression may use, e.g. ``("p", "s", "r", "z")``; besides
            them, the constants ``pi`` and ``e``.
        key: the scene-file key the value was read from, e.g. ``"stimulus.kb1"``; every
            message starts with it.

    Returns:
        :class:`Expression`.

    Raises:
        ValueError: ``text`` is not in the grammar, too long or too deeply nested (one line
            naming ``key``, quoting the piece and its column, saying what is allowed); or
            ``symbols`` is not a collection of identifiers distinct from the function and
            constant names and from ``xp``.
    """
    symbols = _check_symbols(symbols, key)
    if isinstance(text, numbers.Real) and not isinstance(text, (bool, np.bool_)):
        value = _finite(text)
        if value is None:
            raise ValueError(f"{key}: number {_excerpt(repr(text))} is not a finite float")
        text = repr(int(text)) if isinstance(text, numbers.Integral) else repr(value)
        return Expression(text, key, (), repr(value), ("num", value))
    if not isinstance(text, str):
        raise ValueError(f"{key}: expected a number or an expression string, got "
                         f"{type(text).__name__} {_excerpt(repr(text))} ({_hint(symbols)})")
    return _Parser(text, symbols, key).expression()


def _check_symbols(symbols, key):
    if isinstance(symbols, str):
        raise ValueError(f"{key}: symbols must be a collection of names, not the string "
                         f"{symbols!r}")
    symbols = tuple(symbols)
    for name in symbols:
        if not (isinstance(name, str) and name.isidentifier() and not keyword.iskeyword(name)):
            raise ValueError(f"{key}: symbol {name!r} is not a Python identifier")
        if name in FUNCTIONS or name in CONSTANTS or name == "xp":
            raise ValueError(f"{key}: symbol {name!r} clashes with a function, a constant "
                             "or the array-module argument xp")
    return symbols


def _finite(value) -> float | None:
    """``value`` as a float, or None if it is not finite or beyond the range of floats."""
    try:
        value = float(value)
    except OverflowError:
        return None
    return value if math.isfinite(value) else None


def _excerpt(piece: str) -> str:
    """``piece`` on one line and at most a few dozen characters, for a message."""
    piece = " ".join(piece.split())
    return piece if len(piece) <= _EXCERPT else piece[:_EXCERPT - 3] + "..."


def _hint(symbols) -> str:
    names = ", ".join((*symbols, *CONSTANTS))
    return (f"allowed: numbers, the names {names}, unary + -, binary + - * / **, parentheses, "
            f"the functions {', '.join(FUNCTIONS)}")


def _too_deep(tree):
    """The first expression node of ``tree`` deeper than MAX_DEPTH (found without recursion),
    or None. A chain of n comparisons is n levels: it becomes n - 1 nested ``&``."""
    stack = [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        depth += isinstance(node, ast.expr) + len(getattr(node, "ops", ())[1:])
        if depth > MAX_DEPTH:
            return node
        stack.extend((child, depth) for child in ast.iter_child_nodes(node))
    return None


class _Parser:
    """One parse: the text, its symbols and key, and the conversion of the validated tree."""

    def __init__(self, text, symbols, key):
        self.text, self.symbols, self.key = text, symbols, key
        self.body = text.lstrip()
        self.lines = self.body.split("\n")
        self.used = set()

    def expression(self) -> Expression:
        text = self.text
        if len(text) > MAX_LENGTH:
            self.fail(f"expression {_excerpt(text)!r} of {len(text)} characters (at most "
                      f"{MAX_LENGTH} are allowed)")
        if not self.body:
            self.fail(f"empty expression {text!r} ({_hint(self.symbols)})")
        self.check_characters()
        try:
            tree = ast.parse(self.body, mode="eval")
        except SyntaxError as e:
            self.syntax_error(e)
        except (MemoryError, RecursionError):
            self.fail(f"expression {_excerpt(text)!r} too complex to parse "
                      f"({_hint(self.symbols)})")
        deep = _too_deep(tree)
        if deep is not None:
            self.refuse(deep, f"expression nested deeper than {MAX_DEPTH} levels from",
                        f"at most {MAX_DEPTH} levels of operations; group a long chain of "
                        "operations with parentheses")
        node = self.value(tree.body)
        used = tuple(sorted(self.used))
        return Expression(text, self.key, used, _canonical(node), node)

    def check_characters(self):
        """Refuse, before parsing, parentheses nested deeper than MAX_DEPTH, comments and
        control characters (a NUL byte is not even a syntax error to ``ast.parse``)."""
        depth = 0
        for i, char in enumerate(self.text):
            if not (char.isprintable() or char in "\t\n\r"):
                self.fail(f"control character {char!r}{self.position_of(i)} "
                          f"({_hint(self.symbols)})")
            depth += (char in "([{") - (char in ")]}")
            if depth > MAX_DEPTH:
                self.fail(f"parenthesis {char!r}{self.position_of(i)} nested deeper than "
                          f"{MAX_DEPTH} levels (at most {MAX_DEPTH} are allowed)")
            if char == "#":
                self.fail(f"comment {_excerpt(self.text[i:])!r}{self.position_of(i)} "
                          f"({_hint(self.symbols)})")

    def fail(self, message):
        raise ValueError(f"{self.key}: {message}") from None

    def position_of(self, index):
        """' at column C' (1-based; ' at line L, column C' in a text of several lines)."""
        line = self.text.count("\n", 0, index)
        col = index - (self.text.rfind("\n", 0, index) + 1) + 1
        return f" at line {line + 1}, column {col}" if "\n" in self.text else f" at column {col}"

    def position(self, lineno, col):
        """The position of 0-based character column ``col`` of line ``lineno`` of the body."""
        index = sum(len(line) + 1 for line in self.lines[:lineno - 1]) + col
        return self.position_of(len(self.text) - len(self.body) + index)

    def at(self, node):
        """The piece of text of ``node``, quoted, and its position."""
        line = self.lines[node.lineno - 1]
        col = len(line.encode()[:node.col_offset].decode(errors="ignore"))
        piece = ast.get_source_segment(self.body, node) or ""
        return f"{_excerpt(piece)!r}{self.position(node.lineno, col)}"

    def syntax_error(self, e):
        lineno, offset = e.lineno or 0, e.offset or 0
        line = self.lines[lineno - 1] if 1 <= lineno <= len(self.lines) else ""
        if 1 <= offset <= len(line):
            end = e.end_offset if (e.end_lineno == lineno and (e.end_offset or 0) > offset) \
                else offset + 1
            where = f" at {_excerpt(line[offset - 1:end - 1])!r}{self.position(lineno, offset - 1)}"
        else:
            where = " at the end"
        self.fail(f"syntax error{where}: {e.msg} ({_hint(self.symbols)})")

    def refuse(self, node, what=None, allowed=None):
        what = what or _KINDS.get(type(node), type(node).__name__)
        self.fail(f"{what} {self.at(node)} ({allowed or _hint(self.symbols)})")

    def value(self, node):
        """The internal tree of an arithmetic expression (no comparison)."""
        if isinstance(node, ast.Constant):
            kind = type(node.value)
            if kind not in (int, float):
                kinds = {str: "string", bytes: "bytes", bool: "boolean", complex: "complex number",
                         type(None): "None", type(...): "Ellipsis"}
                self.refuse(node, kinds.get(kind, kind.__name__))
            value = _finite(node.value)
            if value is None:
                self.refuse(node, "number", "numbers are finite floats")
            return ("num", value)
        if isinstance(node, ast.Name):
            return self.name(node)
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            operand = self.value(node.operand)
            op = _UNARY[type(node.op)]
            return operand if op is None else (op, operand)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return (_BINARY[type(node.op)], self.value(node.left), self.value(node.right))
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, (ast.Compare, ast.BoolOp)) or (
                isinstance(node, ast.BinOp) and type(node.op) in _LOGICAL):
            self.refuse(node, "comparison" if isinstance(node, ast.Compare) else
                        f"operator {_SYMBOLS[type(node.op)]!r} in",
                        "comparisons < <= > >=, joined by & and |, are allowed only as the "
                        "condition of where(condition, a, b)")
        if isinstance(node, (ast.BinOp, ast.UnaryOp)):
            self.refuse(node, f"operator {_SYMBOLS.get(type(node.op), '?')!r} in",
                        "allowed operators: unary + -, binary + - * / **")
        self.refuse(node)

    def name(self, node):
        if node.id in self.symbols:
            self.used.add(node.id)
            return ("sym", node.id)
        if node.id in CONSTANTS:
            return ("const", node.id)
        if node.id in FUNCTIONS:
            self.refuse(node, "function", f"a function is called: {node.id}(...)")
        names = ", ".join((*self.symbols, *CONSTANTS))
        self.refuse(node, "unknown name",
                    f"allowed names: {names}; functions: {', '.join(FUNCTIONS)}")

    def call(self, node):
        func = node.func
        if not isinstance(func, ast.Name):
            self.refuse(func, None if type(func) in _KINDS else "call of",
                        f"only the functions {', '.join(FUNCTIONS)} may be called")
        if func.id not in FUNCTIONS:
            self.refuse(func, "symbol called as a function" if func.id in self.symbols
                        else "unknown function", f"functions: {', '.join(FUNCTIONS)}")
        if node.keywords:
            self.refuse(node.keywords[0], "keyword argument",
                        f"{func.id} takes positional arguments only")
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                self.refuse(arg, None, f"{func.id} takes positional arguments only")
        arity = FUNCTIONS[func.id]
        if len(node.args) != arity:
            self.refuse(node, f"{func.id} given {len(node.args)} argument"
                        f"{'s' * (len(node.args) != 1)} in",
                        f"{func.id} takes {arity} argument{'s' * (arity != 1)}")
        if func.id == "where":
            condition, *branches = node.args
            return ("where", self.condition(condition), *map(self.value, branches))
        return (func.id, *map(self.value, node.args))

    def condition(self, node):
        """The internal tree of the condition of ``where``."""
        if isinstance(node, ast.Compare):
            if not all(type(op) in _COMPARE for op in node.ops):
                bad = next(op for op in node.ops if type(op) not in _COMPARE)
                self.refuse(node, f"comparison {_SYMBOLS.get(type(bad), '?')!r} in",
                            "comparisons: < <= > >=")
            operands = [self.value(node.left), *map(self.value, node.comparators)]
            pairs = [(_COMPARE[type(op)], a, b)
                     for op, a, b in zip(node.ops, operands, operands[1:])]
            return functools.reduce(lambda a, b: ("logical_and", a, b), pairs)
        if isinstance(node, ast.BinOp) and type(node.op) in _LOGICAL:
            return (_LOGICAL[type(node.op)], self.condition(node.left),
                    self.condition(node.right))
        self.refuse(node, "condition", "the condition of where is a comparison (< <= > >=, "
                    "possibly chained) or parenthesised comparisons joined by & and |")


def _canonical(node) -> str:
    """The canonical text of an internal tree: ``op(arg, ...)``, numbers by their repr."""
    op, *args = node
    if op == "num":
        return repr(args[0])
    if op in ("sym", "const"):
        return args[0]
    return f"{op}({', '.join(map(_canonical, args))})"


def _as_float(xp, value):
    """``value`` as an array of xp, floats kept and anything else converted to float."""
    value = xp.asarray(value)
    return value if np.issubdtype(value.dtype, np.inexact) else value.astype(float)


def _evaluate(node, xp, env):
    """The value of an internal tree: numbers as floats, every operation a function of xp."""
    op, *args = node
    if op == "num":
        return args[0]
    if op == "sym":
        return env[args[0]]
    if op == "const":
        return CONSTANTS[args[0]]
    if op not in _OPERATIONS:
        raise ValueError(f"not an operation of an expression: {op!r}")
    return getattr(xp, op)(*(_evaluate(arg, xp, env) for arg in args))
