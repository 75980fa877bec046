"""The package's structure: no import cycles (imports inside functions included), no private
name imported from a sibling module, a light ``import shellbvp``, scenes that use only the
public API, and no top-level ``problems`` module on the user's path."""

import ast
import subprocess
import sys
from pathlib import Path

import shellbvp

PKG = Path(shellbvp.__file__).parent


def _modules():
    out = {}
    for f in PKG.rglob("*.py"):
        rel = f.relative_to(PKG).with_suffix("")
        parts = ["shellbvp", *rel.parts]
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = f
    import shellbvp.problems as pr

    for f in Path(pr.__path__[0]).glob("*.py"):
        name = "shellbvp.problems" if f.stem == "__init__" else f"shellbvp.problems.{f.stem}"
        out[name] = f
    return out


def _imports(name, path, modules):
    """(imported module, imported names) for every import in the file, at any depth."""
    tree = ast.parse(path.read_text())
    pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                sub = f"{mod}.{a.name}"
                yield (sub if sub in modules else mod), a.name
        elif isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, None


def test_no_import_cycles():
    modules = _modules()
    graph = {m: {i for i, _ in _imports(m, f, modules) if i in modules and i != m}
             for m, f in modules.items()}
    # a package __init__ that only re-exports is allowed to import its children, but the
    # children must not import their package's __init__ (that would be a cycle)
    state = {}

    def visit(m, stack):
        state[m] = 1
        for n in graph[m]:
            if state.get(n) == 1:
                raise AssertionError(f"import cycle: {' -> '.join(stack + [m, n])}")
            if not state.get(n):
                visit(n, stack + [m])
        state[m] = 2

    for m in graph:
        if not state.get(m):
            visit(m, [])


def test_no_private_names_from_sibling_modules():
    modules = _modules()
    bad = [(m, i, n) for m, f in modules.items() for i, n in _imports(m, f, modules)
           if i.startswith("shellbvp") and n and n.startswith("_") and n != "__future__"
           and i != m]
    bad += [(m, i, None) for m, f in modules.items() for i, _ in _imports(m, f, modules)
            if i.startswith("shellbvp") and any(p.startswith("_") and p != "__init__"
                                                  for p in i.split("."))]
    assert not bad, bad


#: the lower tiers a scene may use besides ``shellbvp`` itself (named in its docstring)
LOWER_TIERS = {"shellbvp.methods": ("bracketing_nodes", "default_nodes"),
               "shellbvp.cache": ("atomic_write_text",),
               "shellbvp.series": ("stationary_series",),
               "shellbvp.sweep": ("CHUNK_SIZE", "Chunk", "Journal", "Record", "SweepInterrupted",
                                  "one_line", "run")}


def test_scenes_use_only_the_public_api():
    modules = _modules()
    for m, f in modules.items():
        if m.startswith("shellbvp.problems"):
            for i, n in _imports(m, f, modules):
                if i.startswith("shellbvp") and not i.startswith("shellbvp.problems"):
                    if i in LOWER_TIERS:
                        assert n in LOWER_TIERS[i], (m, i, n)
                        continue
                    assert i == "shellbvp", (m, i, n)
                    assert n is None or n in shellbvp.__all__, (m, n)


def test_public_api_is_explicit():
    """Every public name is bound by an import in ``shellbvp/__init__.py`` (no module
    ``__getattr__``: what an IDE or a type checker reads is what there is), every lower tier
    the docstring names exists, and the package is typed (``py.typed``)."""
    import importlib

    tree = ast.parse((PKG / "__init__.py").read_text())
    bound = {a.asname or a.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
             for a in node.names} | {"__version__"}
    assert set(shellbvp.__all__) <= bound
    assert not any(isinstance(node, ast.FunctionDef) and node.name == "__getattr__"
                   for node in tree.body)
    for mod, names in LOWER_TIERS.items():
        assert all(hasattr(importlib.import_module(mod), n) for n in names), mod
    assert (PKG / "py.typed").is_file()
    from importlib.metadata import version

    assert shellbvp.__version__ == version("shellbvp")


def test_import_is_light_and_problems_is_not_top_level(tmp_path):
    """Run from an empty folder, as a user would (the checkout itself is not on the path):
    ``import shellbvp`` binds the whole public API and loads numpy only (JAX alone takes ~1 s
    to import; the functions that need JAX, sympy, diffrax or scipy import them)."""
    code = ("import sys, importlib.util, shellbvp; "
            "print(sorted(m for m in ('jax', 'sympy', 'diffrax', 'scipy') if m in sys.modules),"
            " importlib.util.find_spec('problems'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=tmp_path)
    assert out.stdout.strip() == "[] None", out.stdout
    assert set(shellbvp.__all__) <= set(dir(shellbvp))
