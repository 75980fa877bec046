"""The reference meridian of a shell of revolution, as data: segments joined end to end.

A shell of revolution is its meridian, a curve (r0(s), z0(s)) in the half-plane r >= 0
traced by arclength s from its first end (s = 0) to its second (s = L). Conventions (the
engine relies on them):

- Tangent angle: (dr0/ds, dz0/ds) = (cos theta0, -sin theta0), i.e. theta0 = -psi0 with
  psi0 the angle of the tangent from e_r. The unit sphere traced from its top pole
  (r0 = sin s, z0 = cos s) has theta0 = s.
- Normal n0 = (-dz0/ds, dr0/ds) = (sin theta0, cos theta0): the tangent turned by +90 degrees
  (the outward normal of a cap traced from its top pole).
- Principal curvatures k1 = -dtheta0/ds (meridional) and k2 = -sin(theta0)/r0 (hoop), with
  the pole limit k2 = k1 where r0 = 0. The unit sphere from its top pole has
  k1 = k2 = -1; a cylinder of radius R traced upward (theta0 = -pi/2) k1 = 0, k2 = +1/R; a
  plate k1 = k2 = 0.
- A pole is an end with r0 = 0. It must meet the axis at a right angle (theta0 = 0 mod 2 pi
  at a first-end pole, pi mod 2 pi at a second-end pole): elsewhere k2 is unbounded (a cone's
  apex), and the meridian is refused.

Every evaluation takes an array module ``xp`` (``numpy`` on the host, ``jax.numpy`` inside
traced and compiled kernels) and is pure array arithmetic in it, so that ``jax.jit``,
``jax.grad`` and ``jax.jvp`` in the arclength work. A segment's ``trace_key()`` is a
hashable tuple of exactly the numbers its ``evaluate`` depends on (the first entry names the
formula): segments with equal keys evaluate identically, so compiled programs can be shared
between them (e.g. spherical caps of different opening angle).

:class:`Ellipse` and :class:`Points` are not parametrised by arclength in closed form. They
carry a table of their curve parameter t(s) (piecewise Chebyshev interpolants of degree
``DEGREE`` in s, built on the host by Newton's method on the arclength, itself by
Gauss-Legendre quadrature), and evaluate the exact curve at t(s); see :class:`ArclengthTable`.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from typing import Callable

import numpy as np

from .checks import check_finite, check_positive

__all__ = ["Segment", "Plate", "Cylinder", "Cone", "Sphere", "Torus", "Ellipse", "Points",
           "Meridian", "ArclengthTable", "spherical_cap", "closed_sphere", "disc", "annulus",
           "cylinder", "wrap_angle", "MEET_TOL", "AXIS_TOL", "RIGHT_ANGLE_TOL", "DEGREE",
           "UNIT_SPEED_TOL", "UNIT_SPEED_FLOOR"]

#: consecutive segments meet where their ends are this close, relative to the meridian's size
MEET_TOL = 1e-9
#: r0 within this of zero (relative to the meridian's size) is on the axis
AXIS_TOL = 1e-12
#: a pole's tangent may deviate from the right angle by this (radians)
RIGHT_ANGLE_TOL = 1e-9
#: samples of r0 per smooth piece of a segment in the meridian's checks
SAMPLES = 64
#: degree of the Chebyshev interpolants of the curve parameter t(s) (:class:`ArclengthTable`):
#: the cost of an evaluation is ~ DEGREE multiply-adds (Clenshaw), and a piece is split
#: until its interpolant meets UNIT_SPEED_TOL
DEGREE = 16
#: accepted |d(r0, z0)/ds| - 1 of a tabulated segment, checked between the interpolation
#: nodes of every piece (the derivative of an interpolant amplifies the round-off of its
#: values up to ~ DEGREE**2 times: ~ 3e-14)
UNIT_SPEED_TOL = 5e-14
#: ... or this, where halving a piece no longer helps (round-off in a rapidly varying speed)
UNIT_SPEED_FLOOR = 1e-12
#: the most pieces a table may have (a curve needing more is refused)
MAX_PIECES = 20000
#: Gauss-Legendre rule of the arclength integrals (exact to round-off on a resolved piece)
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(40)
#: Chebyshev points x_j = cos(pi j / DEGREE), the matrix of the discrete cosine transform
#: (values on them -> coefficients), and the points where a piece is tested (first kind,
#: 2 DEGREE of them: between the nodes, where an interpolant's error peaks)
_CHEB_X = np.cos(np.pi * np.arange(DEGREE + 1) / DEGREE)
_CHEB_DCT = np.cos(np.pi * np.outer(np.arange(DEGREE + 1), np.arange(DEGREE + 1)) / DEGREE)
_CHEB_TEST = np.cos(np.pi * (np.arange(2 * DEGREE) + 0.5) / (2 * DEGREE))


def wrap_angle(x):
    """x wrapped to (-pi, pi] (numpy): ``pi - ((pi - x) mod 2 pi)``."""
    return math.pi - np.mod(math.pi - np.asarray(x, dtype=float), 2 * math.pi)


def _branch(theta: float) -> float:
    """The multiple of 2 pi to add to theta to bring it to (-pi, pi]."""
    return 2 * math.pi * round((float(wrap_angle(theta)) - theta) / (2 * math.pi))


def _locate(starts, x, xp):
    """Index of the piece holding x, pieces starting at the increasing ``starts``: the last
    start <= x (x below the first start: piece 0; a start belongs to its own piece)."""
    if len(starts) == 1:
        return xp.zeros(xp.shape(x), dtype=int)
    return xp.searchsorted(xp.asarray(starts[1:]), x, side="right")


def _clenshaw(c, x):
    """sum_k c[..., k] T_k(x) by Clenshaw's recurrence (array arithmetic only)."""
    b1 = b2 = 0.0 * x
    for k in range(c.shape[-1] - 1, 0, -1):
        b1, b2 = c[..., k] + 2.0 * x * b1 - b2, b1
    return c[..., 0] + x * b1 - b2


def _horner(c, x):
    """sum_m c[..., m, :] x^m for coefficients (..., M, 2) of a planar curve: (..., 2)."""
    out = c[..., -1, :]
    for m in range(c.shape[-2] - 2, -1, -1):
        out = c[..., m, :] + x[..., None] * out
    return out


#: what a segment has besides its abstract methods (a property or a dataclass field)
_SEGMENT_ATTRIBUTES = ("start", "end")


def _pair(owner: str, name: str, value) -> tuple[float, float]:
    arr = check_finite(f"{owner}.{name}", value)
    if arr.shape != (2,):
        raise ValueError(f"{owner}.{name} must be a pair of numbers, got {value!r}")
    return float(arr[0]), float(arr[1])


class Segment(ABC):
    """A piece of a meridian, traced from its first point (local arclength u = 0) to its last
    (u = ``length``).

    Besides the abstract members below, a segment has ``start`` and ``end``, its (r, z) at
    u = 0 and u = ``length`` (a property or a dataclass field: :class:`Cone` takes them as its
    parameters). A subclass that lacks any of these is a ``TypeError`` when it is defined (pass
    ``abstract=True`` in the class statement for an intermediate base). Concrete segments are
    frozen dataclasses validated on construction.
    """

    def __init_subclass__(cls, abstract: bool = False, **kwargs):
        super().__init_subclass__(**kwargs)
        if abstract:
            return
        missing = [name for name in dir(cls)
                   if getattr(getattr(cls, name, None), "__isabstractmethod__", False)]
        missing += [name for name in _SEGMENT_ATTRIBUTES if not hasattr(cls, name)
                    and not any(name in vars(k).get("__annotations__", {}) for k in cls.__mro__)]
        if missing:
            raise TypeError(f"segment {cls.__name__} does not implement {sorted(missing)}")

    @property
    @abstractmethod
    def length(self) -> float:
        """Arclength of the segment (> 0)."""

    @abstractmethod
    def evaluate(self, u, xp=np):
        """(r0, z0, theta0, k1) at local arclength u (arrays shaped like u), k1 = -dtheta0/du.

        theta0(0) lies in (-pi, pi] and theta0 is continuous in u. Array arithmetic in ``xp``
        only; beyond [0, length] the segment's formula is continued.
        """

    @abstractmethod
    def trace_key(self) -> tuple:
        """The formula's name and exactly the numbers ``evaluate`` depends on (hashable)."""

    @abstractmethod
    def with_length(self, length: float) -> "Segment":
        """The same kind of segment with the same start and direction, of arclength
        ``length`` (ValueError where that leaves the segment's admissible range)."""

    @property
    def breaks(self) -> tuple[float, ...]:
        """Interior positions u where ``evaluate`` is not smooth (a spectral discretisation
        converges geometrically only between them): none for a closed-form segment."""
        return ()


# --------------------------------------------------------------------------- straight lines

class _Straight(Segment, abstract=True):
    """A straight segment: r0 = r_a + u cos(theta0), z0 = z_a - u sin(theta0), k1 = 0."""

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    def _direction(self) -> tuple[float, float]:
        (ra, za), (rb, zb), ell = self.start, self.end, self.length
        return (rb - ra) / ell, (zb - za) / ell

    def evaluate(self, u, xp=np):
        (ra, za), (dr, dz) = self.start, self._direction()
        u = xp.asarray(u, dtype=float)
        theta = math.atan2(0.0 - dz, dr)          # 0.0 - dz: a plate traced inward has pi
        return ra + dr * u, za + dz * u, xp.full_like(u, theta), xp.zeros_like(u)

    def trace_key(self) -> tuple:
        return ("line", *self.start, *self._direction())


@dataclass(frozen=True)
class Plate(_Straight):
    """A flat annulus (or a disc, where one end has r = 0) at height z, traced radially from
    r_a to r_b (either direction): theta0 = 0 outward, pi inward; k1 = k2 = 0.

    Attributes:
        r: (r_a, r_b), both >= 0 and different.
        z: the height.
    """

    r: tuple[float, float]
    z: float = 0.0

    def __post_init__(self):
        r = _pair("Plate", "r", self.r)
        if min(r) < 0 or r[0] == r[1]:
            raise ValueError(f"Plate.r = (r_a, r_b) must have r_a, r_b >= 0 and r_a != r_b, "
                             f"got {r}")
        object.__setattr__(self, "r", r)
        object.__setattr__(self, "z", float(check_finite("Plate.z", self.z)))

    @property
    def start(self):
        return (self.r[0], self.z)

    @property
    def end(self):
        return (self.r[1], self.z)

    def with_length(self, length):
        d = math.copysign(1.0, self.r[1] - self.r[0])
        return replace(self, r=(self.r[0], self.r[0] + d * float(length)))


@dataclass(frozen=True)
class Cylinder(_Straight):
    """A cylinder of radius ``radius`` from height z_a to z_b: traced upward theta0 = -pi/2,
    k1 = 0, k2 = +1/radius (n0 points to the axis); downward theta0 = pi/2, k2 = -1/radius.

    Attributes:
        radius: > 0.
        z: (z_a, z_b), different.
    """

    radius: float
    z: tuple[float, float]

    def __post_init__(self):
        object.__setattr__(self, "radius", float(check_positive("Cylinder.radius",
                                                                  self.radius)))
        z = _pair("Cylinder", "z", self.z)
        if z[0] == z[1]:
            raise ValueError(f"Cylinder.z = (z_a, z_b) must have z_a != z_b (a cylinder of "
                             f"zero length), got {z}")
        object.__setattr__(self, "z", z)

    @property
    def start(self):
        return (self.radius, self.z[0])

    @property
    def end(self):
        return (self.radius, self.z[1])

    def with_length(self, length):
        d = math.copysign(1.0, self.z[1] - self.z[0])
        return replace(self, z=(self.z[0], self.z[0] + d * float(length)))


@dataclass(frozen=True)
class Cone(_Straight):
    """A straight segment from ``start`` to ``end`` (a frustum; a plate or a cylinder is one
    too): k1 = 0, k2 = -sin(theta0)/r0.

    An end on the axis is a cone's apex, where k2 is unbounded: refused, unless the segment
    is horizontal (a disc). Cut the cone off as a frustum or round its apex.

    Attributes:
        start, end: (r, z) with r >= 0, distinct points.
    """

    start: tuple[float, float]
    end: tuple[float, float]

    def __post_init__(self):
        a, b = _pair("Cone", "start", self.start), _pair("Cone", "end", self.end)
        if min(a[0], b[0]) < 0:
            raise ValueError(f"Cone: start and end must have r >= 0, got {a} and {b}")
        if a == b:
            raise ValueError(f"Cone: start and end must differ (zero length), got {a} twice")
        for name, p in (("start", a), ("end", b)):
            if p[0] == 0.0 and a[1] != b[1]:
                raise ValueError(f"Cone: {name} {p} is on the axis: a cone's apex is singular "
                                 f"(k2 = -sin(theta0)/r0 is unbounded there); cut it off as a "
                                 f"frustum or round it")
        object.__setattr__(self, "start", a)
        object.__setattr__(self, "end", b)

    def with_length(self, length):
        (ra, za), (dr, dz) = self.start, self._direction()
        return replace(self, end=(ra + dr * float(length), za + dz * float(length)))


# --------------------------------------------------------------------------- circular arcs

class _Arc(Segment, abstract=True):
    """An arc of the circle of radius rho centred at (c, centre_z): points
    (c + rho sin a, centre_z + rho cos a), a the polar angle from +z, traced from a0 to a1.
    With d = sign(a1 - a0): a = a0 + d u / rho, theta0 = theta0(0) + d u / rho (theta0 = a
    tracing a upward, a + pi tracing it downward, mod 2 pi), k1 = -d / rho."""

    @property
    @abstractmethod
    def _circle(self) -> tuple[float, float, float]:
        """(c, centre_z, rho)."""

    @property
    def _sign(self) -> float:
        return math.copysign(1.0, self.angle[1] - self.angle[0])

    def _point(self, a):
        c, zc, rho = self._circle
        return (c + rho * math.sin(a), zc + rho * math.cos(a))

    @property
    def length(self) -> float:
        return self._circle[2] * abs(self.angle[1] - self.angle[0])

    @property
    def start(self):
        return self._point(self.angle[0])

    @property
    def end(self):
        return self._point(self.angle[1])

    def evaluate(self, u, xp=np):
        c, zc, rho = self._circle
        a0, d = self.angle[0], self._sign
        theta_a = a0 + (0.0 if d > 0 else math.pi)
        theta_a += _branch(theta_a)
        u = xp.asarray(u, dtype=float)
        a = a0 + (d / rho) * u
        return (c + rho * xp.sin(a), zc + rho * xp.cos(a), theta_a + (d / rho) * u,
                xp.full_like(u, -d / rho))

    def trace_key(self) -> tuple:
        return ("arc", *self._circle, self.angle[0], self._sign)

    def with_length(self, length):
        a0 = self.angle[0]
        return replace(self, angle=(a0, a0 + self._sign * float(length) / self._circle[2]))


def _angle(owner: str, value, lo: float, hi: float, range_text: str) -> tuple[float, float]:
    a = _pair(owner, "angle", value)
    if not (lo <= min(a) and max(a) <= hi and a[0] != a[1]):
        raise ValueError(f"{owner}.angle = (a0, a1) must have a0 != a1 in {range_text} "
                         f"(polar angles from +z, traced from a0 to a1), got {a}")
    return a


@dataclass(frozen=True)
class Sphere(_Arc):
    """An arc of the sphere of radius ``radius`` centred on the axis at ``centre_z``: points
    (R sin a, centre_z + R cos a), a from +z, traced from a0 to a1 (a1 < a0: traced the other
    way). Traced downward (a1 > a0) k1 = k2 = -1/R; traced upward k1 = k2 = +1/R (a bowl
    opening upward, traced from its bottom pole).

    Attributes:
        radius: > 0.
        centre_z: the centre's height.
        angle: (a0, a1), different, in [0, pi] (the half-plane r >= 0); keyword only.
    """

    radius: float
    centre_z: float = 0.0
    angle: tuple[float, float] = field(kw_only=True)

    def __post_init__(self):
        object.__setattr__(self, "radius", float(check_positive("Sphere.radius", self.radius)))
        object.__setattr__(self, "centre_z", float(check_finite("Sphere.centre_z",
                                                                self.centre_z)))
        object.__setattr__(self, "angle", _angle("Sphere", self.angle, 0.0, math.pi,
                                                 "[0, pi]"))

    @property
    def _circle(self):
        return (0.0, self.centre_z, self.radius)


@dataclass(frozen=True)
class Torus(_Arc):
    """An arc of a torus's tube: the circle of radius ``tube_radius`` = rho centred at
    (``centre_radius`` = c, ``centre_z``), points (c + rho sin a, centre_z + rho cos a), traced
    from a0 to a1. Traced with a increasing: k1 = -1/rho, k2 = -sin(a)/(c + rho sin a) (the
    outer equator a = pi/2: -1/(c + rho); the inner a = -pi/2: +1/(c - rho)); traced the other
    way both change sign.

    Attributes:
        centre_radius: c >= 0.
        tube_radius: rho > 0.
        centre_z: the tube centre's height.
        angle: (a0, a1), different, |a1 - a0| <= 2 pi; keyword only. The arc must keep
            r >= 0 (the meridian checks it).
    """

    centre_radius: float
    tube_radius: float
    centre_z: float = 0.0
    angle: tuple[float, float] = field(kw_only=True)

    def __post_init__(self):
        c = float(check_finite("Torus.centre_radius", self.centre_radius))
        if c < 0:
            raise ValueError(f"Torus.centre_radius must be >= 0, got {c}")
        object.__setattr__(self, "centre_radius", c)
        object.__setattr__(self, "tube_radius", float(check_positive("Torus.tube_radius",
                                                                     self.tube_radius)))
        object.__setattr__(self, "centre_z", float(check_finite("Torus.centre_z",
                                                                self.centre_z)))
        a = _pair("Torus", "angle", self.angle)
        if a[0] == a[1] or abs(a[1] - a[0]) > 2 * math.pi:
            raise ValueError(f"Torus.angle = (a0, a1) must have 0 < |a1 - a0| <= 2 pi, got {a}")
        object.__setattr__(self, "angle", a)

    @property
    def _circle(self):
        return (self.centre_radius, self.centre_z, self.tube_radius)


# --------------------------------------------------------------------------- arclength tables

@dataclass(frozen=True, eq=False)
class ArclengthTable:
    """The curve parameter t as a function of arclength s, for a curve c(t) with speed
    |c'(t)| > 0 given on parameter intervals: piecewise Chebyshev interpolants of degree
    :data:`DEGREE` in s, each piece inside one interval.

    Built by :meth:`build`: on every piece [t_a, t_b] the arclength S(t) = int_{t_a}^t |c'|
    is a 40-point Gauss-Legendre quadrature; t at the DEGREE + 1 Chebyshev points in s is
    found by Newton's method on S(t) = s (to round-off), and the piece is halved until the
    interpolant's unit speed, |c'(t(s))| t'(s), is within :data:`UNIT_SPEED_TOL` of 1 at the
    2 DEGREE Chebyshev points of the first kind (between the nodes). The segment then
    evaluates the exact
    curve at t(s): r0, z0, theta0 and k1 are the curve's, consistent to round-off, and
    |d(r0, z0)/ds| - 1 is the interpolant's derivative error only.

    Attributes:
        s0, ds: (P,) arclength at each piece's start and its width.
        t0, t1: (P,) the parameter at each piece's ends.
        coef: (P, DEGREE + 1) Chebyshev coefficients of delta(s) = t(s) - t0 -
            (t1 - t0) (1 + x) / 2 on each piece, x = 2 (s - s0) / ds - 1.
        interval: (P,) the parameter interval each piece lies in.
        speed: ``speed(t0, tau, i)`` -> |c'(t0 + tau)| on interval i (host, numpy).
    """

    s0: np.ndarray
    ds: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    coef: np.ndarray
    interval: np.ndarray
    speed: Callable

    @property
    def total(self) -> float:
        """The curve's arclength."""
        return float(self.s0[-1] + self.ds[-1])

    def parameter(self, s, xp=np):
        """(t(s) - t0[i], i): the piece i holding s (the first or last piece continued
        beyond the table's ends) and the parameter relative to the piece's start (t itself
        would carry rounding ~ eps |t| into the interpolant's derivative)."""
        i = _locate(self.s0, s, xp)
        x = 2.0 * (s - xp.asarray(self.s0)[i]) / xp.asarray(self.ds)[i] - 1.0
        h = xp.asarray(self.t1 - self.t0)[i]
        return h * (1.0 + x) / 2.0 + _clenshaw(xp.asarray(self.coef)[i], x), i

    def arclength(self, t) -> np.ndarray:
        """S(t) on the host (numpy), by quadrature from the start of the piece holding t."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        i = _locate(self.t0, t, np)
        out = np.empty_like(t)
        for k in np.unique(i):
            m = i == k
            out[m] = self.s0[k] + _integral(self.speed, self.interval[k], self.t0[k],
                                            t[m] - self.t0[k])
        return out

    @classmethod
    def build(cls, breaks, speed: Callable, what: str) -> "ArclengthTable":
        """The table of a curve with speed ``speed(t0, tau, i)`` = |c'(t0 + tau)| on the
        parameter intervals [breaks[i], breaks[i + 1]] (t0 a piece's start, tau >= 0 an
        array: the sum t0 + tau is never formed, whose rounding ~ eps |t0| would show in a
        short piece).

        A piece is halved until it meets :data:`UNIT_SPEED_TOL`, or until its interpolant
        is resolved (its last coefficients at round-off, where halving no longer helps: the
        round-off of a rapidly varying speed) and meets :data:`UNIT_SPEED_FLOOR`.

        Raises:
            ValueError: (naming ``what``) where the speed vanishes (a cusp) or more than
                :data:`MAX_PIECES` pieces would be needed.
        """
        rows, s = [], 0.0
        for i, (ta, tb) in enumerate(zip(breaks[:-1], breaks[1:])):
            todo = [(float(ta), float(tb))]
            while todo:
                a, b = todo.pop()
                width, coef, error = _fit_piece(speed, i, a, b)
                resolved = np.max(np.abs(coef[-3:])) <= 16 * np.finfo(float).eps * (b - a)
                if error > UNIT_SPEED_TOL and not (resolved and error <= UNIT_SPEED_FLOOR):
                    if resolved or len(rows) + len(todo) >= MAX_PIECES:
                        raise ValueError(f"{what}: the arclength cannot be tabulated near "
                                         f"parameter {a:.6g}: the speed nearly vanishes "
                                         f"there (a cusp, points out of order, or too "
                                         f"elongated an ellipse)")
                    todo += [(0.5 * (a + b), b), (a, 0.5 * (a + b))]
                    continue
                rows.append((s, width, a, b, coef, i))
                s += width
        s0, ds, t0, t1, coef, interval = (np.array(c) for c in zip(*rows))
        for arr in (s0, ds, t0, t1, coef, interval):
            arr.flags.writeable = False
        return cls(s0, ds, t0, t1, coef, interval, speed)


def _integral(speed, i, a, h):
    """int_0^h speed(a, tau, i) dtau for every h (Gauss-Legendre)."""
    h = np.asarray(h, dtype=float)
    return h / 2.0 * (speed(a, h[..., None] * (1.0 + _GAUSS_X) / 2.0, i) @ _GAUSS_W)


def _fit_piece(speed, i, a, b):
    """(arclength, Chebyshev coefficients of delta(s), unit-speed error) of the piece [a, b]
    of interval i: the largest |d(r0, z0)/ds| - 1 at the test points.

    With h = b - a, the piece's arclength w and x = 2 s / w - 1, t(s) = a + h (1 + x) / 2 +
    delta(s): Newton's method solves m delta + int_a^t (|c'| - m) = 0 (m = w / h) for delta
    at the Chebyshev points, so that its rounding scales with the variation of the speed on
    the piece, not with w (the derivative of the interpolant amplifies it ~ DEGREE**2).
    """
    h = b - a
    width = float(_integral(speed, i, a, h))
    if not (np.isfinite(width) and width > 0.0):
        return width, np.zeros(DEGREE + 1), math.inf
    mean = width / h
    deviation = lambda t0, tau, k: speed(t0, tau, k) - mean   # noqa: E731 (delta's integrand)
    linear = h * (1.0 + _CHEB_X) / 2.0
    delta = np.zeros(DEGREE + 1)
    for _ in range(60):
        tau = np.clip(linear + delta, 0.0, h)
        step = (mean * delta + _integral(deviation, i, a, tau)) / speed(a, tau, i)
        delta -= step
        if np.max(np.abs(step)) <= np.finfo(float).eps * max(np.max(np.abs(delta)), 1e-3 * h):
            break
    delta[[0, -1]] = 0.0                             # t(0) = a and t(w) = b exactly
    weights = np.full(DEGREE + 1, 2.0 / DEGREE)
    weights[[0, -1]] /= 2.0
    coef = _CHEB_DCT @ (weights * delta)
    coef[[0, -1]] /= 2.0
    cheb = np.polynomial.chebyshev
    tau = h * (1.0 + _CHEB_TEST) / 2.0 + cheb.chebval(_CHEB_TEST, coef)
    dtau = (h + 2.0 * cheb.chebval(_CHEB_TEST, cheb.chebder(coef))) / width
    error = np.max(np.abs(speed(a, tau, i) * dtau - 1.0))
    return width, coef, (error if np.isfinite(error) else math.inf)


# --------------------------------------------------------------------------- tabulated curves

def _rotated(cos0, sin0, tau, xp):
    """(cos(t0 + tau), sin(t0 + tau)) from cos t0, sin t0 by the addition theorem."""
    c, s = xp.cos(tau), xp.sin(tau)
    return cos0 * c - sin0 * s, sin0 * c + cos0 * s


@lru_cache(maxsize=64)
def _ellipse_table(p: float, q: float) -> ArclengthTable:
    """The arclength table of the whole ellipse (p sin a, q cos a), a in [0, 2 pi]."""
    def speed(t0, tau, i):
        cos_a, sin_a = _rotated(math.cos(t0), math.sin(t0), tau, np)
        return np.hypot(p * cos_a, q * sin_a)

    return ArclengthTable.build(np.linspace(0.0, 2 * math.pi, 5), speed, "Ellipse")


@dataclass(frozen=True)
class Ellipse(Segment):
    """An arc of the ellipse of semi-axes ``semi_r`` = p (radial) and ``semi_z`` = q (axial)
    centred on the axis at ``centre_z``: points (p sin a, centre_z + q cos a), the parameter a
    (not arclength, nor the polar angle of the point unless p = q) traced from a0 to a1.

    With d = sign(a1 - a0) and N = sqrt(p^2 cos^2 a + q^2 sin^2 a) (= |d(r, z)/da|):
    theta0 = a + atan((q - p) sin a cos a / (p cos^2 a + q sin^2 a)) (+ pi for d < 0), and
    k1 = -d p q / N^3, k2 = -d q / (p N) (the closed forms of the tests; at the pole a = 0
    both are -d q / p^2).

    Arclength: a(s) from the whole ellipse's :class:`ArclengthTable` (shared by all arcs of
    the same p and q, so that ``trace_key`` needs no table entries); sin a and cos a by the
    addition theorem from each piece's start. |d(r0, z0)/ds| - 1 <= 5e-14 between the nodes
    of every piece, measured <= 1e-13 at 10^5 points (for 1e-3 <= q / p <= 1e3), and theta0,
    k1 are the curve's own at a(s) (round-off). Beyond its ends the arc continues along the
    ellipse (periodically in a).

    Attributes:
        semi_r, semi_z: p, q > 0.
        centre_z: the centre's height.
        angle: (a0, a1), different, in [0, pi] (the half-plane r >= 0); keyword only.
    """

    semi_r: float
    semi_z: float
    centre_z: float = 0.0
    angle: tuple[float, float] = field(kw_only=True)
    _sigma0: float = field(init=False, repr=False, compare=False)   # S(a0) from a = 0

    def __post_init__(self):
        for name in ("semi_r", "semi_z"):
            object.__setattr__(self, name, float(check_positive(f"Ellipse.{name}",
                                                                getattr(self, name))))
        object.__setattr__(self, "centre_z", float(check_finite("Ellipse.centre_z",
                                                                self.centre_z)))
        object.__setattr__(self, "angle", _angle("Ellipse", self.angle, 0.0, math.pi,
                                                 "[0, pi]"))
        object.__setattr__(self, "_sigma0", self._arclength(self.angle[0]))

    @property
    def _table(self) -> ArclengthTable:
        return _ellipse_table(self.semi_r, self.semi_z)

    @property
    def _sign(self) -> float:
        return math.copysign(1.0, self.angle[1] - self.angle[0])

    def _arclength(self, a: float) -> float:
        """S(a) from a = 0 along the ellipse (a in [0, 2 pi])."""
        return float(self._table.arclength(a)[0])

    def _point(self, a):
        return (self.semi_r * math.sin(a), self.centre_z + self.semi_z * math.cos(a))

    @property
    def length(self) -> float:
        return abs(self._arclength(self.angle[1]) - self._sigma0)

    @property
    def start(self):
        return self._point(self.angle[0])

    @property
    def end(self):
        return self._point(self.angle[1])

    def _theta_shift(self) -> float:
        """theta0 - (a + atan(...)): 0 or pi by direction, plus the branch of theta0(0)."""
        p, q, a0 = self.semi_r, self.semi_z, self.angle[0]
        shift = 0.0 if self._sign > 0 else math.pi
        theta = a0 + math.atan2((q - p) * math.sin(a0) * math.cos(a0),
                                p * math.cos(a0) ** 2 + q * math.sin(a0) ** 2) + shift
        return shift + _branch(theta)

    def _parameter(self, u, xp):
        """(a, cos a, sin a) at local arclength u."""
        table, d = self._table, self._sign
        sigma = self._sigma0 + d * u
        turns = xp.floor(sigma / table.total)
        tau, i = table.parameter(sigma - turns * table.total, xp)
        t0 = xp.asarray(table.t0)[i]
        cos_a, sin_a = _rotated(xp.cos(t0), xp.sin(t0), tau, xp)
        return t0 + tau + 2 * math.pi * turns, cos_a, sin_a

    def evaluate(self, u, xp=np):
        p, q, d = self.semi_r, self.semi_z, self._sign
        u = xp.asarray(u, dtype=float)
        a, cos_a, sin_a = self._parameter(u, xp)
        theta = a + xp.arctan2((q - p) * sin_a * cos_a, p * cos_a**2 + q * sin_a**2)
        speed = xp.sqrt((p * cos_a) ** 2 + (q * sin_a) ** 2)
        return (p * sin_a, self.centre_z + q * cos_a, theta + self._theta_shift(),
                -d * p * q / speed**3)

    def trace_key(self) -> tuple:
        return ("ellipse", self.semi_r, self.semi_z, self.centre_z, self.angle[0], self._sign)

    def with_length(self, length):
        a, _, _ = self._parameter(np.asarray(float(length)), np)
        return replace(self, angle=(self.angle[0], float(a)))


@dataclass(frozen=True, eq=False)
class _Spline:
    """A planar spline c(t) = (r, z) by interval j of its breakpoints, and its table.

    Attributes:
        table: the arclength table (its intervals are the spline's).
        coef, d1, d2: (m, K + 1 | K | K - 1, 2) coefficients, ascending powers of t - x_j,
            of c, c' and c'' on each interval j.
        offset: (P,) t0 - x_j of every piece of the table (its local variable at tau = 0).
        theta_ref, cos_ref, sin_ref: (P,) the tangent angle at every piece's middle
            (unwrapped along the curve), from which theta0 is measured (so that atan2
            stays off its cut).
        knots, nodes: arclength at the interior breakpoints and at the given points.
    """

    table: ArclengthTable
    coef: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    offset: np.ndarray
    theta_ref: np.ndarray
    cos_ref: np.ndarray
    sin_ref: np.ndarray
    knots: tuple[float, ...]
    nodes: tuple[float, ...]

    def derivatives(self, u, xp):
        """(c, c', c'', piece index) at arclength u: arrays (..., 2)."""
        tau, k = self.table.parameter(u, xp)
        j = xp.asarray(self.table.interval)[k]
        v = xp.asarray(self.offset)[k] + tau
        return (_horner(xp.asarray(self.coef)[j], v), _horner(xp.asarray(self.d1)[j], v),
                _horner(xp.asarray(self.d2)[j], v), k)


def _mirrored(P: np.ndarray, poles: tuple[bool, bool]):
    """The data a pole's symmetry adds (the points reflected to r < 0 about each pole end),
    the index range of the given points in it, and whether the spline closes (two poles)."""
    n = len(P)
    mirror = P * np.array([-1.0, 1.0])
    if poles[1]:
        ext = np.concatenate([P, mirror[-2::-1]])           # closes at P[0] when poles[0]
        return (ext, 0, n - 1, True) if poles[0] else (ext, 0, n - 1, False)
    if poles[0]:
        return np.concatenate([mirror[:0:-1], P]), n - 1, 2 * n - 2, False
    return P, 0, n - 1, False


@lru_cache(maxsize=64)
def _spline_through(r: tuple, z: tuple) -> _Spline:
    """The curve of :class:`Points` and its arclength table (see there)."""
    from scipy.interpolate import make_interp_spline

    P = np.column_stack([r, z])
    ext, first, last, closed = _mirrored(P, (r[0] == 0.0, r[-1] == 0.0))
    t = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(ext, axis=0).T))])
    K = min(5, len(ext) - 1)
    spline = make_interp_spline(t, ext, k=K, bc_type="periodic" if closed else None)
    x = np.unique(np.concatenate([spline.t, t[[first, last]]]))
    x = x[(x >= t[first]) & (x <= t[last])]
    coef = np.stack([spline(x[:-1], nu=m) / math.factorial(m) for m in range(K + 1)], axis=1)
    d1 = coef[:, 1:] * np.arange(1, K + 1)[None, :, None]
    d2 = d1[:, 1:] * np.arange(1, K)[None, :, None]

    def speed(t0, tau, j):
        return np.linalg.norm(_horner(d1[j], (t0 - x[j]) + tau), axis=-1)

    _check_regular(speed, x, coef)
    table = ArclengthTable.build(x, speed, "Points")
    offset = table.t0 - x[table.interval]
    tangent = _horner(d1[table.interval], offset + (table.t1 - table.t0) / 2)
    theta_ref = np.unwrap(np.arctan2(-tangent[:, 1], tangent[:, 0]))
    curve = _Spline(table, coef, d1, d2, offset, theta_ref, np.cos(theta_ref),
                    np.sin(theta_ref), (), ())
    theta_ref = theta_ref + _branch(float(_points_theta(curve, np.zeros(1), np)[0]))
    nodes = table.arclength(t[first:last + 1])
    nodes[0] = 0.0
    curve = _Spline(table, coef, d1, d2, offset, theta_ref, np.cos(theta_ref),
                    np.sin(theta_ref), tuple(float(v) for v in table.arclength(x[1:-1])),
                    tuple(float(v) for v in nodes))
    _check_turn(curve)
    return curve


def _check_regular(speed, x, coef):
    """ValueError where the spline's tangent nearly vanishes (a cusp: points out of order)."""
    tau = (x[1:] - x[:-1])[:, None] * (1.0 + _GAUSS_X) / 2.0
    v = np.array([speed(x[j], tau[j], j) for j in range(len(x) - 1)])
    if v.min() <= 1e-6 * v.max():
        r, z = coef[int(np.argmin(v.min(axis=1))), 0]
        raise ValueError(f"Points: the curve through the points has a cusp (its tangent "
                         f"vanishes) after (r, z) = ({r:.6g}, {z:.6g}): are the points "
                         f"ordered along the curve?")


def _check_turn(curve: _Spline):
    """ValueError where the tangent turns by more than pi/2 within a piece of the table (the
    reference angle would not keep atan2 off its cut)."""
    table = curve.table
    s = table.s0[:, None] + table.ds[:, None] * np.linspace(0.0, 1.0, 9)[None, :]
    _, c1, _, k = curve.derivatives(s, np)
    turn = np.abs(wrap_angle(np.arctan2(-c1[..., 1], c1[..., 0]) - curve.theta_ref[k]))
    if turn.max() > math.pi / 2:
        raise ValueError("Points: the curve turns by more than pi/2 between two tabulation "
                         "nodes (a loop between the points?): add points there")


def _points_theta(curve: _Spline, u, xp):
    """theta0 of a :class:`Points` curve at arclength u: the reference angle of the piece plus
    the (small) angle of the tangent from it."""
    _, c1, _, k = curve.derivatives(u, xp)
    rp, zp = c1[..., 0], c1[..., 1]
    cr, sr = xp.asarray(curve.cos_ref)[k], xp.asarray(curve.sin_ref)[k]
    return xp.asarray(curve.theta_ref)[k] + xp.arctan2(-zp * cr - rp * sr, rp * cr - zp * sr)


@dataclass(frozen=True)
class Points(Segment):
    """A smooth curve through measured points (r_i, z_i), ordered along the meridian.

    The curve: a parametric interpolating spline c(t) = (r(t), z(t)) of degree 5 in the chord
    length t (the cumulative distance between consecutive points), with not-a-knot ends: C4
    (k1 is C2; its third derivative jumps at the breakpoints, listed by ``breaks``, where a
    spectral discretisation should cut). With 4 or 5 points (and no pole) it is the one
    polynomial of degree 3 or 4 through them (C-infinity). An end point on the axis
    (r = 0, to within 1e-12 of the points' extent) is a pole: the points reflected to r < 0
    about it are added before fitting (both ends: a periodic spline through the closed
    curve), so the curve is mirror-symmetric there and meets the axis at a right angle (to
    round-off) with k2 -> k1, whatever the points near it suggest (points along a cone's
    apex get a rounded tip within their first interval: cut the cone off or round it).

    Closeness: the curve passes through every point (measured <= 1e-15 relative to the
    points' extent at ``nodes``, their arclength positions). Through samples of a smooth
    curve with spacing h it approximates the curve to O(h^6) and its curvature to O(h^4)
    (measured on a circle and an ellipse: tests/test_geometry.py).

    Arclength: as :class:`Ellipse`, an :class:`ArclengthTable` of t(s) on the spline's
    intervals (|d(r0, z0)/ds| - 1 <= 5e-14 between the nodes of every piece), r0, z0, theta0
    and k1 = (r' z'' - z' r'') / |c'|^3 from the spline at t(s). The cost of an evaluation:
    the table (~ DEGREE multiply-adds) plus three Horner sums of degree <= 5. Beyond its ends
    the end pieces' polynomials continue. A measured curve has no natural continuation:
    ``with_length`` is refused.

    Attributes:
        r, z: the coordinates (at least 4 points, r >= 0, finite, all distinct).
    """

    r: tuple[float, ...]
    z: tuple[float, ...]
    _curve: _Spline = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        r = check_finite("Points.r", self.r).astype(float)
        z = check_finite("Points.z", self.z).astype(float)
        if r.ndim != 1 or z.shape != r.shape or len(r) < 4:
            raise ValueError(f"Points.r and Points.z must be sequences of equal length >= 4, "
                             f"got shapes {r.shape} and {z.shape}")
        if r.min() < 0:
            raise ValueError(f"Points.r must be >= 0 (the half-plane of the meridian), got "
                             f"r[{int(np.argmin(r))}] = {r.min()}")
        P = np.column_stack([r, z])
        if len(np.unique(P, axis=0)) < len(P):
            raise ValueError("Points: the points must be distinct (a point appears twice)")
        extent = max(np.ptp(r), np.ptp(z), r.max())
        for end in (0, -1):
            if r[end] <= AXIS_TOL * extent:
                r[end] = 0.0
        object.__setattr__(self, "r", tuple(float(v) for v in r))
        object.__setattr__(self, "z", tuple(float(v) for v in z))
        object.__setattr__(self, "_curve", _spline_through(self.r, self.z))

    @property
    def length(self) -> float:
        return self._curve.table.total

    @property
    def start(self):
        return (self.r[0], self.z[0])

    @property
    def end(self):
        return (self.r[-1], self.z[-1])

    @property
    def breaks(self) -> tuple[float, ...]:
        """Arclength at the spline's interior breakpoints (where the fifth derivative of
        (r0, z0) in s jumps)."""
        return self._curve.knots

    @property
    def nodes(self) -> tuple[float, ...]:
        """Arclength at each of the given points (the curve passes through them there)."""
        return self._curve.nodes

    def evaluate(self, u, xp=np):
        curve = self._curve
        u = xp.asarray(u, dtype=float)
        c, c1, c2, _ = curve.derivatives(u, xp)
        rp, zp = c1[..., 0], c1[..., 1]
        k1 = (rp * c2[..., 1] - zp * c2[..., 0]) / (rp**2 + zp**2) ** 1.5
        return c[..., 0], c[..., 1], _points_theta(curve, u, xp), k1

    def trace_key(self) -> tuple:
        return ("points", self.r, self.z)

    def with_length(self, length):
        raise ValueError("Points: a curve through measured points has no natural "
                         "continuation, so with_length is not defined; end the meridian with "
                         "a closed-form segment (e.g. a Cone or a Sphere) to vary its length")


# --------------------------------------------------------------------------- the meridian

@dataclass(frozen=True)
class _Layout:
    """What :class:`Meridian` derives from its segments on construction."""

    starts: tuple[float, ...]
    lengths: tuple[float, ...]
    offsets: tuple[float, ...]
    kinks: tuple[float, ...]
    size: float
    poles: tuple[bool, bool]


@dataclass(frozen=True)
class Meridian:
    """The reference meridian: segments joined end to end, traced by arclength s in [0, L].

    Validated on construction: consecutive segments meet (to ``MEET_TOL`` x ``size``); every
    segment has a positive length; r0 >= 0 everywhere (on ``SAMPLES`` points per smooth piece
    of every segment and at its local minima, to ``AXIS_TOL`` x ``size``); r0 = 0 only at the
    two ends (a joint or an interior point on the axis is "a pole inside the meridian"); a
    pole meets the axis at a right angle (theta0 = 0 mod 2 pi at the first end, pi mod 2 pi at
    the second, to ``RIGHT_ANGLE_TOL``). A joint may carry a kink (theta0 jumps).

    theta0 along the meridian is each segment's plus ``theta_offsets[i]`` (a multiple of
    2 pi), so that it is continuous but for the kinks (in (-pi, pi]) and theta0(0) lies in
    (-pi, pi]. A compiled kernel that evaluates segment i itself adds ``theta_offsets[i]``.

    Attributes:
        segments: the segments in order (a lone :class:`Segment` is a one-segment meridian).

    Raises:
        ValueError: naming the segment (index and type) and what is wrong.
        TypeError: where an entry is not a :class:`Segment`.
    """

    segments: tuple[Segment, ...]
    _layout: _Layout = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        segments = (self.segments,) if isinstance(self.segments, Segment) else \
            tuple(self.segments)
        if not segments:
            raise ValueError("Meridian: needs at least one segment")
        for i, seg in enumerate(segments):
            if not isinstance(seg, Segment):
                raise TypeError(f"Meridian: segment {i} is a {type(seg).__name__}, not a "
                                f"Segment")
        object.__setattr__(self, "segments", segments)
        lengths = _checked_lengths(segments)
        samples = [_sample(seg) for seg in segments]
        size = max(max(float(np.max(np.abs(r))) for _, r, _ in samples),
                   float(np.ptp(np.concatenate([z for _, _, z in samples]))))
        _check_meet(segments, size)
        poles = _check_axis(segments, samples, size)
        offsets, kinks = _branches(segments)
        _check_poles(segments, offsets, poles)
        starts = tuple(float(v) for v in np.concatenate([[0.0], np.cumsum(lengths)[:-1]]))
        object.__setattr__(self, "_layout", _Layout(starts, lengths, offsets, kinks, size,
                                                    poles))

    @property
    def length(self) -> float:
        """L, the meridian's arclength."""
        return self._layout.starts[-1] + self._layout.lengths[-1]

    @property
    def segment_starts(self) -> tuple[float, ...]:
        """s at the start of every segment (the first is 0)."""
        return self._layout.starts

    @property
    def joints(self) -> tuple[float, ...]:
        """Interior joint positions in s, increasing (segment i + 1 starts at joints[i])."""
        return self._layout.starts[1:]

    @property
    def kinks(self) -> tuple[float, ...]:
        """The jump of theta0 at every joint, right minus left, in (-pi, pi]."""
        return self._layout.kinks

    @property
    def theta_offsets(self) -> tuple[float, ...]:
        """Multiples of 2 pi added to each segment's theta0 (see the class docstring)."""
        return self._layout.offsets

    @property
    def poles(self) -> tuple[bool, bool]:
        """Whether the first and the second end is a pole (r0 = 0)."""
        return self._layout.poles

    @property
    def size(self) -> float:
        """A length scale for tolerances and internal scaling: the largest r0 or the extent
        in z, whichever is larger (> 0)."""
        return self._layout.size

    @property
    def rise(self) -> float:
        """|z0(L) - z0(0)|."""
        return abs(self.at_end("second")[1] - self.at_end("first")[1])

    def evaluate(self, s, xp=np):
        """(r0, z0, theta0, k1) at global arclength s (arrays shaped like s; host use).

        The segment holding s evaluates it (a joint belongs to the next segment); the first
        and the last segment continue beyond 0 and L.
        """
        s = xp.asarray(s, dtype=float)
        lay, n = self._layout, len(self.segments)
        index = _locate(lay.starts, s, xp)
        out = None
        for i, seg in enumerate(self.segments):
            u = xp.clip(s - lay.starts[i], -np.inf if i == 0 else 0.0,
                        np.inf if i == n - 1 else lay.lengths[i])
            r, z, theta, k1 = seg.evaluate(u, xp)
            values = (r, z, theta + lay.offsets[i], k1)
            out = values if out is None else tuple(xp.where(index == i, v, o)
                                                   for v, o in zip(values, out))
        return out

    def curvatures(self, s, xp=np):
        """(k1, k2) at s: k1 = -dtheta0/ds, k2 = -sin(theta0)/r0, and k2 = k1 where r0 = 0
        (to ``AXIS_TOL`` x ``size``: the pole limit)."""
        r, _, theta, k1 = self.evaluate(s, xp)
        off_axis = r > AXIS_TOL * self.size
        k2 = -xp.sin(theta) / xp.where(off_axis, r, 1.0)
        return k1, xp.where(off_axis, k2, k1)

    def at_end(self, which: str) -> tuple[float, float, float]:
        """(r0, z0, theta0) at the ``"first"`` (s = 0) or ``"second"`` (s = L) end."""
        if which not in ("first", "second"):
            raise ValueError(f"Meridian.at_end: which must be 'first' or 'second', got "
                             f"{which!r}")
        return self._end_points[0 if which == "first" else 1]

    @cached_property
    def _end_points(self) -> tuple:
        out = []
        for i, u in ((0, 0.0), (len(self.segments) - 1, self._layout.lengths[-1])):
            r, z, theta, _ = self.segments[i].evaluate(u)
            out.append((float(r), float(z), float(theta) + self._layout.offsets[i]))
        return tuple(out)

    def pieces(self, extra_cuts=()) -> tuple[tuple[float, float, int], ...]:
        """(a, b, segment index) of the pieces [a, b] that cover [0, L], cut at every joint
        and at ``extra_cuts`` (increasing, strictly inside (0, L), none on a joint: each to
        within 1e-12 L).

        Raises:
            ValueError: for cuts out of order, outside (0, L), or on a joint.
        """
        L, tol = self.length, 1e-12 * self.length
        cuts = [float(c) for c in np.atleast_1d(check_finite("Meridian.pieces: extra_cuts",
                                                             extra_cuts))]
        if any(b - a <= tol for a, b in zip(cuts, cuts[1:])):
            raise ValueError(f"Meridian.pieces: extra cuts must be strictly increasing, got "
                             f"{cuts}")
        for c in cuts:
            if not tol < c < L - tol:
                raise ValueError(f"Meridian.pieces: extra cut {c} must lie strictly inside "
                                 f"(0, L = {L})")
            near = [k for k, j in enumerate(self.joints) if abs(c - j) <= tol]
            if near:
                raise ValueError(f"Meridian.pieces: extra cut {c} lies on the joint at "
                                 f"s = {self.joints[near[0]]} (segments {near[0]} and "
                                 f"{near[0] + 1} meet there; joints are cuts already)")
        ends = [0.0, *sorted([*self.joints, *cuts]), L]
        index = _locate(self._layout.starts, 0.5 * (np.array(ends[:-1]) + ends[1:]), np)
        return tuple((a, b, int(i)) for a, b, i in zip(ends[:-1], ends[1:], index))

    def with_length(self, length: float) -> "Meridian":
        """The meridian with its last segment extended or shortened to total arclength
        ``length`` (same start and direction of that segment).

        Raises:
            ValueError: where ``length`` does not exceed the last segment's start, or the
                last segment refuses it (e.g. :class:`Points`).
        """
        length = float(check_finite("Meridian.with_length: length", length))
        start = self._layout.starts[-1]
        if not length > start:
            raise ValueError(f"Meridian.with_length: length must exceed the last segment's "
                             f"start s = {start} (its length would be <= 0), got {length}")
        return Meridian((*self.segments[:-1], self.segments[-1].with_length(length - start)))


def _name(i: int, seg: Segment) -> str:
    return f"segment {i} ({type(seg).__name__})"


def _checked_lengths(segments) -> tuple[float, ...]:
    lengths = tuple(float(seg.length) for seg in segments)
    for i, (seg, ell) in enumerate(zip(segments, lengths)):
        if not (math.isfinite(ell) and ell > 0.0):
            raise ValueError(f"Meridian: {_name(i, seg)} has length {ell}: a segment's length "
                             f"must be finite and > 0")
    return lengths


def _sample(seg: Segment):
    """(u, r0, z0) on ``SAMPLES`` intervals per smooth piece of the segment."""
    u = np.linspace(0.0, seg.length, SAMPLES * (len(seg.breaks) + 1) + 1)
    r, z, _, _ = seg.evaluate(u)
    return u, np.asarray(r, dtype=float), np.asarray(z, dtype=float)


def _check_meet(segments, size: float):
    for i, (a, b) in enumerate(zip(segments, segments[1:])):
        gap = math.dist(a.end, b.start)
        if gap > MEET_TOL * size:
            raise ValueError(f"Meridian: {_name(i + 1, b)} does not meet {_name(i, a)}: it "
                             f"starts at {b.start}, {gap:.3g} from the end {a.end} of "
                             f"segment {i} (tolerance {MEET_TOL} x size = "
                             f"{MEET_TOL * size:.3g})")


def _local_minima(seg: Segment, u, r):
    """(u, r0) at the interior local minima of r0 on the segment (samples refined by a
    bounded scalar minimisation)."""
    out = []
    for j in np.flatnonzero((r[1:-1] < r[:-2]) & (r[1:-1] <= r[2:])) + 1:
        from scipy.optimize import minimize_scalar

        res = minimize_scalar(lambda v: float(seg.evaluate(v)[0]), bounds=(u[j - 1], u[j + 1]),
                              method="bounded", options={"xatol": 1e-14 * seg.length})
        out.append((float(res.x), float(res.fun)) if res.fun < r[j] else (u[j], r[j]))
    return out


def _check_axis(segments, samples, size: float) -> tuple[bool, bool]:
    """r0 >= 0 everywhere and r0 = 0 only at the two ends; returns (first, second) is a
    pole."""
    tol, last = AXIS_TOL * size, len(segments) - 1
    for i, (seg, (u, r, _)) in enumerate(zip(segments, samples)):
        minima = _local_minima(seg, u, r)
        u_min, r_min = min([(u[j], r[j]) for j in (int(np.argmin(r)),)] + minima,
                           key=lambda m: m[1])
        if r_min < -tol:
            raise ValueError(f"Meridian: {_name(i, seg)} reaches r0 = {r_min:.6g} < 0 at its "
                             f"local s = {u_min:.6g}: a meridian lies in the half-plane "
                             f"r >= 0")
        inside = [(v, rv) for v, rv in minima + [(u[j], r[j]) for j in range(1, len(u) - 1)]
                  if rv <= tol]
        if inside:
            raise ValueError(f"Meridian: a pole inside the meridian: {_name(i, seg)} touches "
                             f"the axis (r0 = {inside[0][1]:.3g}) at its local "
                             f"s = {inside[0][0]:.6g}; a pole (r0 = 0) may only be an end")
        for end, is_joint in ((0, i > 0), (-1, i < last)):
            if is_joint and r[end] <= tol:
                k = i - 1 if end == 0 else i
                raise ValueError(f"Meridian: a pole inside the meridian: the joint of "
                                 f"{_name(k, segments[k])} and {_name(k + 1, segments[k + 1])} "
                                 f"is on the axis (r0 = {r[end]:.3g}); a pole (r0 = 0) may "
                                 f"only be an end")
    return bool(samples[0][1][0] <= tol), bool(samples[-1][1][-1] <= tol)


def _branches(segments) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """(theta_offsets, kinks): the 2 pi multiples that make theta0 continuous but for the
    kinks, wrapped to (-pi, pi]."""
    theta_start = [float(seg.evaluate(0.0)[2]) for seg in segments]
    offsets, kinks = [_branch(theta_start[0])], []
    for k, seg in enumerate(segments[:-1]):
        left = float(seg.evaluate(seg.length)[2]) + offsets[k]
        kink = float(wrap_angle(theta_start[k + 1] - left))
        kinks.append(kink)
        offsets.append(2 * math.pi * round((left + kink - theta_start[k + 1]) / (2 * math.pi)))
    return tuple(offsets), tuple(kinks)


def _check_poles(segments, offsets, poles):
    """A pole meets the axis at a right angle."""
    for which, (i, u, right) in zip(("first", "second"),
                                    ((0, 0.0, 0.0), (-1, segments[-1].length, math.pi))):
        if not poles[0 if which == "first" else 1]:
            continue
        theta = float(segments[i].evaluate(u)[2]) + offsets[i]
        if abs(float(wrap_angle(theta - right))) > RIGHT_ANGLE_TOL:
            k = i % len(segments)
            raise ValueError(f"Meridian: {_name(k, segments[k])} meets the axis at the "
                             f"meridian's {which} end with theta0 = {theta:.6g}, not at a right "
                             f"angle (theta0 = {'0' if right == 0 else 'pi'} mod 2 pi there): "
                             f"k2 = -sin(theta0)/r0 is unbounded at such a point (a cone's "
                             f"apex on the axis is singular: cut it off as a frustum or round "
                             f"it)")


# --------------------------------------------------------------------------- common shells

@lru_cache(maxsize=256)
def spherical_cap(theta: float, radius: float = 1.0) -> Meridian:
    """The cap of opening half-angle ``theta`` in (0, pi] of a sphere of radius ``radius``,
    from its top pole at z = 0: r0 = R sin(s/R), z0 = R (cos(s/R) - 1), theta0 = s/R (one
    object per (theta, radius): a meridian is immutable, and its checks run once)."""
    return Meridian((Sphere(radius, -float(radius), angle=(0.0, theta)),))


def closed_sphere(radius: float = 1.0) -> Meridian:
    """The sphere of radius ``radius`` centred at the origin, pole to pole (top first)."""
    return Meridian((Sphere(radius, angle=(0.0, math.pi)),))


def disc(radius: float) -> Meridian:
    """A flat disc of radius ``radius`` at z = 0, from its centre (a pole) outward."""
    return Meridian((Plate((0.0, radius)),))


def annulus(r_in: float, r_out: float) -> Meridian:
    """A flat annulus at z = 0 from r_in > 0 outward to r_out."""
    return Meridian((Plate((r_in, r_out)),))


def cylinder(radius: float, height: float) -> Meridian:
    """A cylinder of radius ``radius`` from z = 0 upward to ``height``."""
    return Meridian((Cylinder(radius, (0.0, height)),))
