"""Parameter grids: many scenes made from one base scene by replacing some of its values.

An axis names a key of the scene model (the keys of a scene file, see
:mod:`mdrvisc.scenefile`), nested keys joined by ``.`` or ``__`` (``medium.tau1`` or
``medium__tau1``), and lists the values it takes. :func:`sweep_scenes` builds every
combination of the axes (a product, the last axis varying fastest), :func:`zip_scenes` takes
the axes' values side by side. A sweep file (:func:`load_sweep`) is a scene file with
``method`` and ``n`` plus a ``[sweep]`` table::

    [sweep]
    mode = "product"                # or "zip"
    [sweep.axes]
    "medium.tau1" = [0.1, 1.0, 10.0]
    force = [0.5, 1.0]
"""

from __future__ import annotations

import itertools
import json
import sys
from pathlib import Path

import numpy as np

from ._validate import _read_text
from .errors import InvalidInputError
from .scene import Scene, _json
from .scenefile import parse_scene

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["sweep_scenes", "zip_scenes", "load_sweep", "axis_path"]


def axis_path(name: str) -> tuple[str, ...]:
    """The model keys of the axis ``name`` ("medium.tau1" or "medium__tau1")."""
    parts = tuple(name.replace("__", ".").split("."))
    if not all(parts):
        raise InvalidInputError(f"sweep: axis name {name!r} has an empty key")
    return parts


#: Axes whose values may be numpy arrays, which go to the core as arrays (the name of each
#: in :meth:`mdrvisc._core.Scene.with_values`).
_ARRAY_AXES = {"indenter.heights": "heights", "indenter.r": "r", "indenter.h": "h", "indenter.slope": "slope"}


def _with_values(base: Scene, assignment: dict) -> Scene:
    """``base`` with the values of ``assignment`` ({axis: value}), set on its core scene: the
    model's other values and its arrays are not read again."""
    changes, arrays = {}, {}
    for name, value in assignment.items():
        key = ".".join(axis_path(name))
        if key in _ARRAY_AXES and isinstance(value, np.ndarray):
            arrays[_ARRAY_AXES[key]] = np.ascontiguousarray(value, dtype=np.float64)
        else:
            changes[key] = value.tolist() if hasattr(value, "tolist") else value
    _json(changes)  # a non-finite value is an error naming its axis
    core = base._model.with_values(json.dumps(list(changes.items())), **arrays)
    # the array axes are the indenter's
    tables = {key.split(".")[0] for key in changes} | ({"indenter"} if arrays else set())
    return Scene._from_core(core, indenter=None if "indenter" in tables else base.indenter,
                            medium=None if "medium" in tables else base.medium)


def _axes(axes: dict) -> dict:
    """The axes as {name: list of values}, each a non-empty sequence."""
    if not axes:
        raise InvalidInputError("sweep: at least one axis is needed")
    out = {}
    for name, values in axes.items():
        if isinstance(values, (str, bytes, dict)) or not hasattr(values, "__iter__"):
            raise InvalidInputError(f"sweep: axis {name!r} must be a sequence of values, got {values!r}")
        values = list(values)
        if not values:
            raise InvalidInputError(f"sweep: axis {name!r} has no values")
        out[name] = values
    return out


def sweep_scenes(base: Scene, **axes) -> list[Scene]:
    """Every combination of the ``axes`` applied to ``base``: a product, the last axis varying
    fastest. ``sweep_scenes(scene, medium__tau1=[0.1, 1, 10], force=[0.5, 1])`` gives six
    scenes. Each scene is validated as it is built (an invalid value raises, naming it)."""
    axes = _axes(axes)
    return [_with_values(base, dict(zip(axes, combo))) for combo in itertools.product(*axes.values())]


def zip_scenes(base: Scene, **axes) -> list[Scene]:
    """The ``axes`` applied to ``base`` side by side: scene i takes value i of every axis; the
    axes must be of equal length."""
    axes = _axes(axes)
    lengths = {name: len(values) for name, values in axes.items()}
    if len(set(lengths.values())) != 1:
        raise InvalidInputError(f"zip_scenes: the axes must be of equal length, got {lengths}")
    return [_with_values(base, dict(zip(axes, combo))) for combo in zip(*axes.values())]


def load_sweep(path) -> tuple[list[Scene], str, int]:
    """``(scenes, method, n)`` of the sweep file at ``path``: its base scene (every key but
    ``sweep``, read as a scene file) with the ``[sweep]`` table's axes, by ``mode``
    ("product", the default, or "zip")."""
    path = Path(path)
    try:
        data = tomllib.loads(_read_text(path, "sweep file"))
    except tomllib.TOMLDecodeError as exc:
        raise InvalidInputError(f"{path}: {exc}") from None
    table = data.pop("sweep", None)
    if not isinstance(table, dict) or not isinstance(table.get("axes"), dict):
        raise InvalidInputError(f"{path}: a sweep file needs a [sweep.axes] table")
    unknown = set(table) - {"mode", "axes"}
    if unknown:
        raise InvalidInputError(f"{path}: unknown key(s) in [sweep]: {sorted(unknown)}")
    mode = table.get("mode", "product")
    builders = {"product": sweep_scenes, "zip": zip_scenes}
    if mode not in builders:
        raise InvalidInputError(f"{path}: sweep.mode must be 'product' or 'zip', got {mode!r}")
    base, method, n = parse_scene(data, str(path))
    try:
        scenes = builders[mode](base, **table["axes"])
    except InvalidInputError as exc:
        raise InvalidInputError(f"{path}: {exc}") from None
    return scenes, method, n
