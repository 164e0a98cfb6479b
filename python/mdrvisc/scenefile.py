"""Scene files (TOML), the format of the Rust binary's ``mdrvisc run SCENE.toml``.

::

    method = "bem"          # "bem" or "mdr"
    n = 257                 # BEM: n x n grid; MDR: elements
    force = 1.0             # N, constant from first touch; or [[t, F], ...] (s, N),
                            # piecewise linear from t = 0, held after the last sample
    duration = 5.0          # s
    dt = 0.01               # s, optional: longest step of the viscoelastic stepping
    times = [1, 2, 3, 4, 5] # s, optional (default: 5 equal steps up to duration)
    outputs = ["depth", "contact_length", "stiffness_length"]  # optional, Python only

    [indenter]
    type = "paraboloid"     # rod (radius) | paraboloid (c, edge) | cone (slope, edge)
    c = 1.0                 # 1/m           | sphere (radius, Python only)
    edge = 2.56             # m, optional side of a square footprint

    [medium]
    type = "viscous"
    eta = 1.0               # Pa s

Viscoelastic media: ``type = "kelvinvoigt"`` (G, eta), ``"maxwell"`` (G, eta),
``"standardsolid"`` (G_inf, G1, tau1), ``"prony"`` (G_inf, terms = [[G_k, tau_k], ...]).
Instead of ``force`` a scene may give ``depth = [[t, d], ...]`` (s, m; piecewise linear from
t = 0) for a time-dependent medium.

Lengths in m, c in 1/m, force in N, times in s, eta in Pa s. Unknown keys, missing keys and
values of the wrong type raise :class:`mdrvisc.InvalidInputError` naming the key.
"""

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

from .errors import InvalidInputError
from .geometry import Cone, Paraboloid, Rod, Sphere
from .media import KelvinVoigt, Maxwell, Prony, StandardSolid, Viscous
from .scene import Scene

__all__ = ["load_scene", "read_scene", "parse_scene"]

_NUMBER = "a number"
_INTEGER = "an integer"
_STRING = "a string"
_NUMBERS = "a list of numbers"
_STRINGS = "a list of strings"
_TABLE = "a table"
_PAIRS = "a list of [number, number] pairs"
_FORCE = "a number or a list of [t, F] pairs"

#: Top-level keys: (kind, required).
_TOP = {"method": (_STRING, True), "n": (_INTEGER, True), "force": (_FORCE, False),
        "depth": (_PAIRS, False),
        "duration": (_NUMBER, True), "dt": (_NUMBER, False), "times": (_NUMBERS, False), "outputs": (_STRINGS, False),
        "indenter": (_TABLE, True), "medium": (_TABLE, True)}
#: Indenter types: (class, {key: required}).
_INDENTERS = {"rod": (Rod, {"radius": True}),
              "paraboloid": (Paraboloid, {"c": True, "edge": False}),
              "cone": (Cone, {"slope": True, "edge": False}), "sphere": (Sphere, {"radius": True})}
#: Medium types: (class, {key: required}).
_MEDIA = {"viscous": (Viscous, {"eta": True}),
          "kelvinvoigt": (KelvinVoigt, {"G": True, "eta": True}),
          "maxwell": (Maxwell, {"G": True, "eta": True}),
          "standardsolid": (StandardSolid, {"G_inf": True, "G1": True, "tau1": True}),
          "prony": (Prony, {"G_inf": True, "terms": (_PAIRS, True)})}


def _is(kind, value):
    """Whether ``value`` (as parsed by tomllib) is of ``kind``."""
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind == _NUMBER:
        return number
    if kind == _INTEGER:
        return isinstance(value, int) and not isinstance(value, bool)
    if kind == _STRING:
        return isinstance(value, str)
    if kind == _TABLE:
        return isinstance(value, dict)
    if kind == _FORCE:
        return _is(_NUMBER, value) or _is(_PAIRS, value)
    if kind == _PAIRS:
        return isinstance(value, list) and all(_is(_NUMBERS, v) and len(v) == 2 for v in value)
    item = _NUMBER if kind == _NUMBERS else _STRING
    return isinstance(value, list) and all(_is(item, v) for v in value)


def _check(source, table, schema, prefix=""):
    """Checks ``table`` against ``schema`` ({key: (kind, required)}); errors name the key."""
    for key in table:
        if key not in schema:
            where = f" in [{prefix[:-1]}]" if prefix else ""
            raise InvalidInputError(
                f"{source}: unknown key '{prefix}{key}'{where}; allowed: {', '.join(schema)}")
    for key, (kind, required) in schema.items():
        if key not in table:
            if required:
                raise InvalidInputError(f"{source}: missing key '{prefix}{key}'")
            continue
        if not _is(kind, table[key]):
            raise InvalidInputError(
                f"{source}: key '{prefix}{key}' must be {kind}, got {table[key]!r}")


def _build(source, table, name, choices):
    """The object of the ``[name]`` table: its ``type`` picks (class, keys) from ``choices``."""
    kind = table.get("type")
    if kind is None:
        raise InvalidInputError(f"{source}: missing key '{name}.type'")
    if kind not in choices:
        raise InvalidInputError(
            f"{source}: key '{name}.type' must be one of {', '.join(choices)}, got {kind!r}")
    cls, keys = choices[kind]
    schema = {"type": (_STRING, True),
              **{k: req if isinstance(req, tuple) else (_NUMBER, req) for k, req in keys.items()}}
    _check(source, table, schema, prefix=f"{name}.")
    return cls(**{k: v for k, v in table.items() if k != "type"})


def read_scene(path):
    """The TOML table of the scene file at ``path``; InvalidInputError if it cannot be read
    or parsed."""
    try:
        with open(path, "rb") as handle:
            return tomllib.load(handle)
    except OSError as exc:
        raise InvalidInputError(f"cannot read scene file {path}: {exc.strerror}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise InvalidInputError(f"{path}: not valid TOML: {exc}") from exc


def parse_scene(data, source="scene"):
    """``(Scene, method, n)`` from a scene file's table ``data``; ``source`` names it in errors."""
    _check(source, data, _TOP)
    method = data["method"]
    if method not in ("bem", "mdr"):
        raise InvalidInputError(
            f"{source}: key 'method' must be \"bem\" or \"mdr\", got {method!r}")
    if data["n"] < 1:
        raise InvalidInputError(f"{source}: key 'n' must be >= 1, got {data['n']}")
    indenter = _build(source, data["indenter"], "indenter", _INDENTERS)
    medium = _build(source, data["medium"], "medium", _MEDIA)
    extra = {k: data[k] for k in ("times", "outputs", "dt") if k in data}
    if "force" not in data and "depth" not in data:
        raise InvalidInputError(f"{source}: missing key 'force' (or 'depth')")
    if "force" in data and "depth" in data:
        raise InvalidInputError(f"{source}: give only one of the keys 'force' and 'depth'")
    for key in ("force", "depth"):
        if isinstance(data.get(key), list):
            extra[key] = ([p[0] for p in data[key]], [p[1] for p in data[key]])
        elif key in data:
            extra[key] = data[key]
    scene = Scene(indenter=indenter, medium=medium, duration=data["duration"], **extra)
    return scene, method, data["n"]


def load_scene(path):
    """``(Scene, method, n)`` from the scene file at ``path`` (see the module docstring)."""
    return parse_scene(read_scene(path), str(path))
