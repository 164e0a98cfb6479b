"""Sphinx configuration of the mdrvisc documentation site.

Build: ``pip install '.[docs]'`` then ``sphinx-build -E -W --keep-going -b html docs docs/_build/html``.
The API reference is generated from the installed package's docstrings: one page per public
function, class and constant (autosummary), the numpy docstring style read by numpydoc; the
pages in Markdown are read by myst-parser; the scripts in ``examples/`` are run at build time
by sphinx-gallery, which turns each into a page with its printed output and figures.
"""

import os
import re
import shutil
from pathlib import Path

import mdrvisc

ROOT = Path(__file__).resolve().parent.parent
HERE = Path(__file__).resolve().parent

project = "mdrvisc"
author = "The mdrvisc developers"
copyright = "the mdrvisc developers"
version = release = mdrvisc.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "auto_examples/*.json"]
templates_path = ["_templates"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# The API reference: one page per object, written by autosummary into generated/.
autosummary_generate = True
autosummary_imported_members = False
# Members are listed on the pages of their classes only (the class template), so that a
# module's section of the index does not document them a second time.
autodoc_default_options = {"show-inheritance": True}
autodoc_member_order = "bysource"
# Hints in the signatures, shortened (numpy.ndarray -> ndarray; numpy's ArrayLike, which
# Python expands into a union of private protocols, back to its name: _short_hints).
autodoc_typehints = "signature"
autodoc_typehints_format = "short"
python_use_unqualified_type_names = True
autodoc_class_signature = "mixed"
# Annotations written as text (modules with "from __future__ import annotations") keep
# numpy's ArrayLike by its name.
autodoc_type_aliases = {"ArrayLike": "ArrayLike", "ProfileFunction": "ProfileFunction"}
# numpydoc renders "a, b : float" once, for both names; the class pages list their members
# through autodoc, so numpydoc's own member tables would repeat them.
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = False

# sphinx-gallery's options hold a function (the examples' arguments), which Sphinx cannot
# pickle into its cache: the site is then rebuilt in full, which is all this warning says.
suppress_warnings = ["config.cache"]
# A class exported at the top level (mdrvisc.Viscous) keeps its defining module's name
# (mdrvisc.media.Viscous) as a canonical alias; a type named in a docstring then finds both,
# which are the same object.
suppress_warnings += ["ref.python"]

html_theme = "furo"
html_title = f"mdrvisc {release}"
html_static_path = ["_static"]
html_css_files = ["mdrvisc.css"]


def _example_arguments(gallery_conf, script_vars):
    """Command-line arguments of each example: ``--quick`` where a script has it, and its
    output file in the build folder where it takes one (its docstring's ``Run:`` line names
    ``[OUT.png]``)."""
    source = Path(script_vars["src_file"])
    text = source.read_text()
    out = Path(gallery_conf["src_dir"]) / gallery_conf["gallery_dirs"][0] / f"{source.stem}.png"
    arguments = ["--quick"] if "[--quick]" in text else []
    return arguments + ([str(out)] if "[OUT.png]" in text else [])


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

#: The top-level names of the API reference, by topic; a name of ``mdrvisc.__all__`` in no
#: topic is listed under "More", so that new public API appears without editing the site.
TOPICS = {
    "Scenes, solving and results": ["Scene", "OUTPUTS", "solve", "load_curve", "Result", "Fields",
                                    "set_num_threads", "num_threads"],
    "Indenters": ["Rod", "Paraboloid", "Cone", "Sphere", "Pyramid", "Axisymmetric", "Profile",
                  "HeightMap", "Indenter"],
    "Media": ["Elastic", "Viscous", "KelvinVoigt", "Maxwell", "StandardSolid", "Prony", "PowerLaw"],
    "Fitting measured curves": ["fit", "FitResult"],
    "Sweeps: many scenes": ["solve_many", "Sweep", "SceneFailure", "sweep_scenes", "zip_scenes",
                            "load_sweep"],
    "Errors and warnings": ["MdrviscError", "InvalidInputError", "DataError", "DomainError",
                            "ConvergenceError", "ResolutionWarning", "IdentifiabilityWarning"],
}


def _autosummary(names):
    return ["", ".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""] + \
        [f"   {name}" for name in names] + [""]


def _write_api_reference(path: Path) -> None:
    """Writes the API reference's index: the top-level names (``mdrvisc.__all__``) by topic,
    then every public module with what it holds beyond them, found by walking the installed
    package; each object gets its own page (autosummary), documented once under the name
    users import it by."""
    import importlib
    import inspect
    import pkgutil

    top = [n for n in mdrvisc.__all__ if not n.startswith("_")]
    modules = [n for n in top if inspect.ismodule(getattr(mdrvisc, n))]
    objects = [n for n in top if n not in modules]
    lines = ["API reference", "=============", "",
             "Generated from the docstrings of the installed package, one page per object. Units "
             "are SI (m, s, N, Pa, Pa s); depths and deflections are positive into the body.",
             "", ".. module:: mdrvisc", ""]
    listed = set()
    for topic, names in list(TOPICS.items()) + [("More", [n for n in objects
                                                          if not any(n in v for v in TOPICS.values())])]:
        names = [n for n in names if n in objects]
        if not names:
            continue
        lines += [topic, "-" * len(topic), ".. currentmodule:: mdrvisc"] + _autosummary(names)
        listed.update(names)
    lines += ["Modules", "-------", "",
              "The modules below hold what the top level does not export; the names above are "
              "documented once, under ``mdrvisc.``.", ""]
    for info in sorted(pkgutil.walk_packages(mdrvisc.__path__, "mdrvisc."), key=lambda i: i.name):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        module = importlib.import_module(info.name)
        names = getattr(module, "__all__", None)
        if names is None:
            names = [n for n, v in vars(module).items() if not n.startswith("_")
                     and getattr(v, "__module__", None) == info.name
                     and (inspect.isfunction(v) or inspect.isclass(v))]
        names = [n for n in names if not (n in listed and getattr(mdrvisc, n) is getattr(module, n))
                 and not inspect.ismodule(getattr(module, n))]
        lines += [info.name, "~" * len(info.name), "", f".. automodule:: {info.name}",
                  "   :no-members:"]
        if info.name.rsplit(".", 1)[1] in objects:
            # a module named as the function it holds (mdrvisc.solve): the function keeps
            # the name's index entry
            lines.append("   :no-index:")
        lines.append("")
        if names:
            lines += [f".. currentmodule:: {info.name}"] + _autosummary(names)
    text = "\n".join(lines) + "\n"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


_write_api_reference(HERE / "api.rst")

#: Python's own spelling of numpy's ``ArrayLike`` (a union of private protocols), as the
#: signatures receive it, put back to its name.
_ARRAY_LIKE = re.compile(r"(~?numpy\._typing\._array_like\.)?_Buffer \| .*?"
                         r"(~?numpy\._typing\._nested_sequence\.)?_NestedSequence\["
                         r"(bool \| int \| float \| )?complex \| (bytes \| str|str \| bytes)\]")


#: An alias of ``autodoc_type_aliases`` inside another type, as Sphinx spells it.
_FORWARD_REF = re.compile(r"TypeAliasForwardRef\('(\w+)'\)")


def _short_hints(app, what, name, obj, options, signature, return_annotation):
    """Signatures with numpy's ArrayLike written as its name."""
    def short(text):
        if text is None:
            return None
        return _FORWARD_REF.sub(r"\1", _ARRAY_LIKE.sub("ArrayLike", text))
    return short(signature), short(return_annotation)


def _public_bases(app, name, obj, options, bases):
    """Leaves private base classes (``_Medium``) out of a class's "Bases" line."""
    bases[:] = [b for b in bases if not getattr(b, "__name__", "").startswith("_")]


#: Pages other parts of the project add (file name, audience); each appears in the landing
#: page's list of its audience and in the contents once its file exists.
OPTIONAL_PAGES = {"afm": "Fit a force map and read instrument files",
                  "layers": "Layers of finite thickness",
                  "adhesion": "Adhesive contact"}


def _optional_pages(app, docname, source):
    """Fills the landing page's places for the optional pages (a line ``{optional}`afm```)
    with links where the page exists, and lists it in the contents when no toctree line does;
    the verification matrix goes after the physics page when the repository has it."""
    if docname != "index":
        return
    text = source[0]
    srcdir = Path(app.srcdir)
    for page, title in OPTIONAL_PAGES.items():
        marker = f"<!-- optional: {page} -->"
        exists = (srcdir / f"{page}.md").exists()
        text = text.replace(marker, f"- [{title}]({page}.md)" if exists else "")
        if exists and not re.search(rf"^{page}$", text, re.M):
            text = text.replace("\nguide\n", f"\nguide\n{page}\n", 1)
    if (srcdir / "verification.md").exists() and not re.search(r"^verification$", text, re.M):
        text = text.replace("\nphysics\n", "\nphysics\nverification\n", 1)
    source[0] = text


def setup(app):
    app.connect("source-read", _optional_pages)
    app.connect("autodoc-process-signature", _short_hints)
    app.connect("autodoc-process-bases", _public_bases)
