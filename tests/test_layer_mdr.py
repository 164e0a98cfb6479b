"""MDR on a layer (``method="mdr"`` with ``body=mv.Layer(...)``): the layer's flat-punch
stiffness and exact contact radius from the punch's integral equation, a weighted MDR
foundation. Checked here against the crate's BEM on a layer (an independent method), the
thick layer's first-order expansion, a viscoelastic layer against BEM, and refusals. The
crate's tests check the punch equation itself (convergence, thick and thin limits,
Dimitriadis's published series, Lee–Radok)."""

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.errors import InvalidInputError

# (2 / pi) integral of (1 - R(t)) dt for the bonded incompressible layer: the punch's
# exact first-order coefficient (docs/layers.md; the crate's tests compute it)
C1_BONDED_INCOMPRESSIBLE = 1.1270


def _factor(indenter, force, k, base, nu, method, n):
    """Bottom-effect factor (d_half / d_layer)^k of `method` at size n (h = 1, G = 1 Pa)
    and the layer's depth."""
    depth = {}
    for body in (None, mv.Layer(1.0, base)):
        scene = mv.Scene(indenter=indenter, medium=mv.Elastic(G=1.0, nu=nu), force=force, body=body)
        depth[body is None] = mv.solve(scene, method, n).depth[-1]
    return (depth[True] / depth[False]) ** k, depth[False]


def test_a_thick_layer_is_the_half_space_to_first_order():
    """A paraboloid on a layer 1000 contact radii thick: MDR's depth is the half-space
    MDR's times (1 + c1 a / h)^(-2/3) (the uniform deflection a thick layer adds) to 1e-6."""
    scene = lambda body: mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=1.0),  # noqa: E731
                                  force=4 / 3 * 4.0 * 1e-9, body=body)
    half = mv.solve(scene(None), "mdr", 4001)
    layer = mv.solve(scene(mv.Layer(1.0)), "mdr", 4001)
    a = np.sqrt(half.depth[-1])
    expected = (1 + C1_BONDED_INCOMPRESSIBLE * a) ** (-2 / 3)
    assert abs(a - 1e-3) < 1e-5
    assert abs(layer.depth[-1] / half.depth[-1] - expected) < 1e-6


@pytest.mark.parametrize("tip, base, nu", [("paraboloid", "bonded", 0.5), ("cone", "frictionless", 0.3),
                                          ("punch", "bonded", 0.3)])
def test_mdr_on_a_layer_agrees_with_bem(tip, base, nu):
    """Bottom-effect factors of MDR (n = 2001) and BEM (n = 65) on a layer, each against its
    own half-space at the same n, for contact radii of about 0.3 and 1 thickness: within
    1e-3 (bench_layer.py --mdr measures paraboloids and cones on both bases at nu = 0.3 and
    0.5 up to a / h = 2.4: within 2e-4 at n = 65, 1e-4 at 129, BEM's discretisation); the
    punch within 4e-3: BEM's error at the punch's singular edge, which the half-space's
    ratio does not cancel, falls like 1 / n towards MDR's exact punch (a / h = 1, bonded,
    nu = 0.3: 3.2e-3, 1.6e-3, 0.9e-3 at n = 65, 97, 129; 1.3e-3 at a / h = 0.3, n = 65)."""
    e_star = 2.0 / (1.0 - nu)
    for chi in (0.3, 1.0):
        if tip == "paraboloid":
            indenter, force, k = mv.Paraboloid(c=0.5), 4 / 3 * e_star * chi**3, 1.5
        elif tip == "cone":
            indenter, force, k = mv.Cone(slope=1.0), 0.5 * np.pi * e_star * chi**2, 2.0
        else:
            indenter, force, k = mv.Rod(radius=chi), e_star * chi, 1.0
        mdr, _ = _factor(indenter, force, k, base, nu, "mdr", 2001)
        bem, _ = _factor(indenter, force, k, base, nu, "bem", 65)
        assert mdr > 1.0
        assert abs(mdr / bem - 1) < (4e-3 if tip == "punch" else 1e-3), (chi, mdr, bem)


def test_a_viscoelastic_layer_agrees_with_bem():
    """A standard solid on a bonded incompressible layer under a force ramp and hold (creep;
    contact radius about 0.4 thicknesses): MDR's depth against BEM's (n = 65) within 1e-3 at
    every output time (measured 2.1e-4; 1.1e-4 at n = 97: BEM's discretisation)."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.StandardSolid(G_inf=1.0, G1=2.0, tau1=0.2),
                     force=([0.0, 0.5, 1.0], [0.0, 1.0, 1.0]), duration=1.0, body=mv.Layer(1.0),
                     times=np.linspace(0.1, 1.0, 10))
    mdr = mv.solve(scene, "mdr", 2001)
    bem = mv.solve(scene, "bem", 65)
    np.testing.assert_allclose(mdr.depth, bem.depth, rtol=1e-3)


def test_what_mdr_on_a_layer_does_not_solve_is_refused():
    """Fields, adhesive contact and a purely viscous medium: errors that say so."""
    kwargs = dict(indenter=mv.Sphere(radius=1e-3), force=1e-6, body=mv.Layer(1e-4))
    with pytest.raises(InvalidInputError, match="MDR on a layer"):
        mv.solve(mv.Scene(medium=mv.Elastic(G=1e3), outputs=["depth", "pressure"], **kwargs),
                 "mdr", 1001)
    with pytest.raises(InvalidInputError, match="hard contact only"):
        mv.solve(mv.Scene(medium=mv.Elastic(G=1e3), contact=mv.JKR(work_of_adhesion=0.05), duration=1.0,
                           **kwargs),
                 "mdr", 1001)
    with pytest.raises(InvalidInputError, match="purely viscous"):
        mv.solve(mv.Scene(medium=mv.Viscous(eta=1e3), duration=1.0, **kwargs), "mdr", 1001)


def test_a_fit_on_a_layer_recovers_a_bem_curve():
    """A standard solid on a bonded incompressible layer, crept by BEM (n = 65) under a
    force ramp and hold to a contact of about 0.4 thicknesses: ``mv.fit`` with the layer
    (depth prescribed, Ting's solution) recovers G_inf, G1 and tau1 within 1 %; the same
    fit on the half-space reports moduli a bottom-effect factor too stiff."""
    truth = dict(G_inf=1.0, G1=2.0, tau1=0.2)
    times = np.linspace(0.05, 1.0, 20)
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.StandardSolid(**truth),
                     force=([0.0, 0.5, 1.0], [0.0, 1.0, 1.0]), duration=1.0, body=mv.Layer(1.0),
                     times=times)
    bem = mv.solve(scene, "bem", 65)
    layer = mv.fit(mv.Paraboloid(c=0.5), mv.StandardSolid, bem.t, depth=bem.depth, force=bem.force,
                   body=mv.Layer(1.0), n=2000)
    assert layer.success, layer.message
    assert layer.forward == "hereditary"
    for name, value in truth.items():
        assert abs(layer.parameters[name] / value - 1) < 1e-2, (name, layer.parameters)
    half = mv.fit(mv.Paraboloid(c=0.5), mv.StandardSolid, bem.t, depth=bem.depth, force=bem.force, n=2000)
    assert half.parameters["G_inf"] > 1.1 * truth["G_inf"]
    with pytest.raises(InvalidInputError, match="body"):
        mv.fit(mv.Paraboloid(c=0.5), mv.StandardSolid, bem.t, depth=bem.depth, force=bem.force, body=1.0)


def test_unloading_on_a_layer_agrees_with_bem():
    """A paraboloid (R = 1) pressed 0.04 deep into a bonded incompressible standard-solid
    layer (h = 0.2, contact up to 1.4 h; tau = 0.1 s against a 0.5 s ramp) and withdrawn at
    the same rate: MDR's receding contact (each element leaving when its force would turn
    tensile, Ting's rule with the layer's profile) against BEM (n = 65), an independent
    method, at loading and unloading times. The forces agree to 0.3 % wherever the force
    exceeds 1 % of its peak (measured 0.02-0.16 %, up to 0.07 % at n = 97: BEM's
    discretisation), the contact radii (BEM's from its area) to a quarter of an element
    (measured 0.06-0.2 of one), and both let go together (zero force at the same output
    times)."""
    times = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.9])
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5),
                     medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.1, nu=0.5),
                     depth=([0.0, 0.5, 1.0], [0.0, 0.04, 0.0]), duration=1.0, times=times,
                     body=mv.Layer(0.2))
    bem = mv.solve(scene, "bem", 65, dt=0.01)
    mdr = mv.solve(scene, "mdr", 4001, dt=0.01)
    pressed = mdr.force > 0.01 * mdr.force.max()
    assert pressed[:9].all() and times[8] > 0.5
    assert np.all(np.abs(bem.force[pressed] / mdr.force[pressed] - 1) < 3e-3)
    radius = np.sqrt(bem.area[pressed] / np.pi)
    assert np.all(np.abs(radius - 0.5 * mdr.contact_length[pressed]) < 0.25 * bem.dx)
    assert np.array_equal(bem.force[~pressed] > 0, mdr.force[~pressed] > 0)
