"""``solve(scene, method, n)``: run a scene by BEM or MDR and return a :class:`Result`."""

import math
import sys
import time

import numpy as np

from . import _core
from ._validate import _positive
from .analytic import lee_radok_depth_from_impulse
from .errors import DomainError, InvalidInputError, MdrviscError
from .media import VISCOELASTIC, Elastic, Viscous
from .scene import Result, Scene

__all__ = ["solve", "bem_grid", "mdr_grid"]

#: An unbounded indenter's grid reaches this factor times its final contact radius.
UNBOUNDED_MARGIN = 1.2


def _progress_printer(stage, done, total):
    """Prints one self-overwriting progress line per stage to stderr."""
    end = "\n" if done >= total else ""
    print(f"\r  {stage}: {done}/{total}".ljust(48), end=end, file=sys.stderr, flush=True)


def _final_contact_radius(scene):
    """Contact radius (m) at the last output time of an unbounded indenter (from MDR)."""
    ind = scene.indenter
    if hasattr(scene, "depth") and not hasattr(scene, "final_load"):
        return ind.contact_radius_at_depth(scene.depth)
    modulus = scene.medium.eta if isinstance(scene.medium, Viscous) else scene.medium.G
    depth = lee_radok_depth_from_impulse(scene.final_load, ind, modulus)
    return ind.contact_radius_at_depth(depth)


def bem_grid(scene, n):
    """Element centres x (= y) (m), spacing dx (m), heights h and footprint mask for BEM.

    Square footprints get n x n elements over the edge; a rod gets dx = diameter / n on a grid
    centred on an element ((n + 1) x (n + 1) for even n: n = 200 puts the paper's 31417
    elements in the disc); other disc footprints get n x n over the diameter; unbounded
    indenters n x n over 1.2 times the final contact diameter.
    """
    ind = scene.indenter
    half = ind.footprint_half_width
    if half is None:
        half = UNBOUNDED_MARGIN * _final_contact_radius(scene)
    dx = 2.0 * half / n
    if ind.is_flat:
        m = n // 2
        x = np.arange(-m, m + 1) * dx
    else:
        x = (np.arange(n) - 0.5 * (n - 1)) * dx
    h, mask = ind.height_map(x, x)
    return x, dx, np.ascontiguousarray(h, dtype=np.float64), np.ascontiguousarray(mask, dtype=bool)


def mdr_grid(scene, n):
    """Element centres x (m), spacing dx (m) and 1D profile g (m) for MDR: n elements over
    the 1D indenter (unbounded: 1.2 times the final contact length)."""
    ind = scene.indenter
    half = ind.mdr_half_length
    if half is None:
        half = UNBOUNDED_MARGIN * _final_contact_radius(scene)
    dx = 2.0 * half / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    return x, dx, np.ascontiguousarray(ind.profile_1d(x), dtype=np.float64)


def _check_n(n, method):
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise InvalidInputError(f"solve: n must be a positive integer, got {n!r}")
    if method == "bem" and n > 4096:
        raise InvalidInputError(f"solve: BEM grid n = {n} exceeds the supported 4096")
    return int(n)


def solve(scene, method="bem", n=None, tol=1e-10, max_iter=5000, progress=None,
          integrator="implicit", step=0.01, area_change=0.01, dt=None):
    """Solves ``scene`` by ``method`` ("bem" or "mdr") at resolution ``n``.

    Parameters
    ----------
    scene : Scene
    method : {"bem", "mdr"}
    n : int
        BEM: elements across the footprint (n x n grid); MDR: elements of the 1D indenter.
        Default 257 (BEM) or 66049 (MDR), the paper's resolutions.
    tol : float
        Relative tolerance of the BEM contact solver (sum |dp| / sum p); MDR is exact.
    max_iter : int
        Iteration limit of the BEM solver; reaching it raises ConvergenceError.
    progress : callable(stage, done, total) or True, optional
        Called from the computing thread between chunks of work; True prints to stderr.
    integrator : {"implicit", "explicit"}
        "implicit" (default): one exact impulse step per output time (no time-discretisation
        error while the contact grows). "explicit": the paper's loop (Fig. 1b): surface
        velocity of the current contact, explicit Euler steps dt = step * t, the contact
        re-solved only when its area grew by more than ``area_change`` (paper: 1 %).
    step, area_change : float
        Controls of the explicit integrator (ignored by the implicit one).
    dt : float, optional
        Longest time step (s) of the viscoelastic stepping (KelvinVoigt, Maxwell,
        StandardSolid, Prony, or depth control); default ``scene.dt``, else duration / 500.

    Returns
    -------
    Result
    """
    if not isinstance(scene, Scene):
        raise InvalidInputError(f"solve: scene must be a Scene, got {scene!r}")
    if method not in ("bem", "mdr"):
        raise InvalidInputError(f"solve: method must be 'bem' or 'mdr', got {method!r}")
    n = _check_n(257 if method == "bem" and n is None else 66049 if n is None else n, method)
    callback = _progress_printer if progress is True else progress
    if integrator not in ("implicit", "explicit"):
        raise InvalidInputError(f"solve: integrator must be 'implicit' or 'explicit', got {integrator!r}")
    explicit = None
    if integrator == "explicit" and not scene.indenter.is_flat:
        if not isinstance(scene.medium, Viscous):
            raise InvalidInputError("solve: the explicit integrator needs a viscous medium")
        explicit = (_positive("solve", "step", step), float(area_change), 1e-6)
        if not (math.isfinite(explicit[1]) and explicit[1] >= 0):
            raise InvalidInputError(f"solve: area_change must be finite and >= 0, got {area_change!r}")
    start = time.perf_counter()
    if isinstance(scene.medium, VISCOELASTIC) or scene.controlled_by == "depth":
        result = _solve_viscoelastic(scene, method, n, tol, max_iter, callback, dt)
    elif method == "bem":
        result = _solve_bem(scene, n, tol, max_iter, callback, explicit)
    else:
        result = _solve_mdr(scene, n, callback, explicit)
    # a flat punch's contact never changes: one solve, whatever integrator was named
    result.integrator = "one solve" if scene.indenter.is_flat else integrator
    result.warnings = _resolution_warnings(result)
    result.wall_time = time.perf_counter() - start
    return result


#: Contacts narrower than this many elements are flagged as under-resolved.
MIN_CONTACT_ELEMENTS = 10


def _resolution_warnings(result):
    """Flags output times whose contact spans fewer than MIN_CONTACT_ELEMENTS elements."""
    spans = np.atleast_1d(result.contact_length) / result.dx
    thin = np.flatnonzero(spans < MIN_CONTACT_ELEMENTS)
    if thin.size == 0:
        return []
    return [f"{result.method.upper()}: the contact spans fewer than {MIN_CONTACT_ELEMENTS} elements "
            f"(min {spans[thin].min():.1f}) at t = {np.atleast_1d(result.t)[thin].tolist()} s; "
            "expect errors of several percent there (refine n)"]


def _field_steps(scene):
    if not scene.wants_fields:
        return []
    return [int(np.argmin(np.abs(scene.times - ft))) for ft in scene.field_times]


def _solve_bem(scene, n, tol, max_iter, callback, explicit):
    x, dx, h, mask = bem_grid(scene, n)
    ind = scene.indenter
    if isinstance(scene.medium, Elastic):
        force = float(scene.history[1][-1])
        r = _core.contact_solve(h, mask, dx, 1.0 / scene.medium.G, force=force, tol=tol,
                                max_iter=max_iter, progress=callback,
                                depth_bound=_static_depth_bound(scene, force),
                                deflection=scene.wants("deflection"))
        area = r["contact_count"] * dx * dx
        fields = {None: {"x": x, "y": x, **{k: r[k] for k in ("pressure", "deflection")
                                            if scene.wants(k)}}}
        return Result("bem", n, dx, np.array([0.0]), np.array([r["depth"]]),
                      np.array([2 * math.sqrt(area / math.pi)]), area=np.array([area]),
                      fields=fields if scene.wants_fields else None, steps=0,
                      solves=r["solves"], iterations=r["iterations"], residual=r["residual"],
                      grid_shape=h.shape)
    eta = scene.medium.eta
    ft, fv = scene.history
    if ind.is_flat:
        return _solve_bem_rod(scene, n, x, dx, mask, eta, tol, max_iter, callback)
    steps = _field_steps(scene)
    rates = scene.wants("velocity") or scene.wants("stiffness_length")
    r = _core.bem_viscous(h, mask, dx, eta, scene.times, ft, fv, rates=rates, fields_at=steps,
                          tol=tol, max_iter=max_iter, progress=callback, explicit=explicit,
                          depth_bounds=_depth_bounds(scene))
    if ind.footprint_half_width is None and np.any(r["at_border"]):
        raise DomainError("BEM: the contact reached the edge of the grid of an unbounded indenter "
                          f"at t = {r['t'][np.argmax(r['at_border'])]} s; the grid is too small")
    fields = None
    if steps:
        fields = {float(ft): {"x": x, "y": x, **_pick(scene, r["fields"][k])}
                  for ft, k in zip(scene.field_times, steps)}
    return Result("bem", n, dx, r["t"], r["depth"], r["contact_length"], area=r["area"],
                  velocity=r["velocity"] if scene.wants("velocity") else None,
                  stiffness_length=r["stiffness_length"] if scene.wants("stiffness_length") else None,
                  fields=fields, saturated=_covers(r["area"], mask, dx), at_edge=r["at_border"],
                  steps=r["steps"], solves=r["solves"],
                  iterations=int(np.sum(r["iterations"])), residual=float(np.max(r["residual"])),
                  grid_shape=h.shape)


def _static_depth_bound(scene, force):
    """1.05 times the MDR (Hertz-type) depth of an elastic contact under ``force``, which sizes
    the solve's window (checked by the solver, which widens it if it was too small); None
    where no closed form applies."""
    try:
        return 1.05 * float(lee_radok_depth_from_impulse(force, scene.indenter, scene.medium.G))
    except MdrviscError:
        return None


def _depth_bounds(scene):
    """1.05 times the MDR (Lee–Radok) depth at each output time, which sizes that step's
    window (the solver checks it and widens the window if it was too small); NaN where no
    closed form applies (e.g. once the contact fills the footprint), None if nowhere."""
    impulses = np.array([scene.impulse(float(t)) for t in scene.times])

    def depth(impulse):
        try:
            return lee_radok_depth_from_impulse(impulse, scene.indenter, scene.medium.eta)
        except MdrviscError:
            return math.nan

    depths = np.asarray(depth(impulses), dtype=np.float64)
    if np.all(np.isnan(depths)):  # one time beyond the closed form fails them all: one by one
        depths = np.array([depth(float(i)) for i in impulses])
    return None if np.all(np.isnan(depths)) else 1.05 * depths


def _covers(area, mask, dx):
    """Whether each contact area is the whole footprint."""
    return np.asarray(area) >= mask.sum() * dx * dx * (1 - 1e-12)


def _pick(scene, fields):
    names = {"pressure": "pressure", "surface_velocity": "velocity", "deflection": "deflection"}
    return {k: fields[v] for k, v in names.items() if scene.wants(k)}


def _solve_bem_rod(scene, n, x, dx, mask, eta, tol, max_iter, callback):
    """A flat punch: its contact never changes, so one solve gives every output time."""
    ft, fv = scene.history
    if fv.size > 1 and np.any(fv != fv[0]):
        raise InvalidInputError("BEM rod: only a constant force is supported")
    force = float(fv[0])
    margin = x.size // 2 if scene.wants("surface_velocity") else None
    r = _core.bem_punch(mask, dx, eta, force, margin=margin, tol=tol, max_iter=max_iter, progress=callback)
    m = x.size
    c = m // 2
    p = r["pressure"]
    p0 = float(p[c, c]) if m % 2 else float(p[c - 1:c + 1, c - 1:c + 1].mean())
    area = float(mask.sum()) * dx * dx
    fields = None
    if scene.wants_fields:
        entry = {"x": x, "y": x}
        if scene.wants("pressure"):
            entry["pressure"] = p
        if scene.wants("surface_velocity"):
            xe = (np.arange(m + 2 * margin) - (m + 2 * margin - 1) / 2) * dx
            entry.update(x_extended=xe, surface_velocity=r["surface_velocity"])
        fields = {float(t): entry for t in scene.field_times}
    t = scene.times
    return Result("bem", n, dx, t, r["velocity"] * t, np.full(t.shape, 2 * math.sqrt(area / math.pi)),
                  area=np.full(t.shape, area), velocity=r["velocity"],
                  stiffness_length=np.full(t.shape, r["damping"] / (4 * eta)),
                  central_pressure=p0, fields=fields, steps=0, solves=1, iterations=r["iterations"],
                  residual=r["residual"], grid_shape=mask.shape)


def _solve_mdr(scene, n, callback, explicit):
    x, dx, g = mdr_grid(scene, n)
    ft, fv = scene.history
    elastic = isinstance(scene.medium, Elastic)
    medium, param = ("elastic", scene.medium.G) if elastic else ("viscous", scene.medium.eta)
    times = np.array([1.0]) if elastic else scene.times
    keys, steps = ([None], [0]) if elastic else ([float(t) for t in scene.field_times], _field_steps(scene))
    rod = scene.indenter.is_flat and not elastic
    core_steps = [] if explicit is not None else sorted(set(steps) | ({0} if rod else set()))
    r = _core.mdr_run(g, dx, medium, param, times, ft, fv, fields_at=core_steps, progress=callback,
                      explicit=explicit)
    fields = None
    if core_steps and scene.wants_fields:
        fields = {key: _mdr_fields(scene, x, dx, r, k) for key, k in zip(keys, steps)}
    central = None
    if scene.indenter.is_flat and not elastic and 0 in r["fields"]:
        central = float(_core.mdr_pressure(r["fields"][0]["line_load"], dx, np.array([0.0]))[0])
    length = r["contact_length"]
    velocity = r["velocity"]
    return Result("mdr", n, dx, np.array([0.0]) if elastic else r["t"], r["depth"], length,
                  velocity=(float(velocity[0]) if scene.indenter.is_flat else velocity)
                  if scene.wants("velocity") or scene.indenter.is_flat else None,
                  stiffness_length=None if elastic else (length if scene.wants("stiffness_length") else None),
                  central_pressure=central, fields=fields, saturated=r["saturated"],
                  steps=r["steps"], solves=len(times), iterations=0, residual=0.0)


def _mdr_fields(scene, x, dx, r, k):
    """3D radial fields from the 1D solution at output k by the inverse MDR transforms."""
    f = r["fields"][k]
    a = 0.5 * float(r["contact_length"][k])
    radius = np.linspace(0.0, 2.0 * max(a, dx), 401)
    out = {"r": radius}
    if scene.wants("pressure"):
        out["pressure"] = _core.mdr_pressure(f["line_load"], dx, radius)
    inside = radius < a
    if scene.wants("surface_velocity"):
        v = _core.mdr_deflection(f["velocity"], dx, radius)
        v[inside] = float(r["velocity"][k])
        out["surface_velocity"] = v
    if scene.wants("deflection"):
        u = _core.mdr_deflection(f["displacement"], dx, radius)
        u[inside] = float(r["depth"][k]) - scene.indenter._height(radius[inside])
        out["deflection"] = u
    return out


def _solve_viscoelastic(scene, method, n, tol, max_iter, callback, dt):
    """General linear viscoelastic stepping (exact exponential updates, dt-limited steps)."""
    dt = scene.dt if dt is None else _positive("solve", "dt", dt)
    dt = scene.duration / 500 if dt is None else dt
    g_inf, terms, eta = scene.medium.rheology()
    lt, lv = scene.history
    common = (g_inf, [tuple(map(float, term)) for term in terms], eta, scene.controlled_by, lt, lv,
              scene.times, dt)
    if method == "mdr":
        x, dx, g = mdr_grid(_sizing_scene(scene), n)
        r = _core.viscoelastic_mdr(g, dx, *common, progress=callback)
        shape = None
    else:
        x, dx, h, mask = bem_grid(_sizing_scene(scene), n)
        r = _core.viscoelastic_bem(h, mask, dx, *common, tol=tol, max_iter=max_iter, progress=callback)
        shape = h.shape
    return Result(method, n, dx, r["t"], r["depth"], r["contact_length"], force=r["force"], steps=r["steps"],
                  solves=r["steps"] if method == "bem" else 0, iterations=int(np.sum(r["iterations"])),
                  grid_shape=shape)


def _sizing_scene(scene):
    """A scene whose final load sizes the grid of an unbounded indenter: the largest contact
    is the elastic one at the largest force with the modulus 1 / J(duration) (the creep
    compliance at the end), or the one at the largest depth."""
    if scene.indenter.footprint_half_width is not None and scene.indenter.mdr_half_length is not None:
        return scene
    _, values = scene.history
    if scene.controlled_by == "depth":
        return _DepthSizing(scene.indenter, float(np.max(values)))
    modulus = 1.0 / float(scene.medium.creep_compliance(scene.duration))
    return _ForceSizing(scene.indenter, float(np.max(values)), modulus)


class _ForceSizing:
    """Stands in for a Scene when sizing grids: the elastic problem at the largest force."""

    def __init__(self, indenter, force, modulus):
        self.indenter, self.final_load, self.medium = indenter, force, Elastic(G=modulus)


class _DepthSizing:
    """Stands in for a Scene when sizing grids: the contact at the largest depth."""

    def __init__(self, indenter, depth):
        self.indenter, self.depth = indenter, depth
