"""Command line: ``mdrvisc paper [--out DIR] [--scenes DIR] [--quick] [--no-study] [--json]`` and
``mdrvisc run SCENE.toml [--json] [--out FILE]`` and ``mdrvisc sweep SWEEP.toml [--scheduler
ADDRESS] [--store DIR] [--json] [--out FILE]`` and ``mdrvisc fit DATA.csv|FILE.jpk-force
--indenter sphere:radius=5e-6 --model standardsolid [--control depth] [--spring-constant K]
[--curve N] [--segments approach,...] [--contact-point Z] [--baseline B]
[--baseline-model offset|tilt] [--guess KEY=VALUE,...] [--contact hard|jkr:W[:equilibrium]|dmt:W]
[--fix NAME,...] [--out FIT.csv] [--json]`` (also ``python -m mdrvisc ...``).

Results go to stdout (tables, or one JSON document with ``--json``), progress and warnings
(``warning: ...`` lines) to stderr; ``--out FILE`` also writes them to a file, its format
by its suffix: ``.json`` (the ``--json`` document), ``.csv`` (one row per output time; per
scene and output time for a sweep) or, for ``run``, ``.npz`` (:meth:`mdrvisc.Result.save`).
Input files are read up to 64 MiB. Bad input exits with status 2 and a one-line
``error: ...`` on stderr. ``mdrvisc paper`` draws its
figures with matplotlib (``pip install 'mdrvisc[paper]'``); without it, it writes the tables
and the CSV/JSON files, and says on stderr that it skipped the figures and what to install.
"""

import argparse
import csv
import dataclasses
import inspect
import json
import logging
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from . import __version__, _core, contact, geometry, media
from ._validate import _read_text
from .errors import IdentifiabilityWarning, InvalidInputError, MdrviscError
from .fitting import fit
from .formatting import text_table, to_jsonable
from .grids import load_sweep
from .many import solve_many
from .paper import report, studies
from .progress import ProgressBar
from .result import SERIES, Result

__all__ = ["main"]

_log = logging.getLogger("mdrvisc")


class _Progress:
    """Prints ``[elapsed s] label`` to stderr for each announced solve."""

    def __init__(self):
        self.start = time.perf_counter()

    def __call__(self, label):
        print(f"[{time.perf_counter() - self.start:7.2f} s] {label}", file=sys.stderr, flush=True)


def _parser():
    parser = argparse.ArgumentParser(
        prog="mdrvisc",
        description="Rigid indenters on a viscous half-space by BEM and MDR "
                    "(Kürschner & Filippov 2012).")
    parser.add_argument("--version", action="version", version=f"mdrvisc {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="log each solve (resolution, iterations, run time) to stderr")
    commands = parser.add_subparsers(dest="command", required=True)
    paper = commands.add_parser(
        "paper", help="the paper's comparisons and viscoelastic unloading against Ting: tables "
                      "on stdout, CSV/JSON/PNG files in --out (PNG with mdrvisc[paper])")
    paper.add_argument("--out", default="mdrvisc-paper",
                       help="output folder (default: ./mdrvisc-paper)")
    paper.add_argument("--scenes", metavar="DIR", default=None,
                       help="folder of the paper's scene files (default: those installed with "
                            "mdrvisc, the same as examples/paper)")
    paper.add_argument("--quick", action="store_true",
                       help="the scene files' [quick] resolutions (BEM rod 50, paraboloids 65, MDR 4097; "
                            "viscoelastic BEM 33, MDR 2001) and the quick error-vs-run-time "
                            "study: seconds")
    paper.add_argument("--no-study", action="store_true",
                       help="skip the error-vs-run-time study (error_vs_runtime.* files)")
    paper.add_argument("--json", action="store_true",
                       help="print the tables as one JSON document instead of text")
    run = commands.add_parser("run", help="run one scene file (TOML)")
    run.add_argument("scene", help="scene file, e.g. examples/rod.toml")
    run.add_argument("--json", action="store_true", help="print the result as JSON")
    run.add_argument("--out", metavar="FILE",
                     help="also write the result to FILE: .json (the --json document), .csv (one "
                          "row per output time) or .npz (mdrvisc.Result.load reads it)")
    run.add_argument("--no-progress", action="store_true",
                     help="no progress bar (by default a bar with the time left on stderr)")
    sweep = commands.add_parser(
        "sweep", help="run a sweep file (a scene file plus [sweep.axes]) in parallel, locally "
                      "or on a Dask cluster")
    sweep.add_argument("sweep", help="sweep file (TOML), e.g. examples/sweeps/relaxation_times.toml")
    sweep.add_argument("--scheduler", metavar="ADDRESS",
                       help="address of a Dask scheduler, e.g. tcp://host:8786 (needs mdrvisc[dask]); "
                            "default: this machine")
    sweep.add_argument("--store", metavar="DIR",
                       help="folder of finished results: each is saved as it arrives, a rerun "
                            "computes only what is missing")
    sweep.add_argument("--json", action="store_true", help="print the table as JSON records")
    sweep.add_argument("--out", metavar="FILE",
                       help="also write the table to FILE: .json (the --json records) or .csv")
    sweep.add_argument("--no-progress", action="store_true",
                       help="no progress bar (by default a bar with the time left on stderr)")
    fitting = commands.add_parser(
        "fit", help="fit a medium to an indentation curve: a CSV file with columns t (s), depth (m), "
                    "force (N) and optionally weight; a raw AFM curve as CSV: t, piezo (m, towards the "
                    "sample), deflection (m) with --spring-constant; or an instrument file read by "
                    "afmformats (.jpk-force, .jpk-force-map, .jpk-qi-data, .ibw, .h5, ...; needs "
                    "mdrvisc[afm]), the contact point fitted")
    fitting.add_argument("data", help="CSV file with a header row naming its columns, or an AFM file")
    fitting.add_argument("--indenter", required=True,
                         help="tip as NAME:KEY=VALUE,..., e.g. sphere:radius=5e-6, paraboloid:c=1e5, "
                              "cone:slope=0.36, pyramid:half_angle=0.61, rod:radius=1e-6 (SI units, "
                              "angles in radians)")
    fitting.add_argument("--model", required=True,
                         help="medium: elastic, viscous, kelvinvoigt, maxwell, standardsolid, prony, "
                              "powerlaw")
    fitting.add_argument("--control", choices=["depth", "force"], default="depth",
                         help="what was prescribed (default depth: the forces are fitted)")
    fitting.add_argument("--nu", type=float, default=0.5,
                         help="Poisson ratio of the medium, held in the fit (default 0.5, incompressible)")
    fitting.add_argument("--spring-constant", type=float, default=None,
                         help="cantilever spring constant (N/m) of a raw AFM curve (CSV columns piezo, "
                              "deflection); for an AFM file it replaces the file's")
    fitting.add_argument("--curve", type=int, default=0,
                         help="AFM files: which curve of the file (0, 1, ...; a map's curves in the "
                              "file's order; default 0)")
    fitting.add_argument("--segments", default="approach",
                         help="AFM files: the segments fitted, comma-separated, of approach, dwell, "
                              "retract (default approach)")
    fitting.add_argument("--contact-point", type=float, default=None, metavar="Z",
                         help="raw AFM curves: first guess of the contact point (m, piezo position)")
    fitting.add_argument("--baseline", type=float, default=None, metavar="B",
                         help="raw AFM curves: first guess of the deflection baseline (m)")
    fitting.add_argument("--baseline-model", choices=("offset", "tilt"), default="offset",
                         help="raw AFM curves: a constant baseline (offset, default) or a line in the "
                              "piezo position fitted with the rest (tilt: drift, virtual deflection)")
    fitting.add_argument("--guess", default=None, metavar="KEY=VALUE,...",
                         help="first guess of the medium's parameters, e.g. G_inf=1e3,G1=2e3,tau1=0.1 "
                              "(SI units; every parameter of the model; default: estimated from the data)")
    fitting.add_argument("--fix", default="", metavar="NAME,...",
                         help="parameters held at their guess, e.g. contact_point, baseline, or a "
                              "medium's (those need --guess)")
    fitting.add_argument("--contact", default="hard", metavar="hard|jkr:W[:equilibrium]|dmt:W",
                         help="contact law: hard (default), or jkr:W or dmt:W, adhesion fitted from the "
                              "initial work of adhesion W (J/m^2; --fix work_of_adhesion holds it): the "
                              "retract's dip below the baseline is data (an elastic model); "
                              "jkr:W:equilibrium loads JKR in equilibrium, jumping in at the touch")
    fitting.add_argument("--terms", type=int, default=2, help="Prony terms (--model prony)")
    fitting.add_argument("--substeps", type=int, default=1, help="time steps per sample interval")
    fitting.add_argument("--out", metavar="FILE.csv", default=None,
                         help="write the fitted curve: t, the data, the model, the residuals and the "
                              "weights (raw AFM curves also piezo, deflection and depth), one row per sample")
    fitting.add_argument("--json", action="store_true",
                         help="print the result as JSON, with the arrays t, data, model, residuals "
                              "(and depth of a raw AFM curve)")
    return parser


def _indenter(spec):
    """The indenter of a NAME:KEY=VALUE,... specification."""
    name, _, rest = spec.partition(":")
    classes = {cls.__name__.lower(): cls for cls in (geometry.Sphere, geometry.Paraboloid, geometry.Cone,
                                                      geometry.Pyramid, geometry.Rod)}
    if name.lower() not in classes:
        raise InvalidInputError(f"--indenter: unknown tip {name!r}; one of {sorted(classes)}")
    values = {}
    for item in filter(None, rest.split(",")):
        key, _, value = item.partition("=")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            raise InvalidInputError(f"--indenter: {item!r} is not KEY=NUMBER") from None
    cls = classes[name.lower()]
    keys = [k for k in inspect.signature(cls).parameters]
    unknown = [k for k in values if k not in keys]
    missing = [k for k, p in inspect.signature(cls).parameters.items()
               if p.default is inspect.Parameter.empty and k not in values]
    if unknown or missing:
        problem = f"unknown key(s) {unknown}" if unknown else f"missing key(s) {missing}"
        raise InvalidInputError(f"--indenter: {problem} for {name.lower()}; its keys: {keys}, "
                                f"e.g. {name.lower()}:{keys[0]}=...")
    return cls(**values)


def _read_columns(path) -> dict[str, np.ndarray]:
    """The columns of a CSV file: a header row of names, then rows of numbers separated by
    commas (blank lines and lines starting with # skipped); InvalidInputError naming the
    file and the line otherwise."""
    text = _read_text(path, "CSV file")
    lines = [(number, line) for number, line in enumerate(text.splitlines(), 1)
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise InvalidInputError(f"{path}: empty; a CSV file needs a header row naming its columns "
                                f"(e.g. t,depth,force) and rows of numbers")
    header = [name.strip().strip('"').strip() for name in lines[0][1].split(",")]
    if len(header) == 1:
        hint = " (a semicolon-separated file? use commas)" if ";" in lines[0][1] else ""
        raise InvalidInputError(f"{path}: the header row {lines[0][1].strip()[:80]!r} names one "
                                f"column; columns are separated by commas{hint}")
    if len(set(header)) != len(header) or "" in header:
        raise InvalidInputError(f"{path}: the header row names columns {header}: each must be named "
                                f"once")
    if len(lines) == 1:
        raise InvalidInputError(f"{path}: a header row and no rows of numbers")
    rows = []
    for number, line in lines[1:]:
        cells = line.split(",")
        if len(cells) != len(header):
            raise InvalidInputError(f"{path}: line {number} has {len(cells)} values, the header "
                                    f"{len(header)} columns")
        try:
            rows.append([float(cell) for cell in cells])
        except ValueError:
            bad = next(c for c in cells if not _is_number(c))
            raise InvalidInputError(f"{path}: line {number}: {bad.strip()[:40]!r} is not a "
                                    f"number") from None
    table = np.array(rows, dtype=np.float64)
    return {name: table[:, j] for j, name in enumerate(header)}


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _write(path, rows: list[dict], document: str | None = None, result: Result | None = None) -> None:
    """Writes ``rows`` (dicts of one row each) to ``path`` as CSV, ``document`` (JSON text)
    as .json, or ``result`` as .npz (when given), by the file's suffix."""
    suffix = Path(path).suffix.lower()
    formats = [".csv", ".json"] + ([".npz"] if result is not None else [])
    if suffix not in formats:
        raise InvalidInputError(f"--out: {str(path)!r} must end in one of {formats}")
    if suffix == ".npz":
        result.save(path)  # type: ignore[union-attr]
        return
    with open(path, "w", newline="", encoding="utf-8") as handle:
        if suffix == ".json":
            handle.write((document if document is not None else json.dumps(to_jsonable(rows))) + "\n")
            return
        writer = csv.DictWriter(handle, fieldnames=list(dict.fromkeys(k for row in rows for k in row)))
        writer.writeheader()
        writer.writerows(rows)


def _print_warnings(caught) -> None:
    """Prints each caught warning as a ``warning: ...`` line on stderr."""
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)


def _keys(option: str, text: str | None) -> dict[str, float]:
    """The numbers of a KEY=VALUE,... option."""
    values = {}
    for item in filter(None, (text or "").split(",")):
        key, _, value = item.partition("=")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            raise InvalidInputError(f"{option}: {item!r} is not KEY=NUMBER") from None
    return values


def _model(args):
    """The medium class of ``--model``, or its instance at ``--guess``'s values."""
    classes = {cls.__name__.lower(): cls for cls in (media.Elastic, media.Viscous) + media.VISCOELASTIC}
    cls = classes.get(args.model.lower())
    if cls is None:
        raise InvalidInputError(f"--model: unknown medium {args.model!r}; one of {sorted(classes)}")
    guess = _keys("--guess", args.guess)
    if not guess:
        return cls
    if cls is media.Prony:
        raise InvalidInputError("--guess: a Prony series' guess is not taken from the command line; "
                                "fit it without --guess")
    try:
        return cls(**guess, nu=args.nu)
    except TypeError as exc:
        names = [f.name for f in dataclasses.fields(cls) if f.name != "nu"]
        raise InvalidInputError(f"--guess: {exc}; {cls.__name__} takes {names}") from None


def _curve(args):
    """(t, the fit's data keywords, weights or None, whether it is a raw AFM curve) of
    ``args.data``: a CSV file (suffix .csv, .txt or none), or an AFM file read by
    :func:`mdrvisc.afm.load`."""
    if Path(args.data).suffix.lower() not in ("", ".csv", ".txt"):
        from . import afm

        curves = afm.load(args.data, spring_constant=args.spring_constant)
        if not 0 <= args.curve < len(curves):
            raise InvalidInputError(f"--curve: {args.data} has {len(curves)} curves (0..{len(curves) - 1}), "
                                    f"got {args.curve}")
        curve = curves[args.curve].select(*[s.strip() for s in args.segments.split(",") if s.strip()])
        model = media.Elastic if args.model.lower() == "elastic" else None
        t = curve.times(model)
        return t, {"piezo": curve.piezo, "deflection": curve.deflection,
                   "spring_constant": curve.spring_constant}, None, True
    data = _read_columns(args.data)
    names = tuple(data)
    raw = args.spring_constant is not None
    missing = [c for c in (("t", "piezo", "deflection") if raw else ("t", "depth", "force"))
               if c not in names]
    if missing:
        hint = "" if raw or "piezo" not in names else " (a raw AFM curve needs --spring-constant)"
        raise InvalidInputError(f"{args.data}: missing columns {missing} (has {list(names)}){hint}")
    curve = ({"piezo": np.atleast_1d(data["piezo"]), "deflection": np.atleast_1d(data["deflection"]),
              "spring_constant": args.spring_constant} if raw else
             {"depth": np.atleast_1d(data["depth"]), "force": np.atleast_1d(data["force"])})
    weights = np.atleast_1d(data["weight"]) if "weight" in names else None
    return np.atleast_1d(data["t"]), curve, weights, raw


def _contact(text: str):
    """The contact law of ``--contact``: "hard", "jkr:W", "jkr:W:equilibrium" (loaded in
    equilibrium, ``mv.JKR(approach="equilibrium")``) or "dmt:W" (W the work of adhesion,
    J/m^2)."""
    kind, _, value = text.partition(":")
    value, _, approach = value.partition(":")
    kind = kind.strip().lower()
    if kind == "hard" and not value:
        return contact.Hard()
    if (kind == "jkr" and approach in ("", "equilibrium")) or (kind == "dmt" and not approach):
        try:
            w = float(value)
        except ValueError:
            pass
        else:
            if kind == "dmt":
                return contact.DMT(work_of_adhesion=w)
            return contact.JKR(work_of_adhesion=w, approach=approach or "touch")
    raise InvalidInputError(f"--contact: {text!r} is not hard, jkr:W, jkr:W:equilibrium or dmt:W (W the "
                            f"work of adhesion in J/m^2)")


def _fit(args):
    """Fits the model to the curve of a CSV or AFM file; prints the result's table or JSON and
    writes the fitted curve with --out."""
    model = _model(args)
    t, curve, weights, raw = _curve(args)
    fixed = tuple(name.strip() for name in args.fix.split(",") if name.strip())
    extra = {}
    if args.contact_point is not None or args.baseline is not None or args.baseline_model != "offset":
        if not raw:
            raise InvalidInputError("--contact-point, --baseline and --baseline-model are for raw AFM curves")
        extra = {"contact_point": args.contact_point, "baseline": args.baseline,
                 "baseline_model": args.baseline_model}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", IdentifiabilityWarning)
        result = fit(_indenter(args.indenter), model, t, **curve, **extra, control=args.control,
                     nu=None if isinstance(model, media._Medium) else args.nu, terms=args.terms,
                     substeps=args.substeps, weights=weights, fixed=fixed,
                     contact=_contact(args.contact))
    _print_warnings(caught)
    w = np.ones_like(result.t) if weights is None else np.asarray(weights, dtype=float)
    columns = {"t": result.t, "data": result.data, "model": result.model, "residual": result.residuals,
               "weight": w}
    if raw:
        columns.update(piezo=curve["piezo"], deflection=curve["deflection"], depth=result.depth)
    if args.out is not None:
        np.savetxt(args.out, np.column_stack(list(columns.values())), delimiter=",",
                   header=",".join(columns), comments="")
        print(f"wrote {args.out}", file=sys.stderr)
    if args.json:
        arrays = {"t": result.t, "data": result.data, "model": result.model, "residuals": result.residuals}
        if raw:
            arrays["depth"] = result.depth
        print(json.dumps(to_jsonable({
            "medium": type(result.medium).__name__, "parameters": result.parameters, "stderr": result.stderr,
            "nu": result.nu, "young_moduli": result.young_moduli, "young_stderr": result.young_stderr,
            "free": result.free, "correlation": result.correlation.tolist(), "rms": result.rms,
            "cost": result.cost, "control": result.control, "nfev": result.nfev, "nit": result.nit,
            "forward": result.forward, "wall_time": result.wall_time, "success": result.success,
            "status": result.status, "message": result.message, "warnings": result.warnings,
            **({"contact_point": result.contact_point, "baseline": result.baseline,
                "baseline_slope": result.baseline_slope,
                "spring_constant": result.spring_constant} if raw else {}),
            "arrays": {name: a.tolist() for name, a in arrays.items()}})))
    else:
        print(repr(result))


def _paper(args):
    figures = report.can_draw()
    if not figures:
        print(f"warning: matplotlib is not installed: writing tables and CSV/JSON files, no figures "
              f"({report.PAPER_EXTRA} draws them)", file=sys.stderr)
    progress = _Progress()
    results = studies.paper(quick=args.quick, progress=progress, directory=args.scenes)
    study = None if args.no_study else studies.error_vs_runtime(quick=args.quick, progress=progress,
                                                                directory=args.scenes)
    progress("writing files")
    paths = report.write_paper(results, args.out, study, figures=figures)
    if study is not None:
        paths += report.write_error_vs_runtime(study, args.out, figures=figures)
    if args.json:
        print(json.dumps(report.paper_document(results, study)))
    else:
        print(report.rod_table(results["rod"]))
        print()
        print(report.paraboloid_tables(results["paraboloids"]))
        print()
        print(report.viscoelastic_table(results["viscoelastic"]))
        if study is not None:
            print()
            print(report.error_table(study))
            print()
            print(report.orders_table(study))
    print(f"wrote {', '.join(str(p) for p in paths)}", file=sys.stderr)
    progress("done")


def _run(args):
    """Runs a scene file as the Rust binary does: same parsing, report, table and JSON."""
    scene, method, n = _core.load_scene_file(args.scene)
    _Progress()(f"{args.scene}: {method.upper()} n={n}")
    progress = None if args.no_progress else ProgressBar()
    try:
        report = _core.run_scene(scene, method, n, progress=progress)
    except MdrviscError as exc:
        exc.args = (f"{args.scene}: {exc}",) + exc.args[1:]
        raise
    finally:
        if progress is not None:
            progress.close()
    _log.info("solved: %s %s n=%d steps=%d solves=%d iterations=%d wall=%.3f s", args.scene,
              method.upper(), n, report.steps, report.solves, report.iterations, report.wall_time)
    document = f"[{report.document(args.scene, scene)}]"
    if args.json:
        print(document)
    else:
        print(report.table(args.scene), end="")
    if args.out is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the table and the document have them
            result = Result._from_report(report)
        rows = [{k: getattr(result, k)[i].item() for k in SERIES if getattr(result, k) is not None}
                for i in range(len(result.t))]
        _write(args.out, rows, document, result)


def _sweep(args):
    """Runs a sweep file; prints one row per scene and output time (the scene's parameters and
    the result's series), and the failed scenes on stderr."""
    scenes, method, n = load_sweep(args.sweep)
    _Progress()(f"{args.sweep}: {len(scenes)} scenes, {method.upper()} n={n}")
    client = None
    if args.scheduler is not None:
        try:
            from distributed import Client
        except ImportError:
            raise MdrviscError("--scheduler needs Dask: pip install 'mdrvisc[dask]'") from None
        client = Client(args.scheduler)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sweep = solve_many(scenes, method, n, client=client, store=args.store,
                               progress=not args.no_progress)
    finally:
        if client is not None:
            client.close()
    _print_warnings(caught)
    for failure in sweep.failures:
        print(f"scene {failure.index} failed: {type(failure.error).__name__}: {failure.error}",
              file=sys.stderr)
    rows = sweep.rows()
    columns = dict.fromkeys(k for row in rows for k in row)
    rows = [{k: row.get(k) for k in columns} for row in rows]
    if args.out is not None:
        _write(args.out, rows)
    if args.json:
        print(json.dumps(to_jsonable(rows)))
    elif rows:
        kinds = {k: next((v for row in rows if (v := row[k]) is not None), None) for k in columns}
        print(text_table([(k, k, "" if isinstance(v, (str, bool)) else ".6g") for k, v in kinds.items()],
                         rows))
    return 2 if sweep.failures else 0


def main(argv: list[str] | None = None) -> int:
    """Runs the command line with ``argv`` (default ``sys.argv[1:]``); returns the exit status
    (0 success, 2 bad input or a failed solve or scene, 130 interrupted)."""
    args = _parser().parse_args(argv)
    if args.verbose:
        logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    try:
        if args.command == "paper":
            _paper(args)
        elif args.command == "sweep":
            return _sweep(args)
        elif args.command == "fit":
            _fit(args)
        else:
            _run(args)
    except (MdrviscError, ValueError, OSError, MemoryError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    return 0
