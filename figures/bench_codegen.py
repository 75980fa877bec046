"""Benchmark: XLA:CPU's two code generators on the package's programs (compile and run time).

Every program shellbvp compiles gets ``shellbvp.jaxsetup.COMPILER_OPTIONS`` (XLA:CPU's older
code generator, fusion emitters off) where the installed jaxlib knows them. This script
measures that choice against XLA's default on the default cap (Theta = pi/6, h0/R0 = 0.01,
lam = 1, tol 1e-8), relaxed and plane strain: each variant in a fresh process with no disk
cache (nothing traced or compiled before), alternating the variants over the rounds, on one
pinned core. Per process: the XLA compilation of the programs one kappa_s needs (the
collocation program; compile calls only, tracing and lowering excluded), a call of the
compiled program in steady state (with the packing of its arguments and outputs; median of
300 calls on the same arguments) and one kappa_s in steady state (median of 15), with its
value (the variants must agree to round-off). Writes bench_codegen.csv.

    python figures/bench_codegen.py [--quick] [--rounds 3]
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import numpy as np

from _common import HERE, parser, write_csv

#: the child process: one variant ("package" or "default"), one model; prints one JSON line
CHILD = r"""
import json, math, sys
import jax
import numpy as np
import shellbvp.packed as P
from shellbvp.problems import cap_eversion as ce

sys.path.insert(0, sys.argv[3])
from _common import clock, wall_times

variant, model = sys.argv[1], sys.argv[2]
if variant == "default":
    P.supported_options = lambda: {}
spent, calls = {"compile": 0.0}, []
# every XLA compilation (tracing and lowering excluded)
lowered_compile = clock(jax.stages.Lowered, "compile", spent, "compile")
call = P.Packed.__call__


def recording(self, *args):
    calls.append((self, args))
    return call(self, *args)


P.Packed.__call__ = recording
args = (math.pi / 6, 0.01, 1.0)
r = ce.snap_curvature(*args, model=model, tol=1e-8)
P.Packed.__call__ = call
jax.stages.Lowered.compile = lowered_compile
owner, a = calls[len(calls) // 2]
runs = wall_times(lambda: owner(*a), 300, warmup=30)
snaps = wall_times(lambda: ce.snap_curvature(*args, model=model, tol=1e-8), 15)
print(json.dumps(dict(compile_s=spent["compile"], kernel_us=1e6 * float(np.median(runs)),
                      kappa_s_ms=1e3 * float(np.median(snaps)), kappa_s=r.kappa_s)))
"""


def child(variant, model):
    env = dict(os.environ, SHELLBVP_CACHE_DIR="off", SHELLBVP_JAX_CACHE="off")
    out = subprocess.run([sys.executable, "-c", CHILD, variant, model, str(HERE)], env=env,
                         check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=3, help="processes per variant and model")
    a = p.parse_args(argv)
    try:
        os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
        pinned = True
    except (AttributeError, OSError):
        pinned = False
    rounds = 1 if a.quick else a.rounds
    print(f"one core pinned: {pinned}; {rounds} fresh processes per variant and model")
    rows = []
    for model in ("relaxed", "plane_strain"):
        got = {"package": [], "default": []}
        for _ in range(rounds):
            for variant in got:
                t = time.perf_counter()
                got[variant].append(child(variant, model))
                got[variant][-1]["process_s"] = time.perf_counter() - t
        for variant, runs in got.items():
            med = {k: float(np.median([r[k] for r in runs]))
                   for k in ("compile_s", "kernel_us", "kappa_s_ms", "process_s")}
            values = [r["kappa_s"] for r in runs]
            rows.append([model, variant, med["compile_s"], med["kernel_us"], med["kappa_s_ms"],
                         med["process_s"], values[0], rounds])
            print(f"{model:>12s} {variant:>7s}: compile {med['compile_s']:.2f} s, program "
                  f"{med['kernel_us']:.0f} us, kappa_s {med['kappa_s_ms']:.2f} ms, whole "
                  f"process {med['process_s']:.1f} s, kappa_s R0 = {values[0]!r}")
        ours, theirs = rows[-2], rows[-1]
        print(f"{model:>12s} package / default: compile {ours[2] / theirs[2]:.2f}, program "
              f"{ours[3] / theirs[3]:.3f}, kappa_s {ours[4] / theirs[4]:.3f}; kappa_s "
              f"difference {abs(ours[6] - theirs[6]):.1e}")
    write_csv(a.out / "bench_codegen.csv",
              ["model", "code_generator", "compile_s", "program_us", "kappa_s_ms",
               "process_s", "kappa_s_R0", "processes"], rows)
    print(f"wrote {a.out / 'bench_codegen.csv'}")


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    main()
