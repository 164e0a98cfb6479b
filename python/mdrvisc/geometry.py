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

Each indenter holds the compiled core's indenter (``_core``), built once and validated by it,
and delegates its height maps, footprint, MDR profile, contact radii and Lee-Radok depths to
it: the numbers are the solvers' own.
"""

import abc
import math

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import _array, _optional_positive, _out, _positive
from .errors import DomainError, InvalidInputError

__all__ = ["Indenter", "Rod", "Paraboloid", "Cone", "Sphere", "Pyramid"]

#: Out-of-range pyramid half-angles from this value up to 90 are taken for degrees in the
#: error message's hint.
DEGREES_HINT = 5.0


class Indenter(abc.ABC):
    """A rigid indenter: height map, footprint and MDR profile (axisymmetric, or the
    pyramid's equivalent cone), computed by the compiled core's indenter it holds.
    """

    #: The compiled core's indenter, built at construction.
    _core: _core.Indenter

    @abc.abstractmethod
    def _build(self) -> _core.Indenter:
        """The compiled core's indenter of this one, validated by the core."""

    def __getstate__(self) -> dict:
        """The state without the compiled core's indenter, which :meth:`__setstate__`
        rebuilds: indenters pickle and copy."""
        return {k: v for k, v in self.__dict__.items() if k != "_core"}

    def __setstate__(self, state: dict) -> None:
        """Restores :meth:`__getstate__`'s state and rebuilds the compiled core's indenter."""
        self.__dict__.update(state)
        self._core = self._build()

    @abc.abstractmethod
    def _model(self, extent: float | None = None) -> dict:
        """The indenter in the scene model's form (a scene file's ``[indenter]`` table);
        ``extent`` (m) is how far an unbounded sampled profile must be tabulated."""

    def _footprint_model(self) -> dict:
        """``edge`` or nothing, for the scene model."""
        edge = getattr(self, "edge", None)
        return {} if edge is None else {"edge": edge}

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
        return self._core.height_map(x, y)

    @property
    def footprint_half_width(self) -> float | None:
        """Half the side of the smallest centred square holding the footprint (m).

        Disc: its radius; square of edge L: L/2; unbounded: None.
        """
        return self._core.half_width

    @property
    def mdr_half_length(self) -> float | None:
        """Half-length of the 1D MDR indenter (m).

        Disc: its radius; square of edge L: L / sqrt(pi) (equal area); unbounded: None.
        """
        return self._core.half_length_1d

    @property
    def is_flat(self) -> bool:
        """True for a flat face (the rod), whose contact never changes."""
        return self._core.is_flat

    def _coordinates(self, x):
        """``x`` (m) validated for :meth:`profile_1d`: finite, and on the 1D indenter of a disc
        footprint (``|x|`` <= radius; < radius where the rim is outside the footprint)."""
        name = type(self).__name__
        x = _array(name, "x", x)
        rim = self._core.rim_inside
        if rim is not None:
            disc = self._core.half_width
            off = np.abs(x) > disc if rim else np.abs(x) >= disc
            if off.any():
                raise InvalidInputError(
                    f"{name}: profile_1d needs |x| {'<=' if rim else '<'} {disc!r} (the 1D "
                    f"indenter), got x = {float(x[off].flat[0])!r}"
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

    def profile_1d(self, x: ArrayLike) -> np.ndarray:
        """MDR 1D profile g(x) (m), even in x; float64 array of the shape of ``x`` (m). For a
        disc footprint ``|x|`` must lie on the 1D indenter (InvalidInputError otherwise)."""
        return self._core.profile_1d(self._coordinates(x))

    def contact_radius_at_depth(self, d: float) -> float:
        """Radius a (m) of the 3D contact at tip depth ``d`` (m), from the MDR relation d = g(a).

        Holds for elastic and viscous media alike. The footprint's edge is ignored except
        for discs, whose radius caps a (the contact then covers the whole face).
        """
        return self._core.radius_at_depth(self._depth(d))

    def depth_from_impulse(self, impulse: ArrayLike, eta: float) -> float | np.ndarray:
        """Depth (m) of the indenter pressed into a viscous half-space by an impulse.

        Monotone contact (Lee-Radok) through MDR: the depth d and contact radius a solve
        g(a) = d and 4 eta * integral_{-a}^{a} (d - g(x)) dx = J, with g the 1D profile and J
        the impulse (integral of the force over time, N s; F t for a constant force F from
        first touch). Parameters: impulse J >= 0 (N s, scalar or array), viscosity eta
        (Pa s); a float for a scalar impulse, else an array of its shape. By Radok's
        correspondence the same map gives the elastic depth under a force F with J -> F and
        eta -> G.

        Computed by the compiled core, as the solvers size their grids: closed forms for Rod,
        Paraboloid, Cone and Pyramid (its equivalent cone), otherwise bisection on a with
        Simpson's rule for the integral. Once the contact fills a disc footprint of radius R
        (Rod, ``Axisymmetric(..., radius=R)``, ``Profile(..., radius=R)``) the indenter moves
        on like a rod: d = g(R) + (J - J_R) / (8 eta R). Raises DomainError once the contact
        circle reaches the edge of a square footprint, where it stops being circular and no
        closed form applies.
        """
        owner = f"{type(self).__name__}.depth_from_impulse"
        impulse = _array(owner, "impulse", impulse, minimum=0.0)
        eta = _positive(owner, "eta", eta)
        depth = self._core.depth_under_load(np.asarray(impulse / (4.0 * eta)))
        outgrown = np.isnan(depth)
        if outgrown.any():
            raise DomainError(
                f"{owner}: at an impulse of {float(impulse[outgrown].flat[0])!r} N s the contact "
                f"radius of {self!r} exceeds half the edge ({self.footprint_half_width!r} m); "
                "the contact is no longer circular"
            )
        return _out(depth)


class Rod(Indenter):
    """Flat cylindrical punch of radius ``radius`` (m): h = 0 on the disc r <= radius.

    Its MDR image is a flat line, g = 0 for ``|x|`` <= radius.
    """

    def __init__(self, radius: float) -> None:
        self._radius = _positive("Rod", "radius", radius)
        self._core = self._build()

    def _build(self):
        return _core.Indenter.rod(self._radius)

    @property
    def radius(self) -> float:
        """Radius of the face (m)."""
        return self._radius

    def _model(self, extent=None):
        return {"type": "rod", "radius": self._radius}

    def __repr__(self) -> str:
        """``Rod(radius=...)``."""
        return f"Rod(radius={self._radius!r})"


class Paraboloid(Indenter):
    """Paraboloid of revolution h = c r^2 (radius of curvature R = 1/(2c)).

    Parameters: ``c`` (1/m) > 0; ``edge`` (m): side of a centred square footprint, or None for
    an unbounded paraboloid. MDR profile g = 2 c x^2; contact radius a = sqrt(d / (2c)).
    """

    def __init__(self, c: float, edge: float | None = None) -> None:
        self._c = _positive("Paraboloid", "c", c)
        self._edge = _optional_positive("Paraboloid", "edge", edge)
        self._core = self._build()

    def _build(self):
        return _core.Indenter.paraboloid(self._c, self._edge)

    @property
    def c(self) -> float:
        """Curvature parameter c (1/m) of h = c r^2."""
        return self._c

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None (unbounded)."""
        return self._edge

    def _model(self, extent=None):
        return {"type": "paraboloid", "c": self._c, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Paraboloid(c=..., edge=...)``."""
        return f"Paraboloid(c={self._c!r}, edge={self._edge!r})"


class Cone(Indenter):
    """Cone h = slope * r.

    Parameters: ``slope`` (dimensionless, the cotangent of the half-opening angle) > 0;
    ``edge`` (m): side of a centred square footprint, or None (unbounded). MDR profile
    g = (pi/2) slope ``|x|``; contact radius a = 2 d / (pi slope).
    """

    def __init__(self, slope: float, edge: float | None = None) -> None:
        self._slope = _positive("Cone", "slope", slope)
        self._edge = _optional_positive("Cone", "edge", edge)
        self._core = self._build()

    def _build(self):
        return _core.Indenter.cone(self._slope, self._edge)

    @property
    def slope(self) -> float:
        """Slope s of h = s r (dimensionless)."""
        return self._slope

    @property
    def edge(self) -> float | None:
        """Side of the square footprint (m), or None (unbounded)."""
        return self._edge

    def _model(self, extent=None):
        return {"type": "cone", "slope": self._slope, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Cone(slope=..., edge=...)``."""
        return f"Cone(slope={self._slope!r}, edge={self._edge!r})"


class Sphere(Indenter):
    """Exact spherical cap of radius ``radius`` = R (m): h = R - sqrt(R^2 - r^2) for r < R.

    Footprint: the open disc r < R. MDR profile (closed form)
    g(x) = (``|x|``/2) ln((R + ``|x|``) / (R - ``|x|``)) for ``|x|`` < R, growing without bound at the rim;
    the contact radius at a depth by bisection on it, to the last bit. BEM grid: 1.2 times
    the scene's largest contact radius (as for unbounded indenters), at most the footprint.
    """

    def __init__(self, radius: float) -> None:
        self._radius = _positive("Sphere", "radius", radius)
        self._core = self._build()

    def _build(self):
        return _core.Indenter.sphere(self._radius)

    @property
    def radius(self) -> float:
        """Radius R of the sphere (m)."""
        return self._radius

    def _model(self, extent=None):
        return {"type": "sphere", "radius": self._radius}

    def __repr__(self) -> str:
        """``Sphere(radius=...)``."""
        return f"Sphere(radius={self._radius!r})"


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
    Its MDR profile, contact radius and Lee-Radok depth are the equivalent cone's.
    """

    def __init__(self, half_angle: float, edge: float | None = None) -> None:
        self._alpha = _positive("Pyramid", "half_angle", half_angle)
        self._edge = _optional_positive("Pyramid", "edge", edge)
        self._core = self._build()
        self._cone = Cone(slope=self._core.equivalent_cone_slope, edge=self._edge)

    def _build(self):
        alpha = self._alpha
        try:
            return _core.Indenter.pyramid(alpha, self._edge)
        except InvalidInputError as exc:  # the core's range check, named as this class names it
            # an angle given in degrees (real tips: 15 to 70 degrees); not pi/2 or just above
            hint = (f" ({alpha!r} degrees is math.radians({alpha!r}) = {math.radians(alpha)!r})"
                    if DEGREES_HINT <= alpha < 90.0 else "")
            raise InvalidInputError(f"Pyramid: {str(exc).split('pyramid ', 1)[-1]}{hint}") from None

    @property
    def half_angle(self) -> float:
        """Face half-angle alpha (radians)."""
        return self._alpha

    @property
    def edge(self) -> float | None:
        """Side of the square base (m), or None (unbounded)."""
        return self._edge

    @property
    def equivalent_cone(self) -> Cone:
        """The cone MDR solves in its place: slope cot(psi) = 1 / (0.7453 (pi/2) tan(alpha)),
        the same footprint."""
        return self._cone

    def _model(self, extent=None):
        return {"type": "pyramid", "half_angle": self._alpha, **self._footprint_model()}

    def __repr__(self) -> str:
        """``Pyramid(half_angle=..., edge=...)``."""
        return f"Pyramid(half_angle={self._alpha!r}, edge={self._edge!r})"
