"""Tables, CSV/JSON files and figures of the paper's comparisons and the viscoelastic section
beyond it (:mod:`mdrvisc.paper.studies`).

Units as in :mod:`mdrvisc.paper.studies`: SI throughout; relative differences are
(a - b) / b.

The figures need matplotlib, an optional dependency (``pip install 'mdrvisc[paper]'``): the
plotting functions raise ImportError naming it when it is missing; the tables and the
CSV/JSON files need nothing beyond numpy, and :func:`write_paper` and
:func:`write_error_vs_runtime` write them without figures when asked (``figures=False``;
:func:`can_draw` says whether matplotlib is there).

One module of about 530 lines, for a reason: it mirrors :mod:`mdrvisc.paper.studies` section
by section (table, files, figure of each), so a change to one section's data and to its
output stay side by side.
"""

import csv
import importlib.util
import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from ..formatting import text_table, to_jsonable
from .studies import (
    ERROR_UNITS,
    ORDER_UNITS,
    PARABOLOID_UNITS,
    QUANTITIES,
    ROD_UNITS,
    ROUNDING,
    VISCOELASTIC_UNITS,
)

__all__ = ["can_draw", "rod_table", "paraboloid_tables", "viscoelastic_table", "write_csv", "paper_document",
           "write_paper", "plot_rod", "plot_paraboloids", "plot_viscoelastic", "error_table",
           "orders_table", "study_document", "write_error_vs_runtime", "plot_error_vs_runtime"]


# ----------------------------------------------------------------------------- text tables
def rod_table(rod: dict) -> str:
    """The rod comparison (:func:`mdrvisc.paper.studies.paper_rod`'s result) as aligned
    text."""
    p = rod["parameters"]
    title = (f"Rod (Section 5): a = {p['radius']:g} m, F = {p['force']:g} N, "
             f"eta = {p['eta']:g} Pa s; errors relative to the closed form")
    columns = [("source", "source", ""), ("elements", "elements", "d"),
               ("p0 [Pa]", "central_pressure", ".6f"), ("err p0", "central_pressure_error", "+.3%"),
               ("dd/dt [m/s]", "velocity", ".6f"), ("err dd/dt", "velocity_error", "+.3%"),
               ("wall [s]", "wall_time", ".3f")]
    return title + "\n" + text_table(columns, rod["rows"])


def paraboloid_tables(par: dict) -> str:
    """The paraboloid comparison (:func:`mdrvisc.paper.studies.paper_paraboloids`'s result)
    as aligned text: depths, contact lengths and run statistics."""
    p = par["parameters"]
    head = [("c [1/m]", "c", "g"), ("t [s]", "t", "g")]
    depth = head + [("BEM [m]", "depth_bem", ".6f"), ("MDR [m]", "depth_mdr", ".6f"),
                    ("Lee-Radok [m]", "depth_lee_radok", ".6f"),
                    ("BEM/MDR-1", "depth_bem_vs_mdr", "+.2e"),
                    ("BEM/LR-1", "depth_bem_vs_lee_radok", "+.2e"),
                    ("MDR/LR-1", "depth_mdr_vs_lee_radok", "+.2e"),
                    ("BEM at edge", "bem_at_edge", ""), ("MDR full", "mdr_saturated", "")]
    length = head + [("BEM Eq.23 [m]", "length_bem", ".5f"),
                     ("BEM area [m]", "length_bem_area", ".5f"),
                     ("MDR [m]", "length_mdr", ".5f"), ("Lee-Radok [m]", "length_lee_radok", ".5f"),
                     ("Eq.23/MDR-1", "length_bem_vs_mdr", "+.2e"),
                     ("area/MDR-1", "length_bem_area_vs_mdr", "+.2e"),
                     ("Eq.23/LR-1", "length_bem_vs_lee_radok", "+.2e"),
                     ("MDR/LR-1", "length_mdr_vs_lee_radok", "+.2e")]
    runs = [("c [1/m]", "c", "g"), ("method", "method", ""), ("n", "n", "d"),
            ("integrator", "integrator", ""), ("steps", "steps", "d"), ("solves", "solves", "d"),
            ("iterations", "iterations", "d"),
            ("residual", "residual", ".1e"), ("wall [s]", "wall_time", ".3f")]
    title = (f"Paraboloids (Section 6): h = c r^2 on a {p['edge']:g} m square, "
             f"F = {p['force']:g} N, eta = {p['eta']:g} Pa s\n"
             f"BEM n = {p['n_bem']} x {p['n_bem']}, MDR n = {p['n_mdr']}; "
             "Lee-Radok (LR) n/a once 2a > edge")
    return "\n\n".join([title, "Depth d(t)\n" + text_table(depth, par["rows"]),
                        "Contact length l(t) (BEM: Eq. 23 l = F/(4 eta dd/dt), and 2 sqrt(A/pi))\n"
                        + text_table(length, par["rows"]),
                        "Runs\n" + text_table(runs, par["runs"])])


def viscoelastic_table(ve: dict) -> str:
    """The viscoelastic section (:func:`mdrvisc.paper.studies.viscoelastic`'s result) as
    aligned text: errors against Ting's closed form and the outputs bracketing the
    separation."""
    p = ve["parameters"]
    title = (f"Beyond the paper: viscoelastic loading and unloading against Ting (1966): "
             f"h = c r^2, c = {p['c']:g} 1/m (R = {p['radius_of_curvature']:g} m), pushed in "
             f"at {p['rate']:g} m/s to t = {p['t_peak']:g} s and pulled out to "
             f"{p['duration']:g} s, outputs every {p['spacing']:g} s\n"
             "F err: max |F - F_Ting| / max F_Ting while loading (t <= t_peak) and unloading; "
             "a err: max |l/2 - a_Ting| in elements dx; separation: Ting's t_s and the last "
             "output with F > 0, first with F = 0")
    columns = [("medium", "medium", ""), ("method", "method", ""), ("n", "n", "d"),
               ("dx [m]", "dx", ".2e"), ("dt [s]", "dt", "g"),
               ("F err load", "force_error_loading", ".2e"),
               ("F err unload", "force_error_unloading", ".2e"),
               ("a err [dx]", "radius_error", ".3f"), ("t_s Ting [s]", "t_separation", ".4f"),
               ("F > 0 until [s]", "t_last_contact", "g"), ("F = 0 from [s]", "t_first_free", "g"),
               ("wall [s]", "wall_time", ".3f")]
    return title + "\n" + text_table(columns, ve["rows"])


# ----------------------------------------------------------------------------- files
def write_csv(path: str | os.PathLike, rows: Iterable[Mapping[str, object]],
              units: Mapping[str, str]) -> None:
    """Writes ``rows`` (dicts with the keys of ``units``) to ``path``; headers carry units as
    ``name [unit]``; None is written empty, NaN as ``nan``."""
    headers = [f"{k} [{u}]" if u else k for k, u in units.items()]
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(headers)
        for row in rows:
            writer.writerow(["" if row[k] is None else repr(row[k]) if isinstance(row[k], float)
                             else row[k] for k in units])


def paper_document(results: dict, study: dict | None = None) -> dict:
    """The JSON document of :func:`mdrvisc.paper.studies.paper`'s result: tables, units,
    runs; with ``study`` (:func:`mdrvisc.paper.studies.error_vs_runtime`'s result) also its
    :func:`study_document` under ``error_vs_runtime``."""
    rod, par, ve = results["rod"], results["paraboloids"], results["viscoelastic"]
    doc = {
        "quick": results["quick"],
        "rod": {"parameters": rod["parameters"], "units": ROD_UNITS, "rows": rod["rows"]},
        "paraboloids": {"parameters": par["parameters"], "units": PARABOLOID_UNITS,
                        "rows": par["rows"], "runs": par["runs"]},
        "viscoelastic": {"parameters": ve["parameters"], "units": VISCOELASTIC_UNITS,
                         "rows": ve["rows"]},
    }
    if study is not None:
        doc["error_vs_runtime"] = study_document(study)
    return to_jsonable(doc)


def write_paper(results: dict, out: str | os.PathLike, study: dict | None = None,
                figures: bool = True) -> list[Path]:
    """Writes rod.csv, paraboloids.csv, viscoelastic.csv, paper.json and, with ``figures``
    (needs matplotlib), fig3_rod.png, fig4_paraboloids.png and fig_viscoelastic.png into the
    folder ``out`` (created if missing); returns their paths. paper.json holds
    :func:`paper_document` (with ``study`` when given; its own files come from
    :func:`write_error_vs_runtime`)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    names = ("rod.csv", "paraboloids.csv", "viscoelastic.csv", "paper.json")
    if figures:
        names += ("fig3_rod.png", "fig4_paraboloids.png", "fig_viscoelastic.png")
    paths = {name: out / name for name in names}
    write_csv(paths["rod.csv"], results["rod"]["rows"], ROD_UNITS)
    write_csv(paths["paraboloids.csv"], results["paraboloids"]["rows"], PARABOLOID_UNITS)
    write_csv(paths["viscoelastic.csv"], results["viscoelastic"]["rows"], VISCOELASTIC_UNITS)
    paths["paper.json"].write_text(json.dumps(paper_document(results, study), indent=1) + "\n",
                                   encoding="utf-8")
    if figures:
        plot_rod(results["rod"], paths["fig3_rod.png"])
        plot_paraboloids(results["paraboloids"], paths["fig4_paraboloids.png"])
        plot_viscoelastic(results["viscoelastic"], paths["fig_viscoelastic.png"])
    return list(paths.values())


# ----------------------------------------------------------------------------- figures
#: What to install for the figures.
PAPER_EXTRA = "pip install 'mdrvisc[paper]'"


def can_draw() -> bool:
    """Whether matplotlib, which the figures need, is installed."""
    try:
        return importlib.util.find_spec("matplotlib") is not None
    except ValueError:  # a module without a spec in sys.modules
        return False


def _pyplot():
    """matplotlib.pyplot on the Agg backend (files only, no display); ImportError naming the
    ``paper`` extra when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError(f"the paper's figures need matplotlib: {PAPER_EXTRA}") from None

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_rod(rod: dict, path: str | os.PathLike) -> None:
    """Fig. 3: surface velocity (m/s) and pressure (Pa) along x through the rod's centre, vs
    x/a: BEM line, closed form dots, MDR inverse transforms dashed. Saves a PNG at ``path``."""
    plt = _pyplot()
    prof = rod["profile"]
    bem, closed, mdr = prof["bem"], prof["closed"], prof["mdr"]
    p = rod["parameters"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    left.plot(bem["x_velocity"], bem["velocity"], "-", color="C0", label=f"BEM (n = {p['n_bem']})")
    left.plot(closed["x"], closed["velocity"], "o", color="k", ms=3.5, label="closed form")
    left.plot(mdr["x"], mdr["velocity"], "--", color="C3", label=f"MDR inverse (n = {p['n_mdr']})")
    left.set(xlabel="x / a", ylabel="surface velocity du/dt [m/s]", xlim=(-2, 2), ylim=(0, None),
             title="(a) displacement rate of the surface")
    right.plot(bem["x_pressure"], bem["pressure"], "-", color="C0", label=f"BEM (n = {p['n_bem']})")
    right.plot(closed["x"], closed["pressure"], "o", color="k", ms=3.5, label="closed form")
    right.plot(mdr["x_pressure"], mdr["pressure"], "--", color="C3",
               label=f"MDR inverse (n = {p['n_mdr']})")
    p0 = rod["rows"][0]["central_pressure"]
    right.set(xlabel="x / a", ylabel="pressure p [Pa]", xlim=(-2, 2), ylim=(0, 5 * p0),
              title="(b) normal stress")
    left.legend(loc="lower center", fontsize=8)
    right.legend(loc="upper center", fontsize=8)
    for ax in (left, right):
        ax.grid(alpha=0.3)
    fig.suptitle(f"Flat rod on a viscous half-space: a = {p['radius']:g} m, F = {p['force']:g} N, "
                 f"eta = {p['eta']:g} Pa s")
    fig.savefig(path, dpi=150)
    plt.close(fig)


def plot_paraboloids(par: dict, path: str | os.PathLike) -> None:
    """Fig. 4: depth d(t) (m) and contact length l(t) (m) of every paraboloid: MDR lines, BEM
    symbols (filled: Eq. 23, open: from the contact area). Saves a PNG at ``path``."""
    plt = _pyplot()
    p = par["parameters"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.9), layout="constrained")
    markers = "osD^v<>ph*"
    for k, curve in enumerate(par["curves"]):
        c = curve["c"]
        rows = [r for r in par["rows"] if r["c"] == c]
        t = [r["t"] for r in rows]
        color, marker = f"C{k}", markers[k % len(markers)]
        left.plot(curve["t"], curve["depth"], "-", color=color, lw=1.2)
        left.plot(t, [r["depth_bem"] for r in rows], marker, color=color, ls="none",
                  label=f"c = {c:g} 1/m")
        right.plot(curve["t"], curve["contact_length"], "-", color=color, lw=1.2)
        right.plot(t, [r["length_bem"] for r in rows], marker, color=color, ls="none",
                   label=f"c = {c:g} 1/m")
        right.plot(t, [r["length_bem_area"] for r in rows], marker, color=color, ls="none",
                   mfc="none", ms=9)
    right.axhline(2 * p["edge"] / math.sqrt(math.pi), color="0.5", ls=":", lw=1)
    left.set(xlabel="time t [s]", ylabel="indentation depth d [m]", xlim=(0, 1.03 * p["duration"]),
             ylim=(0, None), title="(a) indentation depth")
    right.set(xlabel="time t [s]", ylabel="contact length l [m]", xlim=(0, 1.03 * p["duration"]),
              ylim=(0, None), title="(b) contact length")
    handles = [plt.Line2D([], [], color="k", lw=1.2, label=f"MDR (n = {p['n_mdr']})"),
               plt.Line2D([], [], color="k", marker="o", ls="none",
                          label=f"BEM {p['n_bem']}x{p['n_bem']} (l: Eq. 23)"),
               plt.Line2D([], [], color="k", marker="o", ls="none", mfc="none", ms=9,
                          label="BEM, l = 2 sqrt(A/pi)"),
               plt.Line2D([], [], color="0.5", ls=":", lw=1,
                          label=f"MDR indenter length 2L/sqrt(pi), L = {p['edge']:g} m")]
    for ax in (left, right):
        ax.grid(alpha=0.3)
    left.legend(loc="upper left", fontsize=8)
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8)
    fig.suptitle(f"Paraboloids h = c r^2 on a {p['edge']:g} m square, F = {p['force']:g} N, "
                 f"eta = {p['eta']:g} Pa s")
    fig.savefig(path, dpi=150)
    plt.close(fig)


def plot_viscoelastic(ve: dict, path: str | os.PathLike) -> None:
    """Force F(t) (N) and contact radius a(t) (m) of the viscoelastic section, one colour per
    medium: Ting's closed form as lines, MDR and BEM as symbols (every 10th output, offset),
    Ting's separation times dotted. Saves a PNG at ``path``."""
    plt = _pyplot()
    p = ve["parameters"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.9), layout="constrained")
    every = 10
    handles = []
    for k, curve in enumerate(ve["curves"]):
        color = f"C{k}"
        t = curve["t"]
        t_sep = next(r["t_separation"] for r in ve["rows"] if r["medium"] == curve["medium"])
        for ax, quantity in ((left, "force"), (right, "radius")):
            ax.plot(t, curve[f"{quantity}_ting"], "-", color=color, lw=1.3)
            ax.plot(t, curve[f"{quantity}_mdr"], "o", color=color, ms=4, ls="none",
                    markevery=(0, every))
            ax.plot(t, curve[f"{quantity}_bem"], "s", color=color, ms=7, mfc="none", ls="none",
                    markevery=(every // 2, every))
            ax.axvline(t_sep, color=color, ls=":", lw=1)
        handles.append(plt.Line2D([], [], color=color, lw=6, alpha=0.6,
                                  label=f"{curve['medium']}: t_s = {t_sep:.4f} s"))
    for ax in (left, right):
        ax.axvline(p["t_peak"], color="0.5", ls="--", lw=0.8)
        ax.axhline(0.0, color="0.3", lw=0.6)  # below it a margin: the F = 0 symbols show
        ax.grid(alpha=0.3)
        ax.set(xlabel="time t [s]", xlim=(0, p["duration"]))
    left.set(ylabel="force F [N]", title="(a) force")
    right.set(ylabel="contact radius a [m]", title="(b) contact radius (MDR and BEM: l / 2)")
    handles += [plt.Line2D([], [], color="k", lw=1.3, label="Ting (closed form)"),
                plt.Line2D([], [], color="k", marker="o", ms=4, ls="none",
                           label=f"MDR (n = {p['n_mdr']})"),
                plt.Line2D([], [], color="k", marker="s", ms=7, mfc="none", ls="none",
                           label=f"BEM {p['n_bem']}x{p['n_bem']}"),
                plt.Line2D([], [], color="k", ls=":", lw=1, label="Ting's separation t_s"),
                plt.Line2D([], [], color="0.5", ls="--", lw=0.8, label="end of loading")]
    fig.legend(handles=handles, loc="outside lower center", ncol=4, fontsize=8)
    fig.suptitle(f"Paraboloid c = {p['c']:g} 1/m (R = {p['radius_of_curvature']:g} m) pushed "
                 f"into viscoelastic media at {p['rate']:g} m/s to t = {p['t_peak']:g} s and "
                 f"pulled out (dt = {p['dt']:g} s)")
    fig.savefig(path, dpi=150)
    plt.close(fig)


# ----------------------------------------------------------------------------- error vs run time
_QUANTITY_ORDER = ("depth", "contact_length", "stiffness_length", "velocity", "central_pressure")
_QUANTITY_TITLES = {
    "depth": "indentation depth d(5 s)",
    "contact_length": "contact length l(5 s): BEM 2 sqrt(A/pi), MDR count x dx",
    "stiffness_length": "contact length l(5 s) by Eq. 23, l = F / (4 eta dd/dt) (BEM)",
    "velocity": "penetration rate dd/dt",
    "central_pressure": "central pressure p0",
}


def _cases(rows):
    """The study's (case, quantity) pairs in order of appearance, quantities ranked."""
    seen = []
    for r in rows:
        if r["case"] not in seen:
            seen.append(r["case"])
    return [(c, q) for c in seen for q in _QUANTITY_ORDER
            if any(r["case"] == c and r["quantity"] == q for r in rows)]


def _row_order(row):
    """Table order: method; implicit before explicit; larger area rule first; n up; step down."""
    return (row["method"], row["integrator"] == "explicit", -(row["area_change"] or 0.0),
            row["n"], -(row["step"] or 0.0))


def error_table(study: dict) -> str:
    """The error-vs-run-time rows (:func:`mdrvisc.paper.studies.error_vs_runtime`) as aligned
    text: one table per case and quantity; ``*`` marks the paper's settings."""
    p = study["parameters"]
    lines = [f"Error against run time ({'quick' if study['quick'] else 'full'}; "
             f"{study['total_wall_time']:.1f} s): paraboloids h = c r^2 on a {p['edge']:g} m "
             f"square and a rod a = {p['rod_radius']:g} m, F = {p['force']:g} N, "
             f"eta = {p['eta']:g} Pa s",
             "error = value / closed form - 1 (Lee-Radok at t = 5 s; rod closed form); "
             "vs impl = value / implicit at the same n - 1 (time-stepping error alone);",
             "step = dt / t of the explicit loop; area = its re-solve threshold; wall: best of "
             "3 below 0.1 s; * = the paper's setting (explicit step 0.01 assumed)"]
    columns = [("method", "method", ""), ("integrator", "integrator", ""), ("n", "n", "d"),
               ("dx [m]", "dx", ".3e"), ("step", "step", "g"), ("area", "area_change", "g"),
               ("wall [s]", "wall_time", ".2e"), ("value", "value", ".8g"),
               ("error", "error", "+.2e"), ("vs impl", "error_vs_implicit", "+.2e"),
               ("steps", "steps", "d"), ("solves", "solves", "d"), ("", "mark", "")]
    for case, quantity in _cases(study["rows"]):
        rows = sorted((dict(r, mark="*" if r["paper"] else "") for r in study["rows"]
                       if r["case"] == case and r["quantity"] == quantity), key=_row_order)
        label, unit = QUANTITIES[quantity]
        lines += ["", f"{case}: {label} [{unit}], closed form {rows[0]['exact']:.8g} {unit}",
                  text_table(columns, rows)]
    return "\n".join(lines)


def orders_table(study: dict) -> str:
    """The observed convergence orders of the study as aligned text."""
    columns = [("case", "case", ""), ("quantity", "quantity", ""), ("method", "method", ""),
               ("integrator", "integrator", ""), ("fixed", "fixed", ""),
               ("in", "variable", ""), ("against", "against", ""), ("pts", "points", "d"),
               ("from", "from", ".3g"), ("to", "to", ".3g"), ("|err| finest", "error_finest", ".2e"),
               ("order (fit)", "order", "+.2f"), ("order (last)", "order_last", "+.2f"),
               ("note", "note", "")]
    return ("Observed convergence orders: |error| ~ dx^order or step^order (least squares over "
            "the points; 'last': the two finest)\n" + text_table(columns, study["orders"]))


def study_document(study: dict) -> dict:
    """The JSON document of :func:`mdrvisc.paper.studies.error_vs_runtime`'s result."""
    return to_jsonable({"quick": study["quick"], "parameters": study["parameters"],
                        "settings": study["settings"], "paper_settings": study["paper_settings"],
                        "total_wall_time": study["total_wall_time"],
                        "units": ERROR_UNITS, "rows": study["rows"],
                        "order_units": ORDER_UNITS, "orders": study["orders"]})


def write_error_vs_runtime(study: dict, out: str | os.PathLike, figures: bool = True) -> list[Path]:
    """Writes error_vs_runtime.csv (rows), error_vs_runtime_orders.csv, error_vs_runtime.json
    and, with ``figures`` (needs matplotlib), error_vs_runtime.png into the folder ``out``
    (created if missing); returns the paths."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    names = ("error_vs_runtime.csv", "error_vs_runtime_orders.csv", "error_vs_runtime.json")
    if figures:
        names += ("error_vs_runtime.png",)
    paths = {name: out / name for name in names}
    write_csv(paths[names[0]], study["rows"], ERROR_UNITS)
    write_csv(paths[names[1]], study["orders"], ORDER_UNITS)
    paths[names[2]].write_text(json.dumps(study_document(study), indent=1) + "\n",
                               encoding="utf-8")
    if figures:
        plot_error_vs_runtime(study, paths[names[3]])
    return list(paths.values())


#: Errors at or below this (:data:`mdrvisc.paper.studies.ROUNDING`) count as exact and are
#: drawn on the bottom axis (log axes); the MDR rod is exact to rounding.
ERROR_FLOOR = ROUNDING


def _style(row, bem_explicit_n):
    """(legend label, colour, marker, line style) of a row's series."""
    method, integrator = row["method"], row["integrator"]
    if integrator == "one solve":
        return (f"{method} (rod: one solve)", "C0" if method == "BEM" else "C2",
                "o" if method == "BEM" else "s", "-")
    if integrator == "implicit":
        return (f"{method} implicit (n varies)", "C0" if method == "BEM" else "C2",
                "o" if method == "BEM" else "s", "-")
    if method == "BEM":
        k = bem_explicit_n.index(row["n"])
        shades = ["#fdae6b", "#f16913", "#a63603", "#7f2704"]
        return (f"BEM explicit n={row['n']}, area {row['area_change']:g} (step varies)",
                shades[min(k + max(0, 3 - len(bem_explicit_n)), 3)], "^", "--")
    if row["area_change"] > 0:
        return (f"MDR explicit, area {row['area_change']:g} (step varies)", "C4", "v", "--")
    return (f"MDR explicit, area {row['area_change']:g} (step varies)", "C3", "D", "--")


def plot_error_vs_runtime(study: dict, path: str | os.PathLike) -> None:
    """``|relative error|`` against wall time (s), log-log: one panel per case and quantity, one
    curve per method x integrator (explicit: per n or area rule, the step varying; dotted:
    explicit at the fixed step with n varying); stars mark the paper's settings. Saves a PNG."""
    plt = _pyplot()
    rows = study["rows"]
    cross_step = study["settings"]["cross_step"]
    bem_explicit_n = sorted(int(n) for n in study["settings"]["bem_explicit"])
    cases = _cases(rows)
    paraboloids = [c for c in dict.fromkeys(c for c, _ in cases) if c != "rod"]
    quantities = [q for q in ("depth", "contact_length", "stiffness_length")
                  if any(q == qq for _, qq in cases)]
    ncols = len(quantities) + (1 if any(c == "rod" for c, _ in cases) else 0)
    nrows = max(len(paraboloids), 2)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 4.0 * nrows + 1.2),
                             layout="constrained", squeeze=False)
    panels = {(c, q): axes[i, j] for i, c in enumerate(paraboloids)
              for j, q in enumerate(quantities)}
    rod_quantities = [q for c, q in cases if c == "rod"]
    for i, q in enumerate(rod_quantities):
        panels[("rod", q)] = axes[i, ncols - 1]
    handles = {}
    letters = iter("abcdefghijklmnop")
    walls = [r["wall_time"] for r in rows]
    xlim = (10 ** (math.floor(math.log10(min(walls)) * 2) / 2),
            10 ** (math.ceil(math.log10(max(walls)) * 2) / 2))
    for i in range(nrows):
        for j in range(ncols):
            ax = axes[i, j]
            key = next((k for k, v in panels.items() if v is ax), None)
            if key is None:
                ax.set_visible(False)
                continue
            _error_panel(ax, key, rows, cross_step, bem_explicit_n, handles, next(letters), xlim)
    handles["paper"] = plt.Line2D([], [], color="w", marker="*", mec="k", mfc="0.6", ms=13,
                                  ls="none", label="paper's setting (BEM 257 explicit area 0.01, "
                                  "MDR 66049, rod BEM 200; step 0.01 assumed)")
    handles["cross"] = plt.Line2D([], [], color="k", ls=":", lw=1.2, alpha=0.6,
                                  label=f"explicit at step {cross_step:g}, n varies")
    fig.legend(handles=list(handles.values()), loc="outside lower center", ncol=3, fontsize=8)
    p = study["parameters"]
    fig.suptitle(f"Error against run time{' (quick)' if study['quick'] else ''}: paraboloids "
                 f"h = c r^2 on a {p['edge']:g} m square and a rod a = {p['rod_radius']:g} m, "
                 f"F = {p['force']:g} N, eta = {p['eta']:g} Pa s; closed forms: Lee-Radok at "
                 f"t = {p['duration']:g} s, flat punch")
    fig.savefig(path, dpi=130)
    plt.close(fig)


def _sweep_key(row):
    """Coarse to fine along a series: n up (implicit), step down (explicit)."""
    return (row["n"], -(row["step"] or 0.0))


def _error_panel(ax, key, rows, cross_step, bem_explicit_n, handles, letter, xlim):
    """One panel of :func:`plot_error_vs_runtime`. Errors below :data:`ERROR_FLOOR` (exact to
    rounding) are drawn as down triangles on the bottom edge."""
    case, quantity = key
    mine = [r for r in rows if r["case"] == case and r["quantity"] == quantity]
    shown = [abs(r["error"]) for r in mine if abs(r["error"]) > ERROR_FLOOR]
    ylim = (10 ** math.floor(math.log10(min(shown)) - 0.3), 10 ** math.ceil(math.log10(max(shown)) + 0.2))
    bottom = ax.get_xaxis_transform()  # x in data, y in axes fraction
    series = {}
    for r in mine:
        series.setdefault(r["series"], []).append(r)
    floored = False
    for group in series.values():
        label, color, marker, ls = _style(group[0], bem_explicit_n)
        group = sorted(group, key=_sweep_key)
        exact = [r for r in group if abs(r["error"]) <= ERROR_FLOOR]
        group = [r for r in group if abs(r["error"]) > ERROR_FLOOR]
        if exact:
            floored = True
            (line,) = ax.plot([r["wall_time"] for r in exact], [0.0] * len(exact), transform=bottom,
                              marker="v", color=color, ms=7, ls="none", clip_on=False,
                              label=label)
            handles.setdefault(label, line)
            for r in exact:
                if r["paper"]:
                    ax.plot(r["wall_time"], 0.0, transform=bottom, marker="*", ms=15, mfc=color,
                            mec="k", mew=0.8, ls="none", zorder=5, clip_on=False)
        if not group:
            continue
        t = [r["wall_time"] for r in group]
        e = [abs(r["error"]) for r in group]
        (line,) = ax.plot(t, e, ls=ls if len(group) > 1 else "none", marker=marker, color=color,
                          ms=5, lw=1.3, label=label)
        handles.setdefault(label, line)
        for r, tt, ee in zip(group, t, e):
            if r["paper"]:
                ax.plot(tt, ee, marker="*", ms=15, mfc=color, mec="k", mew=0.8, ls="none",
                        zorder=5)
                ax.annotate("paper", (tt, ee), xytext=(8, 4), textcoords="offset points",
                            fontsize=6.5, color="k", zorder=6,
                            bbox={"boxstyle": "round,pad=0.15", "fc": "w", "ec": "none",
                                  "alpha": 0.75})
    # explicit runs at the fixed step, n varying
    cross = {}
    for r in mine:
        if r["integrator"] == "explicit" and r["step"] == cross_step:
            cross.setdefault((r["method"], r["area_change"]), []).append(r)
    for group in cross.values():
        if len(group) > 1:
            group = sorted(group, key=lambda r: r["n"])
            ax.plot([r["wall_time"] for r in group], [abs(r["error"]) for r in group],
                    ls=":", color="k", lw=1.2, alpha=0.6)
    # resolution labels at the ends of the implicit and one-solve curves
    for group in series.values():
        if group[0]["integrator"] in ("implicit", "one solve") and len(group) > 1:
            group = sorted(group, key=lambda r: r["n"])
            for r in (group[0], group[-1]):
                if abs(r["error"]) <= ERROR_FLOOR:
                    ax.annotate(f"n={r['n']}", (r["wall_time"], 0.0), xycoords=bottom,
                                xytext=(0, 7), textcoords="offset points", fontsize=6.5,
                                ha="center", color="0.3")
                else:
                    ax.annotate(f"n={r['n']}", (r["wall_time"], abs(r["error"])),
                                xytext=(0, -11), textcoords="offset points", fontsize=6.5,
                                ha="center", color="0.3")
    if floored:
        ax.text(0.03, 0.97, "MDR: exact to rounding\n(error 0: triangles on the axis)",
                transform=ax.transAxes, ha="left", va="top", fontsize=7, color="0.3")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(xlim)
    ax.set_ylim(ylim)
    label, unit = QUANTITIES[quantity]
    title = _QUANTITY_TITLES[quantity]
    where = "rod a = 1 m" if case == "rod" else case.replace("paraboloid ", "") + " 1/m"
    ax.set_title(f"({letter}) {where}: {title}", fontsize=8.5)
    ax.set(xlabel="wall time [s]", ylabel=f"|relative error of {label}| [-]")
    ax.grid(alpha=0.3, which="major", lw=0.5)
    # whole decades only: minor log ticks over ten decades cost seconds of drawing
    from matplotlib.ticker import LogLocator, NullLocator

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(LogLocator(base=10.0, numticks=12))
        axis.set_minor_locator(NullLocator())
