"""Benchmark: the start-up of ``shellbvp snap`` beside an earlier revision, in one run.

The whole command ``shellbvp snap --model M`` in fresh processes, for this checkout and for
an earlier revision (``--against``, default 6c31928: the last revision before the reference
shell became data, against which issue 55 measured start-up's regression), alternated
round by round so that the machine's slow spells fall on both:

* cold: an empty cache folder (``SHELLBVP_CACHE_DIR``): tracing and XLA compilation, or
  what of them the revision ships;
* warm: the folder filled by an earlier process of the same revision (what a later command
  finds).

Each revision runs as a wheel installs it: its ``shellbvp/`` folder with ``problems/`` inside
as ``shellbvp/problems``, copied to a temporary folder (this checkout's working tree; the
other revision by ``git archive``), on Python's normal path (``PYTHONPATH``), with bytecode
written (an untimed first process fills it). Pinned to one core (``_pinned``), single
threaded. Prints the medians and their ratios (this checkout over the other) and writes
``bench_startup.csv``.

    python figures/bench_startup.py [--against REV] [--runs 5] [--models relaxed plane_strain]
"""

from __future__ import annotations

import _pinned  # noqa: F401  (first: thread settings and the core)

import os  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from _common import HERE, parser, write_csv  # noqa: E402

ROOT = HERE.parent
AGAINST = "6c31928"


def install(source: Path | None, rev: str | None, folder: Path) -> Path:
    """``folder/shellbvp`` with ``problems`` inside, from this working tree (``source``) or
    from revision ``rev`` of the repository; returns ``folder``."""
    folder.mkdir(parents=True)
    if source is not None:
        shutil.copytree(source / "shellbvp", folder / "shellbvp",
                        ignore=shutil.ignore_patterns("__pycache__"))
        shutil.copytree(source / "problems", folder / "shellbvp" / "problems",
                        ignore=shutil.ignore_patterns("__pycache__"))
    else:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "shellbvp",
                                  "problems"], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
        shutil.move(str(folder / "problems"), str(folder / "shellbvp" / "problems"))
    return folder


def snap(tree: Path, cache: Path, model: str) -> tuple[float, str]:
    """Wall time (s) of ``shellbvp snap --model model`` run from ``tree`` with the cache
    folder ``cache``, and its kappa_s line."""
    env = dict(os.environ, PYTHONPATH=str(tree), SHELLBVP_CACHE_DIR=str(cache))
    for name in ("PYTHONDONTWRITEBYTECODE", "JAX_COMPILATION_CACHE_DIR", "SHELLBVP_JAX_CACHE",
                 "SHELLBVP_SHIPPED"):
        env.pop(name, None)
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "shellbvp.cli", "snap", "--model", model],
                         cwd=tree, env=env, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t
    return wall, next((x for x in out.stdout.splitlines() if x.startswith("kappa_s")), "")


def main():
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--against", default=AGAINST, help="the earlier revision (default %(default)s)")
    p.add_argument("--runs", type=int, default=5, help="processes of each kind (default 5)")
    p.add_argument("--models", nargs="+", default=["relaxed", "plane_strain"])
    a = p.parse_args()
    runs = 2 if a.quick else a.runs
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        trees = {"this checkout": install(ROOT, None, tmp / "this"),
                 a.against: install(None, a.against, tmp / "other")}
        rows, lines = [], {}
        for model in a.models:
            times = {(name, cache): [] for name in trees for cache in ("cold", "warm")}
            for name, tree in trees.items():     # bytecode, and the warm folder filled
                snap(tree, tmp / f"warm-{model}-{tree.name}", model)
            for r in range(runs):
                for name, tree in trees.items():
                    cold = tmp / f"cold-{model}-{r}-{tree.name}"
                    wall, lines[name, model] = snap(tree, cold, model)
                    times[name, "cold"].append(wall)
                    shutil.rmtree(cold, ignore_errors=True)
                    times[name, "warm"].append(snap(tree, tmp / f"warm-{model}-{tree.name}",
                                                    model)[0])
            for cache in ("cold", "warm"):
                med = {name: float(np.median(times[name, cache])) for name in trees}
                ratio = med["this checkout"] / med[a.against]
                for name in trees:
                    w = times[name, cache]
                    rows.append([model, cache, name, f"{med[name]:.3f}", f"{min(w):.3f}",
                                 f"{max(w):.3f}", len(w),
                                 f"{ratio:.3f}" if name == "this checkout" else ""])
                    print(f"{model:>12s} {cache}: {name:>14s} median {med[name]:6.2f} s "
                          f"({min(w):.2f}-{max(w):.2f}, {len(w)} processes)")
                print(f"{model:>12s} {cache}: ratio this checkout / {a.against} = {ratio:.3f}")
            for name in trees:
                print(f"{model:>12s} {name:>14s}: {lines[name, model]}")
    write_csv(a.out / "bench_startup.csv",
              ["model", "cache", "revision", "median_s", "min_s", "max_s", "processes",
               "ratio_to_earlier"], rows)
    print(f"wrote {a.out / 'bench_startup.csv'}")


if __name__ == "__main__":
    main()
