"""Fuzzing of every public constructor and function and of both command lines with hostile
values (NaN, +-inf, 0, negatives, 1e+-308, subnormals, huge integers, wrong types and
dtypes, empty, 0-d, non-contiguous, read-only and aliased arrays, unsorted or duplicate
times, callables that raise or return NaN).

Each call must end in a typed ``MdrviscError`` or a result whose numbers are all finite:
never another exception, a crash, a hang or a NaN. Outcomes are counted; the table is
printed at the end of the run (``tests/conftest.py``). Hypothesis is derandomized under CI
(the ``ci`` profile), so the suite's cost and findings repeat.
"""

import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mdrvisc as mv
from mdrvisc import cli

ROOT = Path(__file__).resolve().parents[1]

#: Outcomes per target: typed errors, valid results, other outcomes.
OUTCOMES: dict[str, dict[str, int]] = {}

HOSTILE_FLOATS = st.sampled_from(
    [
        math.nan,
        math.inf,
        -math.inf,
        0.0,
        -0.0,
        -1.0,
        1e308,
        -1e308,
        1e-308,
        5e-324,
        1e100,
        1e-100,
        1.0,
        2.5,
        10**400,
        True,
        "1",
        None,
        [1.0],
        1j,
    ]
)
NUMBERS = st.one_of(
    HOSTILE_FLOATS,
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**20), max_value=10**20),
)
PLAUSIBLE = st.floats(min_value=1e-3, max_value=1e3)
#: Half plausible values (so that valid runs are reached and their numbers checked), half hostile.
VALUES = st.one_of(PLAUSIBLE, NUMBERS)
TIMES = st.lists(st.floats(min_value=0.01, max_value=2.0), min_size=1, max_size=4)


def mostly(valid, hostile=NUMBERS):
    """``valid`` three times in four: a call with several arguments then still reaches a
    valid run often enough for its numbers to be checked."""
    return st.one_of(valid, valid, valid, hostile)


FUZZ = settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def finite(value) -> bool:
    """Whether every number reachable in ``value`` (a Result, arrays, floats) is finite."""
    if isinstance(value, mv.Result):
        arrays = [
            np.asarray(getattr(value, k), dtype=float) for k in ("t", "depth", "contact_length", "force")
        ]
        for f in (value.fields or {}).values():
            arrays += [
                np.asarray(getattr(f, k), dtype=float)
                for k in ("pressure", "deflection", "surface_velocity")
                if getattr(f, k) is not None
            ]
        return all(np.all(np.isfinite(a)) for a in arrays)
    if isinstance(value, (float, int, np.ndarray, np.floating)):
        return bool(np.all(np.isfinite(np.asarray(value, dtype=float))))
    return True


class CallbackFailed(Exception):
    """Raised by the hostile progress callback: a run stops and re-raises it, as documented."""


def raising(stage, done, total):
    raise CallbackFailed(stage)


def outcome(target: str, call) -> None:
    """Runs ``call``; counts a typed error, a finite result or the hostile callback's own
    exception (which a run re-raises, as documented), and fails on anything else."""
    counts = OUTCOMES.setdefault(
        target, {"typed error": 0, "valid result": 0, "callback re-raised": 0, "other": 0}
    )
    try:
        value = call()
    except mv.MdrviscError:
        counts["typed error"] += 1
        return
    except CallbackFailed:
        counts["callback re-raised"] += 1
        return
    except Exception:
        counts["other"] += 1
        raise
    if not finite(value):
        counts["other"] += 1
        raise AssertionError(f"{target}: a non-finite result without an error: {value!r}")
    counts["valid result"] += 1


MEDIA = {
    "Viscous": lambda a, b, c: mv.Viscous(a),
    "Elastic": lambda a, b, c: mv.Elastic(a),
    "KelvinVoigt": lambda a, b, c: mv.KelvinVoigt(a, b),
    "Maxwell": lambda a, b, c: mv.Maxwell(a, b),
    "StandardSolid": lambda a, b, c: mv.StandardSolid(a, b, c),
    "Prony": lambda a, b, c: mv.Prony(G_inf=a, terms=[(b, c)]),
}
INDENTERS = {
    "Rod": lambda a, b: mv.Rod(a),
    "Paraboloid": lambda a, b: mv.Paraboloid(a, b),
    "Cone": lambda a, b: mv.Cone(a, b),
    "Sphere": lambda a, b: mv.Sphere(a),
    "Pyramid": lambda a, b: mv.Pyramid(a, b),
}


@pytest.mark.parametrize("name", MEDIA)
@FUZZ
@given(a=VALUES, b=VALUES, c=VALUES, t=st.one_of(VALUES, TIMES, st.lists(NUMBERS, max_size=4)))
def test_media_and_their_functions(name, a, b, c, t):
    def build_and_evaluate():
        medium = MEDIA[name](a, b, c)
        return medium.relaxation_modulus(t), medium.creep_compliance(t)

    def both_finite():
        g, j = build_and_evaluate()
        return np.concatenate([np.ravel(g), np.ravel(j)])

    outcome(f"media.{name}", both_finite)


@pytest.mark.parametrize("name", INDENTERS)
@FUZZ
@given(a=VALUES, b=st.one_of(st.none(), VALUES))
def test_indenters(name, a, b):
    outcome(f"geometry.{name}", lambda: INDENTERS[name](a, b) and 0.0)


SCENE_VALUES = st.one_of(
    PLAUSIBLE,
    TIMES,
    NUMBERS,
    st.lists(NUMBERS, max_size=3),
    st.tuples(st.lists(NUMBERS, min_size=1, max_size=3), st.lists(NUMBERS, min_size=1, max_size=3)),
    st.just(lambda t: 1.0 / 0.0),
    st.just(lambda t: math.nan),
    st.just(lambda t: "x"),
)


@FUZZ
@given(
    force=mostly(PLAUSIBLE, SCENE_VALUES),
    duration=mostly(st.just(2.0)),
    times=mostly(st.none(), SCENE_VALUES),
    outputs=st.one_of(
        st.none(), st.just(("depth", "pressure")), st.just(("nope",)), st.just(3), st.just("velocity")
    ),
    field_times=mostly(st.none(), SCENE_VALUES),
    dt=mostly(st.none()),
    method=st.sampled_from(["bem", "mdr", "mdr", "fem", 3]),
)
def test_scenes_and_solve(force, duration, times, outputs, field_times, dt, method):
    def run():
        scene = mv.Scene(
            indenter=mv.Paraboloid(1.0, 2.56),
            medium=mv.StandardSolid(1.0, 3.0, 0.5),
            force=force,
            duration=duration,
            times=times,
            outputs=outputs,
            field_times=field_times,
            dt=dt,
        )
        return mv.solve(scene, method, 9 if method == "bem" else 101)

    outcome("Scene + solve", run)


VISCOUS = mv.Scene(
    indenter=mv.Paraboloid(1.0, 2.56), medium=mv.Viscous(1.0), force=1.0, duration=2.0, times=[1.0, 2.0]
)


@FUZZ
@given(
    n=mostly(st.integers(1, 3000)),
    tol=mostly(st.just(1e-8)),
    max_iter=mostly(st.integers(1, 500)),
    step=mostly(st.just(0.01)),
    area_change=mostly(st.just(0.01)),
    dt=mostly(st.none()),
    integrator=mostly(st.just("implicit"), st.sampled_from(["explicit", "euler", None])),
    progress=mostly(st.none(), st.sampled_from([True, False, 3, raising, lambda s, d, t: math.nan])),
    method=st.sampled_from(["bem", "mdr"]),
)
def test_solve_options(n, tol, max_iter, step, area_change, dt, integrator, progress, method):
    def run():
        # valid sizes are capped to keep the suite quick; anything else goes in as drawn
        valid = isinstance(n, int) and not isinstance(n, bool) and n > 0
        size = min(n, 33 if method == "bem" else 2001) if valid else n
        return mv.solve(
            VISCOUS,
            method,
            size,
            tol=tol,
            max_iter=max_iter,
            step=step,
            area_change=area_change,
            dt=dt,
            integrator=integrator,
            progress=progress,
        )

    outcome("solve options", run)


ARRAYS = st.one_of(
    st.sampled_from(
        [
            "empty",
            "0-d",
            "nan",
            "inf",
            "complex",
            "object",
            "strided",
            "readonly",
            "int",
            "bool",
            "3-d",
            "negative",
            "huge",
            "tiny",
        ]
    ),
    st.integers(min_value=1, max_value=6),
)


def hostile_array(kind, shape=(6, 6)):
    base = np.abs(np.random.default_rng(0).standard_normal(shape))
    if isinstance(kind, int):
        return base[:kind, :kind]
    return {
        "empty": np.zeros((0, 0)),
        "0-d": np.float64(1.0),
        "nan": np.where(base > 1, np.nan, base),
        "inf": np.where(base > 1, np.inf, base),
        "complex": base.astype(complex),
        "object": base.astype(object),
        "strided": np.abs(np.random.default_rng(1).standard_normal((12, 12)))[::2, ::2],
        "readonly": _readonly(base),
        "int": (base * 10).astype(np.int32),
        "bool": base > 1,
        "3-d": base[None],
        "negative": -base,
        "huge": base * 1e300,
        "tiny": base * 1e-310,
    }[kind]


def _readonly(a):
    a = a.copy()
    a.setflags(write=False)
    return a


@FUZZ
@given(
    kind=mostly(st.integers(1, 6), ARRAYS),
    dx=mostly(PLAUSIBLE),
    G=mostly(PLAUSIBLE),
    force=mostly(PLAUSIBLE, st.one_of(st.none(), NUMBERS)),
    depth=mostly(st.none()),
    max_iter=mostly(st.just(50)),
    active_limit=mostly(st.one_of(st.none(), st.integers(0, 50))),
    precondition=st.sampled_from([True, False, "yes", 1]),
)
def test_arrays_contact(kind, dx, G, force, depth, max_iter, active_limit, precondition):
    outcome(
        "arrays.contact",
        lambda: mv.arrays.contact(
            hostile_array(kind),
            dx,
            G,
            force=force,
            depth=depth,
            max_iter=max_iter,
            active_limit=active_limit,
            precondition=precondition,
        ),
    )


@FUZZ
@given(
    kind=mostly(st.integers(1, 6), ARRAYS),
    dx=mostly(PLAUSIBLE),
    eta=mostly(PLAUSIBLE),
    force=mostly(PLAUSIBLE, SCENE_VALUES),
    times=mostly(TIMES, SCENE_VALUES),
    rates=st.sampled_from([True, False, 0]),
    progress=st.sampled_from([None, raising, 5]),
)
def test_arrays_viscous(kind, dx, eta, force, times, rates, progress):
    outcome(
        "arrays.viscous",
        lambda: mv.arrays.viscous(hostile_array(kind), dx, eta, force, times, rates=rates, progress=progress),
    )


@FUZZ
@given(
    shape=mostly(st.sampled_from([(4, 4), (3, 5)]), st.one_of(st.tuples(NUMBERS, NUMBERS), NUMBERS)),
    dx=mostly(PLAUSIBLE),
    kind=mostly(st.just(6), ARRAYS),
    out=st.sampled_from([None, "alias", "readonly", "wrong-dtype", "wrong-shape", "list"]),
)
def test_surface_operator(shape, dx, kind, out):
    def run():
        op = mv.arrays.SurfaceOperator(shape, dx)
        p = hostile_array(kind, op.shape)
        target = {
            None: None,
            "alias": p,
            "readonly": _readonly(np.zeros(op.shape)),
            "wrong-dtype": np.zeros(op.shape, np.float32),
            "wrong-shape": np.zeros((2, 2)),
            "list": [0.0],
        }[out]
        return op.apply(p, out=target)

    outcome("arrays.SurfaceOperator", run)


BAD_TOML = st.one_of(
    st.text(max_size=200),
    st.sampled_from(
        [
            'method = "bem"\nn = 1e400\n',
            'method = "mdr"\nn = -1\n[indenter]\ntype = "rod"\nradius = 1\n',
            'method = "mdr"\nn = 101\nforce = nan\nduration = 1\n[indenter]\ntype = "rod"\nradius = 1\n'
            '[medium]\ntype = "viscous"\neta = 1\n',
            'method = "mdr"\nn = 101\nforce = 1\nduration = 1e308\ndt = 1e-308\n'
            '[indenter]\ntype = "paraboloid"\nc = 1\n[medium]\ntype = "maxwell"\nG = 1\neta = 1\n',
            'method = "bem"\nn = 9223372036854775807\nforce = 1\nduration = 1\n[indenter]\ntype = "sphere"\n'
            'radius = 1\n[medium]\ntype = "viscous"\neta = 1\n',
            "\x00\x01\x02",
            'method = "mdr"\nn = 101\nforce = 1\nduration = 1\ntimes = [0.5, 0.5]\n'
            '[indenter]\ntype = "rod"\nradius = 1\n[medium]\ntype = "viscous"\neta = 1\n',
        ]
    ),
)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=BAD_TOML)
def test_python_command_line(tmp_path, text):
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")

    def run():
        status = cli.main(["run", str(path)])
        if status == 2:
            raise mv.InvalidInputError("exit status 2")
        if status != 0:
            raise AssertionError(f"exit status {status}")
        return 0.0

    outcome("command line (Python)", run)


@pytest.fixture(scope="module")
def binary():
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=ROOT, check=True)
    return ROOT / "target" / "release" / "mdrvisc"


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=BAD_TOML)
def test_rust_command_line(binary, tmp_path, text):
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")

    def run():
        out = subprocess.run([str(binary), "run", str(path)], capture_output=True, text=True, timeout=60)
        if out.returncode not in (0, 2) or "panicked" in out.stderr:
            raise AssertionError(f"exit status {out.returncode}: {out.stderr[-500:]}")
        if out.returncode == 2:
            raise mv.InvalidInputError("exit status 2")
        return 0.0

    outcome("command line (Rust)", run)


def test_python_m_mdrvisc_and_the_binary_print_usage_on_no_arguments(binary):
    for argv in ([sys.executable, "-m", "mdrvisc"], [str(binary)]):
        out = subprocess.run(argv, capture_output=True, text=True, timeout=60)
        assert out.returncode == 2 and "usage" in out.stderr.lower(), out.stderr


# --- the fit, sweep, store, surfaces and result-file entry points -------------------------

#: Sample arrays for the fit: a plausible curve (times, depths, forces of one shape) three
#: times in four, else hostile arrays or values.
CURVE_ARRAYS = st.one_of(
    st.just("plausible"), st.just("plausible"), st.just("plausible"),
    st.sampled_from(["empty", "nan", "inf", "negative", "unsorted", "short", "2-d", "strings", "huge"]),
    NUMBERS,
)


def curve_array(kind, base):
    """A hostile variant ``kind`` of the plausible array ``base`` (or ``kind`` itself)."""
    variants = {
        "plausible": base,
        "empty": np.array([]),
        "nan": np.where(np.arange(base.size) == 2, np.nan, base),
        "inf": np.where(np.arange(base.size) == 1, np.inf, base),
        "negative": -base,
        "unsorted": base[::-1].copy(),
        "short": base[:1],
        "2-d": np.vstack([base, base]),
        "strings": base.astype(str),
        "huge": base * 1e300,
    }
    return variants[kind] if isinstance(kind, str) and kind in variants else kind


FIT_T = np.linspace(0.1, 1.0, 8)


@FUZZ
@given(
    t=CURVE_ARRAYS,
    depth=CURVE_ARRAYS,
    force=CURVE_ARRAYS,
    model=st.sampled_from([mv.Elastic, mv.Viscous, mv.KelvinVoigt, mv.Maxwell, mv.StandardSolid, mv.Prony,
                           mv.PowerLaw, mv.StandardSolid(1e3, 1e3, 0.5), "standardsolid", 3]),
    control=mostly(st.sampled_from(["depth", "force"]), st.sampled_from(["piezo", None, 1])),
    nu=mostly(st.sampled_from([None, 0.5, 0.3])),
    terms=mostly(st.integers(1, 3), st.one_of(NUMBERS, st.just(10**6))),
    n=mostly(st.integers(8, 40)),
    substeps=mostly(st.integers(1, 3), st.one_of(NUMBERS, st.just(10**9))),
    indenter=st.sampled_from(["sphere", "rod", "cone"]),
)
def test_fit(t, depth, force, model, control, nu, terms, n, substeps, indenter):
    tip = {"sphere": mv.Sphere(5e-6), "rod": mv.Rod(1e-6), "cone": mv.Cone(0.4)}[indenter]

    def run():
        result = mv.fit(tip, model, curve_array(t, FIT_T), depth=curve_array(depth, 1e-7 * FIT_T),
                        force=curve_array(force, 1e-9 * FIT_T), control=control, nu=nu, terms=terms, n=n,
                        substeps=substeps, max_iter=5)
        return np.array(list(result.parameters.values()) + [result.rms])

    outcome("fit", run)


@FUZZ
@given(
    piezo=CURVE_ARRAYS,
    deflection=CURVE_ARRAYS,
    spring_constant=mostly(st.sampled_from([0.05, 1.0])),
    contact_point=mostly(st.none()),
)
def test_fit_raw_afm(piezo, deflection, spring_constant, contact_point):
    t = np.linspace(0.0, 1.0, 40)
    z = np.where(t < 0.5, 1e-7 * (t - 0.4), 1e-7 * (0.6 - t))

    def run():
        result = mv.fit(mv.Sphere(5e-6), mv.StandardSolid, t, piezo=curve_array(piezo, z),
                        deflection=curve_array(deflection, np.maximum(z, 0.0) * 0.1),
                        spring_constant=spring_constant, contact_point=contact_point, n=16, max_iter=3)
        return np.array(list(result.parameters.values()))

    outcome("fit (raw AFM)", run)


SWEEP_BASE = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(1.0, 3.0, 0.5), force=0.5,
                      duration=1.0, times=[0.5, 1.0])


@FUZZ
@given(
    tau=st.lists(mostly(st.floats(0.1, 5.0)), min_size=0, max_size=3),
    extra=st.sampled_from([None, "not a scene", 3]),
    method=mostly(st.just("mdr"), st.sampled_from(["bem", "fem", None, 1])),
    n=mostly(st.integers(1, 301), st.one_of(NUMBERS, st.just(2**64))),
    workers=mostly(st.just(1), st.one_of(NUMBERS, st.just(0))),
    option=st.sampled_from([{}, {"dt": 0.01}, {"tol": math.nan}, {"nope": 1}, {"max_iter": -1},
                            {"integrator": "euler"}]),
)
def test_solve_many(tau, extra, method, n, workers, option):
    def run():
        scenes = mv.sweep_scenes(SWEEP_BASE, medium__tau1=tau) if tau else []
        if extra is not None:
            scenes.append(extra)
        valid_n = isinstance(n, int) and not isinstance(n, bool) and n > 0
        size = min(n, 9) if valid_n and method == "bem" else n
        sweep = mv.solve_many(scenes, method, size, progress=False, workers=workers, **option)
        for failure in sweep.failures:
            if not isinstance(failure.error, mv.MdrviscError):
                raise failure.error
        return np.concatenate([[0.0]] + [r.depth for r in sweep.results if r is not None])

    outcome("solve_many", run)


#: Bytes of a stored file: garbage, truncations and foreign archives of a valid result.
def _valid_result_bytes(tmp_path):
    path = tmp_path / "valid.npz"
    mv.solve(SWEEP_BASE, "mdr", 101).save(path)
    return path.read_bytes()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    cut=st.one_of(st.none(), st.integers(0, 4000)),
    garbage=st.binary(max_size=200),
    kind=st.sampled_from(["truncated", "garbage", "npy", "pickle", "foreign npz", "empty", "folder"]),
)
def test_result_files_and_store_entries(tmp_path, cut, garbage, kind):
    import pickle
    import tempfile
    import zipfile

    from mdrvisc.store import Store

    tmp_path = Path(tempfile.mkdtemp(dir=tmp_path))  # one folder per example
    valid = _valid_result_bytes(tmp_path)
    path = tmp_path / "entry.npz"
    if kind == "truncated":
        path.write_bytes(valid[: (cut or 0) % len(valid)])
    elif kind == "garbage":
        path.write_bytes(garbage)
    elif kind == "npy":
        np.save(path.with_suffix(".npy"), np.arange(3))
        path.write_bytes(path.with_suffix(".npy").read_bytes())
    elif kind == "pickle":
        path.write_bytes(pickle.dumps({"t": np.arange(3)}))
    elif kind == "foreign npz":
        with open(path, "wb") as handle:
            np.savez(handle, t=np.arange(3.0), depth="x", method=np.array([1, 2]))
    elif kind == "empty":
        with zipfile.ZipFile(path, "w"):
            pass
    else:
        path.mkdir()

    def load():
        return mv.Result.load(path)

    def from_store():
        store = Store(tmp_path / "store")
        key = "0" * 64
        target = store.file(key)
        if path.is_dir():
            target.mkdir(exist_ok=True)
        else:
            target.write_bytes(path.read_bytes())
        return store.load(key)

    outcome("Result.load", load)
    outcome("Store.load", from_store)


@FUZZ
@given(
    shape=mostly(st.sampled_from([(8, 8), (16, 4), (1, 32), (3, 5)]),
                 st.one_of(st.tuples(NUMBERS, NUMBERS), NUMBERS, st.just((8192, 8193)))),
    dx=mostly(PLAUSIBLE),
    hurst=mostly(st.floats(0.05, 0.95)),
    rms=mostly(PLAUSIBLE),
    which=st.sampled_from(["rms_slope", "rms_height", "both", "neither"]),
    rolloff=mostly(st.none()),
    short_cutoff=mostly(st.none()),
    seed=mostly(st.integers(0, 2**64 - 1), st.one_of(NUMBERS, st.just(2**64), st.just(-1))),
)
def test_self_affine(shape, dx, hurst, rms, which, rolloff, short_cutoff, seed):
    def run():
        scale = {"rms_slope": {"rms_slope": rms}, "rms_height": {"rms_height": rms},
                 "both": {"rms_slope": rms, "rms_height": rms}, "neither": {}}[which]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", mv.ResolutionWarning)
            return mv.surfaces.self_affine(shape, dx, hurst, rolloff=rolloff, short_cutoff=short_cutoff,
                                           seed=seed, **scale)

    outcome("surfaces.self_affine", run)


@FUZZ
@given(kind=mostly(st.integers(1, 6), ARRAYS), shape=st.sampled_from([(6, 6), (1, 8), (8, 1), (2, 2)]),
       dx=mostly(PLAUSIBLE))
def test_psd(kind, shape, dx):
    def run():
        q, c = mv.surfaces.psd(hostile_array(kind, shape), dx)
        return np.concatenate([q, c])

    outcome("surfaces.psd", run)


BAD_CSV = st.one_of(
    st.text(max_size=200),
    st.sampled_from([
        "",
        "t,depth,force\n",
        "t;depth;force\n0.1;1e-7;1e-9\n",
        "t,depth,force\n0.1,1e-7\n",
        "t,depth,force\n0.1,1e-7,1e-9,4\n",
        "t,depth,force\nnan,inf,-inf\n",
        "t,t,t\n1,2,3\n",
        "\ufefft,depth,force\n0.1,1e-7,1e-9\n0.2,2e-7,2e-9\n0.3,3e-7,3e-9\n",
        "t,piezo,deflection\n0.1,1e-7,1e-9\n",
        "t,depth,force,weight\n0.1,1e-7,1e-9,-1\n0.2,2e-7,2e-9,1\n",
    ]),
)
SWEEP_TAIL = st.sampled_from([
    "",
    "[sweep]\n",
    "[sweep.axes]\n",
    "[sweep]\nmode = \"grid\"\n[sweep.axes]\nforce = [1, 2]\n",
    "[sweep.axes]\nforce = []\n",
    "[sweep.axes]\nnope = [1, 2]\n",
    "[sweep.axes]\nforce = [1, nan]\n",
    "[sweep.axes]\n\"medium.tau1\" = [0.5, -1]\n",
    "[sweep.axes]\nforce = 3\n",
])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=BAD_CSV, model=st.sampled_from(["elastic", "standardsolid", "nope"]),
       indenter=st.sampled_from(["sphere:radius=5e-6", "sphere:r=5e-6", "rod:radius=1e-6", "blob:x=1",
                                 "cone"]),
       extra=st.sampled_from([(), ("--spring-constant", "0.1"), ("--terms", "100000"),
                              ("--control", "force")]))
def test_python_command_line_fit(tmp_path, text, model, indenter, extra):
    path = tmp_path / "curve.csv"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")

    def run():
        status = cli.main(["fit", str(path), "--indenter", indenter, "--model", model, *extra])
        if status == 2:
            raise mv.InvalidInputError("exit status 2")
        if status != 0:
            raise AssertionError(f"exit status {status}")
        return 0.0

    outcome("command line fit (Python)", run)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(head=st.one_of(BAD_TOML, st.just('method = "mdr"\nn = 101\nforce = 1\nduration = 1\ntimes = [1]\n'
                                        '[indenter]\ntype = "paraboloid"\nc = 1\n'
                                        '[medium]\ntype = "standardsolid"\nG_inf = 1\nG1 = 1\ntau1 = 1\n')),
       tail=SWEEP_TAIL, out=st.sampled_from([None, "t.csv", "t.json", "t.txt"]))
def test_python_command_line_sweep(tmp_path, head, tail, out):
    path = tmp_path / "sweep.toml"
    path.write_text(head + tail, encoding="utf-8", errors="surrogatepass")

    def run():
        argv = ["sweep", str(path), "--no-progress"] + ([] if out is None else ["--out", str(tmp_path / out)])
        status = cli.main(argv)
        if status == 2:
            raise mv.InvalidInputError("exit status 2")
        if status != 0:
            raise AssertionError(f"exit status {status}")
        return 0.0

    outcome("command line sweep (Python)", run)
