"""Sweeps that keep every item: per-item outcomes, a journal that survives a kill, resumption,
and chunks run on any executor (local processes, a Dask or Ray cluster).

A sweep is a sequence of items (e.g. the caps of a kappa_s curve, one per shallowness T) cut
into **chunks** of consecutive items, ``chunk_size`` each. A chunk is the unit of work: a
picklable task ``task(chunk)`` (:class:`Chunk`) that returns one :class:`Record` per item,
in order, and may carry state from one item to the next (a cap's fold seeds the next cap's
fold curve). The chunking depends on the items and ``chunk_size`` only, never on the number
of workers, so a sweep gives the same records, value for value, serially, on two processes
or on a cluster.

Every task computes with BLAS on one thread (and local workers with XLA on one thread):
N workers on N cores with the libraries' thread pools each were 6x slower per item, and the
factorisations round differently with the number of threads. So serial, two local processes
and a Dask cluster give the same values to the last bit (tested); a sweep's kappa_s may
differ from a ``snap_curvature`` call outside a sweep (BLAS on its default threads) by
round-off (~1e-15 relative).

Durability: with a journal (a file beside the output), every finished item is appended as
one JSON line, flushed and fsync'd by whoever finished it (the worker, so a kill of the
parent loses no finished item; O_APPEND writes of one line are atomic). ``resume`` reads
the journal and skips every chunk whose items are all there; a chunk finished only in part
is run again from its first item (its carried state is rebuilt the same way; the journal's
values are kept), so the final records are those of an uninterrupted run.
"""

from __future__ import annotations

import json
import os
import signal
import threading
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from typing import Callable, Sequence

__all__ = ["Record", "Chunk", "Journal", "run", "SweepInterrupted", "local_executor",
           "STATUSES", "CHUNK_SIZE", "one_line"]

#: the outcome of one item: converged with a value, converged with no value to report
#: (e.g. a cap that does not snap), or failed (the reason is kept)
STATUSES = ("ok", "no snap", "failed")
#: items per chunk by default: each chunk starts from scratch (a cap continued from
#: kappa = 0) and follows its own fold curve after that
CHUNK_SIZE = 12
#: the longest reason kept for a failed item (the first line of the error, cut)
REASON_CHARS = 300


def one_line(exc: BaseException) -> str:
    """The first line of an error's message, with its type where that is not a
    ConvergenceError, cut to ``REASON_CHARS``."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    if type(exc).__name__ != "ConvergenceError":
        text = f"{type(exc).__name__}: {text}"
    return text[:REASON_CHARS]


@dataclass(frozen=True)
class Record:
    """One item of a sweep: its position ``index``, its ``key`` (e.g. T), ``status`` (one of
    ``STATUSES``), the ``reason`` where it failed ("" otherwise) and its ``values`` (a dict of
    numbers and flags, nan where not computed)."""

    index: int
    key: float
    status: str
    reason: str = ""
    values: dict = field(default_factory=dict)

    def to_json(self) -> str:
        return json.dumps({"index": self.index, "key": self.key, "status": self.status,
                           "reason": self.reason, "values": self.values})

    @classmethod
    def from_json(cls, line: str) -> "Record":
        d = json.loads(line)
        return cls(int(d["index"]), float(d["key"]), str(d["status"]), str(d["reason"]),
                   dict(d["values"]))


@dataclass(frozen=True)
class Chunk:
    """The items ``keys`` at positions ``first``, ``first + 1``, ... of a sweep, the
    parameters ``spec`` the task needs, and the journal to append to (None: none)."""

    first: int
    keys: tuple
    spec: dict
    journal: str | None = None
    #: positions already in the journal (a chunk run again on resume): not written twice
    journaled: frozenset = frozenset()

    def emit(self, record: Record) -> Record:
        """Append a finished record to the journal (durably), and return it."""
        if self.journal is not None and record.index not in self.journaled:
            Journal(self.journal).append(record)
        return record


class Journal:
    """An append-only file of finished records, one JSON line each after a header line that
    identifies the sweep (its parameters and items): resuming a different sweep from it is
    refused."""

    def __init__(self, path):
        self.path = os.fspath(path)

    def start(self, header: dict, *, resume: bool) -> dict[int, Record]:
        """Open the journal for a sweep described by ``header``: with ``resume``, the records
        already in it (ValueError if it belongs to another sweep), else a new journal."""
        if resume and os.path.exists(self.path):
            with open(self.path, encoding="utf-8") as f:
                lines = f.read().splitlines()
            if not lines or json.loads(lines[0]) != json.loads(json.dumps(header)):
                raise ValueError(f"resume: the journal {self.path} belongs to another sweep "
                                 f"(different parameters or items); remove it or drop "
                                 f"resume")
            done = {}
            for line in lines[1:]:
                try:
                    r = Record.from_json(line)
                except (ValueError, KeyError):
                    continue        # a line cut by a kill mid-write: that item is redone
                done[r.index] = r
            return done
        folder = os.path.dirname(os.path.abspath(self.path))
        os.makedirs(folder, exist_ok=True)
        with open(self.path, "w", encoding="utf-8") as f:
            f.write(json.dumps(header) + "\n")
            f.flush()
            os.fsync(f.fileno())
        return {}

    def append(self, record: Record) -> None:
        line = (record.to_json() + "\n").encode("utf-8")
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, line)
            os.fsync(fd)
        finally:
            os.close(fd)

    def remove(self) -> None:
        if os.path.exists(self.path):
            os.remove(self.path)


class SweepInterrupted(KeyboardInterrupt):
    """A sweep interrupted (Ctrl-C, SIGTERM): ``records`` are the items finished before it
    (in order), ``total`` the sweep's size."""

    def __init__(self, records, total):
        super().__init__(f"interrupted after {len(records)} of {total} items")
        self.records, self.total = records, total


#: a local worker's XLA computes on one thread (XLA reads its flags when it starts: this is
#: the environment a worker is started with); BLAS runs on one thread in every task
#: (:func:`_one_thread`). Two workers on two cores with their libraries' own thread pools
#: (whose threads spin while they wait) took 6x longer per cap than one process alone
WORKER_ENVIRONMENT = {"XLA_FLAGS": "--xla_cpu_multi_thread_eigen=false"}


def _worker_start(jax_cache: bool):
    # workers leave Ctrl-C to the parent, which stops the sweep and writes what it has
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if jax_cache:   # as the parent: compiled programs from disk, not compiled again
        os.environ["SHELLBVP_JAX_CACHE"] = "on"
        # the spawned worker may have imported the package already (with the main module
        # it re-imports), before this initializer: turn the cache on now
        from .jaxsetup import use_persistent_cache

        use_persistent_cache(default=True)


def local_executor(jobs: int) -> Executor:
    """``jobs`` local worker processes (spawned: JAX does not survive a fork), which ignore
    Ctrl-C (the parent handles it) and use JAX's persistent compilation cache where this
    process does (the command line: a worker then starts in ~2 s instead of compiling for
    10-30 s)."""
    import multiprocessing
    import sys

    jax = sys.modules.get("jax")
    cache = bool(jax is not None and getattr(jax.config, "jax_compilation_cache_dir", None))
    pool = ProcessPoolExecutor(max_workers=jobs, initializer=_worker_start, initargs=(cache,),
                               mp_context=multiprocessing.get_context("spawn"))
    # start every worker now, with WORKER_ENVIRONMENT (a spawned process takes this
    # process's environment when it starts; a pool starts a worker on a submit that finds
    # none idle): this process's environment is restored at once
    saved = {k: os.environ.get(k) for k in WORKER_ENVIRONMENT}
    with _ENVIRONMENT_LOCK:
        try:
            os.environ.update(WORKER_ENVIRONMENT)
            started = [pool.submit(_started) for _ in range(jobs)]
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
    for f in started:
        f.result()
    return pool


def _started() -> bool:
    return True


def _one_thread(task, chunk):
    """``task(chunk)`` with BLAS on one thread, wherever it runs (this process, a local
    worker, a cluster's): the LU factorisations round differently on one thread than on
    two (kappa_s 11 ulp apart), so one thread everywhere makes the values independent of
    who computes them. The BLAS libraries are loaded first (a library loaded inside the
    limit would escape it: scipy's LAPACK loads on the first factorisation)."""
    from threadpoolctl import threadpool_limits

    import numpy  # noqa: F401
    import scipy.linalg.lapack  # noqa: F401

    with threadpool_limits(limits=1, user_api="blas"):
        return task(chunk)


_ENVIRONMENT_LOCK = threading.Lock()


def run(keys: Sequence[float], task: Callable[[Chunk], list], spec: dict, *,
        chunk_size: int = CHUNK_SIZE, journal: str | None = None, resume: bool = False,
        jobs: int = 1, executor: Executor | None = None, progress=None) -> list[Record]:
    """Run ``task`` on every chunk of ``keys`` and return all records in order.

    Arguments:
        keys: the items (floats), in sweep order.
        task: a picklable function of a :class:`Chunk` returning its records in order,
            calling ``chunk.emit(record)`` for each as it finishes (the journal).
        spec: the parameters of every chunk (picklable; part of the journal's header).
        chunk_size: items per chunk (the results depend on it, not on ``jobs``).
        journal: path of the journal (None: none); ``resume``: continue from it.
        jobs: local worker processes (1: in this process), unless ``executor`` is given:
            any ``concurrent.futures.Executor`` (e.g. ``dask.distributed.Client(...)
            .get_executor()``), not shut down here.
        progress: called with the number of items just finished (e.g. a tqdm bar's
            ``update``).

    Raises:
        ValueError: bad ``jobs`` or ``chunk_size``, or a journal of another sweep.
        SweepInterrupted: on Ctrl-C, with the records finished before it.
    """
    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError(f"jobs must be an integer >= 1, got {jobs!r}")
    if not (isinstance(chunk_size, int) and chunk_size >= 1):
        raise ValueError(f"chunk_size must be an integer >= 1, got {chunk_size!r}")
    if executor is not None and not isinstance(executor, Executor):
        raise ValueError(f"executor must be a concurrent.futures.Executor, got "
                         f"{type(executor).__name__}")
    keys = [float(k) for k in keys]
    done: dict[int, Record] = {}
    if journal is not None:
        header = {"spec": {k: repr(v) for k, v in sorted(spec.items())}, "keys": keys,
                  "chunk_size": chunk_size}
        done = Journal(journal).start(header, resume=resume)
    chunks = [Chunk(i, tuple(keys[i:i + chunk_size]), spec, journal,
                    frozenset(j for j in range(i, i + chunk_size) if j in done))
              for i in range(0, len(keys), chunk_size)]
    todo = [c for c in chunks if len(c.journaled) < len(c.keys)]
    tick = progress or (lambda n: None)
    tick(sum(len(c.keys) for c in chunks if len(c.journaled) == len(c.keys)))
    results: dict[int, Record] = dict(done)

    def collect(records):
        new = 0
        for r in records:
            if r.index not in results:
                new += 1
            results.setdefault(r.index, r)      # the journal's value is kept
        tick(new)

    own = None
    try:
        if executor is None and jobs == 1:
            for c in todo:
                collect(_one_thread(task, c))
        else:
            pool = executor if executor is not None else (own := local_executor(jobs))
            futures = [pool.submit(_one_thread, task, c) for c in todo]
            for fut in as_completed(futures):
                collect(fut.result())
    except KeyboardInterrupt:
        if journal is not None:     # what workers finished and journaled counts too
            results.update({i: r for i, r in Journal(journal).start(
                header, resume=True).items() if i not in results})
        raise SweepInterrupted([results[i] for i in sorted(results)], len(keys)) from None
    finally:
        if own is not None:
            own.shutdown(wait=False, cancel_futures=True)
    return [results[i] for i in range(len(keys))]
