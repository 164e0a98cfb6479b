"""One schema: the outputs, the report's quantities and units, the solver defaults and the
default resolutions are the compiled core's; the Python layer and the stub ``_core.pyi``
repeat them and must agree with it."""

import ast
import dataclasses
import importlib
import inspect
from pathlib import Path

import mdrvisc as mv
from mdrvisc import _core, arrays, many, result, scene

solve_module = importlib.import_module("mdrvisc.solve")

STUB = Path(scene.__file__).with_name("_core.pyi")

#: The keyword arguments of mdrvisc.solve that are solver options of the core.
SOLVE_OPTIONS = ("tol", "max_iter", "integrator", "step", "area_change", "dt")


def stub_defaults(function: str) -> dict:
    """{argument: default} of ``function`` in the stub, for literal defaults."""
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and node.name == function:
            args = node.args.args
            defaults = node.args.defaults
            out = {}
            for arg, default in zip(args[len(args) - len(defaults):], defaults):
                if not (isinstance(default, ast.Constant) and default.value is Ellipsis):
                    out[arg.arg] = ast.literal_eval(default)
            return out
    raise AssertionError(f"{function} is not in the stub")


def test_outputs_are_the_cores():
    names = [name for name, *_ in _core.OUTPUTS]
    assert scene.OUTPUTS == mv.OUTPUTS == tuple(names) and len(set(names)) == len(names)
    assert scene.DEFAULT_OUTPUTS == ("depth", "contact_length")
    assert scene.DEFAULT_OUTPUTS == tuple(name for name, _, _, default, _ in _core.OUTPUTS if default)
    kinds = {name: kind for name, _, kind, _, _ in _core.OUTPUTS}
    assert {kinds[n] for n in ("pressure", "surface_velocity", "deflection", "gap")} == {"field"}
    # every output is a quantity of the report with the same unit
    units = {name: unit for name, unit, _ in _core.QUANTITIES}
    for name, unit, kind, _, _ in _core.OUTPUTS:
        assert units[name] == unit, name
        assert kind == ("field" if name in result._FIELD_NAMES else "series"), name
    # a scene accepts exactly these
    paraboloid = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Viscous(eta=1.0), force=1.0,
                          duration=1.0, outputs=names[:7])
    assert paraboloid.outputs == tuple(names[:7])


def test_result_fields_and_units_are_the_cores():
    kinds = {}
    for name, _, kind in _core.QUANTITIES:
        kinds.setdefault(kind, []).append(name)
    assert result.SERIES == tuple(kinds["series"])
    assert result.SCALARS == tuple(kinds["scalar"])
    assert result.SHAPES == tuple(kinds["shape"])
    assert result._FIELD_NAMES == ("t", *kinds["coordinate"], *kinds["field"])
    assert mv.Result.units == result.UNITS == {n: u for n, u, _ in _core.QUANTITIES if u}
    # the core's report has every series, scalar and shape, and Result takes each
    parameters = inspect.signature(mv.Result).parameters
    report_names = {name for name in dir(_core.Report) if not name.startswith("_")}
    for name in (*kinds["series"], *kinds["scalar"], *kinds["shape"]):
        assert name in report_names and name in parameters, name
    field_names = {name for name in dir(_core.FieldSet) if not name.startswith("_")}
    assert field_names == set(result._FIELD_NAMES)
    assert {f.name for f in dataclasses.fields(mv.Fields)} == field_names


def test_solve_defaults_are_the_cores():
    defaults = _core.SOLVER_DEFAULTS
    signature = inspect.signature(mv.solve).parameters
    for name in SOLVE_OPTIONS:
        assert signature[name].default == defaults[name], name
    assert {k: many.SOLVE_OPTIONS[k] for k in SOLVE_OPTIONS} == {k: defaults[k] for k in SOLVE_OPTIONS}
    assert solve_module.DEFAULT_N == _core.DEFAULT_N == {"bem": 257, "mdr": 66049}
    # the array-level solvers repeat the contact solver's defaults
    for function in (arrays.contact, arrays.viscous):
        params = inspect.signature(function).parameters
        for name in ("tol", "max_iter"):
            if name in params:
                assert params[name].default == defaults[name], (function.__name__, name)


def test_the_stub_repeats_the_cores_defaults():
    # run_scene's defaults are the core's own (the stub may write them as ...)
    stub = stub_defaults("run_scene")
    runtime = inspect.signature(_core.run_scene).parameters
    for name in ("tol", "max_iter", "integrator", "step", "area_change", "dt", "precondition",
                 "dense_limit", "active_limit"):
        if name in stub:
            assert stub[name] == _core.SOLVER_DEFAULTS[name], name
        if runtime[name].default is not Ellipsis:
            assert runtime[name].default == _core.SOLVER_DEFAULTS[name], name
    for function in ("contact_solve", "bem_viscous", "bem_punch"):
        stub = stub_defaults(function)
        for name in ("tol", "max_iter", "precondition"):
            assert stub[name] == _core.SOLVER_DEFAULTS[name], (function, name)
    # the stub declares the schema the module exports
    tree = ast.parse(STUB.read_text())
    declared = {node.target.id for node in tree.body if isinstance(node, ast.AnnAssign)}
    assert {"OUTPUTS", "QUANTITIES", "SOLVER_DEFAULTS", "DEFAULT_N"} <= declared


def test_a_solve_runs_with_the_defaults_the_core_names():
    sc = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.0), medium=mv.Viscous(eta=1.0), force=1.0,
                  duration=1.0, times=[1.0])
    plain = mv.solve(sc, "bem", 17)
    named = mv.solve(sc, "bem", 17, **{k: _core.SOLVER_DEFAULTS[k] for k in SOLVE_OPTIONS})
    assert plain.integrator == _core.SOLVER_DEFAULTS["integrator"]
    assert plain.depth.tolist() == named.depth.tolist() and plain.iterations == named.iterations
