"""Memory of a run against its estimate: the peak every BEM run checks before it allocates
(``mdrvisc._core.run_memory``, the same function ``mv.solve`` calls) against the peak it
reaches, for static rough contact (free and periodic; nested grids, and single-level with
``--single``), viscoelastic rough creep and viscous stepping.

Each case runs in a fresh subprocess: the scene is built (the rough benchmark's self-affine
surface, ``bench_rough.self_affine``, H 0.8, ~5 % contact under the force), then the
resident peak is reset (``/proc/self/clear_refs``), the run made through ``mv.solve`` and the
resident peak read (``VmHWM``); "measured" is that peak minus the resident size just before
the run, so it counts everything the run allocates, the result's arrays included, and not
the interpreter, numpy or the scene. Linux only.

Cases: ``static`` (``mv.HeightMap`` under a force, outputs pressure, tol ``--tol``), ``creep``
(the same map on a standard solid, ``--steps`` steps, pressure fields at two times),
``viscous`` (the paper's paraboloid on a viscous half-space, fields at the default times).
Run: ``python benchmarks/bench_memory.py`` (256^2 to 1024^2), ``--sizes 2048 4096``,
``--kinds static``, ``--modes free``. The estimate must be within 20 % of the measured peak.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent


def status(key: str) -> int:
    """A "Key: N kB" value of /proc/self/status, in bytes."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key):
                return int(line.split()[1]) * 1024
    raise SystemExit(f"no {key} in /proc/self/status")


def scene_of(kind: str, mode: str, n: int, steps: int):
    """The case's scene (see the module's docstring)."""
    import mdrvisc as mv
    from bench_rough import self_affine

    periodic = mode == "periodic"
    if kind == "viscous":
        return mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.Viscous(1.0), force=1.0,
                        duration=2.0, outputs=("depth", "pressure"))
    z = self_affine(n, 7, 0.8, 128 if n > 256 else 64)
    hm = mv.HeightMap(z, 1.0 / n, periodic=periodic)
    del z
    # ~5 % contact: mean pressure ~ fraction E* rms slope / 2 (E* = 4 Pa, slope 0.1)
    force = 0.05 * 4.0 * 0.1 / 2.0
    if kind == "static":
        return mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=force, outputs=("pressure",))
    return mv.Scene(indenter=hm, medium=mv.StandardSolid(1.0, 3.0, 1.0), force=force, duration=2.0,
                    times=[1.0, 2.0], dt=2.0 / steps, outputs=("pressure",), field_times=[1.0, 2.0])


def one(kind: str, mode: str, n: int, tol: float, steps: int, single: bool) -> dict:
    """Runs one case in this process; returns its numbers."""
    import gc

    import mdrvisc as mv
    from mdrvisc import _core

    sys.path.insert(0, str(HERE))
    scene = scene_of(kind, mode, n, steps)
    estimate = _core.run_memory(scene._model, "bem", n, precondition=not single)
    gc.collect()
    base = status("VmRSS:")
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mv.ResolutionWarning)
        if single:
            # no preconditioner: no nested coarse levels either
            r = _core.run_scene(scene._model, "bem", n, tol=tol, precondition=False)
        else:
            r = mv.solve(scene, "bem", n, tol=tol, max_iter=100000)
    measured = status("VmHWM:") - base
    del r
    return dict(kind=kind, mode=mode, n=n, single=single, estimate=estimate, measured=measured)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    ap.add_argument("--kinds", nargs="+", default=["static", "creep", "viscous"])
    ap.add_argument("--modes", nargs="+", default=["free", "periodic"])
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--single", action="store_true", help="also static single-level solves")
    ap.add_argument("--one", nargs=3, metavar=("KIND", "MODE", "N"), help=argparse.SUPPRESS)
    ap.add_argument("--single-level", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        kind, mode, n = args.one
        print(json.dumps(one(kind, mode, int(n), args.tol, args.steps, args.single_level)))
        return
    cases = []
    for kind in args.kinds:
        for mode in (["free"] if kind == "viscous" else args.modes):
            for n in args.sizes:
                n = n + 1 if kind == "viscous" else n
                cases.append((kind, mode, n, False))
                if args.single and kind == "static":
                    cases.append((kind, mode, n, True))
    print(f"{'n':>6} {'kind':>8} {'mode':>9} {'levels':>7} {'estimate MB':>12} {'measured MB':>12} "
          f"{'ratio':>6}")
    for kind, mode, n, single in cases:
        cmd = [sys.executable, __file__, "--one", kind, mode, str(n), "--tol", repr(args.tol),
               "--steps", str(args.steps)] + (["--single-level"] if single else [])
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            print(f"{n:>6} {kind:>8} {mode:>9}: failed: {out.stderr.strip().splitlines()[-1:]}")
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{n:>6} {kind:>8} {mode:>9} {'single' if single else 'nested':>7} "
              f"{r['estimate'] / 1e6:12.1f} {r['measured'] / 1e6:12.1f} "
              f"{r['estimate'] / r['measured']:6.2f}", flush=True)


if __name__ == "__main__":
    main()
