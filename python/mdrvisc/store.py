"""A store of finished scenes: one ``.npz`` file per scene (the :meth:`Result.save` format)
in a folder, named by a hash of what decides the result, so that a rerun of a sweep finds
what it already computed and computes only the rest."""

from __future__ import annotations

import hashlib
import io
import json
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from .errors import DataError, InvalidInputError
from .result import STORE_PREFIX, Result
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


#: The entry of a stored file that holds its key.
KEY_ENTRY = f"{STORE_PREFIX}key"


class Store:
    """The folder ``path`` (made when missing) of finished results, ``<key>.npz`` each: the
    :meth:`Result.save` format plus the key it was stored under, checked when it is loaded.

    Writes are atomic: a result goes to a temporary file in the folder, then is renamed onto
    its name, so a process killed while writing leaves no partial result under a key.

    Raises
    ------
    InvalidInputError
        ``path`` exists and is not a folder, or the folder cannot be made.
    """

    def __init__(self, path) -> None:
        self.path = Path(path)
        if self.path.exists() and not self.path.is_dir():
            raise InvalidInputError(f"store: {str(path)!r} is a file, not a folder")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InvalidInputError(f"store: cannot make the folder {str(path)!r}: "
                                    f"{exc.strerror or exc}") from None

    def file(self, key: str) -> Path:
        """The file of ``key``."""
        return self.path / f"{key}.npz"

    def __contains__(self, key: str) -> bool:
        return self.file(key).is_file()

    def load(self, key: str) -> Result:
        """The stored result of ``key``.

        Raises
        ------
        DataError
            The file is damaged or not a result, or it was stored under another key (a file
            copied or renamed onto this one's name): it is not this scene's result.
        """
        file = self.file(key)
        result = Result.load(file)
        with np.load(file, allow_pickle=False) as data:
            stored = str(data[KEY_ENTRY]) if KEY_ENTRY in data.files else None
        if stored != key:
            where = "no key" if stored is None else f"the key {stored[:16]}..."
            raise DataError(f"store: {str(file)!r} holds {where}, not {key[:16]}...: the result "
                            f"of another scene (copied or renamed), or written before stores "
                            f"kept their keys")
        return result

    def save(self, key: str, result: Result) -> Path:
        """Stores ``result`` under ``key`` atomically; returns its file."""
        handle, temporary = tempfile.mkstemp(dir=self.path, prefix=f".{key}.", suffix=".tmp")
        os.close(handle)
        try:
            result.save(temporary)
            entry = io.BytesIO()
            np.save(entry, np.asarray(key))
            with zipfile.ZipFile(temporary, "a") as archive:
                archive.writestr(f"{KEY_ENTRY}.npy", entry.getvalue())
            os.replace(temporary, self.file(key))
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
        return self.file(key)
