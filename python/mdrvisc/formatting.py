"""Plain-text tables and JSON-ready values, which the paper's reports
(:mod:`mdrvisc.paper.report`) build on."""

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["text_table", "to_jsonable"]


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
