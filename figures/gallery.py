"""The benchmark gallery: every published case beside its data, in one table.

Runs every ``figures/gallery_*.py`` (each a published shell benchmark: its scene file in
``problems/gallery/``, its published data in ``figures/gallery/``, its own CSV and PNG of our
curve over the published one) as a process of its own, two at a time, and collects the one
JSON line each prints last: case, source, quantity, published value, shellbvp's, their
relative difference, the tolerance the case states (with its reason, in the case's
docstring), whether the difference is within it, and the case's wall time. A case we do not
match is a row with ``ok`` false, never dropped. Writes gallery.csv and
gallery_summary.csv (the docs' table).

    python figures/gallery.py [--quick] [--jobs 2]
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from _common import HERE, parser, write_csv

COLUMNS = ("case", "source", "quantity", "published", "shellbvp", "difference",
           "tolerance", "ok", "seconds", "script")


def cases() -> list:
    """The case scripts, longest first by the last run's times (gallery.csv; a new case
    first of all), so that two at a time finish together."""
    last = {}
    if (HERE / "gallery.csv").exists():
        with open(HERE / "gallery.csv", newline="") as f:
            for row in csv.DictReader(f):
                try:
                    last[row.get("script", "")] = float(row["seconds"])
                except (KeyError, ValueError):
                    pass
    return sorted(HERE.glob("gallery_*.py"), key=lambda p: (-last.get(p.stem, math.inf),
                                                            p.name))


def run_case(path, quick: bool) -> dict:
    """Run one case script in a process of its own; its summary (the last JSON line it
    prints), or a row that says how it failed."""
    t0 = time.perf_counter()
    argv = [sys.executable, str(path)] + (["--quick"] if quick else [])
    done = subprocess.run(argv, capture_output=True, text=True, cwd=HERE)
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("{")]
    if done.returncode != 0 or not lines:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return {"case": path.stem, "source": "", "quantity": "", "published": "",
                "shellbvp": "", "difference": "", "tolerance": "", "ok": False,
                "seconds": time.perf_counter() - t0, "error": last}
    return json.loads(lines[-1])


def summary(r: dict) -> list:
    """The docs' row of a case: numbers to four digits, differences in percent."""
    def num(x, fmt):
        return format(x, fmt) if isinstance(x, (int, float)) and not isinstance(x, bool) \
            else str(x)

    def percent(d):
        # a difference far below 0.1 % (a closed form met to the theory's O((t/a)^2)) in
        # two significant digits, not as -0.0 %
        if not isinstance(d, float):
            return ""
        return format(100 * d, "+.2g" if 0 < abs(d) < 5e-4 else "+.1f") + " %"
    return [r["case"], r.get("quantity", ""), num(r.get("published"), ".4g"),
            num(r.get("shellbvp"), ".4g"), percent(r.get("difference")),
            num(100 * r["tolerance"], ".2g") + " %" if isinstance(r.get("tolerance"), float)
            else "", "yes" if r.get("ok") else "no", num(r.get("seconds"), ".0f") + " s"]


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    a = p.parse_args(argv)
    t0 = time.perf_counter()
    order = cases()
    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        rows = list(pool.map(lambda path: run_case(path, a.quick), order))
    for r, path in zip(rows, order):
        r["script"] = path.stem
    rows.sort(key=lambda r: r["case"])
    for r in rows:
        state = "ok" if r.get("ok") else "MISS" if "error" not in r else "FAILED"
        print(f"{state:6s} {r['case']}: {r.get('quantity', '')}: published "
              f"{r.get('published', '')}, shellbvp {r.get('shellbvp', '')} "
              f"({r.get('seconds', 0.0):.1f} s){'; ' + r['error'] if 'error' in r else ''}")
    write_csv(a.out / "gallery.csv", list(COLUMNS), [[r.get(c, "") for c in COLUMNS]
                                                      for r in rows])
    write_csv(a.out / "gallery_summary.csv",
              ["case", "quantity", "published", "shellbvp", "difference", "tolerance", "ok",
               "time"], [summary(r) for r in rows])
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
