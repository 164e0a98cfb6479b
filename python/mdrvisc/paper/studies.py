"""The paper's comparisons (Kürschner & Filippov 2012, Sections 5 and 6) as plain data, and
one beyond it: viscoelastic loading and unloading against Ting's closed form.

Every function runs its scenes and returns dicts of numbers, lists of row dicts and numpy
arrays; nothing is printed (:mod:`mdrvisc.paper.report` formats and plots). Units are SI:
lengths and depths in m, times in s, forces in N, pressures in Pa, velocities in m/s,
viscosities in Pa s, wall times in s. Relative differences are (a - b) / b, dimensionless.
NaN marks a closed form that does not apply.

``progress``, where accepted, is a callable ``progress(label)`` called before each solve with a
short label naming it (e.g. ``"paraboloid c=1 BEM n=257"``).

The paper's scenes are its scene files (:mod:`mdrvisc.paper.runs`), read when a function
runs: ``scenes`` (a :class:`~mdrvisc.paper.runs.PaperScenes`), where accepted, gives them
instead, and the force, viscosity, sizes and durations of every section come from them.

One module of about 650 lines, for a reason: the three sections and the error study share the
paper's scenes and the timing helpers, and each section is a few functions that read top to
bottom as the paper does.
"""

import dataclasses
import math
import os
import time
import warnings
from collections.abc import Callable, Sequence

import numpy as np

from .. import analytic
from ..errors import ResolutionWarning
from ..geometry import Paraboloid
from ..media import KelvinVoigt, StandardSolid, Viscous
from ..scene import Scene
from ..solve import solve
from .runs import PaperScenes, load_scenes

__all__ = ["paper", "paper_rod", "paper_paraboloids", "PAPER_ROD",
           "ROD_UNITS", "PARABOLOID_UNITS", "viscoelastic", "VISCOELASTIC", "VISCOELASTIC_QUICK",
           "VISCOELASTIC_MEDIA", "VISCOELASTIC_UNITS", "error_vs_runtime", "ERROR_STUDY",
           "ERROR_STUDY_QUICK", "ERROR_UNITS", "ORDER_UNITS", "PAPER_LOOPS", "paper_settings"]

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

#: Units of the keys of :func:`viscoelastic`'s rows. Force errors: max ``|F - F_Ting|`` / max
#: F_Ting over the outputs while loading (t <= t_peak) and unloading (t > t_peak);
#: ``radius_error``: max ``|contact_length / 2 - a_Ting|`` in elements (units of ``dx``);
#: ``t_last_contact`` / ``t_first_free``: the last output time with F > 0 and the first with
#: F = 0 (None if there is none), which should bracket Ting's ``t_separation``.
VISCOELASTIC_UNITS = {
    "medium": "", "method": "", "n": "", "dx": "m", "dt": "s", "peak_force": "N",
    "force_error_loading": "1", "force_error_unloading": "1", "radius_error": "dx",
    "t_separation": "s", "t_last_contact": "s", "t_first_free": "s", "wall_time": "s",
}
#: Resolutions of :func:`viscoelastic`: MDR and BEM elements (as in ``solve``) and the
#: longest viscoelastic time step ``dt`` (s).
VISCOELASTIC = {"n_mdr": 8001, "n_bem": 65, "dt": 0.005}
#: Coarser ones that run the section in about a second.
VISCOELASTIC_QUICK = {"n_mdr": 2001, "n_bem": 33, "dt": 0.01}
#: The media of :func:`viscoelastic` (moduli in Pa, times in s, viscosities in Pa s).
VISCOELASTIC_MEDIA = (StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5), KelvinVoigt(G=1.5, eta=0.4))


def _announced(progress):
    """``solve`` that first calls ``progress(label)`` (when given) with its first argument."""

    def run(label, *args, **kwargs):
        if progress is not None:
            progress(label)
        with warnings.catch_warnings():
            # coarse runs are the point of the study, which measures their errors itself
            warnings.simplefilter("ignore", ResolutionWarning)
            return solve(*args, **kwargs)

    return run


def _rel(a, b):
    """(a - b) / b, element-wise (NaN where b is NaN)."""
    return (np.asarray(a, dtype=float) - b) / b


def paper_rod(n_bem: int | None = None, n_mdr: int | None = None,
              progress: Callable[[str], object] | None = None, scenes: PaperScenes | None = None) -> dict:
    """Section 5: a flat rod (a = 1 m) pressed by F = 1 N into a viscous half-space (1 Pa s).

    Parameters
    ----------
    n_bem : int, optional
        BEM grid: elements across the diameter (the paper's scene file: 200, the paper's 31417
        in the disc).
    n_mdr : int, optional
        MDR elements over the 1D rod (length 2a; the paper's scene file: 66049).
    progress : callable(label), optional
    scenes : PaperScenes, optional
        The paper's scenes (default: its scene files, :func:`~mdrvisc.paper.runs.load_scenes`).

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
    scenes = load_scenes() if scenes is None else scenes
    n_bem = scenes.rod_resolutions.n_bem if n_bem is None else n_bem
    n_mdr = scenes.rod_resolutions.n_mdr if n_mdr is None else n_mdr
    scene = scenes.rod
    a, force, eta = scene.indenter.radius, scene.force, scene.medium.eta
    run = _announced(progress)
    bem = run(f"rod BEM n={n_bem}", scene, "bem", n_bem)
    mdr = run(f"rod MDR n={n_mdr}", scene, "mdr", n_mdr)

    p0 = analytic.rod_central_pressure(force, a)
    v0 = analytic.rod_velocity(force, a, eta)

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
        row(f"BEM n={n_bem}", int(round(bem.area[0] / bem.dx**2)), float(bem.central_pressure[0]),
            float(bem.velocity[0]), bem.wall_time),
        row("paper MDR", None, None, PAPER_ROD["mdr"]["velocity"]),
        row(f"MDR n={n_mdr}", n_mdr, float(mdr.central_pressure[0]), float(mdr.velocity[0]),
            mdr.wall_time),
    ]
    return {"parameters": {"radius": a, "force": force, "eta": eta, "n_bem": n_bem,
                           "n_mdr": n_mdr},
            "rows": rows, "profile": _rod_profile(bem, mdr, a, force, eta)}


def _rod_profile(bem, mdr, a, force, eta):
    """Fig. 3 data (x in units of a) from the BEM grid row through the centre, the closed
    forms and the MDR radial fields mirrored to negative x."""
    fb = next(iter(bem.fields.values()))
    centre = fb.x.size // 2
    centre_ext = fb.x_extended.size // 2
    x = (np.arange(40) + 0.5) * 0.1 - 2.0  # dots between the edges at |x| = a
    fm = next(iter(mdr.fields.values()))
    r = fm.r
    inside = r < a
    return {
        "bem": {"x_velocity": fb.x_extended / a,
                "velocity": fb.surface_velocity[centre_ext, :],
                "x_pressure": fb.x / a, "pressure": fb.pressure[centre, :]},
        "closed": {"x": x,
                   "velocity": analytic.rod_surface_velocity(np.abs(x) * a, force, a, eta),
                   "pressure": analytic.rod_pressure(np.abs(x) * a, force, a)},
        "mdr": {"x": np.concatenate([-r[::-1], r]) / a,
                "velocity": np.concatenate([fm.surface_velocity[::-1], fm.surface_velocity]),
                "pressure": np.concatenate([fm.pressure[inside][::-1], fm.pressure[inside]]),
                "x_pressure": np.concatenate([-r[inside][::-1], r[inside]]) / a},
    }


def paper_paraboloids(cs: Sequence[float] | None = None, n_bem: int | None = None,
                      n_mdr: int | None = None, times: Sequence[float] = (1.0, 2.0, 3.0, 4.0, 5.0),
                      progress: Callable[[str], object] | None = None, fine: int = 200,
                      scenes: PaperScenes | None = None) -> dict:
    """Section 6: paraboloids h = c r^2 on a 2.56 m square, F = 1 N, eta = 1 Pa s, 5 s.

    Parameters
    ----------
    cs : sequence of float, optional
        Curvature parameters c (1/m) (the paper's scene files: 0.05, 0.2, 1, 5, 20).
    n_bem : int, optional
        BEM grid n x n over the square (the paper's scene files: 257).
    n_mdr : int, optional
        MDR elements over the 1D indenter (length 2 x 2.56 m / sqrt(pi), equal area; the
        paper's scene files: 66049).
    times : sequence of float
        Compared output times (s), in (0, 5].
    progress : callable(label), optional
    fine : int
        MDR output times for the Fig. 4 lines: ``fine`` equal steps up to 5 s.
    scenes : PaperScenes, optional
        The paper's scenes (default: its scene files, :func:`~mdrvisc.paper.runs.load_scenes`).

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
    scenes = load_scenes() if scenes is None else scenes
    cs = scenes.curvatures if cs is None else cs
    n_bem = scenes.paraboloid_resolutions.n_bem if n_bem is None else n_bem
    n_mdr = scenes.paraboloid_resolutions.n_mdr if n_mdr is None else n_mdr
    base = scenes.paraboloid
    edge = base.indenter.edge
    times = np.asarray(times, dtype=float)
    fine_times = base.duration * np.arange(1, fine + 1) / fine
    all_times = np.union1d(times, fine_times)
    at = np.searchsorted(all_times, times)
    run = _announced(progress)
    rows, curves, runs = [], [], []
    for c in cs:
        scene = dataclasses.replace(base, indenter=Paraboloid(c=c, edge=edge), times=times)
        bem = run(f"paraboloid c={c:g} BEM n={n_bem}", scene, "bem", n_bem)
        mdr = run(f"paraboloid c={c:g} MDR n={n_mdr}", dataclasses.replace(
            scene, times=all_times, outputs=("depth", "contact_length")), "mdr", n_mdr)
        runs += [{"c": c, "method": r.method, "n": r.n, "integrator": r.integrator,
                  "wall_time": r.wall_time, "steps": r.steps, "solves": r.solves,
                  "iterations": r.iterations, "residual": r.residual} for r in (bem, mdr)]
        curves.append({"c": c, "t": np.concatenate([[0.0], mdr.t]),
                       "depth": np.concatenate([[0.0], mdr.depth]),
                       "contact_length": np.concatenate([[0.0], mdr.contact_length])})
        rows += _paraboloid_rows(scene, times, bem, mdr, at)
    return {"parameters": {"edge": edge, "force": base.force, "eta": base.medium.eta,
                           "duration": base.duration, "n_bem": n_bem, "n_mdr": n_mdr},
            "rows": rows, "curves": curves, "runs": runs}


def _paraboloid_rows(scene, times, bem, mdr, at):
    """Table rows of one paraboloid's ``scene``: BEM at ``times``, MDR at indices ``at`` of its
    times."""
    c, force, eta = scene.indenter.c, scene.force, scene.medium.eta
    length_lr = analytic.paraboloid_contact_length(times, force, c, eta)
    valid = length_lr <= scene.indenter.edge
    length_lr = np.where(valid, length_lr, np.nan)
    depth_lr = np.where(valid, analytic.paraboloid_depth(times, force, c, eta), np.nan)
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
    for row, edge, full in zip(rows, bem.at_edge, mdr.saturated[at]):
        row["bem_at_edge"] = bool(edge)
        row["mdr_saturated"] = bool(full)
    return rows


VE_C = 1.0  # 1/m, paraboloid h = c r^2 of the viscoelastic section (R = 0.5 m)
VE_RATE = 0.2  # m/s, indentation and withdrawal rate
VE_T_PEAK = 1.0  # s, end of loading; the depth is back at 0 at 2 t_peak
VE_SPACING = 0.01  # s, between output times


def _medium_label(medium):
    """``Name(p=v, ...)`` of a medium with its parameters in %g."""
    values = ", ".join(f"{f.name}={getattr(medium, f.name):g}" for f in dataclasses.fields(medium))
    return f"{type(medium).__name__}({values})"


def viscoelastic(quick: bool = False, progress: Callable[[str], object] | None = None) -> dict:
    """Beyond the paper: a paraboloid pushed into viscoelastic media and pulled out, against
    Ting's closed form (:func:`mdrvisc.analytic.ting_paraboloid_triangle`).

    h = c r^2 with c = 1 1/m (R = 0.5 m), unbounded; depth d = v t up to t_peak = 1 s and
    v (2 t_peak - t) after, v = 0.2 m/s (history ([0, 1, 2] s, [0, 0.2, 0] m)), duration
    2 s, outputs every 0.01 s; media :data:`VISCOELASTIC_MEDIA` (a standard solid and a
    Kelvin-Voigt body), each solved by MDR and BEM at :data:`VISCOELASTIC` (or
    :data:`VISCOELASTIC_QUICK`).

    Parameters
    ----------
    quick : bool
        :data:`VISCOELASTIC_QUICK` (coarser elements, longer step) instead of
        :data:`VISCOELASTIC`.
    progress : callable(label), optional

    Returns
    -------
    dict
        ``rows``: one dict per medium x method, keys :data:`VISCOELASTIC_UNITS`: n, element
        size dx (m), time step dt (s), Ting's peak force (N), the largest force errors
        relative to it while loading and unloading, the largest contact-radius error in
        elements, Ting's separation time (s), the outputs bracketing the separation (s), wall
        time (s). ``curves``: per medium, ``medium`` (label), ``t`` (s, from 0),
        ``force_ting`` (N), ``radius_ting`` (m), and ``force_mdr``, ``radius_mdr``,
        ``force_bem``, ``radius_bem`` (N, m; radius = contact_length / 2) at those times.
        ``parameters``: c (1/m), radius_of_curvature (m), rate (m/s), t_peak (s), duration
        (s), spacing (s), n_mdr, n_bem, dt (s), media (labels). ``quick``.
    """
    sizes = VISCOELASTIC_QUICK if quick else VISCOELASTIC
    radius_of_curvature = 1.0 / (2.0 * VE_C)
    duration = 2.0 * VE_T_PEAK
    times = np.arange(1, round(duration / VE_SPACING) + 1) * VE_SPACING
    depth = ([0.0, VE_T_PEAK, duration], [0.0, VE_RATE * VE_T_PEAK, 0.0])
    run = _announced(progress)
    rows, curves = [], []
    for medium in VISCOELASTIC_MEDIA:
        label = _medium_label(medium)
        scene = Scene(indenter=Paraboloid(c=VE_C), medium=medium, depth=depth, duration=duration,
                      times=times, dt=sizes["dt"])
        force, radius, t_sep = analytic.ting_paraboloid_triangle(
            times, medium, radius_of_curvature, VE_RATE, VE_T_PEAK)
        peak = float(force.max())
        curve = {"medium": label, "t": np.concatenate([[0.0], times]),
                 "force_ting": np.concatenate([[0.0], force]),
                 "radius_ting": np.concatenate([[0.0], radius])}
        for method in ("mdr", "bem"):
            n = sizes[f"n_{method}"]
            r = run(f"viscoelastic {type(medium).__name__} {method.upper()} n={n} "
                    f"dt={sizes['dt']:g}", scene, method, n)
            error = np.abs(r.force - force) / peak
            loading = r.t <= VE_T_PEAK
            touching, free = r.t[r.force > 0], r.t[r.force == 0]
            rows.append({
                "medium": label, "method": method.upper(), "n": r.n, "dx": float(r.dx),
                "dt": sizes["dt"], "peak_force": peak,
                "force_error_loading": float(error[loading].max()),
                "force_error_unloading": float(error[~loading].max()),
                "radius_error": float(np.max(np.abs(r.contact_length / 2 - radius)) / r.dx),
                "t_separation": float(t_sep),
                "t_last_contact": float(touching.max()) if touching.size else None,
                "t_first_free": float(free.min()) if free.size else None,
                "wall_time": r.wall_time})
            curve[f"force_{method}"] = np.concatenate([[0.0], r.force])
            curve[f"radius_{method}"] = np.concatenate([[0.0], r.contact_length / 2])
        curves.append(curve)
    return {"quick": bool(quick),
            "parameters": {"c": VE_C, "radius_of_curvature": radius_of_curvature,
                           "rate": VE_RATE, "t_peak": VE_T_PEAK, "duration": duration,
                           "spacing": VE_SPACING, **sizes,
                           "media": [_medium_label(m) for m in VISCOELASTIC_MEDIA]},
            "rows": rows, "curves": curves}


def paper(quick: bool = False, progress: Callable[[str], object] | None = None,
          directory: str | os.PathLike | None = None) -> dict:
    """Both comparisons of the paper, from its scene files in ``directory`` (default: those
    shipped with the package, :data:`mdrvisc.paper.runs.SCENES`) at their resolutions or, with
    ``quick``, their ``[quick]`` ones; and the viscoelastic section beyond it
    (:data:`VISCOELASTIC` or :data:`VISCOELASTIC_QUICK`).

    Returns ``{"quick": bool, "rod": paper_rod(...), "paraboloids": paper_paraboloids(...),
    "viscoelastic": viscoelastic(...)}``; ``progress(label)`` is announced before each solve.
    """
    scenes = load_scenes(quick, directory)
    return {"quick": bool(quick),
            "rod": paper_rod(progress=progress, scenes=scenes),
            "paraboloids": paper_paraboloids(progress=progress, scenes=scenes),
            "viscoelastic": viscoelastic(quick=quick, progress=progress)}


# ----------------------------------------------------------------------------- error vs run time
#: The error-vs-run-time sweep. Paraboloids h = c r^2 on the 2.56 m square (F = 1 N,
#: eta = 1 Pa s, errors of d(5 s) and l(5 s) against Lee-Radok) and the rod (a = 1 m, errors of
#: dd/dt and p0 against the closed form). ``bem_n``: elements across the square (implicit);
#: ``bem_explicit``: {n: relative steps dt / t} of the explicit loop, with ``bem_area_change``;
#: ``mdr_n``: elements of the 1D indenter (implicit); the explicit MDR loop runs at
#: ``mdr_explicit_n`` for every step in ``mdr_steps`` and area rule in ``mdr_area_changes``,
#: and at ``mdr_explicit_cross_n`` for ``cross_step`` only (its error against n);
#: ``rod_bem_n``: elements across the rod's diameter; ``rod_mdr_n``: elements of the 1D rod.
ERROR_STUDY = {
    "cs": (1.0, 5.0),
    "bem_n": (33, 65, 129, 257, 513),
    "bem_explicit": {65: (0.1, 0.03, 0.01, 0.003), 129: (0.1, 0.03, 0.01, 0.003),
                     257: (0.1, 0.03, 0.01)},
    "bem_area_change": 0.01,
    "mdr_n": (257, 1025, 4097, 16385, 66049, 263169, 1050625),
    "mdr_explicit_n": 66049,
    "mdr_steps": (0.1, 0.03, 0.01, 0.003, 0.001),
    "mdr_area_changes": (0.01, 0.0),
    "mdr_explicit_cross_n": (4097, 1050625),
    "cross_step": 0.01,
    "rod_bem_n": (50, 100, 200, 400),
    "rod_mdr_n": (257, 1025, 4097, 16385, 66049, 263169, 1050625),
}
#: The same study in seconds: coarse BEM, no BEM at the paper's 257 x 257.
ERROR_STUDY_QUICK = {
    "cs": (1.0, 5.0),
    "bem_n": (33, 65, 129),
    "bem_explicit": {33: (0.1, 0.03, 0.01), 65: (0.1, 0.03, 0.01)},
    "bem_area_change": 0.01,
    "mdr_n": (257, 1025, 4097, 16385, 66049),
    "mdr_explicit_n": 66049,
    "mdr_steps": (0.1, 0.03, 0.01, 0.003),
    "mdr_area_changes": (0.01, 0.0),
    "mdr_explicit_cross_n": (4097,),
    "cross_step": 0.01,
    "rod_bem_n": (50, 100, 200),
    "rod_mdr_n": (257, 4097, 66049),
}

#: The paper's explicit loops, marked in the study (``paper`` = True) at the resolutions of its
#: scene files (:func:`paper_settings`). BEM re-solves at 1 % area growth; the paper gives no
#: time step, dt = 0.01 t is assumed. MDR: the explicit loop without the area rule (the
#: paper's MDR used "no speed-up techniques") at the assumed step.
PAPER_LOOPS = {"bem": {"step": 0.01, "area_change": 0.01}, "mdr": {"step": 0.01, "area_change": 0.0}}


def paper_settings(scenes: PaperScenes) -> dict:
    """The paper's own settings, marked in the study: :data:`PAPER_LOOPS` at the resolutions
    of ``scenes`` (the paper's: BEM 257 x 257 and MDR 66049 elements for the paraboloids, BEM
    n = 200 (31417 elements) and MDR 66049 for the rod). ``{"bem": {"n", "step",
    "area_change"}, "mdr": {...}, "rod": {"n_bem", "n_mdr"}}``."""
    par, rod = scenes.paraboloid_resolutions, scenes.rod_resolutions
    return {"bem": {"n": par.n_bem, **PAPER_LOOPS["bem"]},
            "mdr": {"n": par.n_mdr, **PAPER_LOOPS["mdr"]},
            "rod": {"n_bem": rod.n_bem, "n_mdr": rod.n_mdr}}

#: Runs shorter than this (s) are timed as the best of :data:`BEST_OF` runs.
REPEAT_BELOW = 0.1
BEST_OF = 3
#: Relative errors below this count as exact (rounding).
ROUNDING = 1e-14
#: Explicit and implicit answers closer than this (relative) count as equal: the same final
#: contact set, differing by the contact solver's tolerance (1e-10) only.
SAME_AS_IMPLICIT = 1e-9

#: Quantities of the study: (label, unit).
QUANTITIES = {"depth": ("d(5 s)", "m"), "contact_length": ("l(5 s)", "m"),
              "stiffness_length": ("l Eq.23 (5 s)", "m"), "velocity": ("dd/dt", "m/s"),
              "central_pressure": ("p0", "Pa")}

#: Units of the keys of :func:`error_vs_runtime`'s rows. ``value`` and ``exact`` are in
#: ``unit``; ``step`` is dt / t of the explicit loop; ``error``: (value - exact) / exact;
#: ``error_vs_implicit``: (value - implicit value at the same n) / implicit value (explicit
#: rows: the time-discretisation error alone).
ERROR_UNITS = {
    "case": "", "quantity": "", "unit": "", "method": "", "integrator": "", "series": "",
    "n": "", "dx": "m", "step": "1", "area_change": "1", "value": "", "exact": "",
    "error": "1", "error_vs_implicit": "1", "wall_time": "s", "steps": "", "solves": "",
    "iterations": "", "paper": "",
}

#: Units of the keys of :func:`error_vs_runtime`'s ``orders``: ``|error|`` ~ variable^order.
ORDER_UNITS = {
    "method": "", "integrator": "", "case": "", "quantity": "", "fixed": "", "variable": "",
    "against": "", "points": "", "from": "", "to": "", "error_finest": "1", "order": "1",
    "order_last": "1", "note": "",
}


def _timed(run, label, *args, **kwargs):
    """(result, wall time in s): runs ``solve`` once, and twice more for short runs (best of 3)."""
    result = run(label, *args, **kwargs)
    best = result.wall_time
    if best < REPEAT_BELOW:
        for _ in range(BEST_OF - 1):
            best = min(best, solve(*args, **kwargs).wall_time)
    return result, best


def error_vs_runtime(quick: bool = False, progress: Callable[[str], object] | None = None,
                     settings: dict | None = None, directory: str | os.PathLike | None = None) -> dict:
    """Error against run time of BEM and MDR, implicit and explicit.

    Paraboloids c = 1 and 5 (1/m) on the 2.56 m square, F = 1 N, eta = 1 Pa s: relative errors
    of d(5 s) and l(5 s) against Lee-Radok (the contact stays inside the square until 5 s);
    BEM l both from the area (2 sqrt(A / pi)) and by Eq. 23 (F / (4 eta dd/dt)). The rod
    (a = 1 m, F = 1 N, eta = 1 Pa s): dd/dt and p0 against the closed form (one solve, no time
    stepping). Wall times are the best of 3 for runs under 0.1 s.

    Parameters
    ----------
    quick : bool
        :data:`ERROR_STUDY_QUICK` (seconds) instead of :data:`ERROR_STUDY`.
    progress : callable(label), optional
    settings : dict, optional
        Overrides keys of the chosen sweep.
    directory : path, optional
        The paper's scene files (default: those shipped with the package): the rod, the
        paraboloids' square, force, viscosity and duration, and the paper's resolutions
        marked in the study.

    Returns
    -------
    dict
        ``rows``: one dict per (run, quantity), keys :data:`ERROR_UNITS`. ``orders``: observed
        convergence orders, keys :data:`ORDER_UNITS`: ``|error|`` ~ dx^order along every
        resolution sweep (implicit; explicit at a fixed step), ~ step^order along every step
        sweep (against the closed form and against the implicit answer at the same n), fitted
        by least squares in log-log (``order``) and from the two finest points
        (``order_last``). ``settings``: the sweep; ``paper_settings``:
        :func:`paper_settings`; ``parameters``: edge (m), force (N), eta (Pa s), duration (s),
        rod radius (m); ``quick``; ``total_wall_time`` (s).
    """
    sweep = dict(ERROR_STUDY_QUICK if quick else ERROR_STUDY)
    sweep.update(settings or {})
    scenes = load_scenes(False, directory)
    marks = paper_settings(scenes)
    run = _announced(progress)
    start = time.perf_counter()
    rows = []
    for c in sweep["cs"]:
        rows += _paraboloid_sweep(scenes.paraboloid, float(c), sweep, run, marks)
    rows += _rod_sweep(scenes.rod, sweep, run, marks)
    base, rod = scenes.paraboloid, scenes.rod
    return {"quick": bool(quick), "settings": sweep, "paper_settings": marks,
            "parameters": {"edge": base.indenter.edge, "force": base.force, "eta": base.medium.eta,
                           "duration": base.duration, "rod_radius": rod.indenter.radius},
            "rows": rows, "orders": convergence_orders(rows, sweep["cross_step"]),
            "total_wall_time": time.perf_counter() - start}


def _row(case, quantity, result, wall_time, value, exact, series, step=None, area_change=None,
         implicit=None, paper=False, integrator=None):
    label, unit = QUANTITIES[quantity]
    value = float(value)
    return {"case": case, "quantity": quantity, "unit": unit, "method": result.method.upper(),
            "integrator": integrator or result.integrator, "series": series, "n": result.n,
            "dx": result.dx, "step": step, "area_change": area_change, "value": value,
            "exact": float(exact), "error": float((value - exact) / exact),
            "error_vs_implicit": None if implicit is None else float((value - implicit) / implicit),
            "wall_time": wall_time, "steps": int(result.steps), "solves": int(result.solves),
            "iterations": int(result.iterations), "paper": bool(paper)}


def _paraboloid_sweep(base, c, sweep, run, marks):
    """Rows of one paraboloid, the scene ``base`` with curvature ``c``: BEM and MDR, implicit
    and explicit; the paper's settings ``marks``."""
    edge, force, eta, duration = base.indenter.edge, base.force, base.medium.eta, base.duration
    exact = {"depth": float(analytic.paraboloid_depth(duration, force, c, eta)),
             "contact_length": float(analytic.paraboloid_contact_length(duration, force, c, eta))}
    exact["stiffness_length"] = exact["contact_length"]
    if exact["contact_length"] > edge:
        raise ValueError(f"error_vs_runtime: c = {c} leaves the {edge} m square before "
                         f"{duration} s; Lee-Radok does not apply")
    case = f"paraboloid c={c:g}"
    indenter, medium = Paraboloid(c=c, edge=edge), Viscous(eta=eta)
    scene = {m: Scene(indenter=indenter, medium=medium, force=force, duration=duration,
                      times=[duration], outputs=outputs)
             for m, outputs in (("bem", ("depth", "contact_length", "stiffness_length")),
                                ("mdr", ("depth", "contact_length")))}
    quantities = {"bem": ("depth", "contact_length", "stiffness_length"),
                  "mdr": ("depth", "contact_length")}
    rows, implicit = [], {}

    def add(method, n, series, step=None, area_change=None, paper=False):
        kwargs = {} if step is None else {"integrator": "explicit", "step": step,
                                          "area_change": area_change}
        what = "implicit" if step is None else f"explicit step={step:g} area_change={area_change:g}"
        result, wall = _timed(run, f"study: {case} {method.upper()} n={n} {what}",
                              scene[method], method, n, **kwargs)
        for q in quantities[method]:
            value = getattr(result, q)[-1]
            if step is None:
                implicit[(method, n, q)] = value
            rows.append(_row(case, q, result, wall, value, exact[q], series, step, area_change,
                             implicit.get((method, n, q)) if step is not None else None, paper))

    pb, pm = marks["bem"], marks["mdr"]
    for n in sweep["bem_n"]:
        add("bem", n, "BEM implicit")
    for n, steps in sweep["bem_explicit"].items():
        ac = sweep["bem_area_change"]
        for step in steps:
            add("bem", n, f"BEM explicit n={n} area_change={ac:g}", step, ac,
                paper=(n, step, ac) == (pb["n"], pb["step"], pb["area_change"]))
    for n in sweep["mdr_n"]:
        add("mdr", n, "MDR implicit", paper=n == pm["n"])
    n = sweep["mdr_explicit_n"]
    for ac in sweep["mdr_area_changes"]:
        for step in sweep["mdr_steps"]:
            add("mdr", n, f"MDR explicit n={n} area_change={ac:g}", step, ac,
                paper=(n, step, ac) == (pm["n"], pm["step"], pm["area_change"]))
        for m in sweep["mdr_explicit_cross_n"]:
            add("mdr", m, f"MDR explicit n={m} area_change={ac:g}", sweep["cross_step"], ac)
    return rows


def _rod_sweep(rod, sweep, run, marks):
    """Rows of the rod's scene ``rod``: one solve per resolution (its contact never changes);
    the paper's settings ``marks``."""
    scene = dataclasses.replace(rod, outputs=("depth", "contact_length"))
    a, force, eta = rod.indenter.radius, rod.force, rod.medium.eta
    exact = {"velocity": analytic.rod_velocity(force, a, eta),
             "central_pressure": analytic.rod_central_pressure(force, a)}
    paper = marks["rod"]
    rows = []
    for method, ns, n_paper in (("bem", sweep["rod_bem_n"], paper["n_bem"]),
                                ("mdr", sweep["rod_mdr_n"], paper["n_mdr"])):
        for n in ns:
            result, wall = _timed(run, f"study: rod {method.upper()} n={n}", scene, method, n)
            for q in ("velocity", "central_pressure"):
                rows.append(_row("rod", q, result, wall, float(getattr(result, q)[-1]), exact[q],
                                 f"{method.upper()} one solve", paper=n == n_paper,
                                 integrator="one solve"))
    return rows


def _fit_order(x, err, floor):
    """(least-squares order, order of the two finest points) of ``|err|`` ~ x^order, the points
    ordered coarse to fine; errors at or below ``floor`` are left out of the fit, and the
    two-point order is None unless both finest errors are above it. None where fewer than two
    errors are above ``floor``."""
    x, err = np.asarray(x, dtype=float), np.abs(np.asarray(err, dtype=float))
    keep = err > floor
    if keep.sum() < 2:
        return None, None
    order = float(np.polyfit(np.log(x[keep]), np.log(err[keep]), 1)[0])
    last = None
    if keep[-1] and keep[-2]:
        last = float(math.log(err[-2] / err[-1]) / math.log(x[-2] / x[-1]))
    return order, last


def _order_entry(group, variable, against, fixed):
    closed = against == "closed form"
    key, floor = ("error", ROUNDING) if closed else ("error_vs_implicit", SAME_AS_IMPLICIT)
    group = sorted(group, key=lambda r: -r[variable])  # coarse to fine
    x = [r[variable] for r in group]
    err = [r[key] for r in group]
    order, last = _fit_order(x, err, floor)
    first = group[0]
    zero = sum(abs(e) <= floor for e in err)
    note = []
    if zero == len(err):
        note.append("exact to rounding" if closed else "equals the implicit answer")
    elif zero:
        note.append(f"{zero} of {len(err)} " + ("exact to rounding" if closed
                                                else "equal the implicit answer"))
    if zero < len(err) - 1 and order is None:
        note.append("fewer than two errors to fit")
    signs = [np.sign(e) for e in err if abs(e) > floor]
    if any(a != b for a, b in zip(signs, signs[1:])):
        note.append("error changes sign")
    return {"method": first["method"], "integrator": first["integrator"], "case": first["case"],
            "quantity": first["quantity"], "fixed": fixed, "variable": variable,
            "against": against, "points": len(group), "from": x[0], "to": x[-1],
            "error_finest": float(abs(err[-1])), "order": order, "order_last": last,
            "note": "; ".join(note)}


def convergence_orders(rows: list[dict], cross_step: float = 0.01) -> list[dict]:
    """Observed orders ``|error|`` ~ variable^order of the study's ``rows``: along dx for every
    implicit (and one-solve) series, along dx for the explicit runs at step ``cross_step``, and
    along the step for every explicit series of more than one step (against the closed form
    and against the implicit answer at the same n)."""
    groups = {}
    for r in rows:
        if r["integrator"] == "explicit":
            groups.setdefault(("step", r["series"], r["case"], r["quantity"]), []).append(r)
            if r["step"] == cross_step:
                key = (r["method"], r["area_change"])
                groups.setdefault(("dx", key, r["case"], r["quantity"]), []).append(r)
        else:
            groups.setdefault(("dx", r["series"], r["case"], r["quantity"]), []).append(r)
    orders = []
    for (variable, _, _, _), group in groups.items():
        if len(group) < 2:
            continue
        first = group[0]
        if variable == "step":
            fixed = f"n={first['n']}, area_change={first['area_change']:g}"
            for against in ("closed form", "implicit, same n"):
                orders.append(_order_entry(group, "step", against, fixed))
        else:
            fixed = ("" if first["integrator"] != "explicit"
                     else f"step={cross_step:g}, area_change={first['area_change']:g}")
            orders.append(_order_entry(group, "dx", "closed form", fixed))
    rank = {"depth": 0, "contact_length": 1, "stiffness_length": 2, "velocity": 3,
            "central_pressure": 4}

    def fixed_n(entry):
        head = entry["fixed"].split(",")[0]
        return int(head[2:]) if head.startswith("n=") else -1

    orders.sort(key=lambda o: (o["case"], rank[o["quantity"]], o["method"], o["integrator"],
                               o["variable"], fixed_n(o), o["fixed"], o["against"]))
    return orders
