"""Scenes: what to compute. A :class:`Scene` builds the compiled core's scene model, which
validates it, fills in its defaults and later solves it; this module only converts Python
inputs (numbers, arrays, callables) into that model's parts: its numbers as JSON text, its
arrays (height maps, tabulated profiles, sampled histories) as numpy arrays, each copied
once into the core."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np

from . import _core
from ._validate import _array, _finite_positive, _integer, _number, _positive
from .body import Layer
from .contact import ContactLaw, Hard, contact_from_model
from .errors import DomainError, InvalidInputError
from .geometry import Cone, Indenter, Paraboloid, Pyramid, Rod, Sphere
from .heightmap import HeightMap
from .media import _Medium, medium_from_model
from .profiles import Axisymmetric, Profile

__all__ = ["Scene", "OUTPUTS"]

#: Outputs a scene may ask for (the compiled core's list, ``mdrvisc._core.OUTPUTS``, with
#: their units and kinds). ``depth`` and ``contact_length`` are always computed;
#: ``velocity`` (dd/dt, m/s) is a series of every time-dependent medium (exact for a viscous
#: one, a second-order backward difference over the steps for the others);
#: ``stiffness_length`` (F / (4 eta dd/dt), m; F (1 - nu) / (2 eta dd/dt) for a Poisson ratio
#: nu) is a series of a purely viscous medium;
#: ``pressure`` (Pa), ``surface_velocity`` (m/s) and ``deflection`` (m) are fields at
#: ``field_times``. A :class:`~mdrvisc.HeightMap` always reports ``contact_fraction`` (real
#: contact area over the map's), ``patches`` (connected contact patches) and ``mean_gap`` (m),
#: and ``gap`` (m) fields when named; other indenters refuse these four.
OUTPUTS = tuple(name for name, *_ in _core.OUTPUTS)
#: Outputs of a scene that names none.
DEFAULT_OUTPUTS = tuple(name for name, _, _, default, _ in _core.OUTPUTS if default)
#: Samples taken of a loading history given as a callable.
CALLABLE_SAMPLES = 4001
#: Keys of an indenter's table that the core takes as arrays, by the indenter's type.
ARRAY_KEYS = {"heightmap": ("heights",), "profile": ("r", "h", "slope")}


def _history(value, name, duration):
    """A force or depth given as a number, (times, values) or a callable, in the model's form:
    a number, or a (k, 2) array of [t, value] rows."""
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        return _number("Scene", name, value)
    if callable(value):
        if duration is None:
            raise InvalidInputError(f"Scene: a callable {name} history needs a duration")
        span = np.linspace(0.0, _positive("Scene", "duration", duration), CALLABLE_SAMPLES)
        samples = []
        for t in span:
            try:
                samples.append(value(float(t)))
            except Exception as exc:
                raise InvalidInputError(
                    f"Scene: the {name} callable raised at t = {float(t)!r} s: {exc!r}") from exc
        value = (span, samples)
    try:
        t, v = (np.asarray(a, dtype=np.float64) for a in value)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(
            f"Scene: {name} must be a number, a pair (times, values) or a callable, got {value!r}") from exc
    if t.ndim != 1 or t.shape != v.shape or t.size == 0:
        raise InvalidInputError(f"Scene: the {name} history needs two 1-D arrays of equal, non-zero length")
    return np.column_stack([t, v])


def _array_or_none(name, value):
    return None if value is None else _array("Scene", name, value).ravel().tolist()


def _json(model):
    """``model`` as JSON text; a non-finite number is an error naming its key (searched for
    only when the encoder refuses one: a height map's million numbers are not walked), a
    value JSON has no form for (a complex number, an object) an error too."""
    def walk(value, path):
        if isinstance(value, float) and not math.isfinite(value):
            raise InvalidInputError(f"Scene: {path} must be finite, got {value!r}")
        if isinstance(value, dict):
            for k, v in value.items():
                walk(v, f"{path}.{k}" if path else k)
        elif isinstance(value, list):
            for v in value:
                walk(v, path)
    try:
        return json.dumps(model, allow_nan=False)
    except ValueError:
        walk(model, "")
        raise
    except TypeError as exc:  # e.g. "Object of type complex is not JSON serializable"
        raise InvalidInputError(f"Scene: every value must be a number, a string or a list of them: "
                                f"{exc}") from None


def _split(table: dict) -> tuple[dict, dict]:
    """An indenter's table as (its numbers, its arrays as contiguous float64 arrays)."""
    keys = ARRAY_KEYS.get(table["type"], ())
    numbers = {k: v for k, v in table.items() if k not in keys}
    arrays = {k: np.ascontiguousarray(table[k], dtype=np.float64) for k in keys if k in table}
    return numbers, arrays


def indenter_from_model(model: dict, arrays: dict | None = None) -> Indenter | HeightMap:
    """The indenter of a scene model's ``[indenter]`` table; ``arrays``: the core's arrays
    of a scene (:meth:`mdrvisc._core.Scene.arrays`), for the table's keys that it leaves out."""
    kind = model["type"]
    args = {k: v for k, v in model.items() if k != "type"}
    if kind == "heightmap" and arrays is not None:
        return HeightMap._of_core(arrays["heights"], **args)
    args.update({k: v for k, v in (arrays or {}).items() if k in ARRAY_KEYS.get(kind, ())})
    if kind == "heightmap":
        return HeightMap(np.asarray(args.pop("heights"), dtype=np.float64), **args)
    classes = {"rod": Rod, "paraboloid": Paraboloid, "cone": Cone, "sphere": Sphere,
               "pyramid": Pyramid, "profile": Profile}
    return classes[kind](**args)


@dataclasses.dataclass(frozen=True, eq=False)
class Scene:
    """A rigid indenter pressed into a half-space.

    Parameters
    ----------
    indenter : Indenter or HeightMap
        Rod, Paraboloid, Cone, Sphere, Pyramid, Profile or Axisymmetric (see
        :mod:`mdrvisc.geometry`); an Axisymmetric profile is sampled into a tabulated profile;
        a Pyramid is exact in the BEM and its equivalent cone in MDR. Or a
        :class:`~mdrvisc.HeightMap`, solved by BEM on its own grid.
    medium : Elastic, Viscous, KelvinVoigt, Maxwell, StandardSolid, Prony or PowerLaw
        With its Poisson ratio ``nu`` (default 0.5): the contact modulus is 2 G(t) / (1 - nu).
    force : float, (array, array) or callable
        Constant force (N) from t = 0, or a piecewise-linear history (times in s from 0,
        forces in N, >= 0), held after its last sample, or a callable F(t) (sampled at 4001
        points over the duration). An elastic scene solves for its final force, statically.
    depth : float, (array, array) or callable
        Instead of ``force``: a prescribed depth history (m; negative = above the surface).
        Give exactly one of the two. An elastic scene solves statically at its final depth
        (> 0), for the force (the displacement control of rough-contact codes): the approach from
        the first touch, on a periodic :class:`~mdrvisc.HeightMap` from the deflected
        surface's mean plane (mean gap = mean height below the highest point - depth).
    duration : float, optional
        Simulated time (s); required unless the medium is elastic.
    times : array_like, optional
        Output times (s) in (0, duration], increasing; default five equal steps up to the
        duration. After construction: the output times, field times included. Times below
        1e-12 of the duration are refused (a step that short is lost to rounding); a time
        within 1e-9 of its value of the one before is reported from the same solved state.
    outputs : iterable of str, optional
        What to compute, from :data:`OUTPUTS`; fields only when named. Default (also for
        None): depth and contact length.
    field_times : array_like, optional
        Times (s) of the field outputs; default the duration. They are added to ``times``.
    dt : float, optional
        Longest time step (s) of the viscoelastic stepping (default duration / 500);
        ``solve(..., dt=...)`` overrides it.
    contact : Hard, JKR or DMT, optional
        How the indenter and the body interact (see :mod:`mdrvisc.contact`; default
        :class:`~mdrvisc.Hard`). An adhesive law carries tension (forces may be negative),
        is solved by MDR and follows the loading history on an elastic medium too, which then
        takes a duration (and may be depth-controlled).
    body : Layer, optional
        A :class:`~mdrvisc.Layer` of the medium on a rigid base in place of the half-space
        (default None: the half-space); scene files' ``[layer]`` table.

    Notes
    -----
    Validation, defaults and everything a solve decides (grids, steps) live in the compiled
    scene model; errors name the bad value. ``to_toml``/``from_toml`` round-trip the scene.

    See Also
    --------
    mdrvisc.solve : solve a scene by BEM or MDR.
    mdrvisc.load_curve : a static scene under several loads.
    mdrvisc.solve_many : many scenes in parallel.

    Examples
    --------
    A sphere of radius 5 um pushed 1 um into a standard solid and pulled out, by MDR:

    >>> import mdrvisc as mv
    >>> scene = mv.Scene(indenter=mv.Sphere(radius=5e-6),
    ...                  medium=mv.StandardSolid(G_inf=1e3, G1=3e3, tau1=0.5),
    ...                  depth=([0.0, 1.0, 2.0], [0.0, 1e-6, 0.0]), duration=2.0)
    >>> result = mv.solve(scene, method="mdr")     # doctest: +SKIP
    >>> result.force                                # N, one entry per output time  # doctest: +SKIP
    """

    indenter: Indenter | HeightMap
    medium: _Medium
    force: object = None
    duration: float | None = None
    times: object = None
    outputs: tuple | None = DEFAULT_OUTPUTS
    field_times: object = None
    depth: object = None
    dt: float | None = None
    contact: ContactLaw = Hard()
    body: Layer | None = None
    _model: object = dataclasses.field(init=False, repr=False)

    def __post_init__(self):
        if not isinstance(self.indenter, (Indenter, HeightMap)):
            raise InvalidInputError(
                f"Scene: indenter must be an mdrvisc indenter or HeightMap, got {self.indenter!r:.200}")
        if not isinstance(self.medium, _Medium):
            raise InvalidInputError(f"Scene: medium must be an mdrvisc medium, got {self.medium!r}")
        if self.outputs is None:
            object.__setattr__(self, "outputs", DEFAULT_OUTPUTS)
        try:
            outputs = (self.outputs,) if isinstance(self.outputs, str) else tuple(self.outputs)
        except TypeError:
            raise InvalidInputError(
                f"Scene: outputs must be names from {OUTPUTS}, got {self.outputs!r}") from None
        if not isinstance(self.contact, ContactLaw):
            raise InvalidInputError(
                f"Scene: contact must be mdrvisc.Hard(), JKR(...) or DMT(...), got {self.contact!r}")
        model = {"medium": self.medium._model(), "outputs": list(outputs)}
        if not isinstance(self.contact, Hard):
            model["contact"] = self.contact._model()
        if self.body is not None:
            if not isinstance(self.body, Layer):
                raise InvalidInputError(
                    f"Scene: body must be an mdrvisc.Layer or None, got {self.body!r:.200}")
            model["layer"] = self.body._model()
        arrays = {}
        for name in ("force", "depth"):
            if getattr(self, name) is not None:
                history = _history(getattr(self, name), name, self.duration)
                if isinstance(history, np.ndarray):
                    arrays[name] = history
                else:
                    model[name] = history
        if self.duration is not None:
            model["duration"] = _positive("Scene", "duration", self.duration)
        if self.dt is not None:
            model["dt"] = _finite_positive("Scene", "dt", self.dt)
        for name in ("times", "field_times"):
            if getattr(self, name) is not None:
                model[name] = _array_or_none(name, getattr(self, name))
        self._adopt(self._build(model, arrays), outputs, model.get("field_times"))

    def _adopt(self, core, outputs: tuple, field_times) -> None:
        """Holds the core scene ``core``, with the ``outputs`` and requested ``field_times``
        (None: the duration) it was built with; a time-dependent scene's times are the core's."""
        set_ = object.__setattr__.__get__(self)
        set_("_model", core)
        set_("outputs", outputs)
        if self.duration is not None:
            set_("duration", float(self.duration))
            set_("times", core.output_times())
            set_("field_times", np.asarray(field_times if field_times is not None else [self.duration],
                                           dtype=np.float64))

    def _build(self, model, arrays):
        """The core scene of ``model`` and ``arrays`` with its indenter; an unbounded sampled
        profile is tabulated as far as the solve needs it (from 1 m, doubling)."""

        def build(table):
            numbers, own = _split(table)
            return _core.Scene.build(_json({**model, "indenter": numbers}), **arrays, **own)

        if not (isinstance(self.indenter, Axisymmetric) and self.indenter.footprint_half_width is None):
            return build(self.indenter._model())
        extent = 1.0
        for _ in range(60):
            core = build(self.indenter._model(extent))
            try:
                needed = core.extent_needed()
            except DomainError:
                extent *= 2.0
                continue
            if needed <= extent:
                return core
            extent = 1.01 * needed
        raise DomainError(f"Scene: {self.indenter!r} does not reach the scene's load within {extent} m")

    @property
    def controlled_by(self) -> str:
        """"force" or "depth"."""
        return "force" if self.depth is None else "depth"

    @property
    def history(self) -> tuple[np.ndarray, np.ndarray]:
        """(times (s), values) of the force (N) or depth (m) history as the model holds it; a
        constant is one sample at t = 0."""
        return self._model.history()

    def wants(self, output: str) -> bool:
        """Whether the scene asks for ``output``."""
        return output in self.outputs

    def to_json(self) -> str:
        """The scene model as JSON text."""
        return self._model.to_json()

    def to_toml(self, method: str | None = None, n: int | None = None, path=None) -> str:
        """The scene as a scene file (TOML), with ``method`` and ``n`` when given. With
        ``path`` the file is also written there, and a height map's heights go to a ``.npy``
        file beside it (``scene.toml``: ``scene.npy``), which the file names; without, they
        are inline."""
        if n is not None:
            n = _integer("Scene.to_toml", "n", n, 1)
        return self._model.to_toml(method, n, None if path is None else str(path))

    @classmethod
    def from_toml(cls, path) -> Scene:
        """The scene of the scene file at ``path``, with or without ``method`` and ``n`` (as
        :meth:`to_toml` writes it without them; :func:`mdrvisc.scenefile.load_scene` gives
        them too)."""
        return cls._from_core(_core.read_scene_file(str(path)))

    @classmethod
    def _from_core(cls, core, indenter: Indenter | HeightMap | None = None,
                   medium: _Medium | None = None) -> Scene:
        """The Scene of a core scene, which it holds as it is (not built again); ``indenter``
        and ``medium``: the Python objects of the core's, when the caller has them."""
        model = json.loads(core.model())
        if "outputs" not in model:  # a scene built here names its outputs, the defaults too
            model["outputs"] = list(DEFAULT_OUTPUTS)
            core = core.with_values(json.dumps([["outputs", model["outputs"]]]))
        scene = cls.__new__(cls)
        values = {f.name: f.default for f in dataclasses.fields(cls) if f.init}
        values.update({k: model[k] for k in ("duration", "dt", "times") if k in model})
        name = core.controlled_by()
        values[name] = model[name] if name in model else core.history()
        values["indenter"] = indenter if indenter is not None else indenter_from_model(
            model["indenter"], core.arrays())
        values["medium"] = medium if medium is not None else medium_from_model(model["medium"])
        values["contact"] = contact_from_model(model.get("contact"))
        if "layer" in model:
            values["body"] = Layer._of_model(model["layer"])
        for key, value in values.items():
            object.__setattr__(scene, key, value)
        scene._adopt(core, tuple(model.get("outputs", DEFAULT_OUTPUTS)), model.get("field_times"))
        return scene

    def __reduce__(self):
        """Pickles as the core scene (its model's text and its arrays); a callable history
        comes back as its samples, an Axisymmetric indenter as its tabulated Profile."""
        return (Scene._from_core, (self._model,))

    def __eq__(self, other) -> bool:
        """Scenes are equal when their models and arrays are."""
        return isinstance(other, Scene) and self._model == other._model

    __hash__ = None

    def bem_grid(self, n: int) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
        """(x, dx, height, mask) of the BEM grid with ``n`` elements across: element centres
        (m), element size (m), heights above the tip (m, (ny, nx)) and footprint mask."""
        return self._model.bem_grid(n)

    def mdr_grid(self, n: int) -> tuple[np.ndarray, float, np.ndarray]:
        """(x, dx, g) of the MDR foundation with ``n`` elements: centres (m), spacing (m),
        1D profile (m)."""
        return self._model.mdr_grid(n)

