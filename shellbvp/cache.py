"""On-disk cache for symbolic derivations, so each is paid once per machine.

Entries are pickles keyed by a SHA-256 of everything the derivation depends on (its source
text, its arguments, the sympy and Python versions). The folder is ``$SHELLBVP_CACHE_DIR`` or
``~/.cache/shellbvp``; ``SHELLBVP_CACHE_DIR=off`` disables the disk (the in-process caches
still apply). Writes are atomic (temporary file + ``os.replace``), so a killed process never
leaves a half-written entry, and a corrupt entry is recomputed.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable

__all__ = ["key", "memo", "files_digest", "cache_dir", "atomic_write_text", "atomic_write_bytes",
           "atomic_write"]


def cache_dir() -> Path | None:
    env = os.environ.get("SHELLBVP_CACHE_DIR")
    if env is not None and env.strip().lower() in {"off", "0", "none", ""}:
        return None
    return Path(env) if env else Path.home() / ".cache" / "shellbvp"


def key(*parts: Any) -> str:
    from importlib.metadata import version   # sympy's version without importing sympy

    h = hashlib.sha256()
    for p in (sys.version_info[:2], version("sympy"), *parts):
        h.update(repr(p).encode())
        h.update(b"\0")
    return h.hexdigest()[:32]


def files_digest(paths) -> str:
    """SHA-256 of the bytes of ``paths`` (in the given order): the part of a disk key that
    changes whenever the code a cached value came from changes."""
    h = hashlib.sha256()
    for path in paths:
        h.update(Path(path).read_bytes())
    return h.hexdigest()


def memo(k: str, compute: Callable[[], Any]) -> Any:
    """Return the cached value for key ``k``, computing and storing it if absent."""
    folder = cache_dir()
    path = None if folder is None else folder / f"{k}.pkl"
    if path is not None and path.exists():
        try:
            with open(path, "rb") as f:
                return pickle.load(f)
        except Exception:  # corrupt or incompatible entry: recompute below
            pass
    value = compute()
    if path is not None:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
            with os.fdopen(fd, "wb") as f:
                pickle.dump(value, f, protocol=pickle.HIGHEST_PROTOCOL)
            os.replace(tmp, path)
        except OSError:  # a read-only home is not an error: the value is still returned
            pass
    return value


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``path`` atomically (no half-written file is ever visible), with the
    permissions an ordinary ``open(path, "w")`` would give (0666 less the umask), not the
    private 0600 of the temporary file."""
    atomic_write_bytes(path, text.encode())


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """:func:`atomic_write_text` for bytes (e.g. a rendered PNG)."""
    def write(tmp: Path) -> None:
        with open(tmp, "wb") as f:
            f.write(data)

    atomic_write(path, write)


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None], *,
                 keep_suffix: bool = False) -> None:
    """Let ``write(tmp)`` write a file at a temporary path beside ``path`` (in the same
    folder, so that the final rename is atomic), then move it to ``path`` with the
    permissions of an ordinary ``open(path, "w")``. On any error, or an interrupt, the
    temporary file is removed and ``path`` is untouched. The temporary name ends in
    ``.tmp``, or with ``keep_suffix`` in ``path``'s own suffix (for writers that take the
    format from the name, e.g. an animation's ``.gif``).

    Raises:
        OSError: the folder cannot be created or written (the message names ``path``),
            or whatever ``write`` raises.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.",
                                   suffix=f".tmp{path.suffix}" if keep_suffix else ".tmp")
    except OSError as exc:
        raise OSError(exc.errno, f"cannot write {path}: {exc.strerror}") from None
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
