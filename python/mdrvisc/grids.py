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

from . import _core
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


def _with_values(base: dict, assignment: dict) -> Scene:
    """The scene of the model ``base`` with the values of ``assignment`` ({axis: value})."""
    model = json.loads(json.dumps(base))
    for name, value in assignment.items():
        *head, last = axis_path(name)
        table = model
        for key in head:
            if not isinstance(table.get(key), dict):
                raise InvalidInputError(f"sweep: axis {name!r}: the scene has no table {key!r}")
            table = table[key]
        table[last] = value.tolist() if hasattr(value, "tolist") else value
    return Scene._from_core(_core.Scene.from_json(_json(model)))


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
    model = json.loads(base.to_json())
    return [_with_values(model, dict(zip(axes, combo))) for combo in itertools.product(*axes.values())]


def zip_scenes(base: Scene, **axes) -> list[Scene]:
    """The ``axes`` applied to ``base`` side by side: scene i takes value i of every axis; the
    axes must be of equal length."""
    axes = _axes(axes)
    lengths = {name: len(values) for name, values in axes.items()}
    if len(set(lengths.values())) != 1:
        raise InvalidInputError(f"zip_scenes: the axes must be of equal length, got {lengths}")
    model = json.loads(base.to_json())
    return [_with_values(model, dict(zip(axes, combo))) for combo in zip(*axes.values())]


def load_sweep(path) -> tuple[list[Scene], str, int]:
    """``(scenes, method, n)`` of the sweep file at ``path``: its base scene (every key but
    ``sweep``, read as a scene file) with the ``[sweep]`` table's axes, by ``mode``
    ("product", the default, or "zip")."""
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
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
