"""Helpers shared by the figure scripts: argument parsing, atomic CSV/PNG output, and wall
clocks around a function (benchmarks)."""

from __future__ import annotations

import argparse
import csv
import io
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def clock(owner, name: str, spent: dict, key: str):
    """Replace ``owner.name`` by a wrapper that adds the wall time of every call to
    ``spent[key]`` (nested clocks each count their own); returns the original, to restore."""
    f = getattr(owner, name)

    def wrapper(*args, **kwargs):
        t = time.perf_counter()
        try:
            return f(*args, **kwargs)
        finally:
            spent[key] = spent.get(key, 0.0) + time.perf_counter() - t
    setattr(owner, name, wrapper)
    return f


def wall_times(f, repeat: int, warmup: int = 0) -> list[float]:
    """Wall times (s) of ``repeat`` calls of ``f()``, after ``warmup`` untimed calls."""
    for _ in range(warmup):
        f()
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return out


def parser(description: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--quick", action="store_true", help="coarse run (a few points) for a smoke test")
    p.add_argument("--out", type=Path, default=HERE, help="output folder (default: figures/)")
    return p


def write_csv(path: Path, header: list[str], rows) -> None:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    from shellbvp.cache import atomic_write_text

    atomic_write_text(path, buf.getvalue())


def save_png(fig, path: Path) -> None:
    """Render ``fig`` and write it atomically with the user's normal permissions."""
    from shellbvp.cache import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=150, bbox_inches="tight")
    atomic_write_bytes(path, buf.getvalue())


def pyplot():
    """matplotlib.pyplot on the non-interactive Agg back-end (scripts write files only)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def finish(fig, out: Path, stem: str) -> None:
    """Lay out, write ``out/stem.png`` atomically and say which files were written."""
    fig.tight_layout()
    save_png(fig, out / f"{stem}.png")
    print(f"wrote {out / (stem + '.png')} and .csv")


def print_summary(result: dict, drop=("curves",)) -> None:
    """A gallery case's last line: its summary (everything but the keys ``drop``, its curves)
    as one JSON object, the line ``figures/gallery.py`` collects."""
    import json

    print(json.dumps({k: v for k, v in result.items() if k not in drop}))


def scene_copy(path: Path, folder: Path, replacements) -> Path:
    """A copy of the scene file ``path`` in ``folder`` with each (old, new) of
    ``replacements`` made, every ``old`` found exactly once (else RuntimeError): one file,
    several shells (a thickness, a length, a range)."""
    text = path.read_text()
    for old, new in replacements:
        if text.count(old) != 1:
            raise RuntimeError(f"{path.name}: expected one '{old}'")
        text = text.replace(old, new)
    copy = Path(folder) / path.name
    copy.write_text(text)
    return copy


def scene_with_thickness(path: Path, t_file: float, t: float):
    """The scene file ``path`` (its line ``thickness = t_file``) loaded with the thickness t
    instead, from a temporary copy: one file, several thicknesses."""
    import tempfile

    import shellbvp

    key = f"thickness = {t_file}"
    if path.read_text().count(key) != 1:
        raise RuntimeError(f"{path.name}: expected one line '{key}'")
    if t == t_file:
        return shellbvp.load_scene(path)
    with tempfile.TemporaryDirectory() as d:
        return shellbvp.load_scene(scene_copy(path, Path(d), [(key, f"thickness = {t!r}")]))


def read_series(path: Path, x: str, y: str) -> dict:
    """{series: (x values, y values)} of a published-data CSV with a ``series`` column and
    the columns ``x`` and ``y`` (the gallery's digitised curves)."""
    import csv

    import numpy as np

    out = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            xs, ys = out.setdefault(r["series"], ([], []))
            xs.append(float(r[x]))
            ys.append(float(r[y]))
    return {k: (np.array(a), np.array(b)) for k, (a, b) in out.items()}


def states_and_branch(states, field: str, curve, *, xlabel: str, ylabel: str, label: str,
                      units=None, folds=()):
    """A figure of equilibria in 3D (``Equilibrium.plot3d``), one colour scale symmetric
    about zero (the coolwarm map, its bar on the left, ``label``), and beside them a
    branch's diagram ``curve`` = (x, y) with its ``folds`` (x, y) and the states marked and
    numbered. ``states``: (equilibrium, x, y, title) each."""
    import numpy as np
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    from shellbvp.surface import equilibrium_surface

    plt = pyplot()
    top = max(np.abs(equilibrium_surface(eq, omega=4, units=units).scalar(field)).max()
              for eq, *_ in states)
    n = len(states)
    fig = plt.figure(figsize=(2.6 * n + 2.6, 3.4))
    grid = fig.add_gridspec(1, n + 1, width_ratios=(1,) * n + (1.1,), wspace=0.05,
                            left=0.08, right=0.94)
    for k, (eq, _, _, title) in enumerate(states):
        ax = fig.add_subplot(grid[k], projection="3d")
        eq.plot3d(field, ax, vmin=-top, vmax=top, cmap="coolwarm", colorbar=False,
                  units=units, title=f"{k + 1}: {title}")
    fig.colorbar(ScalarMappable(Normalize(-top, top), "coolwarm"), ax=fig.axes,
                 shrink=0.6, pad=0.01, location="left").set_label(label, fontsize=8)
    ax = fig.add_subplot(grid[n])
    ax.plot(*curve, "-", lw=1.0)
    for fx, fy in folds:
        ax.plot(fx, fy, ".", color="C0", ms=4)
    for k, (_, x, y, _) in enumerate(states):
        ax.plot(x, y, "o", color="C3", ms=6)
        ax.annotate(str(k + 1), (x, y), xytext=(4, -10), textcoords="offset points",
                    fontsize=8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.yaxis.set_label_position("right")
    ax.yaxis.tick_right()
    ax.set_title(f"the branch: 1-{n} drawn", fontsize=9)
    return fig
