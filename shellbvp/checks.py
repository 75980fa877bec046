"""Input validation at the public boundary: ValueError naming the parameter and its range.

Never ``assert`` (it vanishes under ``python -O``). Complex inputs are accepted where a
function documents complex-step differentiation; ranges are then checked on the real part.
"""

from __future__ import annotations

import numpy as np

__all__ = ["as_array", "check_choice", "check_open_interval", "check_positive", "check_finite"]


def as_array(name: str, value) -> np.ndarray:
    try:
        arr = np.asarray(value)
    except Exception as exc:  # pragma: no cover - numpy accepts almost anything
        raise ValueError(f"{name} must be a number or an array of numbers") from exc
    if arr.dtype.kind not in "biufc":
        raise ValueError(f"{name} must be numeric, got dtype {arr.dtype}")
    return arr


def check_finite(name: str, value) -> np.ndarray:
    arr = as_array(name, value)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


def check_positive(name: str, value) -> np.ndarray:
    arr = check_finite(name, value)
    if not np.all(np.real(arr) > 0):
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return arr


def check_open_interval(name: str, value, lo: float, hi: float, what: str = "") -> float:
    arr = check_finite(name, value)
    if arr.ndim != 0:
        raise ValueError(f"{name} must be a scalar, got shape {arr.shape}")
    v = float(np.real(arr))
    if not lo < v < hi:
        raise ValueError(f"{name} must lie in ({lo:g}, {hi:g}){what}, got {v!r}")
    return v


def check_choice(name: str, value, allowed) -> str:
    if value not in allowed:
        raise ValueError(f"{name} must be one of {tuple(allowed)}, got {value!r}")
    return value
