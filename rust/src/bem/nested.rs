//! The levels of a nested solve: a grid coarsened by two, and the pressures carried between
//! a level and the next coarser one (averaged to start a coarse level from a fine start,
//! prolonged to start a finer level from a coarse solution).

use crate::halfspace::influence;
use crate::model::grid::Grid;
use rayon::prelude::*;

/// The smallest side (elements) of a coarse level of a nested solve: below it, a level costs
/// more in set-up than it saves.
pub(super) const NESTED_COARSEST: usize = 128;

/// Relative tolerance of the coarse levels of a nested solve at most: their pressure only
/// starts the next level. On the benchmark's 2048 x 2048 self-affine cell (5 % contact, tol
/// 1e-8) the finest level took 60 iterations from a uniform start, 38–42 from coarse levels
/// solved to 1e-6..1e-3. On held-out self-affine surfaces (Hurst 0.8 at 5 % and 0.3 at 2 %
/// contact, tol 1e-8) up to 2048 x 2048 the finest level took the same iterations (+-2) from
/// coarse levels solved to 1e-2 as to 1e-4 or 1e-8, with half the coarse iterations at 1e-2,
/// but on a free 4096 x 4096 grid 37-38 instead of 35 from 1e-3 or 1e-2, which costs more than
/// the coarse levels save.
pub(super) const NESTED_TOL: f64 = 1e-4;

/// The grid (or periodic cell) `grid` coarsened by two in each direction (heights averaged
/// over 2 x 2 elements, an element allowed where all four are), when its sides are even,
/// their halves at least `NESTED_COARSEST` and some element stays allowed.
pub(super) fn coarsened(grid: &Grid) -> Option<Grid> {
    let (nx, ny) = (grid.nx, grid.ny);
    if nx % 2 != 0 || ny % 2 != 0 || nx.min(ny) / 2 < NESTED_COARSEST {
        return None;
    }
    let (cx, cy) = (nx / 2, ny / 2);
    let coarse = Grid {
        nx: cx,
        ny: cy,
        dx: 2.0 * grid.dx,
        height: averaged(&grid.height, nx),
        allowed: of_children(&grid.allowed, nx, |a, b, c, d| a && b && c && d),
        body: grid.body,
    };
    coarse.allowed.contains(&true).then_some(coarse)
}

/// `f` of the four children (row-major: a pair in each of two rows) of each element of the
/// grid coarsened by two from `fine`, a grid of even sides `nx` wide.
fn of_children<T: Copy + Default>(fine: &[T], nx: usize, f: impl Fn(T, T, T, T) -> T) -> Vec<T> {
    let cx = nx / 2;
    let mut coarse = vec![T::default(); fine.len() / 4];
    for (row, pair) in coarse.chunks_exact_mut(cx).zip(fine.chunks_exact(2 * nx)) {
        let (a, b) = pair.split_at(nx);
        for ((v, a), b) in row.iter_mut().zip(a.chunks_exact(2)).zip(b.chunks_exact(2)) {
            *v = f(a[0], a[1], b[0], b[1]);
        }
    }
    coarse
}

/// The pressure (or height) `fine` of a grid of even sides `nx` wide averaged over each
/// element's four children: its value on the grid coarsened by two (`coarsened`), a
/// pressure with the same force.
pub(super) fn averaged(fine: &[f64], nx: usize) -> Vec<f64> {
    of_children(fine, nx, |a, b, c, d| 0.25 * (a + b + c + d))
}

/// Weight of the redistribution among an edge element's children in [`prolonged`], a
/// fraction of the local equilibrium estimate. On `benchmarks/bench_rough.py`'s surfaces
/// (Hurst 0.3, 0.5, 0.8 at 2, 5 and 20 % contact, tol 1e-8) the levels' iterations, weighted
/// by their cost (a quarter per level down), summed over the nine cases at 512^2 fell from
/// 221 (none) to 208, 206, 205 at 0.25, 0.4, 0.6 (periodic; free: 305 to 275 at 0.4), and on
/// the 1024^2 cells (Hurst 0.8 at 5 %, 0.3 at 2 %, 0.5 at 20 %) from 83 to 76, 76 and 79; on
/// surfaces of another generator (`mv.surfaces.self_affine`, Hurst 0.5 and 0.8) the weight
/// 0.4 cut them by 3.5 % to 14 % at 512^2 and 1024^2, free and periodic. Redistributing in
/// every contact element, not only at patch edges, did as well at 512^2 but cost the 2048^2
/// cell's finest level 3 of its 22 iterations, where the patches span many elements and the
/// pressure varies smoothly across them.
const REDISTRIBUTION: f64 = 0.4;

/// The start (Pa) of a nested solve's level `fine` (sides even; gap = `compliance` u + h -
/// depth, u the deflection at unit compliance) from the pressure `coarse` (Pa) of the level
/// coarsened by two (`coarsened`): each coarse element's pressure P repeated over its four
/// children, except on the edges of the contact patches (a coarse element with pressure with
/// one of its four neighbours without, or, on a grid that does not wrap, on the grid's
/// edge), where the children share 4 P by their heights: a child below the four's mean
/// height by dh (m) takes P + `REDISTRIBUTION` dh / (compliance kappa), none less than zero,
/// the four rescaled to 4 P. kappa = K(0, 0) - K(1, 0) is the deflection of an element under
/// its own unit pressure less its neighbour's (the half-space's coefficients of the
/// element's side, m/Pa at unit compliance; the result is a start, so a layer takes them
/// too), the stiffness of a pressure difference between neighbours. A patch's edge runs
/// through its coarse edge elements, where repeating P puts pressure on children that do not
/// touch: on rough surfaces those were most of the elements the finest level's first
/// iterations released. Every coarse element keeps its force, so the start carries the
/// coarse force.
pub(super) fn prolonged(coarse: &[f64], fine: &Grid, compliance: f64) -> Vec<f64> {
    let (nx, ny, dx, height) = (fine.nx, fine.ny, fine.dx, &fine.height);
    let periodic = fine.body.is_periodic();
    let mut start = refined(coarse, nx, ny);
    let (cx, cy) = (nx / 2, ny / 2);
    let kappa = influence::coefficient(0, 0, dx) - influence::coefficient(1, 0, dx);
    let weight = REDISTRIBUTION / (compliance * kappa);
    // the coarse pressure at (x, y), zero off a grid that does not wrap
    let at = |x: isize, y: isize| {
        let inside = (0..cx as isize).contains(&x) && (0..cy as isize).contains(&y);
        if inside || periodic {
            coarse[y.rem_euclid(cy as isize) as usize * cx + x.rem_euclid(cx as isize) as usize]
        } else {
            0.0
        }
    };
    start
        .par_chunks_exact_mut(2 * nx)
        .enumerate()
        .for_each(|(y, rows)| {
            let (top, bottom) = rows.split_at_mut(nx);
            let heights = &height[2 * y * nx..2 * (y + 1) * nx];
            let (h_top, h_bottom) = heights.split_at(nx);
            for x in 0..cx {
                let p = coarse[y * cx + x];
                let (xi, yi) = (x as isize, y as isize);
                let edge = [(-1, 0), (1, 0), (0, -1), (0, 1)]
                    .iter()
                    .any(|&(ox, oy)| at(xi + ox, yi + oy) <= 0.0);
                if p <= 0.0 || !edge {
                    continue;
                }
                let hs = [
                    h_top[2 * x],
                    h_top[2 * x + 1],
                    h_bottom[2 * x],
                    h_bottom[2 * x + 1],
                ];
                let mean = 0.25 * hs.iter().sum::<f64>();
                let share = hs.map(|h| (p + weight * (mean - h)).max(0.0));
                let sum: f64 = share.iter().sum();
                let [a, b, c, d] = share.map(|s| 4.0 * p * s / sum);
                top[2 * x..2 * x + 2].copy_from_slice(&[a, b]);
                bottom[2 * x..2 * x + 2].copy_from_slice(&[c, d]);
            }
        });
    start
}

/// The pressure (Pa) of a cell coarsened by two repeated over each element's four children
/// on the `nx` x `ny` cell (sides even).
fn refined(coarse: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    let cx = nx / 2;
    let mut fine = vec![0.0; nx * ny];
    for (iy, row) in fine.chunks_exact_mut(nx).enumerate() {
        let from = &coarse[(iy / 2) * cx..(iy / 2 + 1) * cx];
        for (pair, &v) in row.chunks_exact_mut(2).zip(from) {
            pair.fill(v);
        }
    }
    fine
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bem::contact::tests::rough_separation;
    use crate::bem::contact::Target;
    use crate::bem::static_contact::solve_whole;
    use crate::model::body::Body;
    use crate::model::settings::SolverOptions;
    use crate::support::monitor::Silent;

    /// Coarsening averages each element's four children (allowed where all four are) and
    /// refining repeats a coarse element over them, on a grid wider than tall.
    #[test]
    fn coarse_levels_average_and_repeat_the_children() {
        let (nx, ny) = (2 * NESTED_COARSEST + 6, 2 * NESTED_COARSEST);
        let value = |i: usize| ((i * 7919) % 1013) as f64 / 1013.0;
        let height: Vec<f64> = (0..nx * ny).map(value).collect();
        let allowed: Vec<bool> = (0..nx * ny).map(|i| i % 37 != 5).collect();
        let grid = Grid::new(nx, ny, 0.1, height.clone(), allowed.clone()).unwrap();
        let coarse = coarsened(&grid).unwrap();
        let (cx, cy) = (nx / 2, ny / 2);
        assert_eq!((coarse.nx, coarse.ny, coarse.dx), (cx, cy, 0.2));
        for j in 0..cx * cy {
            let c = (2 * (j / cx)) * nx + 2 * (j % cx);
            let children = [c, c + 1, c + nx, c + nx + 1];
            let mean = 0.25 * children.iter().map(|&k| height[k]).sum::<f64>();
            assert_eq!(coarse.height[j], mean, "{j}");
            assert_eq!(
                coarse.allowed[j],
                children.iter().all(|&k| allowed[k]),
                "{j}"
            );
        }
        let fine = refined(&coarse.height, nx, ny);
        for (i, v) in fine.iter().enumerate() {
            assert_eq!(*v, coarse.height[(i / nx / 2) * cx + (i % nx) / 2], "{i}");
        }
    }

    /// On a 10 x 8 coarse grid with a 3 x 3 patch, a lone element and a patch across the
    /// grid's corner: every coarse element keeps its force over its children, none is
    /// negative, children of elements without pressure have none, interior elements repeat
    /// their pressure, and at the patches' edges the lower children take more. The corner
    /// patch is interior on a cell whose edges meet and on the edge of a free grid.
    #[test]
    fn prolonged_keeps_each_force_and_shares_it_by_height_at_patch_edges() {
        let (cx, cy) = (10, 8);
        let (nx, ny) = (2 * cx, 2 * cy);
        let mut coarse = vec![0.0; cx * cy];
        for (x, y) in [
            (3, 2),
            (4, 2),
            (5, 2),
            (3, 3),
            (4, 3),
            (5, 3),
            (3, 4),
            (4, 4),
            (5, 4),
        ] {
            coarse[y * cx + x] = 1.0 + 0.1 * x as f64;
        }
        coarse[6 * cx + 8] = 2.0;
        // the corner patch: rows 0, 1 and cy - 1, columns 0, 1 and cx - 1 (wrapped)
        for y in [cy - 1, 0, 1] {
            for x in [cx - 1, 0, 1] {
                coarse[y * cx + x] = 0.5;
            }
        }
        let height: Vec<f64> = (0..nx * ny)
            .map(|i| 1e-3 * (((i * 7919) % 1013) as f64 / 1013.0))
            .collect();
        let free = Grid::new(nx, ny, 0.01, height.clone(), vec![true; nx * ny]).unwrap();
        for periodic in [true, false] {
            let body = if periodic {
                Body::Periodic
            } else {
                Body::HalfSpace
            };
            let grid = Grid {
                body,
                ..free.clone()
            };
            let fine = prolonged(&coarse, &grid, 0.5);
            for y in 0..cy {
                for x in 0..cx {
                    let p = coarse[y * cx + x];
                    let c = 2 * y * nx + 2 * x;
                    let kids = [c, c + 1, c + nx, c + nx + 1];
                    let sum: f64 = kids.iter().map(|&k| fine[k]).sum();
                    assert!((sum - 4.0 * p).abs() <= 1e-12 * p, "({x}, {y}) {sum} {p}");
                    assert!(kids.iter().all(|&k| fine[k] >= 0.0));
                    let interior = (x, y) == (4, 3) || (periodic && (x, y) == (0, 0));
                    if interior {
                        assert!(kids.iter().all(|&k| fine[k] == p), "({x}, {y})");
                    }
                    if p > 0.0 && !interior {
                        for &a in &kids {
                            for &b in &kids {
                                if height[a] < height[b] {
                                    assert!(fine[a] >= fine[b], "({x}, {y})");
                                }
                            }
                        }
                        assert!(kids.iter().any(|&k| fine[k] != p), "({x}, {y})");
                    }
                }
            }
        }
    }

    /// On a rough periodic cell (self-affine, Hurst 0.5, 256^2, about 5 % contact), the
    /// prolonged coarse solution lies nearer the fine solution than the coarse pressure
    /// repeated over the children, in the L1 norm and in the elements given pressure off the
    /// fine contact.
    #[test]
    fn prolonged_starts_nearer_the_fine_solution_than_repeated() {
        let n = 256;
        let dx = 1.0 / n as f64;
        let h = rough_separation(n, dx, 0.5, 11);
        let grid = Grid {
            body: Body::Periodic,
            ..Grid::new(n, n, dx, h, vec![true; n * n]).unwrap()
        };
        let coarse = coarsened(&grid).unwrap();
        let opts = SolverOptions {
            tol: 1e-10,
            precondition: false,
            ..SolverOptions::default()
        };
        // G = 1 Pa: mean pressure 0.01 Pa, about 5 % contact at rms slope 0.1 (2 pbar / (E*
        // slope), E* = 4 Pa)
        let target = Target::Force(0.01);
        let fine = solve_whole(&grid, 1.0, target, false, &opts, &mut Silent).unwrap();
        let coarse = solve_whole(&coarse, 1.0, target, false, &opts, &mut Silent).unwrap();
        let fraction = fine.pressure.iter().filter(|&&p| p > 0.0).count() as f64 / (n * n) as f64;
        assert!((0.02..0.1).contains(&fraction), "{fraction}");
        let distance = |start: &[f64]| -> (f64, usize) {
            let l1 = start
                .iter()
                .zip(&fine.pressure)
                .map(|(a, b)| (a - b).abs())
                .sum();
            let off = start
                .iter()
                .zip(&fine.pressure)
                .filter(|&(&a, &b)| a > 0.0 && b <= 0.0);
            (l1, off.count())
        };
        let (l1_rep, off_rep) = distance(&refined(&coarse.pressure, n, n));
        let start = prolonged(&coarse.pressure, &grid, 1.0);
        let (l1_pro, off_pro) = distance(&start);
        assert!(l1_pro < 0.75 * l1_rep, "{l1_pro} {l1_rep}");
        assert!(off_pro < off_rep, "{off_pro} {off_rep}");
    }
}
