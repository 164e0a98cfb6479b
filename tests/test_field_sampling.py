"""Returned fields hold what they claim: MDR's radial samples avoid the contact edge, where
the pressure of a sharp-edged or viscous contact is singular, so that the trapezoid rule over
them gives the force; a BEM pressure field sums to the force; and a sphere whose contact
reaches its equator is refused rather than solved as a sphere on a cylinder."""

import numpy as np
import pytest

import mdrvisc as mv


def radial_force(field):
    return np.trapezoid(2 * np.pi * field.r * field.pressure, field.r)


@pytest.mark.parametrize("indenter,measured",
                         [(mv.Paraboloid(c=1.0, edge=2.56), 2.6e-4), (mv.Rod(radius=1.0), 3.7e-4)],
                         ids=["paraboloid", "rod"])
def test_mdr_viscous_pressure_samples_integrate_to_the_force(indenter, measured):
    scene = mv.Scene(indenter=indenter, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0,
                     times=[1.0, 5.0], outputs=("depth", "pressure"), field_times=[1.0, 5.0])
    r = mv.solve(scene, "mdr", 8001)
    for t in (1.0, 5.0):
        f = r.fields[t]
        a = 0.5 * r.contact_length[list(r.t).index(t)]
        assert not np.any(np.isclose(f.r, a, rtol=1e-12, atol=0))
        assert np.all(np.isfinite(f.pressure)) and np.all(f.pressure >= 0)
        assert radial_force(f) == pytest.approx(1.0, abs=3 * measured)


@pytest.mark.parametrize("medium", [mv.Viscous(eta=1.0), mv.StandardSolid(1.0, 3.0, 0.5)],
                         ids=["viscous", "sls"])
def test_bem_pressure_sums_to_the_force(medium):
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=medium, force=([0, 5], [0, 2]),
                     duration=5.0, times=[1.0, 5.0], outputs=("depth", "pressure"), field_times=[1.0, 5.0])
    r = mv.solve(scene, "bem", 65, dt=0.05)
    for t, force in ((1.0, 0.4), (5.0, 2.0)):
        assert r.fields[t].pressure.sum() * r.dx**2 == pytest.approx(force, rel=1e-9)


@pytest.mark.parametrize("medium,extra", [(mv.Elastic(G=1.0), {}), (mv.Viscous(eta=1.0), {"duration": 5.0}),
                                          (mv.StandardSolid(1.0, 3.0, 0.5), {"duration": 5.0})],
                         ids=["elastic", "viscous", "sls"])
@pytest.mark.parametrize("method,n", [("mdr", 201), ("bem", 33)])
def test_a_sphere_pushed_to_its_equator_is_refused(medium, extra, method, n):
    scene = mv.Scene(indenter=mv.Sphere(radius=1.0), medium=medium, force=100.0, **extra)
    with pytest.raises(mv.DomainError, match=r"sphere \(radius 1 m\) reached its equator"):
        mv.solve(scene, method, n)
    within = mv.Scene(indenter=mv.Sphere(radius=1.0), medium=medium, force=1.0, **extra)
    assert np.all(mv.solve(within, method, n).contact_length < 2.0)
