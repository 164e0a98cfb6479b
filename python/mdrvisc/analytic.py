"""Closed-form solutions: the analytic side of every comparison.

Units throughout: lengths in m, times in s, forces in N, pressures and moduli in Pa,
viscosities in Pa s, impulses (force x time) in N s. Depths and deflections are positive into
the body. A half-space of shear modulus G and Poisson ratio nu has the effective modulus
E* = 2 G / (1 - nu) = E / (1 - nu^2) (4 G when incompressible, nu = 1/2), and by Radok's
correspondence a viscous half-space of viscosity eta behaves like an elastic one with
E* = 2 eta / (1 - nu) once forces are replaced by impulses (constant force F from t = 0:
impulse F t) and deflections by deflection rates. The functions that take a viscosity are
written for nu = 1/2 (for another nu pass eta / (2 (1 - nu)), the viscosity with the same E*);
``ting_paraboloid_triangle`` takes the medium's nu. Functions taking times, radii or
coordinates accept scalars or numpy arrays and return a float or an array of the broadcast
shape.

This module is the bottom layer of the package: it imports neither :mod:`mdrvisc.geometry`
nor :mod:`mdrvisc.media`. The functions that take an indenter or a medium call their methods
(``depth_from_impulse``, ``rheology``) and accept any object that has them.
"""

import math
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike

from ._validate import _array, _out, _positive
from .errors import InvalidInputError

__all__ = [
    "rod_velocity",
    "rod_central_pressure",
    "rod_pressure",
    "rod_surface_velocity",
    "paraboloid_depth",
    "paraboloid_contact_radius",
    "paraboloid_contact_length",
    "cone_depth",
    "cone_contact_radius",
    "power_law_mdr_factor",
    "sphere_mdr_profile",
    "hertz",
    "hertz_pressure",
    "lee_radok_depth_from_impulse",
    "ting_paraboloid_triangle",
    "maugis_pull_off",
    "maugis_dugdale",
]


# ----------------------------------------------------------------------------- flat rod
def rod_velocity(force: float, radius: float, eta: float) -> float:
    """Indentation velocity of a flat rod on a viscous half-space, ddot = F / (8 a eta).

    Parameters: force F (N), rod radius a (m), viscosity eta (Pa s). Returns m/s.
    """
    force = _positive("rod_velocity", "force", force)
    radius = _positive("rod_velocity", "radius", radius)
    eta = _positive("rod_velocity", "eta", eta)
    return force / (8.0 * radius * eta)


def rod_central_pressure(force: float, radius: float) -> float:
    """Pressure at the centre of a flat rod's contact, p0 = F / (2 pi a^2) (Pa).

    Parameters: force F (N), rod radius a (m). Holds for elastic and viscous half-spaces.
    """
    force = _positive("rod_central_pressure", "force", force)
    radius = _positive("rod_central_pressure", "radius", radius)
    return force / (2.0 * math.pi * radius**2)


def rod_pressure(r: ArrayLike, force: float, radius: float) -> float | np.ndarray:
    """Pressure under a flat rod, p(r) = p0 (1 - r^2/a^2)^(-1/2) for r < a, 0 for r >= a (Pa).

    Parameters: radial distance r >= 0 (m, scalar or array), force F (N), rod radius a (m).
    The pressure is (integrably) infinite at the edge r = a; it is returned as 0 there, with
    the outside.
    """
    r = _array("rod_pressure", "r", r, minimum=0.0)
    p0 = rod_central_pressure(force, radius)
    radius = float(radius)
    inside = r < radius
    ratio = np.where(inside, r / radius, 0.0)
    return _out(np.where(inside, p0 / np.sqrt((1.0 - ratio) * (1.0 + ratio)), 0.0))


def rod_surface_velocity(r: ArrayLike, force: float, radius: float, eta: float) -> float | np.ndarray:
    """Surface deflection rate around a flat rod on a viscous half-space (m/s).

    du/dt = ddot for r <= a and (2/pi) ddot asin(a/r) for r > a, with ddot = F / (8 a eta).
    Parameters: radial distance r >= 0 (m, scalar or array), force F (N), rod radius a (m),
    viscosity eta (Pa s).
    """
    r = _array("rod_surface_velocity", "r", r, minimum=0.0)
    velocity = rod_velocity(force, radius, eta)
    radius = float(radius)
    outside = r > radius
    ratio = np.where(outside, radius / np.where(outside, r, 1.0), 1.0)
    return _out(np.where(outside, (2.0 / math.pi) * velocity * np.arcsin(ratio), velocity))


# ----------------------------------------------------------------------------- paraboloid
def paraboloid_depth(t: ArrayLike, force: float, c: float, eta: float) -> float | np.ndarray:
    """Depth of a paraboloid h = c r^2 under a constant force on a viscous half-space (m).

    Lee-Radok: d(t) = (3 F t sqrt(2c) / (16 eta))^(2/3), the force F (N) acting from first touch
    at t = 0 on an unbounded paraboloid of curvature parameter c (1/m; radius R = 1/(2c)),
    viscosity eta (Pa s). Time t >= 0 (s, scalar or array).
    """
    t = _array("paraboloid_depth", "t", t, minimum=0.0)
    force = _positive("paraboloid_depth", "force", force)
    c = _positive("paraboloid_depth", "c", c)
    eta = _positive("paraboloid_depth", "eta", eta)
    return _out((3.0 * force * t * math.sqrt(2.0 * c) / (16.0 * eta)) ** (2.0 / 3.0))


def paraboloid_contact_radius(t: ArrayLike, force: float, c: float, eta: float) -> float | np.ndarray:
    """Contact radius a = sqrt(d / (2c)) of :func:`paraboloid_depth`'s indentation (m).

    Same parameters as :func:`paraboloid_depth`.
    """
    depth = paraboloid_depth(t, force, c, eta)
    return _out(np.sqrt(np.asarray(depth) / (2.0 * float(c))))


def paraboloid_contact_length(t: ArrayLike, force: float, c: float, eta: float) -> float | np.ndarray:
    """Contact length l = 2a of :func:`paraboloid_depth`'s indentation (m).

    Same parameters as :func:`paraboloid_depth`.
    """
    return _out(2.0 * np.asarray(paraboloid_contact_radius(t, force, c, eta)))


# ----------------------------------------------------------------------------- cone
def cone_depth(t: ArrayLike, force: float, slope: float, eta: float) -> float | np.ndarray:
    """Depth of a cone h = slope r under a constant force on a viscous half-space (m).

    The elastic cone (MDR profile g = (pi/2) s ``|x|``, contact radius a = 2d / (pi s)) carries
    F = E* d a = 2 E* d^2 / (pi s); with E* -> 4 eta and F -> F t (Lee-Radok) this gives
    d(t) = sqrt(pi s F t / (8 eta)). Parameters: time t >= 0 (s, scalar or array), force F (N)
    acting from first touch at t = 0, slope s (dimensionless), viscosity eta (Pa s).
    """
    t = _array("cone_depth", "t", t, minimum=0.0)
    force = _positive("cone_depth", "force", force)
    slope = _positive("cone_depth", "slope", slope)
    eta = _positive("cone_depth", "eta", eta)
    return _out(np.sqrt(math.pi * slope * force * t / (8.0 * eta)))


def cone_contact_radius(t: ArrayLike, force: float, slope: float, eta: float) -> float | np.ndarray:
    """Contact radius a = 2d / (pi s) of :func:`cone_depth`'s indentation (m).

    Same parameters as :func:`cone_depth`.
    """
    depth = cone_depth(t, force, slope, eta)
    return _out(2.0 * np.asarray(depth) / (math.pi * float(slope)))


# ----------------------------------------------------------------------------- MDR maps
def power_law_mdr_factor(n: float) -> float:
    """Factor kappa_n of the MDR map of a power-law profile (dimensionless).

    f(r) = c r^n maps to g(x) = kappa_n c ``|x|^n`` with
    kappa_n = sqrt(pi) Gamma(n/2 + 1) / Gamma(n/2 + 1/2) (kappa_1 = pi/2, kappa_2 = 2).
    Parameter: exponent n > 0.
    """
    n = _positive("power_law_mdr_factor", "n", n)
    return math.sqrt(math.pi) * math.exp(math.lgamma(0.5 * n + 1.0) - math.lgamma(0.5 * n + 0.5))


def sphere_mdr_profile(x: ArrayLike, radius: float) -> float | np.ndarray:
    """MDR profile of a spherical cap of radius R: g(x) = (``|x|``/2) ln((R + ``|x|``) / (R - ``|x|``)) (m).

    Evaluated as ``|x|`` artanh(``|x|``/R). Parameters: 1D coordinate x (m, scalar or array) with
    ``|x|`` < R, sphere radius R (m); g grows without bound as ``|x|`` -> R.
    """
    radius = _positive("sphere_mdr_profile", "radius", radius)
    x = np.abs(_array("sphere_mdr_profile", "x", x))
    if (x >= radius).any():
        bad = float(x[x >= radius].flat[0])
        raise InvalidInputError(
            f"sphere_mdr_profile: |x| must be < radius = {radius!r}, got |x| = {bad!r}"
        )
    return _out(x * np.arctanh(x / radius))


# ----------------------------------------------------------------------------- Hertz
def hertz(force: float, radius_of_curvature: float, e_star: float) -> tuple[float, float, float]:
    """Hertz contact of a rigid paraboloid on an elastic half-space.

    Parameters: force F (N), radius of curvature R (m; h = r^2 / (2R)), effective modulus E*
    (Pa; 2 G / (1 - nu) = E / (1 - nu^2), 4 G for an incompressible body). Returns
    ``(a, d, p0)``: contact radius a = (3 F R / (4 E*))^(1/3) (m), depth d = a^2 / R (m),
    central pressure p0 = 3 F / (2 pi a^2) (Pa).
    """
    force = _positive("hertz", "force", force)
    radius = _positive("hertz", "radius_of_curvature", radius_of_curvature)
    e_star = _positive("hertz", "e_star", e_star)
    a = (3.0 * force * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return a, a * a / radius, 3.0 * force / (2.0 * math.pi * a * a)


def hertz_pressure(r: ArrayLike, a: float, p0: float) -> float | np.ndarray:
    """Hertz pressure p(r) = p0 sqrt(1 - r^2/a^2) for r < a, 0 outside (Pa).

    Parameters: radial distance r >= 0 (m, scalar or array), contact radius a (m), central
    pressure p0 (Pa).
    """
    r = _array("hertz_pressure", "r", r, minimum=0.0)
    a = _positive("hertz_pressure", "a", a)
    p0 = _positive("hertz_pressure", "p0", p0)
    ratio = np.minimum(r / a, 1.0)
    return _out(p0 * np.sqrt((1.0 - ratio) * (1.0 + ratio)))


# ----------------------------------------------------------------------------- Lee-Radok
class _DepthFromImpulse(Protocol):
    """What :func:`lee_radok_depth_from_impulse` needs of an indenter (an
    :class:`mdrvisc.geometry.Indenter` has it)."""

    def depth_from_impulse(self, impulse: ArrayLike, eta: float) -> float | np.ndarray: ...


def lee_radok_depth_from_impulse(
    impulse: ArrayLike, indenter: _DepthFromImpulse, eta: float
) -> float | np.ndarray:
    """Depth of any :mod:`mdrvisc.geometry` indenter pressed into a viscous half-space (m).

    Monotone contact (Lee-Radok) through MDR: the depth d and contact radius a solve
    g(a) = d and 4 eta * integral_{-a}^{a} (d - g(x)) dx = J, with g the indenter's 1D profile
    and J the impulse (integral of the force over time, N s; F t for a constant force F from
    first touch). Parameters: impulse J >= 0 (scalar or array), indenter (a
    :class:`mdrvisc.geometry.Indenter`), viscosity eta (Pa s).

    The indenter computes it: this is :meth:`mdrvisc.geometry.Indenter.depth_from_impulse`
    (the compiled core's closed forms for Rod, Paraboloid, Cone and Pyramid; bisection and
    Simpson's rule otherwise, as the solvers size their grids), which raises DomainError once
    the contact circle reaches the edge of a square footprint. Any object with a
    ``depth_from_impulse(impulse, eta)`` method is accepted as the indenter. The closed forms
    here (:func:`paraboloid_depth`, :func:`cone_depth`, :func:`rod_velocity`) are independent
    of it.
    """
    depth_from_impulse = getattr(indenter, "depth_from_impulse", None)
    if isinstance(indenter, type) or not callable(depth_from_impulse):
        raise InvalidInputError(
            f"lee_radok_depth_from_impulse: indenter must be an mdrvisc Indenter, got {indenter!r}"
        )
    impulse = _array("lee_radok_depth_from_impulse", "impulse", impulse, minimum=0.0)
    eta = _positive("lee_radok_depth_from_impulse", "eta", eta)
    return depth_from_impulse(impulse, eta)


# ----------------------------------------------------------------------------- Ting
class _Rheology(Protocol):
    """What :func:`ting_paraboloid_triangle` needs of a medium (every
    :mod:`mdrvisc.media` medium has it): its shear modulus (G_inf, [(G_k, tau_k), ...], eta)
    and its Poisson ratio nu."""

    nu: float

    def rheology(self) -> tuple[float, list[tuple[float, float]], float]: ...


def ting_paraboloid_triangle(
    t: ArrayLike, medium: _Rheology, radius_of_curvature: float, rate: float, t_peak: float
) -> tuple[float | np.ndarray, float | np.ndarray, float]:
    """Ting's solution for a paraboloid pushed in and pulled out at a constant rate.

    A rigid paraboloid h = r^2 / (2R) on a linear viscoelastic half-space of shear
    relaxation modulus G(t) = G_inf + sum_k G_k exp(-t / tau_k) + eta delta(t) and constant
    Poisson ratio nu (any :mod:`mdrvisc.media` medium; its ``nu``, 1/2 if it has none), whose
    contact modulus is E*(t) = 2 G(t) / (1 - nu), depth d(s) = v s up to s = t_peak and
    v (2 t_peak - s) after (Ting 1966, J. Appl. Mech. 33:845; Greenwood 2010, Int. J. Mech.
    Sci. 52:829). In MDR terms the element at ``|x|`` is pressed since the contact radius first
    reached ``|x|``, and carries dx int E*(t - s) ddot(s) ds:

    * loading, t <= t_peak: a(t)^2 = R d(t) and
      F(t) = 4 / (1 - nu) sqrt(R) v^(3/2) [int_0^t G(t - s) s^(1/2) ds + eta t^(1/2)]
      (8 sqrt(R) ... when incompressible);
    * unloading, t > t_peak: a(t) = a(t1), where t1 in [0, t_peak] makes the edge element's
      force vanish, int_{t1}^t G(t - s) ddot(s) ds = 0 (the dashpot adds eta ddot(t) = -eta v),
      and F(t) = 4 / (1 - nu) sqrt(R) v^(3/2) int_0^t1 G(t - s) s^(1/2) ds;
    * contact is lost (F = a = 0) from the separation time t_s in [t_peak, 2 t_peak], where
      int_0^t_s G(t_s - s) ddot(s) ds = 0 (t_s = t_peak if the dashpot alone outweighs it).

    Parameters: time t >= 0 (s, scalar or array), medium, radius of curvature R (m), rate v
    (m/s), t_peak (s). Returns ``(F, a, t_s)``: force (N) and contact radius (m) at t, and
    t_s (s). The roots are found by bisection to within t_peak * 2^-53; the integrals of the Prony
    terms by Gauss-Legendre quadrature (relative error ~1e-13 for t / tau_k up to 1e3).
    """
    # Duck-typed, so that this module stays below media and imports nothing from it: any
    # object with the media's rheology() will do.
    if isinstance(medium, type) or not callable(getattr(medium, "rheology", None)):
        raise InvalidInputError(
            f"ting_paraboloid_triangle: medium must be an mdrvisc medium, got {medium!r}"
        )
    t = _array("ting_paraboloid_triangle", "t", t, minimum=0.0)
    curvature = _positive("ting_paraboloid_triangle", "radius_of_curvature", radius_of_curvature)
    rate = _positive("ting_paraboloid_triangle", "rate", rate)
    t_peak = _positive("ting_paraboloid_triangle", "t_peak", t_peak)
    g_inf, terms, eta = medium.rheology()
    nu = getattr(medium, "nu", 0.5)
    moduli = np.array([g for g, _ in terms])
    taus = np.array([tau for _, tau in terms])

    def modulus_integral(now, a, b):
        """int_a^b G(now - s) ds without the dashpot (Pa s), elementwise."""
        decay = np.exp(-(now - b)[..., None] / taus) - np.exp(-(now - a)[..., None] / taus)
        return g_inf * (b - a) + np.sum(moduli * taus * decay, -1)

    def edge_balance(t1, now):
        """int_{t1}^now G(now - s) ddot(s) ds / v for t1 <= t_peak <= now (Pa s); decreasing in
        both."""
        return modulus_integral(now, t1, t_peak) - modulus_integral(now, t_peak, now) - eta

    def bisect(balance, low, high):
        """The root of a decreasing ``balance`` between the arrays ``low`` and ``high``."""
        for _ in range(53):
            middle = 0.5 * (low + high)
            positive = balance(middle) > 0.0
            low, high = np.where(positive, middle, low), np.where(positive, high, middle)
        return 0.5 * (low + high)

    zero, peak = np.zeros(()), np.array(t_peak)
    t_sep = t_peak
    if edge_balance(zero, peak) > 0.0:
        t_sep = float(bisect(lambda now: edge_balance(zero, now), peak, 2.0 * peak))
    loading = t <= t_peak
    now = np.where(loading, t_peak, t)
    touching = ~loading & (edge_balance(np.zeros_like(t), now) > 0.0)
    t1 = np.where(loading, t, 0.0)
    t1[touching] = bisect(lambda s: edge_balance(s, now[touching]), np.zeros(touching.sum()),
                          np.full(touching.sum(), t_peak))
    # int_0^t1 G(t - s) s^(1/2) ds; per Prony term tau^(3/2) exp(-(t - t1)/tau) K(t1 / tau)
    hereditary = g_inf * t1**1.5 / 1.5 + np.sum(
        moduli * taus**1.5 * np.exp(-(t - t1)[..., None] / taus)
        * _relaxing_root_integral(t1[..., None] / taus), -1)
    dashpot = np.where(loading, eta * np.sqrt(t), 0.0)
    contact = loading | touching
    # F = 2 sqrt(R) v^(3/2) int E*(t - s) s^(1/2) ds with E* = 2 G / (1 - nu) (8 sqrt(R) ... at nu = 1/2)
    force = np.where(contact, 4.0 / (1.0 - nu) * math.sqrt(curvature) * rate**1.5 * (hereditary + dashpot),
                     0.0)
    radius = np.where(contact, np.sqrt(curvature * rate * t1), 0.0)
    return _out(force), _out(radius), t_sep


def _relaxing_root_integral(x):
    """K(x) = int_0^x exp(-(x - s)) s^(1/2) ds for x >= 0 (array; dimensionless).

    With x - s = w and s = y^2 the integrand 2 y^2 exp(-w) is smooth in y; composite
    Gauss-Legendre in y on panels of equal width in w, which only needs w <= 40.
    """
    nodes, weights = np.polynomial.legendre.leggauss(16)
    w = np.minimum(np.linspace(0.0, 40.0, 21), np.asarray(x)[..., None])
    y = np.sqrt(np.asarray(x)[..., None] - w)  # decreasing panel edges
    middle, half = 0.5 * (y[..., :-1] + y[..., 1:]), 0.5 * (y[..., :-1] - y[..., 1:])
    s = (middle[..., None] + half[..., None] * nodes) ** 2
    integrand = 2.0 * s * np.exp(s - np.asarray(x)[..., None, None])
    return np.sum(half * np.sum(weights * integrand, -1), -1)


# ----------------------------------------------------------------------------- adhesion
def maugis_pull_off(transition: float) -> float:
    """Pull-off force of a rigid sphere (paraboloid) under Maugis-Dugdale adhesion, in units
    of pi w R (w the work of adhesion, J/m^2; R the radius of curvature, m).

    Maugis (1992) in Johnson and Greenwood's (1997) form: at the transition parameter
    ``transition`` = lambda = 2 sigma0 (R / (pi w K^2))^(1/3), K = 4 E* / 3, the load is
    P = A^3 - lambda A^2 (mu + m^2 atan mu) with mu = sqrt(m^2 - 1), the zone ratio m = c / a
    solving Maugis's zone equation at each dimensionless radius A (bisection); the pull-off is
    -min over A of P (a scan refined three times). It tends to JKR's 3/2 as lambda grows and
    to DMT's 2 as lambda falls.

    Examples
    --------
    >>> import mdrvisc as mv
    >>> round(mv.analytic.maugis_pull_off(1.0), 3)
    1.601
    """
    lam = _positive("maugis_pull_off", "transition", transition)

    def load(a: float) -> float:
        return _maugis_state(lam, a)[0]

    grid = np.linspace(0.01, 2.0, 200)
    for _ in range(3):
        best = grid[int(np.argmin([load(a) for a in grid]))]
        step = grid[1] - grid[0]
        grid = np.linspace(max(best - step, 1e-6), best + step, 41)
    return -min(load(a) for a in grid)


def _maugis_state(lam: float, a: float) -> tuple[float, float, float]:
    """(P, Delta, m) of Maugis's solution at transition parameter ``lam`` and reduced contact
    radius ``a`` > 0 (see :func:`maugis_dugdale`)."""
    def zone(m: float) -> float:
        mu = math.sqrt(m * m - 1.0)
        t = math.atan(mu)
        return lam * a * a / 2 * (mu + (m * m - 2) * t) + 4 * lam * lam * a / 3 * (mu * t - m + 1) - 1

    lo, hi = 1.0, 2.0
    while zone(hi) < 0:
        lo, hi = hi, 2 * hi
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if zone(mid) < 0 else (lo, mid)
    m = 0.5 * (lo + hi)
    mu = math.sqrt(m * m - 1.0)
    return (a**3 - lam * a * a * (mu + m * m * math.atan(mu)),
            a * a - 4.0 / 3.0 * lam * a * mu, m)


def maugis_dugdale(transition: float, radius: float) -> tuple[float, float, float]:
    """Maugis's (1992) Maugis-Dugdale contact of a rigid sphere (paraboloid of radius R) at
    one contact radius, in Johnson and Greenwood's (1997) reduced variables: contact radius
    A = a (K / (pi w R^2))^(1/3), load P = F / (pi w R), depth
    Delta = d (K^2 / (pi^2 w^2 R))^(1/3), with K = 4 E* / 3, w the work of adhesion (J/m^2),
    and the transition parameter lambda = 2 sigma0 (R / (pi w K^2))^(1/3).

    Returns (P, Delta, m) at A = ``radius``: m = c / a, the ratio of the cohesive zone's
    outer radius c to the contact radius, solves Maugis's zone equation
    lambda A^2 / 2 (mu + (m^2 - 2) atan mu) + 4 lambda^2 A / 3 (mu atan mu - m + 1) = 1
    (mu = sqrt(m^2 - 1); bisection), then P = A^3 - lambda A^2 (mu + m^2 atan mu) and
    Delta = A^2 - 4/3 lambda A mu. Large lambda gives JKR's P = A^3 - sqrt(6 A^3),
    Delta = A^2 - sqrt(8 A / 3); small lambda Hertz's Delta = A^2 with DMT's zone.

    Examples
    --------
    >>> import mdrvisc as mv
    >>> p, delta, m = mv.analytic.maugis_dugdale(1.0, 1.0)
    >>> round(p, 3), round(delta, 3), round(m, 3)
    (-1.58, -0.337, 1.416)
    """
    lam = _positive("maugis_dugdale", "transition", transition)
    return _maugis_state(lam, _positive("maugis_dugdale", "radius", radius))
