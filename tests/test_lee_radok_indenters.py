"""Cone, sphere and tabulated indenters under a constant force on a viscous half-space, by
BEM and MDR through ``mv.solve``, against Lee–Radok written here (impulse J = F t):
* cone h = s r: d^2 = pi s J / (8 eta);
* sphere of radius R: the contact radius a solves J = 8 eta int_0^a (g(a) - g(x)) dx with
  the MDR profile g(x) = (x / 2) ln((R + x) / (R - x)), and d = g(a) (scipy quad and brentq);
* a paraboloid h = r^2 given as a callable (``mv.Axisymmetric``) and as samples
  (``mv.Profile``): d^(3/2) = 3 J / (16 eta sqrt(R)), R = 1/2.
"""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import mdrvisc as mv

FORCE, ETA = 1.0, 1.0
TIMES = np.array([0.5, 1.0, 2.0])
SLOPE, SPHERE_RADIUS = 0.5, 1.0


def cone_depth(t):
    return np.sqrt(np.pi * SLOPE * FORCE * t / (8 * ETA))


def sphere_depth(t):
    def g(x):
        return 0.5 * x * np.log((SPHERE_RADIUS + x) / (SPHERE_RADIUS - x))

    def impulse(a):
        return 8 * ETA * quad(lambda x: g(a) - g(x), 0.0, a, epsrel=1e-13, limit=200)[0]

    def radius(j):
        return brentq(lambda a: impulse(a) - j, 1e-12, SPHERE_RADIUS * (1 - 1e-12), xtol=1e-15)

    return np.array([g(radius(FORCE * s)) for s in t])


def paraboloid_depth(t):
    return (3 * FORCE * t / (16 * ETA * np.sqrt(0.5))) ** (2 / 3)


r_samples = np.linspace(0.0, 2.0, 2001)
INDENTERS = {
    "cone": (lambda: mv.Cone(slope=SLOPE), cone_depth),
    "sphere": (lambda: mv.Sphere(radius=SPHERE_RADIUS), sphere_depth),
    "axisymmetric": (lambda: mv.Axisymmetric(lambda r: r**2, radius=2.0), paraboloid_depth),
    "profile": (lambda: mv.Profile(r_samples, r_samples**2, radius=2.0), paraboloid_depth),
}
# measured: MDR (8001) cone 2.0e-8, sphere 2.0e-8, axisymmetric 6.4e-8, profile 2.8e-5 (2001 samples);
# BEM (65^2) cone 1.6e-4, sphere 2.7e-4, axisymmetric 1.2e-3, profile 1.2e-3
BOUNDS = {
    ("cone", "mdr"): 1e-7,
    ("sphere", "mdr"): 1e-7,
    ("axisymmetric", "mdr"): 3e-7,
    ("profile", "mdr"): 1e-4,
    ("cone", "bem"): 5e-4,
    ("sphere", "bem"): 8e-4,
    ("axisymmetric", "bem"): 4e-3,
    ("profile", "bem"): 4e-3,
}


@pytest.mark.parametrize("method,n", [("mdr", 8001), ("bem", 65)])
@pytest.mark.parametrize("name", INDENTERS)
def test_viscous_depth_follows_lee_radok(name, method, n):
    indenter, exact = INDENTERS[name]
    scene = mv.Scene(indenter=indenter(), medium=mv.Viscous(eta=ETA), force=FORCE, duration=2.0, times=TIMES)
    error = np.max(np.abs(mv.solve(scene, method, n).depth / exact(TIMES) - 1))
    assert error < BOUNDS[(name, method)]
