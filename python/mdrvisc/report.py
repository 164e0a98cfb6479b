"""Tables, CSV/JSON files and figures of the paper's comparisons (:mod:`mdrvisc.studies`).

Units as in :mod:`mdrvisc.studies`: SI throughout; relative differences are (a - b) / b.
"""

import csv
import json
import math
from pathlib import Path

import numpy as np

from .studies import ERROR_UNITS, ORDER_UNITS, PARABOLOID_UNITS, QUANTITIES, ROD_UNITS

__all__ = ["rod_table", "paraboloid_tables", "result_table", "to_jsonable", "write_csv",
           "paper_document", "write_paper", "plot_rod", "plot_paraboloids",
           "error_table", "orders_table", "study_document", "write_error_vs_runtime",
           "plot_error_vs_runtime"]


# ----------------------------------------------------------------------------- text tables
def _cell(value, fmt):
    """``value`` formatted with ``fmt``; None as '-', NaN as 'n/a' (closed form not valid)."""
    if value is None:
        return "-"
    if isinstance(value, float) and math.isnan(value):
        return "n/a"
    return format(value, fmt)


def _table(columns, rows):
    """Right-aligned text table; ``columns``: (header, key, format spec) triples."""
    cells = [[_cell(row[key], fmt) for _, key, fmt in columns] for row in rows]
    headers = [h for h, _, _ in columns]
    widths = [max(len(h), *(len(c[i]) for c in cells)) for i, h in enumerate(headers)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.rjust(w) for c, w in zip(cell, widths)) for cell in cells]
    return "\n".join(lines)


def rod_table(rod):
    """The rod comparison (:func:`mdrvisc.studies.paper_rod`'s result) as aligned text."""
    p = rod["parameters"]
    title = (f"Rod (Section 5): a = {p['radius']:g} m, F = {p['force']:g} N, "
             f"eta = {p['eta']:g} Pa s; errors relative to the closed form")
    columns = [("source", "source", ""), ("elements", "elements", "d"),
               ("p0 [Pa]", "central_pressure", ".6f"), ("err p0", "central_pressure_error", "+.3%"),
               ("dd/dt [m/s]", "velocity", ".6f"), ("err dd/dt", "velocity_error", "+.3%"),
               ("wall [s]", "wall_time", ".3f")]
    return title + "\n" + _table(columns, rod["rows"])


def paraboloid_tables(par):
    """The paraboloid comparison (:func:`mdrvisc.studies.paper_paraboloids`'s result) as
    aligned text: depths, contact lengths and run statistics."""
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
    return "\n\n".join([title, "Depth d(t)\n" + _table(depth, par["rows"]),
                        "Contact length l(t) (BEM: Eq. 23 l = F/(4 eta dd/dt), and 2 sqrt(A/pi))\n"
                        + _table(length, par["rows"]),
                        "Runs\n" + _table(runs, par["runs"])])


def result_table(name, result):
    """One :class:`mdrvisc.Result` as aligned text: its summary and its time series."""
    lines = [f"{name}: {result.summary()}"]
    if result.central_pressure is not None:
        lines.append(f"central pressure p0 = {result.central_pressure:.6f} Pa")
    series = {"t": result.t, "depth": result.depth, "contact_length": result.contact_length,
              "velocity": result.velocity, "stiffness_length": result.stiffness_length}
    series = {k: np.broadcast_to(v, result.t.shape) for k, v in series.items() if v is not None}
    headers = {"t": "t [s]", "depth": "d [m]", "contact_length": "l [m]",
               "velocity": "dd/dt [m/s]", "stiffness_length": "l Eq.23 [m]"}
    columns = [(headers[k], k, ".8g") for k in series]
    rows = [{k: float(v[i]) for k, v in series.items()} for i in range(result.t.size)]
    lines.append(_table(columns, rows))
    for when, fields in (result.fields or {}).items():
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in fields.items())
        lines.append(f"fields at t = {when} s: {shapes}")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- files
def to_jsonable(value):
    """``value`` with numpy arrays and scalars as lists and numbers, NaN and inf as None."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer, int)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    return value


def write_csv(path, rows, units):
    """Writes ``rows`` (dicts with the keys of ``units``) to ``path``; headers carry units as
    ``name [unit]``; None is written empty, NaN as ``nan``."""
    headers = [f"{k} [{u}]" if u else k for k, u in units.items()]
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(headers)
        for row in rows:
            writer.writerow(["" if row[k] is None else repr(row[k]) if isinstance(row[k], float)
                             else row[k] for k in units])


def paper_document(results, study=None):
    """The JSON document of :func:`mdrvisc.studies.paper`'s result: tables, units, runs; with
    ``study`` (:func:`mdrvisc.studies.error_vs_runtime`'s result) also its
    :func:`study_document` under ``error_vs_runtime``."""
    rod, par = results["rod"], results["paraboloids"]
    doc = {
        "quick": results["quick"],
        "rod": {"parameters": rod["parameters"], "units": ROD_UNITS, "rows": rod["rows"]},
        "paraboloids": {"parameters": par["parameters"], "units": PARABOLOID_UNITS,
                        "rows": par["rows"], "runs": par["runs"]},
    }
    if study is not None:
        doc["error_vs_runtime"] = study_document(study)
    return to_jsonable(doc)


def write_paper(results, out, study=None):
    """Writes rod.csv, paraboloids.csv, paper.json, fig3_rod.png and fig4_paraboloids.png
    into the folder ``out`` (created if missing); returns their paths. paper.json holds
    :func:`paper_document` (with ``study`` when given; its own files come from
    :func:`write_error_vs_runtime`)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = {name: out / name for name in ("rod.csv", "paraboloids.csv", "paper.json",
                                           "fig3_rod.png", "fig4_paraboloids.png")}
    write_csv(paths["rod.csv"], results["rod"]["rows"], ROD_UNITS)
    write_csv(paths["paraboloids.csv"], results["paraboloids"]["rows"], PARABOLOID_UNITS)
    paths["paper.json"].write_text(json.dumps(paper_document(results, study), indent=1) + "\n",
                                   encoding="utf-8")
    plot_rod(results["rod"], paths["fig3_rod.png"])
    plot_paraboloids(results["paraboloids"], paths["fig4_paraboloids.png"])
    return list(paths.values())


# ----------------------------------------------------------------------------- figures
def _pyplot():
    """matplotlib.pyplot on the Agg backend (files only, no display)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_rod(rod, path):
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


def plot_paraboloids(par, path):
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
