"""Wall time of the first instability of five scene files (one core, pinned): the branch
from ``from`` and the harmonics along it, the bifurcation located (``SceneFile.
first_instability``, what ``shellbvp stability FILE`` runs).

* Zoelly's sphere under external pressure (``problems/gallery/zoelly-sphere.toml``,
  R/t = 100) and the same file at R/t = 1000 (a copy: t = 1 mm, ``to`` scaled with p_cl);
* the clamped cylinder in axial compression (``problems/gallery/cylinder-axial.toml``);
* the long cylinder under lateral pressure (``problems/gallery/long-cylinder-pressure.toml``,
  R/t = 100, L/R = 100);
* the short cylinder between mirror planes in axial compression
  (``problems/gallery/cylinder-classical.toml``: n = 0 and n = 1, 2 in one bracket).

Per scene: the first call in this process (it traces the kernels; compiled code may come
from the disk cache), the median of ``repeat`` further calls (steady state), and one run of
the command line ``shellbvp stability -q FILE --json`` in a process of its own (start-up,
imports and the disk cache included). Writes bench_instability.csv.

    python figures/bench_instability.py [--quick]
"""

from __future__ import annotations

import _pinned  # noqa: F401  (first: thread pools and the core, before numpy and JAX)

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import HERE, parser, scene_copy, wall_times, write_csv

GALLERY = HERE.parent / "problems" / "gallery"


def zoelly_copy(folder: Path, t: float, to: float) -> Path:
    """The Zoelly scene file with thickness t (mm) and range end ``to`` (MPa)."""
    return scene_copy(GALLERY / "zoelly-sphere.toml", folder,
                      [("thickness = 10.0", f"thickness = {t!r}"),
                       ("to = 40.0 ", f"to = {to!r} ")])


def cli_seconds(path: Path) -> float:
    t = time.perf_counter()
    subprocess.run(["shellbvp", "stability", "-q", str(path), "--json"], check=True,
                   capture_output=True)
    return time.perf_counter() - t


def main(argv=None):
    import shellbvp

    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    repeat = 1 if a.quick else 2
    rows = []
    with tempfile.TemporaryDirectory() as d:
        cases = [("zoelly sphere R/t = 100", GALLERY / "zoelly-sphere.toml"),
                 ("zoelly sphere R/t = 1000", zoelly_copy(Path(d), 1.0, 0.4)),
                 ("cylinder axial R/t = 1000, Z = 500", GALLERY / "cylinder-axial.toml"),
                 ("long cylinder pressure R/t = 100, L/R = 100",
                  GALLERY / "long-cylinder-pressure.toml"),
                 ("cylinder between mirror planes R/t = 100",
                  GALLERY / "cylinder-classical.toml")]
        for name, path in cases:
            sf = shellbvp.load_scene(path)
            found = []
            first = wall_times(lambda: found.append(sf.first_instability()), 1)[0]
            times = wall_times(lambda: found.append(sf.first_instability()), repeat)
            cli = cli_seconds(path)
            ins = found[-1]
            rows.append([name, ins.kind, ins.n, ins.p, ins.error_estimate, first,
                         statistics.median(times), min(times), max(times), repeat, cli,
                         _pinned.PINNED])
            print(f"{name}: {ins.kind} n = {ins.n} at {ins.p:.8g}; first call {first:.1f} s, "
                  f"median {statistics.median(times):.1f} s ({repeat} runs), command line "
                  f"{cli:.1f} s", flush=True)
    write_csv(a.out / "bench_instability.csv",
              ["scene", "kind", "n", "p", "error_estimate", "first_call_s", "median_s",
               "min_s", "max_s", "runs", "cli_s", "pinned"], rows)


if __name__ == "__main__":
    sys.exit(main())
