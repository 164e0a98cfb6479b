"""The paper's scenes, read from its scene files.

The scenes of Kürschner & Filippov (2012) are data, not code: one scene file per run in
``examples/paper/`` of the source tree, shipped with the package as
``mdrvisc/paper/scenes/`` (the same files, a test checks it). The Rust binary's
``mdrvisc paper`` reads the same files. Each is a scene file (:mod:`mdrvisc.scenefile`) plus
two keys that only ``mdrvisc paper`` reads:

``name``
    The run's label, e.g. ``"paraboloid c=1"``.
``[quick]``
    Keys that replace the file's under ``--quick`` (coarse resolutions: ``n``).

Files run in the order of their names. :func:`load_runs` reads them as :class:`Run` s;
:func:`load_scenes` sorts them into the rod of Section 5 and the paraboloids of Section 6
(:class:`PaperScenes`) as :mod:`mdrvisc.paper.studies` uses them. Nothing here runs at import.
"""

from __future__ import annotations

import dataclasses
import os
import sys
from pathlib import Path

from ..errors import InvalidInputError
from ..geometry import Paraboloid, Rod
from ..scene import Scene
from ..scenefile import parse_scene

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["SCENES", "Run", "Resolutions", "PaperScenes", "load_runs", "load_scenes"]

#: The folder of the paper's scene files shipped with the package.
SCENES = Path(__file__).resolve().parent / "scenes"

#: Keys of the paper's scene files beyond a scene file's.
NAME, QUICK = "name", "quick"


@dataclasses.dataclass(frozen=True)
class Run:
    """One run of the paper: its label, the scene and how it is solved."""

    #: The run's label, e.g. ``"rod a=1"``.
    name: str
    scene: Scene
    #: ``"bem"`` or ``"mdr"``.
    method: str
    #: Resolution, as in :func:`mdrvisc.solve`.
    n: int


@dataclasses.dataclass(frozen=True)
class Resolutions:
    """The resolutions of one comparison: BEM ``n`` (elements across the rod's diameter, or
    the paraboloid's grid side) and MDR ``n`` (elements of the 1D indenter)."""

    n_bem: int
    n_mdr: int


@dataclasses.dataclass(frozen=True)
class PaperScenes:
    """The paper's scenes, sorted into its two sections."""

    #: Section 5: the flat rod.
    rod: Scene
    #: Section 6: the first paraboloid (the others differ in their curvature c only).
    paraboloid: Scene
    #: Curvatures c (1/m) of the paraboloids, in the files' order.
    curvatures: tuple[float, ...]
    rod_resolutions: Resolutions
    paraboloid_resolutions: Resolutions


def load_runs(quick: bool = False, directory: str | os.PathLike | None = None) -> list[Run]:
    """The runs of the scene files (``*.toml``) in ``directory`` (default :data:`SCENES`), in
    the order of their names, with their ``[quick]`` values when ``quick``.

    Raises :class:`~mdrvisc.InvalidInputError` for a folder without scene files and for a file
    that is not a valid scene file plus ``name`` and ``[quick]`` (naming the file and key).
    """
    folder = SCENES if directory is None else Path(directory)
    paths = sorted(folder.glob("*.toml"))
    if not paths:
        raise InvalidInputError(f"no scene files (*.toml) in {folder}")
    return [_run(path, quick) for path in paths]


def _run(path: Path, quick: bool) -> Run:
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except tomllib.TOMLDecodeError as exc:
        raise InvalidInputError(f"{path}: {exc}") from None
    name = data.pop(NAME, None)
    if not isinstance(name, str):
        raise InvalidInputError(f"{path}: key '{NAME}' (the run's label) must be a string, got {name!r}")
    values = data.pop(QUICK, {})
    if not isinstance(values, dict):
        raise InvalidInputError(f"{path}: key '{QUICK}' must be a table, got {values!r}")
    if quick:
        data.update(values)
    scene, method, n = parse_scene(data, str(path))
    return Run(name, scene, method, n)


def load_scenes(quick: bool = False, directory: str | os.PathLike | None = None) -> PaperScenes:
    """The paper's scenes (:func:`load_runs`) as its sections: the rod's runs (a :class:`Rod`
    indenter) and the paraboloids' (a :class:`Paraboloid`), each by BEM and by MDR at one
    resolution per method and section."""
    runs = load_runs(quick, directory)
    sections = {"rod": [r for r in runs if isinstance(r.scene.indenter, Rod)],
                "paraboloids": [r for r in runs if isinstance(r.scene.indenter, Paraboloid)]}
    resolutions = {}
    for section, members in sections.items():
        sizes = {}
        for method in ("bem", "mdr"):
            ns = {r.n for r in members if r.method == method}
            if len(ns) != 1:
                raise InvalidInputError(f"the paper's scenes need the {section} by {method.upper()} at one "
                                        f"resolution, got {sorted(ns)}")
            sizes[f"n_{method}"] = ns.pop()
        resolutions[section] = Resolutions(**sizes)
    paraboloids = sections["paraboloids"]
    return PaperScenes(
        rod=sections["rod"][0].scene, paraboloid=paraboloids[0].scene,
        curvatures=tuple(dict.fromkeys(r.scene.indenter.c for r in paraboloids)),
        rod_resolutions=resolutions["rod"], paraboloid_resolutions=resolutions["paraboloids"])
