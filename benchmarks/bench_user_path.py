"""Representative solves through the path users take (``mv.Scene`` + ``mv.solve``, the
scene's construction included), for comparing two builds of mdrvisc on one machine: run the
script with each build's Python in turn (e.g. a venv of the last release and one of the
working tree) and compare the tables. The last column is a number each solve returns (a
depth in m, or the iteration count of a rough solve), which two builds that compute the
same thing print to the last digit.

Rows: the paper's paraboloid (viscous, BEM 257 and MDR 66049), a standard solid under a
step force (BEM 65 and MDR 20001, 500 steps each), and an elastic self-affine rough surface
(H = 0.8, rms height 1 mm on a 1 m cell, about 5 % contact) at 512^2 and 1024^2, free and
periodic, at the solver's default tolerance. Each time is the best of ``--repeats`` runs.
Run: ``python benchmarks/bench_user_path.py [--repeats 3] [--rough 512 1024]``.
"""

from __future__ import annotations

import argparse
import warnings

import mdrvisc as mv
from _bench import best_of, header, table

PARABOLOID = mv.Paraboloid(c=1.0, edge=2.56)


def paper(method: str, n: int) -> float:
    scene = mv.Scene(indenter=PARABOLOID, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0)
    return float(mv.solve(scene, method, n).depth[-1])


def standard_solid(method: str, n: int) -> float:
    scene = mv.Scene(indenter=PARABOLOID, medium=mv.StandardSolid(1.0, 3.0, 0.5), force=1.0,
                     duration=2.0)
    return float(mv.solve(scene, method, n).depth[-1])


def rough(heights, n: int, periodic: bool) -> int:
    scene = mv.Scene(indenter=mv.HeightMap(heights, dx=1.0 / n, periodic=periodic),
                     medium=mv.Elastic(G=1.0), force=5e-3)
    return int(mv.solve(scene, "bem").iterations)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--rough", type=int, nargs="*", default=[512, 1024],
                        help="sides of the rough maps (default 512 1024)")
    args = parser.parse_args()
    header("mdrvisc through mv.Scene + mv.solve")
    cases = {
        "paper paraboloid, viscous, BEM 257": lambda: paper("bem", 257),
        "paper paraboloid, viscous, MDR 66049": lambda: paper("mdr", 66049),
        "standard solid, BEM 65, 500 steps": lambda: standard_solid("bem", 65),
        "standard solid, MDR 20001, 500 steps": lambda: standard_solid("mdr", 20001),
    }
    for n in args.rough:
        heights = mv.surfaces.self_affine((n, n), 1.0 / n, hurst=0.8, rms_height=1e-3, seed=11)
        for periodic in (False, True):
            mode = "periodic" if periodic else "free"
            cases[f"rough {n}^2, {mode}, elastic"] = (
                lambda h=heights, n=n, p=periodic: rough(h, n, p))
    rows = []
    with warnings.catch_warnings():
        # the rough maps' patches are a few elements wide: the resolution warning is expected
        warnings.simplefilter("ignore", mv.ResolutionWarning)
        for name, case in cases.items():
            seconds, value = best_of(case, args.repeats)
            rows.append((name, seconds, value))
    table(["case", "wall [s]", "result"], rows, ["{}", "{:.3f}", "{!r}"])


if __name__ == "__main__":
    main()
