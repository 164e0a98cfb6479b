"""A store of finished scenes: one ``.npz`` file per scene (the :meth:`Result.save` format)
in a folder, named by a hash of what decides the result, so that a rerun of a sweep finds
what it already computed and computes only the rest."""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

from .result import Result
from .scene import Scene

__all__ = ["Store", "scene_key"]


def scene_key(scene: Scene, method: str, n: int, options: dict) -> str:
    """A SHA-256 (hex) of what decides the result: the scene's model (its numbers, as JSON),
    the shape and a SHA-256 of the bytes of each of its arrays (a height map's heights, a
    tabulated profile's samples, sampled histories), the method, the resolution and the
    solve options (every one, defaults included): equal keys, equal results."""
    document = {"scene": json.loads(scene._model.model()), "method": method, "n": int(n),
                "options": options}
    arrays = scene._model.arrays()
    if arrays:
        document["arrays"] = {name: [list(a.shape), hashlib.sha256(a).hexdigest()]
                              for name, a in arrays.items()}
    text = json.dumps(document, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


class Store:
    """The folder ``path`` (made when missing) of finished results, ``<key>.npz`` each.

    Writes are atomic: a result goes to a temporary file in the folder, then is renamed onto
    its name, so a process killed while writing leaves no partial result under a key."""

    def __init__(self, path) -> None:
        self.path = Path(path)
        self.path.mkdir(parents=True, exist_ok=True)

    def file(self, key: str) -> Path:
        """The file of ``key``."""
        return self.path / f"{key}.npz"

    def __contains__(self, key: str) -> bool:
        return self.file(key).is_file()

    def load(self, key: str) -> Result:
        """The stored result of ``key``."""
        return Result.load(self.file(key))

    def save(self, key: str, result: Result) -> Path:
        """Stores ``result`` under ``key`` atomically; returns its file."""
        handle, temporary = tempfile.mkstemp(dir=self.path, prefix=f".{key}.", suffix=".tmp")
        os.close(handle)
        try:
            result.save(temporary)
            os.replace(temporary, self.file(key))
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
        return self.file(key)
