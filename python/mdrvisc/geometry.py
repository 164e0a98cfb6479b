"""Rigid indenters: 2D height maps for the BEM and 1D profiles for the MDR.

Units: lengths in m, angles in radians. Sign convention: h(x, y) >= 0 is the height of the
indenter surface above its tip; the tip sits at the origin and the axis at x = y = 0. Every
indenter here but the four-sided :class:`Pyramid` is axisymmetric, h = f(r) with
r = sqrt(x^2 + y^2); the pyramid is solved exactly by the BEM and as an equivalent cone by MDR.
Each has a footprint (the part of the plane it
covers, where it can touch): a disc, a centred square of edge L (``edge``), or the whole plane
(unbounded). Its MDR profile is g(x) = ``|x|`` * integral_0^``|x|`` f'(r) / sqrt(x^2 - r^2) dr
(Popov & Hess), the 1D indenter that, pressed into a foundation of independent elements,
reproduces the depth, force and contact radius of the 3D contact; a square footprint of edge
L maps to a 1D indenter of half-length L / sqrt(pi) (equal area). Tabulated and
user-defined profiles are in :mod:`mdrvisc.profiles`.
"""

import abc
import math

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import _array, _optional_positive, _out, _positive
from .analytic import cone_depth, paraboloid_depth, sphere_mdr_profile
from .errors import DomainError, InvalidInputError

__all__ = ["Indenter", "Rod", "Paraboloid", "Cone", "Sphere", "Pyramid"]


def _bisect(g, target, hi):
    """Root a in [0, hi] of the increasing function g(a) = target, to the last bit.

    Requires g(0) <= target <= g(hi); g is only called strictly inside (0, hi), so ``hi`` may be
    a point where g is undefined (the sphere's rim).
    """
    lo = 0.0
    while True:
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            return hi
        if g(mid) < target:
            lo = mid
        else:
            hi = mid


class Indenter(abc.ABC):
    """A rigid indenter: height map, footprint and MDR profile (axisymmetric, or the
    pyramid's equivalent cone).

    Subclasses describe the footprint with ``_disc`` (its radius, m) or ``_square`` (its edge,
    m); neither means an unbounded footprint.
    """

    _disc = None
    _square = None
    #: Whether element centres exactly on the rim of a disc footprint belong to it.
    _rim_inside = True

    @abc.abstractmethod
    def _model(self, extent: float | None = None) -> dict:
        """The indenter in the scene model's form (a scene file's ``[indenter]`` table);
        ``extent`` (m) is how far an unbounded sampled profile must be tabulated."""

    def _footprint_model(self) -> dict:
        """``edge`` or nothing, for the scene model."""
        return {} if self._square is None else {"edge": self._square}

    def height_map(self, x: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Heights of the indenter over a grid of element centres.

        Parameters: x (nx,), y (ny,) 1-D arrays of element-centre coordinates (m).
        Returns ``(h, mask)``: h, float64 C-contiguous (ny, nx) array of heights above the tip
        (m; row index = y index), and mask, bool (ny, nx) array, True where the centre lies in
        the footprint. Outside the mask h is 0.0 (the solver ignores it there).
        """
        name = type(self).__name__
        x = _array(name, "x", x)
        y = _array(name, "y", y)
        for axis, values in (("x", x), ("y", y)):
            if values.ndim != 1 or values.size == 0:
                raise InvalidInputError(
                    f"{name}: {axis} must be a non-empty 1-D array, got shape {values.shape}"
                )
        xx, yy = np.meshgrid(x, y)
        r = np.hypot(xx, yy)
        if self._disc is not None:
            mask = r <= self._disc if self._rim_inside else r < self._disc
        elif self._square is not None:
            half = 0.5 * self._square
            mask = (np.abs(xx) <= half) & (np.abs(yy) <= half)
        else:
            mask = np.ones(r.shape, dtype=bool)
        h = np.zeros(r.shape)
        h[mask] = self._surface(xx[mask], yy[mask])
        return h, mask

    def _surface(self, x, y):
        """Height (m) of the true shape at points (``x``, ``y``) (m, 1-D arrays) inside the
        footprint: f(r) for an axisymmetric indenter."""
        return self._height(np.hypot(x, y))

    @abc.abstractmethod
    def _height(self, r):
        """Height f(r) (m) at radii ``r`` (m, 1-D array) inside the footprint, of the
        axisymmetric indenter MDR solves."""

    @property
    def footprint_half_width(self) -> float | None:
        """Half the side of the smallest centred square holding the footprint (m).

        Disc: its radius; square of edge L: L/2; unbounded: None.
        """
        if self._disc is not None:
            return self._disc
        if self._square is not None:
            return 0.5 * self._square
        return None

    @property
    def mdr_half_length(self) -> float | None:
        """Half-length of the 1D MDR indenter (m).

        Disc: its radius; square of edge L: L / sqrt(pi) (equal area); unbounded: None.
        """
        if self._disc is not None:
            return self._disc
        if self._square is not None:
            return self._square / math.sqrt(math.pi)
        return None

    @property
    def is_flat(self) -> bool:
        """True for a flat face (the rod), whose contact never changes."""
        return False

    def _coordinates(self, x):
        """``x`` (m) validated for :meth:`profile_1d`: finite, and on the 1D indenter of a disc
        footprint (``|x|`` <= radius; < radius where the rim is outside the footprint)."""
        name = type(self).__name__
        x = _array(name, "x", x)
        if self._disc is not None:
            off = np.abs(x) > self._disc if self._rim_inside else np.abs(x) >= self._disc
            if off.any():
                bound = "<=" if self._rim_inside else "<"
                raise InvalidInputError(
                    f"{name}: profile_1d needs |x| {bound} {self._disc!r} (the 1D indenter), "
                    f"got x = {float(x[off].flat[0])!r}"
                )
        return x

    def _depth(self, d):
        """Tip depth ``d`` (m) validated for :meth:`contact_radius_at_depth`: finite, >= 0."""
        d = _array(type(self).__name__, "d", d, minimum=0.0)
        if d.ndim != 0:
            raise InvalidInputError(
                f"{type(self).__name__}: d must be a single depth, got shape {d.shape}"
            )
        return float(d)

    @abc.abstractmethod
    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR 1D profile g(x) (m), even in x; float64 array of the shape of ``x`` (m)."""

    @abc.abstractmethod
    def contact_radius_at_depth(self, d: float) -> float:
        """Radius a (m) of the 3D contact at tip depth ``d`` (m), from the MDR relation d = g(a).

        Holds for elastic and viscous half-spaces alike. The footprint's edge is ignored except
        for discs, whose radius caps a (the contact then covers the whole face).
        """

    def depth_from_impulse(self, impulse: ArrayLike, eta: float) -> float | np.ndarray:
        """Depth (m) of the indenter pressed into a viscous half-space by an impulse.

        Monotone contact (Lee-Radok) through MDR: the depth d and contact radius a solve
        g(a) = d and 4 eta * integral_{-a}^{a} (d - g(x)) dx = J, with g the 1D profile and J
        the impulse (integral of the force over time, N s; F t for a constant force F from
        first touch). Parameters: impulse J >= 0 (N s, scalar or array), viscosity eta
        (Pa s); a float for a scalar impulse, else an array of its shape. By Radok's
        correspondence the same map gives the elastic depth under a force F with J -> F and
        eta -> G.

        Rod, Paraboloid and Cone use closed forms (:mod:`mdrvisc.analytic`); other indenters
        are solved numerically (bisection on a, Gauss-Legendre quadrature of the integral). Once
        the contact fills a disc footprint of radius R (Rod, ``Axisymmetric(..., radius=R)``)
        the indenter moves on like a rod: d = g(R) + (J - J_R) / (8 eta R). Raises
        DomainError once the contact circle reaches the edge of a square footprint, where it
        stops being circular and no closed form applies.
        """
        owner = f"{type(self).__name__}.depth_from_impulse"
        impulse = _array(owner, "impulse", impulse, minimum=0.0)
        eta = _positive(owner, "eta", eta)
        return self._depth_from_impulse(impulse, eta)

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """:meth:`depth_from_impulse` for a validated ``impulse`` (array, N s) and ``eta``
        (Pa s). Here numerically; subclasses with a closed form or a bounded footprint
        override it."""
        return _LeeRadok(self, eta, disc=None, rim=None,
                         edge=getattr(self, "edge", None)).depths(impulse)

    def _check_square(self, depth, impulse):
        """DomainError if the contact circle at the largest ``depth`` (m) outgrows the square
        footprint (the largest ``impulse``, N s, is named); nothing without a square."""
        if self._square is not None and np.size(depth):
            radius = self.contact_radius_at_depth(float(np.max(depth)))
            if radius > 0.5 * self._square:
                raise _edge_error(self, float(np.max(impulse)))


class Rod(Indenter):
    """Flat cylindrical punch of radius ``radius`` (m): h = 0 on the disc r <= radius.

    Its MDR image is a flat line, g = 0 for ``|x|`` <= radius.
    """

    def __init__(self, radius: float) -> None:
        self._disc = _positive("Rod", "radius", radius)

    @property
    def radius(self) -> float:
        """Radius of the face (m)."""
        return self._disc

    @property
    def is_flat(self) -> bool:
        """True: the rod's contact is its whole face, at every depth."""
        return True

    def _height(self, r):
        return np.zeros_like(r)

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile g = 0 (m) for ``|x|`` <= radius (m); other x raise InvalidInputError."""
        return np.zeros_like(self._coordinates(x))

    def contact_radius_at_depth(self, d: float) -> float:
        """The rod's radius (m): the whole face touches at any depth ``d`` >= 0 (m)."""
        self._depth(d)
        return self._disc

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """8 eta a d = J: the rod's depth rate is F / (8 a eta)."""
        return _out(impulse / (8.0 * eta * self._disc))

    def _model(self, extent=None):
        return {"type": "rod", "radius": self._disc}

    def __repr__(self) -> str:
        """``Rod(radius=...)``."""
        return f"Rod(radius={self._disc!r})"


class Paraboloid(Indenter):
    """Paraboloid of revolution h = c r^2 (radius of curvature R = 1/(2c)).

    Parameters: ``c`` (1/m) > 0; ``edge`` (m): side of a centred square footprint, or None for
    an unbounded paraboloid. MDR profile g = 2 c x^2.
    """

    def __init__(self, c: float, edge: float | None = None) -> None:
        self._c = _positive("Paraboloid", "c", c)
        self._square = _optional_positive("Paraboloid", "edge", edge)

    @property
    def c(self) -> float:
        """Curvature parameter c (1/m) of h = c r^2."""
        return self._c

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None (unbounded)."""
        return self._square

    def _height(self, r):
        return self._c * r * r

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile g = 2 c x^2 (m) at ``x`` (m)."""
        x = self._coordinates(x)
        return 2.0 * self._c * x * x

    def contact_radius_at_depth(self, d: float) -> float:
        """Contact radius a = sqrt(d / (2c)) (m) at depth ``d`` (m)."""
        return math.sqrt(self._depth(d) / (2.0 * self._c))

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """Closed form d = (3 J sqrt(2c) / (16 eta))^(2/3) (:func:`analytic.paraboloid_depth`)."""
        depth = paraboloid_depth(impulse, 1.0, self._c, eta)
        self._check_square(depth, impulse)
        return depth

    def _model(self, extent=None):
        return {"type": "paraboloid", "c": self._c, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Paraboloid(c=..., edge=...)``."""
        return f"Paraboloid(c={self._c!r}, edge={self._square!r})"


class Cone(Indenter):
    """Cone h = slope * r.

    Parameters: ``slope`` (dimensionless, the cotangent of the half-opening angle) > 0;
    ``edge`` (m): side of a centred square footprint, or None (unbounded). MDR profile
    g = (pi/2) slope ``|x|``.
    """

    def __init__(self, slope: float, edge: float | None = None) -> None:
        self._slope = _positive("Cone", "slope", slope)
        self._square = _optional_positive("Cone", "edge", edge)

    @property
    def slope(self) -> float:
        """Slope s of h = s r (dimensionless)."""
        return self._slope

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None (unbounded)."""
        return self._square

    def _height(self, r):
        return self._slope * r

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile g = (pi/2) slope ``|x|`` (m) at ``x`` (m)."""
        x = self._coordinates(x)
        return 0.5 * math.pi * self._slope * np.abs(x)

    def contact_radius_at_depth(self, d: float) -> float:
        """Contact radius a = 2 d / (pi slope) (m) at depth ``d`` (m)."""
        return 2.0 * self._depth(d) / (math.pi * self._slope)

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """Closed form d = sqrt(pi s J / (8 eta)) (:func:`analytic.cone_depth`)."""
        depth = cone_depth(impulse, 1.0, self._slope, eta)
        self._check_square(depth, impulse)
        return depth

    def _model(self, extent=None):
        return {"type": "cone", "slope": self._slope, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Cone(slope=..., edge=...)``."""
        return f"Cone(slope={self._slope!r}, edge={self._square!r})"


class Sphere(Indenter):
    """Exact spherical cap of radius ``radius`` = R (m): h = R - sqrt(R^2 - r^2) for r < R.

    Footprint: the open disc r < R. MDR profile (closed form)
    g(x) = (``|x|``/2) ln((R + ``|x|``) / (R - ``|x|``)) for ``|x|`` < R, growing without bound at the rim.
    """

    _rim_inside = False

    def __init__(self, radius: float) -> None:
        self._disc = _positive("Sphere", "radius", radius)

    @property
    def radius(self) -> float:
        """Radius R of the sphere (m)."""
        return self._disc

    def _height(self, r):
        radius = self._disc
        return r * r / (radius + np.sqrt((radius - r) * (radius + r)))

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile g(x) (m) at ``x`` (m); ``|x|`` >= radius raises InvalidInputError."""
        x = self._coordinates(x)
        return np.asarray(sphere_mdr_profile(x, self._disc), dtype=np.float64)

    def contact_radius_at_depth(self, d: float) -> float:
        """Contact radius a < R (m) with g(a) = ``d`` (m), by bisection on the closed form."""
        d = self._depth(d)
        return _bisect(lambda a: sphere_mdr_profile(a, self._disc), d, self._disc)

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """Numerical; the rim, where g diverges, bounds the contact radius."""
        return _LeeRadok(self, eta, disc=None, rim=self._disc, edge=None).depths(impulse)

    def _model(self, extent=None):
        return {"type": "sphere", "radius": self._disc}

    def __repr__(self) -> str:
        """``Sphere(radius=...)``."""
        return f"Sphere(radius={self._disc!r})"


class Pyramid(Indenter):
    """Four-sided pyramid h = max(``|x|``, ``|y|``) / tan(alpha), the usual AFM cantilever tip.

    Parameters: ``half_angle`` alpha (radians, in (0, pi/2)): the face half-angle, between the
    axis and a face (``math.radians(35)`` for a 35 degree tip); ``edge`` (m): side of the
    square base, a centred square footprint, or None (unbounded). Its faces are normal to x
    and y, its edges run along the diagonals.

    The BEM solves the exact pyramid. MDR needs an axisymmetric indenter and solves the
    equivalent cone (:attr:`equivalent_cone`) of half-opening angle psi,
    tan(psi) = 0.7453 (pi/2) tan(alpha): Bilodeau's (1992) approximation, elastic force
    F = 0.7453 E / (1 - nu^2) tan(alpha) d^2 (the model of AFM tools such as nanite). The
    BEM of the exact pyramid, converged in the element size, carries 1.04 % less force at a
    given depth (F = 0.7376 E / (1 - nu^2) tan(alpha) d^2); the cone of equal projected area
    at every depth, tan(psi) = 2 tan(alpha) / sqrt(pi), would carry 2.6 % less than the BEM.
    Contact radius, in both methods: the radius sqrt(A / pi) of the disc of the contact's
    area A; the cone's is 8 % larger than the pyramid's at the same force (the pyramid's
    contact is a square with inward-curved sides and corners along its edges).
    """

    def __init__(self, half_angle: float, edge: float | None = None) -> None:
        alpha = _positive("Pyramid", "half_angle", half_angle)
        if not alpha < 0.5 * math.pi:
            hint = (f" ({alpha!r} degrees is math.radians({alpha!r}) = {math.radians(alpha)!r})"
                    if alpha < 90.0 else "")
            raise InvalidInputError(
                f"Pyramid: half_angle must be an angle in (0, pi/2) radians, got {alpha!r}{hint}")
        self._alpha = alpha
        self._square = _optional_positive("Pyramid", "edge", edge)
        self._cone = Cone(slope=1.0 / (_core.EQUIVALENT_CONE_FACTOR * math.tan(alpha)), edge=self._square)

    @property
    def half_angle(self) -> float:
        """Face half-angle alpha (radians)."""
        return self._alpha

    @property
    def edge(self) -> float | None:
        """Side of the square base (m), or None (unbounded)."""
        return self._square

    @property
    def equivalent_cone(self) -> Cone:
        """The cone MDR solves in its place: slope cot(psi) = 1 / (0.7453 (pi/2) tan(alpha)),
        the same footprint."""
        return self._cone

    def _surface(self, x, y):
        return np.maximum(np.abs(x), np.abs(y)) / math.tan(self._alpha)

    def _height(self, r):
        return self._cone._height(r)

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR profile (m) of the equivalent cone, g = (pi/2) cot(psi) ``|x|``, at ``x`` (m)."""
        return self._cone.profile_1d(x)

    def contact_radius_at_depth(self, d: float) -> float:
        """The equivalent cone's contact radius a = 2 d / (pi cot(psi)) (m) at depth ``d`` (m):
        the radius of the disc of the pyramid's contact area."""
        return self._cone.contact_radius_at_depth(d)

    def _depth_from_impulse(self, impulse: np.ndarray, eta: float) -> float | np.ndarray:
        """The equivalent cone's closed form (:func:`analytic.cone_depth`)."""
        depth = cone_depth(impulse, 1.0, self._cone.slope, eta)
        self._check_square(depth, impulse)
        return depth

    def _model(self, extent=None):
        return {"type": "pyramid", "half_angle": self._alpha, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Pyramid(half_angle=..., edge=...)``."""
        return f"Pyramid(half_angle={self._alpha!r}, edge={self._square!r})"


# ----------------------------------------------------------------------------- Lee-Radok
def _edge_error(indenter, impulse):
    """The DomainError for a contact circle that outgrows a square footprint."""
    return DomainError(
        f"{type(indenter).__name__}.depth_from_impulse: at an impulse of {impulse!r} N s the "
        f"contact radius of {indenter!r} exceeds half the edge ({0.5 * indenter.edge!r} m); "
        "the contact is no longer circular"
    )


#: Gauss-Legendre rule of the Lee-Radok impulse integral (exact for polynomials of degree 127).
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(64)


class _LeeRadok:
    """Numerical Lee-Radok depth of one indenter from J(a) = 8 eta int_0^a (g(a) - g(x)) dx.

    ``disc``: radius of a disc footprint the contact can fill (then the indenter moves on like a
    rod); ``rim``: radius where g diverges (the sphere), which bounds the contact radius;
    ``edge``: side of a square footprint, whose half bounds it. None of them: the contact radius
    is sought up to 2^20 m.
    """

    def __init__(self, indenter, eta, disc, rim, edge):
        self.indenter = indenter
        self.eta = eta
        self.disc = disc
        self.rim = rim
        self.edge = edge

    def depths(self, impulse):
        """Depths (m) at the validated ``impulse`` array (N s): a float for a 0-d one."""
        return _out(np.vectorize(self, otypes=[np.float64])(impulse))

    def g(self, x):
        """The indenter's 1D profile at one point (m)."""
        return float(self.indenter.profile_1d(x))

    def impulse(self, a):
        """Impulse (N s) that brings the contact radius to ``a`` (m): 8 eta times
        integral_0^a (g(a) - g(x)) dx by Gauss-Legendre quadrature on nodes graded towards
        x = a, x = a (1 - (1 - u)^2), where g' may be log-singular (a sphere near its rim)."""
        if a == 0.0:
            return 0.0
        u = 0.5 * (_GAUSS_NODES + 1.0)
        x = a * (1.0 - (1.0 - u) ** 2)
        jacobian = 2.0 * a * (1.0 - u)
        values = self.g(a) - np.asarray(self.indenter.profile_1d(x), dtype=np.float64)
        return 8.0 * self.eta * float(np.sum(0.5 * _GAUSS_WEIGHTS * jacobian * values))

    def __call__(self, impulse):
        """Depth (m) reached at ``impulse`` (N s)."""
        if impulse == 0.0:
            return 0.0
        if self.disc is not None:
            filled = self.impulse(self.disc)
            if impulse >= filled:
                return self.g(self.disc) + (impulse - filled) / (8.0 * self.eta * self.disc)
            upper = self.disc
        else:
            upper = self._bracket(impulse)
        # bisection: the impulse grows with the contact radius
        low, high = 0.0, upper
        while high - low > 4.0 * np.finfo(float).eps * high:
            middle = 0.5 * (low + high)
            if self.impulse(middle) < impulse:
                low = middle
            else:
                high = middle
        return self.g(0.5 * (low + high))

    def _bracket(self, impulse):
        """A contact radius (m) whose impulse is at least ``impulse``."""
        if self.edge is not None:
            candidates = [0.5 * self.edge]
        elif self.rim is not None:
            candidates = [self.rim * (1.0 - 2.0**-k) for k in range(1, 53)]
        else:
            candidates = [2.0**k for k in range(21)]
        for upper in candidates:
            if self.impulse(upper) >= impulse:
                return upper
        if self.edge is not None:
            raise _edge_error(self.indenter, impulse)
        raise DomainError(
            f"{type(self.indenter).__name__}.depth_from_impulse: no contact radius of "
            f"{self.indenter!r} up to {candidates[-1]!r} m carries an impulse of {impulse!r} N s"
        )
