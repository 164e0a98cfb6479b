"""Plain-text tables and JSON-ready values: what ``mdrvisc run`` prints for a
:class:`mdrvisc.Result`, and the table and JSON helpers the paper's reports
(:mod:`mdrvisc.paper.report`) build on.
"""

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from .scene import Result

__all__ = ["text_table", "result_table", "to_jsonable"]


def _cell(value, fmt):
    """``value`` formatted with ``fmt``; None as '-', NaN as 'n/a' (closed form not valid)."""
    if value is None:
        return "-"
    if isinstance(value, float) and math.isnan(value):
        return "n/a"
    return format(value, fmt)


def text_table(columns: Sequence[tuple[str, str, str]], rows: Iterable[Mapping[str, object]]) -> str:
    """Right-aligned text table; ``columns``: (header, key, format spec) triples."""
    cells = [[_cell(row[key], fmt) for _, key, fmt in columns] for row in rows]
    headers = [h for h, _, _ in columns]
    widths = [max(len(h), *(len(c[i]) for c in cells)) for i, h in enumerate(headers)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.rjust(w) for c, w in zip(cell, widths)) for cell in cells]
    return "\n".join(lines)


def result_table(name: str, result: Result) -> str:
    """One :class:`mdrvisc.Result` as aligned text: its summary and its time series."""
    lines = [f"{name}: {result.summary()}"]
    if result.central_pressure is not None:
        lines.append(f"central pressure p0 = {result.central_pressure:.6f} Pa")
    series = {"t": result.t, "depth": result.depth, "force": result.force,
              "contact_length": result.contact_length, "velocity": result.velocity,
              "stiffness_length": result.stiffness_length}
    series = {k: np.broadcast_to(v, result.t.shape) for k, v in series.items() if v is not None}
    headers = {"t": "t [s]", "depth": "d [m]", "force": "F [N]", "contact_length": "l [m]",
               "velocity": "dd/dt [m/s]", "stiffness_length": "l Eq.23 [m]"}
    columns = [(headers[k], k, ".8g") for k in series]
    rows = [{k: float(v[i]) for k, v in series.items()} for i in range(result.t.size)]
    lines.append(text_table(columns, rows))
    for when, fields in (result.fields or {}).items():
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in fields.items())
        lines.append(f"fields at t = {when} s: {shapes}")
    return "\n".join(lines)


def to_jsonable(value: object) -> Any:
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
