"""Indenters given by samples or by a function: ``Profile`` (a tabulated profile, e.g. a
measured tip, held by the compiled core) and ``Axisymmetric`` (any profile f(r), sampled into
a table for the scene model and integrated by tanh-sinh quadrature for its own MDR profile,
the one thing only Python can evaluate; its contact radii and Lee-Radok depths are the
compiled core's bisection and quadrature of that profile). Lengths in m."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import _array, _optional_positive
from .errors import InvalidInputError, MdrviscError
from .geometry import Indenter

__all__ = ["Axisymmetric", "Profile", "PROFILE_SAMPLES"]


# Tanh-sinh (double exponential) rule on [0, pi/2]: theta = (pi/4) (1 + tanh((pi/2) sinh t)),
# t = k * _TS_STEP for |t| <= _TS_T_MAX. Step and range were chosen by comparison with the
# closed-form maps: power laws r^n (n from 1/4 to 4) and the sphere up to |x| = 0.95 R come out
# within 1e-15 relative (1e-11 up to 0.999 R), with 109 nodes.
_TS_STEP = 1.0 / 12.0
_TS_T_MAX = 4.5


def _tanh_sinh_sin_nodes():
    """Nodes sin(theta_k) and weights w_k of the tanh-sinh rule for integrals over [0, pi/2].

    Both endpoints are approached to ~1e-61 without being reached, which takes integrable
    endpoint singularities in stride. theta near 0 and pi/2 - theta near 0 are each computed
    without cancellation, and 1/cosh^2 without overflow.
    """
    count = round(_TS_T_MAX / _TS_STEP)
    t = _TS_STEP * np.arange(-count, count + 1)
    u = 0.5 * math.pi * np.sinh(t)
    theta = 0.5 * math.pi / (1.0 + np.exp(-2.0 * u))
    complement = 0.5 * math.pi / (1.0 + np.exp(2.0 * u))
    sin_theta = np.where(theta < 0.25 * math.pi, np.sin(theta), np.cos(complement))
    decay = np.exp(-2.0 * np.abs(u))
    sech_squared = 4.0 * decay / (1.0 + decay) ** 2
    weights = _TS_STEP * (math.pi / 4.0) * (math.pi / 2.0) * np.cosh(t) * sech_squared
    return sin_theta, weights


# Relative step of the central difference used when no derivative is given (see Axisymmetric).
_CBRT_EPS = float(np.finfo(np.float64).eps) ** (1.0 / 3.0)


#: A vectorised function of radii r (m, an array) to heights or slopes: an Axisymmetric
#: profile f(r) (m) or its derivative f'(r).
ProfileFunction = Callable[[np.ndarray], ArrayLike]


class Axisymmetric(Indenter):
    """Any axisymmetric indenter h = f(r).

    Parameters
    ----------
    f : callable
        Vectorised profile f(r) (m) of radii r >= 0 (m), with f(0) = 0 (checked to 1e-12 of
        its largest value at r = L/4, L/2, L, L = footprint half-width or 1 m) and f >= 0.
    df : callable, optional
        Its derivative f'(r) (dimensionless), vectorised. If None, a central difference with
        the relative step h = eps^(1/3) r is used: it balances the truncation error
        (~h^2 f''') against rounding (~eps f / h); for power-law-like profiles (f ~ r f') whose
        f is computed to full relative precision (no cancellation: e.g. a spherical cap as
        r^2 / (R + sqrt(R^2 - r^2))) the relative error is ~eps^(2/3) ~ 4e-11. Profiles that
        level off (f' << f / r) lose precision: give df for them. The points r +- h stay >= 0
        (and within ``radius``), so f is only called where it is defined.
    edge : float, optional
        Side of a centred square footprint (m).
    radius : float, optional
        Radius of a disc footprint (m); not together with ``edge``. Neither: unbounded.

    Notes
    -----
    The MDR profile is computed numerically: with r = ``|x|`` sin(theta) the weak singularity
    of the map goes away, g(x) = ``|x|`` * integral_0^{pi/2} f'(``|x|`` sin theta) d theta, which a
    tanh-sinh rule (109 nodes) evaluates for all x at once; f' may have integrable endpoint
    singularities (power laws r^n with n < 2, a sphere near its rim). Scale-free profiles
    (power laws) come out to ~1e-15 at every x; a profile with a feature of size l near the
    axis (f' changing over r ~ l) is resolved while ``|x|`` is within a few decades of l (relative
    error ~1e-10 at ``|x|`` = 10 l, ~1e-7 at 100 l for a bump of width l).
    """

    def __init__(self, f: ProfileFunction, df: ProfileFunction | None = None,
                 edge: float | None = None, radius: float | None = None) -> None:
        if not callable(f):
            raise InvalidInputError(f"Axisymmetric: f must be callable, got {f!r}")
        if df is not None and not callable(df):
            raise InvalidInputError(f"Axisymmetric: df must be callable or None, got {df!r}")
        if edge is not None and radius is not None:
            raise InvalidInputError(
                f"Axisymmetric: give edge or radius, not both (got edge={edge!r}, "
                f"radius={radius!r})"
            )
        self._edge = _optional_positive("Axisymmetric", "edge", edge)
        self._radius = _optional_positive("Axisymmetric", "radius", radius)
        self._function = _Function(f, df, self._radius, self._edge)
        self._core = self._build()

    def _build(self):
        fills = True
        if self._radius is not None:
            try:  # g diverges at the rim (a spherical cap): the contact never fills the disc
                with np.errstate(divide="ignore", invalid="ignore"):
                    self._function.profile(np.array([self._radius]))
            except InvalidInputError:
                fills = False
        return _core.Indenter.from_functions(self._function.height, self._function.profile,
                                             edge=self._edge, radius=self._radius, fills=fills)

    @property
    def f(self) -> ProfileFunction:
        """The profile f(r) (m)."""
        return self._function.f

    @property
    def df(self) -> ProfileFunction | None:
        """The derivative f'(r) given by the caller, or None (central differences)."""
        return self._function.df

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None."""
        return self._edge

    @property
    def radius(self) -> float | None:
        """Radius of the disc footprint (m), or None."""
        return self._radius

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile g(x) (m) at ``x`` (m) by tanh-sinh quadrature (see the class docstring).

        For a disc footprint ``|x|`` <= radius is required.
        """
        return self._function.profile(self._coordinates(x))

    def contact_radius_at_depth(self, d: float) -> float:
        """Contact radius a (m) with g(a) = ``d`` (m), by the compiled core's bisection on the
        numerical profile.

        A disc footprint caps a at its radius. Otherwise a is sought up to 2^20 times the
        footprint's half-width (or 1 m when unbounded); DomainError when no radius there
        reaches d.
        """
        return super().contact_radius_at_depth(d)

    def _model(self, extent=None):
        """The profile sampled at PROFILE_SAMPLES equal steps of r from 0 to the footprint's
        farthest point (a disc's radius, a square's corner) or, unbounded, to ``extent``,
        with its slopes; where a slope is not finite (a cap's rim) without slopes."""
        if self._radius is not None:
            extent = self._radius
        elif self._edge is not None:
            extent = self._edge / math.sqrt(2.0)
        elif extent is None:
            raise InvalidInputError("Axisymmetric: an unbounded profile needs an extent to be tabulated")
        r = np.linspace(0.0, extent, PROFILE_SAMPLES)
        h = self._function.height(r)
        inner = np.concatenate([[r[1] * 1e-6], r[1:]])
        with np.errstate(divide="ignore", invalid="ignore"):
            try:
                slope = self._function.slope(inner)
            except InvalidInputError:
                slope = None
        table = {"type": "profile", "r": r.tolist(), "h": h.tolist()}
        if slope is not None and np.all(np.isfinite(slope)):
            table["slope"] = slope.tolist()
        if self._radius is not None:
            table["radius"] = self._radius
        return {**table, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Axisymmetric(f=<name>, df=<name or None>, edge=..., radius=...)``."""

        def name(func):
            return None if func is None else getattr(func, "__qualname__", repr(func))

        return (
            f"Axisymmetric(f={name(self.f)}, df={name(self.df)}, edge={self._edge!r}, "
            f"radius={self._radius!r})"
        )


class _Function:
    """An Axisymmetric's profile f(r) (m) with its slope and its MDR profile g(x) (m) by
    tanh-sinh quadrature: what the compiled core calls back (it holds no reference to the
    indenter, so the two form no cycle). ``radius`` (m) bounds a disc footprint, ``edge`` (m)
    a square one; f is checked at construction (see Axisymmetric)."""

    # x values per block of the vectorised quadrature (block * nodes ~ 2^18 evaluations).
    _BLOCK = 2048

    def __init__(self, f, df, radius, edge):
        self.f, self.df, self.radius = f, df, radius
        size = radius or (None if edge is None else 0.5 * edge) or 1.0
        values = self._call(f, "f", size * np.array([0.0, 0.25, 0.5, 1.0]), checking=True)
        self.scale = float(np.max(np.abs(values[1:])))
        if self.scale == 0.0 and radius is None and edge is None:
            raise InvalidInputError(
                f"Axisymmetric: f is 0 at r = 0, {0.25 * size!r}, {0.5 * size!r} and {size!r} m: a flat "
                f"profile without a footprint has no contact radius to solve for (a flat punch is "
                f"mdrvisc.Rod, or give a radius or an edge)")
        if abs(values[0]) > 1e-12 * self.scale:
            raise InvalidInputError(
                f"Axisymmetric: f(0) must be 0 (the tip is the origin), got {float(values[0])!r}"
            )
        if df is not None:
            self._call(df, "df", size * np.array([0.25, 0.5]), checking=True)
        self.sin_theta, self.weights = _tanh_sinh_sin_nodes()

    @staticmethod
    def _call(func, name, r, checking=False):
        """``func(r)`` as a finite float64 array of r's shape, or InvalidInputError. While
        ``checking`` (at construction) any error of the function itself is an
        InvalidInputError naming it; later (inside a computation) an error other than a
        TypeError or ValueError comes back as itself."""
        def not_an_array(exc):
            return InvalidInputError(f"Axisymmetric: {name} must map an array of radii to an array "
                                     f"of the same shape ({exc})")

        try:
            values = func(r)
        except MdrviscError:
            raise
        except Exception as exc:
            if checking:
                label = getattr(func, "__qualname__", repr(func))
                raise InvalidInputError(
                    f"Axisymmetric: {name} = {label} raised {type(exc).__name__} at radii from "
                    f"{float(r.min())!r} to {float(r.max())!r} m: {exc}"
                ) from exc
            if isinstance(exc, (TypeError, ValueError)):
                raise not_an_array(exc) from None
            raise
        try:
            out = np.broadcast_to(np.asarray(values, dtype=np.float64), r.shape)
        except (TypeError, ValueError) as exc:
            raise not_an_array(exc) from None
        bad = ~np.isfinite(out)
        if bad.any():
            raise InvalidInputError(
                f"Axisymmetric: {name}(r) is not finite at r = {float(r[bad].flat[0])!r}"
            )
        return out

    def height(self, r):
        """f(r) (m) at radii ``r`` (m), checked: >= 0 (to 1e-12 of its scale), clipped at 0."""
        h = self._call(self.f, "f", r)
        if (h < -1e-12 * self.scale).any():
            raise InvalidInputError(
                f"Axisymmetric: f must be >= 0 (height above the tip), got "
                f"{float(h.min())!r}"
            )
        return np.maximum(h, 0.0)

    def slope(self, r):
        """f'(r) (dimensionless) at radii r > 0 (m)."""
        if self.df is not None:
            return self._call(self.df, "df", r)
        step = _CBRT_EPS * r
        upper = r + step
        if self.radius is not None:
            upper = np.minimum(upper, self.radius)
        lower = r - step
        return (self._call(self.f, "f", upper) - self._call(self.f, "f", lower)) / (upper - lower)

    def profile(self, x):
        """g(x) (m) at ``x`` (m, any shape) by the tanh-sinh rule."""
        flat = np.abs(np.asarray(x, dtype=np.float64)).ravel()
        g = np.zeros_like(flat)
        positive = np.flatnonzero(flat)
        for start in range(0, positive.size, self._BLOCK):
            index = positive[start : start + self._BLOCK]
            r = flat[index, np.newaxis] * self.sin_theta
            g[index] = flat[index] * (self.slope(r) @ self.weights)
        return g.reshape(np.shape(x))


#: Samples of an Axisymmetric profile in the scene model (cubic Hermite between them).
PROFILE_SAMPLES = 4001


class Profile(Indenter):
    """A tabulated axisymmetric indenter: a measured tip or any profile known at samples.

    Parameters
    ----------
    r : array_like
        Radii (m), from 0, increasing.
    h : array_like
        Heights above the tip (m) at ``r``: h[0] = 0, h >= 0.
    slope : array_like, optional
        dh/dr at ``r``; with it h is the cubic Hermite interpolant between samples, without
        it piecewise linear.
    edge, radius : float, optional
        Side of a centred square footprint, or radius of a disc footprint (m). Neither:
        unbounded, up to the last sample (a solve that needs more is an error).

    Notes
    -----
    The MDR profile g(x) = x integral_0^x h'(r) / sqrt(x^2 - r^2) dr of the interpolant is
    integrated exactly at the samples (and interpolated between them) by the compiled core,
    which also validates the table.
    """

    def __init__(self, r: ArrayLike, h: ArrayLike, slope: ArrayLike | None = None,
                 edge: float | None = None, radius: float | None = None) -> None:
        self._r = _array("Profile", "r", r).ravel()
        self._h = _array("Profile", "h", h).ravel()
        self._slope_samples = None if slope is None else _array("Profile", "slope", slope).ravel()
        self._edge = _optional_positive("Profile", "edge", edge)
        self._radius = _optional_positive("Profile", "radius", radius)
        self._core = self._build()

    def _build(self):
        return _core.Indenter.profile(self._r, self._h, self._slope_samples, self._edge,
                                      self._radius)

    @property
    def r(self) -> np.ndarray:
        """Sample radii (m)."""
        return self._r

    @property
    def h(self) -> np.ndarray:
        """Heights at the samples (m)."""
        return self._h

    @property
    def slope(self) -> np.ndarray | None:
        """Slopes at the samples, or None (piecewise linear)."""
        return self._slope_samples

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None."""
        return self._edge

    @property
    def radius(self) -> float | None:
        """Radius of the disc footprint (m), or None."""
        return self._radius

    def _model(self, extent=None):
        table = {"type": "profile", "r": self._r.tolist(), "h": self._h.tolist()}
        if self._slope_samples is not None:
            table["slope"] = self._slope_samples.tolist()
        if self._radius is not None:
            table["radius"] = self._radius
        return {**table, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Profile(<n> samples up to r=..., slope=..., edge=..., radius=...)``."""
        return (f"Profile({self._r.size} samples up to r={float(self._r[-1])!r}, "
                f"slope={'given' if self._slope_samples is not None else None}, "
                f"edge={self._edge!r}, radius={self._radius!r})")
