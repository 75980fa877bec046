"""One core for a benchmark: import this module first (before numpy, scipy or JAX read
their thread settings). It limits the BLAS and XLA thread pools to one thread and pins the
process to the machine's last core; ``PINNED`` says whether the pinning took (not on every
operating system: a benchmark then runs unpinned and says so)."""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false "
                                   "intra_op_parallelism_threads=1")
try:
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
    PINNED = True
except (AttributeError, OSError):
    PINNED = False
