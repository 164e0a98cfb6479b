"""Sphinx configuration of the mdrvisc documentation site.

Build: ``pip install '.[docs]'`` then ``sphinx-build -E -W --keep-going -b html docs docs/_build/html``.
The API reference is generated from the installed package's docstrings (autodoc, autosummary,
napoleon for the numpy docstring style); the pages in Markdown are read by myst-parser; the
scripts in ``examples/`` are run at build time by sphinx-gallery, which turns each into a page
with its printed output and figures.
"""

import os
import shutil
from pathlib import Path

import mdrvisc

ROOT = Path(__file__).resolve().parent.parent

project = "mdrvisc"
author = "The mdrvisc developers"
copyright = "the mdrvisc developers"
version = release = mdrvisc.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "auto_examples/*.json"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

autosummary_generate = True
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
napoleon_google_docstring = False

# sphinx-gallery's options hold a function (the examples' arguments), which Sphinx cannot
# pickle into its cache: the site is then rebuilt in full, which is all this warning says.
suppress_warnings = ["config.cache"]
# A class exported at the top level (mdrvisc.Viscous) keeps its defining module's name
# (mdrvisc.media.Viscous) as a canonical alias; a type named in a docstring then finds both,
# which are the same object.
suppress_warnings += ["ref.python"]

html_theme = "alabaster"
html_title = f"mdrvisc {release}"


def _example_arguments(gallery_conf, script_vars):
    """Command-line arguments of each example: the quick variant where a script has one, and
    its output file in the build folder (figure, sweep and rough-surface scripts)."""
    name = Path(script_vars["src_file"]).stem
    out = Path(gallery_conf["src_dir"]) / gallery_conf["gallery_dirs"][0] / f"{name}.png"
    if name.startswith("fig"):
        return ["--quick", str(out)]
    return [str(out)] if name.startswith(("sweep", "rough")) else []


class _WrittenFigures:
    """sphinx-gallery image scraper for the figures an example saved as PNG files in the
    gallery folder, named after the example (the figure scripts save theirs and close them):
    each is shown once, after the code block that wrote it."""

    def __init__(self):
        self.shown = set()

    def __repr__(self):
        return "_WrittenFigures()"

    def __call__(self, block, block_vars, gallery_conf):
        from sphinx_gallery.scrapers import figure_rst

        folder = Path(gallery_conf["src_dir"]) / gallery_conf["gallery_dirs"][0]
        stem = Path(block_vars["src_file"]).stem
        written = sorted(p for p in folder.glob(f"{stem}*.png") if p not in self.shown)
        self.shown.update(written)
        names = []
        for png, target in zip(written, block_vars["image_path_iterator"]):
            shutil.copyfile(png, target)
            names.append(target)
        return figure_rst(names, gallery_conf["src_dir"])


sphinx_gallery_conf = {
    "image_scrapers": ("matplotlib", _WrittenFigures()),
    "examples_dirs": [str(ROOT / "examples")],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r".*\.py$",
    "reset_argv": _example_arguments,
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
}

# Figures are drawn off screen.
os.environ.setdefault("MPLBACKEND", "Agg")


def _write_api_reference(path: Path) -> None:
    """Writes the API reference page: the top-level names (``mdrvisc.__all__``), then every
    public module with what it holds beyond them, found by walking the installed package, so
    that new public API appears without editing the site."""
    import importlib
    import pkgutil

    top = set(mdrvisc.__all__)
    lines = ["API reference", "=============", "",
             "Generated from the docstrings of the installed package. Units are SI (m, s, N, Pa, "
             "Pa s).", "", "mdrvisc", "-------", "", ".. automodule:: mdrvisc", "   :members:", ""]
    for info in sorted(pkgutil.walk_packages(mdrvisc.__path__, "mdrvisc."), key=lambda i: i.name):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        module = importlib.import_module(info.name)
        names = getattr(module, "__all__", None)
        if names is None:
            names = [n for n, v in vars(module).items() if not n.startswith("_")
                     and getattr(v, "__module__", None) == info.name]
        names = [n for n in names if not (n in top and getattr(mdrvisc, n) is getattr(module, n))]
        lines += [info.name, "-" * len(info.name), "", f".. automodule:: {info.name}"]
        if names:
            lines.append(f"   :members: {', '.join(names)}")
        if info.name.rsplit(".", 1)[1] in top:
            # a module named as a function it holds (mdrvisc.solve): its page entry only
            lines.append("   :no-index:")
        lines.append("")
    text = "\n".join(lines)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


_write_api_reference(Path(__file__).resolve().parent / "api.rst")


def _list_verification(app, docname, source):
    """Puts the verification matrix (docs/verification.md) in the contents, after the physics
    page, when the repository has it."""
    if docname == "index" and (Path(app.srcdir) / "verification.md").exists():
        source[0] = source[0].replace("\nphysics\n", "\nphysics\nverification\n", 1)


def setup(app):
    app.connect("source-read", _list_verification)
