"""The paper's comparisons (Kürschner & Filippov 2012, Sections 5 and 6) as plain data.

Every function runs its scenes and returns dicts of numbers, lists of row dicts and numpy
arrays; nothing is printed (:mod:`mdrvisc.report` formats and plots). Units are SI: lengths and
depths in m, times in s, forces in N, pressures in Pa, velocities in m/s, viscosities in Pa s,
wall times in s. Relative differences are (a - b) / b, dimensionless. NaN marks a closed form
that does not apply.

``progress``, where accepted, is a callable ``progress(label)`` called before each solve with a
short label naming it (e.g. ``"paraboloid c=1 BEM n=257"``).
"""

import numpy as np

from . import analytic
from .geometry import Paraboloid, Rod
from .media import Viscous
from .scene import Scene
from .solve import solve

__all__ = ["paper", "paper_rod", "paper_paraboloids", "PAPER", "QUICK", "PAPER_ROD",
           "ROD_UNITS", "PARABOLOID_UNITS"]

#: Resolutions of the paper: rod BEM n = 200 (31417 elements in the disc), paraboloid BEM
#: 257 x 257, MDR 66049 elements.
PAPER = {"rod": {"n_bem": 200, "n_mdr": 66049}, "paraboloids": {"n_bem": 257, "n_mdr": 66049}}
#: Coarse resolutions that run the whole comparison in seconds.
QUICK = {"rod": {"n_bem": 50, "n_mdr": 4097}, "paraboloids": {"n_bem": 65, "n_mdr": 4097}}

#: The paper's own rod results (Eqs. 24-26): BEM on 31417 elements, and MDR.
PAPER_ROD = {"bem": {"elements": 31417, "central_pressure": 0.1608, "velocity": 0.1252},
             "mdr": {"velocity": 0.125}}

#: Units of the keys of :func:`paper_rod`'s rows.
ROD_UNITS = {"source": "", "elements": "", "central_pressure": "Pa", "velocity": "m/s",
             "central_pressure_error": "1", "velocity_error": "1", "wall_time": "s"}

#: Units of the keys of :func:`paper_paraboloids`' rows. ``*_vs_*``: relative differences;
#: ``length_bem``: the paper's Eq. 23 (F / (4 eta dd/dt)); ``length_bem_area``: 2 sqrt(A / pi).
PARABOLOID_UNITS = {
    "c": "1/m", "t": "s",
    "depth_bem": "m", "depth_mdr": "m", "depth_lee_radok": "m",
    "length_bem": "m", "length_bem_area": "m", "length_mdr": "m", "length_lee_radok": "m",
    "depth_bem_vs_mdr": "1", "depth_bem_vs_lee_radok": "1", "depth_mdr_vs_lee_radok": "1",
    "length_bem_vs_mdr": "1", "length_bem_area_vs_mdr": "1", "length_bem_vs_lee_radok": "1",
    "length_mdr_vs_lee_radok": "1", "bem_at_edge": "", "mdr_saturated": "",
}

ROD_RADIUS = 1.0  # m
FORCE = 1.0  # N
ETA = 1.0  # Pa s
EDGE = 2.56  # m, side of the square paraboloid indenters
DURATION = 5.0  # s


def _announced(progress):
    """``solve`` that first calls ``progress(label)`` (when given) with its first argument."""

    def run(label, *args, **kwargs):
        if progress is not None:
            progress(label)
        return solve(*args, **kwargs)

    return run


def _rel(a, b):
    """(a - b) / b, element-wise (NaN where b is NaN)."""
    return (np.asarray(a, dtype=float) - b) / b


def paper_rod(n_bem=200, n_mdr=66049, progress=None):
    """Section 5: a flat rod (a = 1 m) pressed by F = 1 N into a viscous half-space (1 Pa s).

    Parameters
    ----------
    n_bem : int
        BEM grid: elements across the diameter (200 gives the paper's 31417 in the disc).
    n_mdr : int
        MDR elements over the 1D rod (length 2a).
    progress : callable(label), optional

    Returns
    -------
    dict
        ``rows``: list of dicts (keys :data:`ROD_UNITS`) for the closed form, the paper's BEM,
        this BEM, the paper's MDR and this MDR: central pressure p0 (Pa), penetration rate
        (m/s), their relative errors against the closed form, element count, wall time (s);
        None where a source gives no value. ``profile``: Fig. 3 data along the x axis through
        the centre, in units of x/a: ``bem`` (``x_velocity``, ``velocity`` out to 2a;
        ``x_pressure``, ``pressure`` over the face), ``closed`` (``x``, ``velocity``,
        ``pressure``) and ``mdr`` (``x``, ``velocity``, ``pressure`` from the inverse
        transforms, mirrored to negative x). ``parameters``: radius (m), force (N), eta (Pa s),
        n_bem, n_mdr.
    """
    a = ROD_RADIUS
    scene = Scene(indenter=Rod(radius=a), medium=Viscous(eta=ETA), force=FORCE, duration=1.0,
                  times=[1.0], outputs=("depth", "pressure", "surface_velocity"))
    run = _announced(progress)
    bem = run(f"rod BEM n={n_bem}", scene, "bem", n_bem)
    mdr = run(f"rod MDR n={n_mdr}", scene, "mdr", n_mdr)

    p0 = analytic.rod_central_pressure(FORCE, a)
    v0 = analytic.rod_velocity(FORCE, a, ETA)

    def row(source, elements, pressure, velocity, wall_time=None):
        return {"source": source, "elements": elements, "central_pressure": pressure,
                "velocity": velocity,
                "central_pressure_error": None if pressure is None else (pressure - p0) / p0,
                "velocity_error": (velocity - v0) / v0, "wall_time": wall_time}

    paper_bem = PAPER_ROD["bem"]
    rows = [
        row("closed form", None, p0, v0),
        row("paper BEM", paper_bem["elements"], paper_bem["central_pressure"],
            paper_bem["velocity"]),
        row(f"BEM n={n_bem}", int(round(bem.area[0] / bem.dx**2)), bem.central_pressure,
            float(bem.velocity), bem.wall_time),
        row("paper MDR", None, None, PAPER_ROD["mdr"]["velocity"]),
        row(f"MDR n={n_mdr}", n_mdr, mdr.central_pressure, float(mdr.velocity), mdr.wall_time),
    ]
    return {"parameters": {"radius": a, "force": FORCE, "eta": ETA, "n_bem": n_bem,
                           "n_mdr": n_mdr},
            "rows": rows, "profile": _rod_profile(bem, mdr, a)}


def _rod_profile(bem, mdr, a):
    """Fig. 3 data (x in units of a) from the BEM grid row through the centre, the closed
    forms and the MDR radial fields mirrored to negative x."""
    fb = next(iter(bem.fields.values()))
    centre = fb["x"].size // 2
    centre_ext = fb["x_extended"].size // 2
    x = (np.arange(40) + 0.5) * 0.1 - 2.0  # dots between the edges at |x| = a
    fm = next(iter(mdr.fields.values()))
    r = fm["r"]
    inside = r < a
    return {
        "bem": {"x_velocity": fb["x_extended"] / a,
                "velocity": fb["surface_velocity"][centre_ext, :],
                "x_pressure": fb["x"] / a, "pressure": fb["pressure"][centre, :]},
        "closed": {"x": x,
                   "velocity": analytic.rod_surface_velocity(np.abs(x) * a, FORCE, a, ETA),
                   "pressure": analytic.rod_pressure(np.abs(x) * a, FORCE, a)},
        "mdr": {"x": np.concatenate([-r[::-1], r]) / a,
                "velocity": np.concatenate([fm["surface_velocity"][::-1], fm["surface_velocity"]]),
                "pressure": np.concatenate([fm["pressure"][inside][::-1], fm["pressure"][inside]]),
                "x_pressure": np.concatenate([-r[inside][::-1], r[inside]]) / a},
    }


def paper_paraboloids(cs=(0.05, 0.2, 1.0, 5.0, 20.0), n_bem=257, n_mdr=66049,
                      times=(1.0, 2.0, 3.0, 4.0, 5.0), progress=None, fine=200):
    """Section 6: paraboloids h = c r^2 on a 2.56 m square, F = 1 N, eta = 1 Pa s, 5 s.

    Parameters
    ----------
    cs : sequence of float
        Curvature parameters c (1/m).
    n_bem : int
        BEM grid n x n over the square.
    n_mdr : int
        MDR elements over the 1D indenter (length 2 x 2.56 m / sqrt(pi), equal area).
    times : sequence of float
        Compared output times (s), in (0, 5].
    progress : callable(label), optional
    fine : int
        MDR output times for the Fig. 4 lines: ``fine`` equal steps up to 5 s.

    Returns
    -------
    dict
        ``rows``: one dict per (c, t) with keys :data:`PARABOLOID_UNITS`: depths (m) and contact
        lengths (m) from BEM (Eq. 23 and area-based), MDR and Lee-Radok (NaN once the closed
        form's contact diameter exceeds the 2.56 m edge), their relative differences,
        and whether the BEM contact touched the square's edge / the MDR contact filled the 1D
        indenter. ``curves``: per c, MDR ``t`` (s), ``depth`` (m), ``contact_length`` (m) at
        the fine times, starting at (0, 0). ``runs``: per solve, c, method, n, integrator,
        wall time (s), steps, solves, iterations, largest residual. ``parameters``: edge (m),
        force (N), eta (Pa s), duration (s), n_bem, n_mdr.
    """
    times = np.asarray(times, dtype=float)
    fine_times = DURATION * np.arange(1, fine + 1) / fine
    all_times = np.union1d(times, fine_times)
    at = np.searchsorted(all_times, times)
    run = _announced(progress)
    rows, curves, runs = [], [], []
    for c in cs:
        indenter = Paraboloid(c=c, edge=EDGE)
        medium = Viscous(eta=ETA)
        bem = run(f"paraboloid c={c:g} BEM n={n_bem}", Scene(
            indenter=indenter, medium=medium, force=FORCE, duration=DURATION, times=times,
            outputs=("depth", "contact_length", "stiffness_length")), "bem", n_bem)
        mdr = run(f"paraboloid c={c:g} MDR n={n_mdr}", Scene(
            indenter=indenter, medium=medium, force=FORCE, duration=DURATION, times=all_times),
            "mdr", n_mdr)
        runs += [{"c": c, "method": r.method, "n": r.n, "integrator": r.integrator,
                  "wall_time": r.wall_time, "steps": r.steps, "solves": r.solves,
                  "iterations": r.iterations, "residual": r.residual} for r in (bem, mdr)]
        curves.append({"c": c, "t": np.concatenate([[0.0], mdr.t]),
                       "depth": np.concatenate([[0.0], mdr.depth]),
                       "contact_length": np.concatenate([[0.0], mdr.contact_length])})
        rows += _paraboloid_rows(c, times, bem, mdr, at)
    return {"parameters": {"edge": EDGE, "force": FORCE, "eta": ETA, "duration": DURATION,
                           "n_bem": n_bem, "n_mdr": n_mdr},
            "rows": rows, "curves": curves, "runs": runs}


def _paraboloid_rows(c, times, bem, mdr, at):
    """Table rows of one paraboloid: BEM at ``times``, MDR at indices ``at`` of its times."""
    length_lr = analytic.paraboloid_contact_length(times, FORCE, c, ETA)
    valid = length_lr <= EDGE
    length_lr = np.where(valid, length_lr, np.nan)
    depth_lr = np.where(valid, analytic.paraboloid_depth(times, FORCE, c, ETA), np.nan)
    d_b, d_m = bem.depth, mdr.depth[at]
    l_b, l_a, l_m = bem.stiffness_length, bem.contact_length, mdr.contact_length[at]
    columns = {
        "c": np.full(times.shape, float(c)), "t": times,
        "depth_bem": d_b, "depth_mdr": d_m, "depth_lee_radok": depth_lr,
        "length_bem": l_b, "length_bem_area": l_a, "length_mdr": l_m,
        "length_lee_radok": length_lr,
        "depth_bem_vs_mdr": _rel(d_b, d_m), "depth_bem_vs_lee_radok": _rel(d_b, depth_lr),
        "depth_mdr_vs_lee_radok": _rel(d_m, depth_lr),
        "length_bem_vs_mdr": _rel(l_b, l_m), "length_bem_area_vs_mdr": _rel(l_a, l_m),
        "length_bem_vs_lee_radok": _rel(l_b, length_lr),
        "length_mdr_vs_lee_radok": _rel(l_m, length_lr),
    }
    rows = [{k: float(v[i]) for k, v in columns.items()} for i in range(times.size)]
    for row, edge, full in zip(rows, bem.saturated, mdr.saturated[at]):
        row["bem_at_edge"] = bool(edge)
        row["mdr_saturated"] = bool(full)
    return rows


def paper(quick=False, progress=None):
    """Both comparisons of the paper, at its resolutions (:data:`PAPER`) or :data:`QUICK`.

    Returns ``{"quick": bool, "rod": paper_rod(...), "paraboloids": paper_paraboloids(...)}``;
    ``progress(label)`` is announced before each solve.
    """
    sizes = QUICK if quick else PAPER
    return {"quick": bool(quick),
            "rod": paper_rod(progress=progress, **sizes["rod"]),
            "paraboloids": paper_paraboloids(progress=progress, **sizes["paraboloids"])}
