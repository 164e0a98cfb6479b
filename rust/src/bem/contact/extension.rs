//! The contact set's residual continued onto a band around the set, so that the
//! preconditioner acts on a field without jumps at the edges of the contact patches.
//!
//! The preconditioner S (dx times the operator's inverse on the whole plane, the "|q|"
//! symbol, `SurfaceOperator::precondition`) stands in for the inverse of the operator
//! restricted to the contact set. Applied to a residual cut to zero off the set, S sees a
//! jump at every patch edge, which |q| amplifies: a few of the preconditioned operator's
//! eigenvalues stand far above the rest (median 1.01, 99th percentile 2.1, largest 5 at
//! 256^2), and its condition number grows with the grid (about 3 at 128^2 and 5 at 256^2
//! on rough surfaces at 5 % contact), so the conjugate gradients converge at about 0.45 per
//! iteration at 512^2. The residual of the set is the deflection
//! of a pressure error on the set, which continues smoothly beyond it. So the solver
//! preconditions by E^T S E instead: E continues a field on the set to the elements within
//! `RADIUS` of it, each taking the value of its nearest set element (Euclidean) times
//! exp(-d / `DECAY`), d the distance in elements; E^T, its transpose, adds those elements'
//! values back to their nearest set elements with the same weights, which keeps the
//! preconditioner symmetric (the one-sided S E needed as many iterations as S or more). On
//! the fixed contact sets of `benchmarks/bench_rough.py`'s surfaces (periodic cells, H 0.3
//! at 2 % and H 0.8 at 5 % contact), conjugate gradients to 1e-8 took 14 instead of 22
//! iterations at 512^2 and 17 instead of 24 at 1024^2 (a decay length of 2 elements did
//! best among 1 to 6, and a band of 3 elements nearly as well as 6). In the nested solves
//! of those surfaces the finest level takes 18-25 instead of 24-31 iterations at 512^2.
//! The band is found again only after a tenth of the set has changed (`STALE_SHARE`), and
//! `Tuning::residual_band` says on which grids it is used. The band is held per block of
//! rows as lists of its elements, so that the search and both passes run on the blocks in
//! parallel (E^T in phases of blocks that reach no common row): at 512^2 they cost a search
//! of about 1 ms (a grid's two row sweeps and seven-row minima) every few iterations and
//! passes of 0.1-0.2 ms, against about 1 ms for S's FFT pair.

use super::{ContactSolver, ResidualBand};
use crate::halfspace::operator::SurfaceOperator;
use rayon::prelude::*;

/// Largest distance (elements) of a band element from its nearest set element.
pub const RADIUS: usize = 3;

/// Decay length (elements) of the continuation's weight exp(-d / DECAY).
pub const DECAY: f64 = 2.0;

/// Marks an element with no set element within `RADIUS` in its row.
const NONE: i8 = i8::MIN;

/// Share of the contact set that may have entered or left it before the band is found
/// anew: a band a few elements off costs the preconditioner little, a search about as
/// much as the preconditioner's FFT pair (1-1.8 ms against 0.9-1.2 ms on a 512^2 cell; 0.05
/// to 0.4 of the set did no better).
const STALE_SHARE: f64 = 0.1;

/// A squared row offset beyond `RADIUS` (and `NONE`'s), small enough that keys fit i16.
const OUT_OF_REACH: i16 = 64;

/// Rows of the grid per block of the band (a parallel task of its search and passes); at
/// least 2 `RADIUS` + 1, so that blocks two apart never reach the same row.
const ROWS_PER_TASK: usize = 16;

/// exp(-d / `DECAY`) for each squared distance d^2 within `RADIUS`, made once.
static WEIGHTS: std::sync::LazyLock<[f64; RADIUS * RADIUS + 1]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|d2| (-(d2 as f64).sqrt() / DECAY).exp()));

/// The band elements of one block of rows: elements off a contact set, each with its
/// nearest set element and their squared distance.
#[derive(Default)]
struct Band {
    /// Band elements: off the set, within `RADIUS` of it, in element order.
    element: Vec<u32>,
    /// The nearest set element of each band element.
    nearest: Vec<u32>,
    /// The squared distance (elements^2) of each band element from its nearest.
    dist2: Vec<u8>,
}

impl Band {
    /// The entries still off the set {p > 0} (a band found for an earlier set may hold
    /// elements that entered it since): (element, nearest set element, squared distance).
    fn entries<'a>(&'a self, p: &'a [f64]) -> impl Iterator<Item = (usize, usize, usize)> + 'a {
        self.element
            .iter()
            .zip(&self.nearest)
            .zip(&self.dist2)
            .map(|((&b, &s), &d2)| (b as usize, s as usize, d2 as usize))
            .filter(move |&(b, _, _)| p[b] <= 0.0)
    }
}

/// The band around a contact set and the weights of the continuation onto it, by blocks of
/// `ROWS_PER_TASK` rows.
#[derive(Default)]
pub(super) struct Extension {
    /// The band of the set it was last found for, per block of rows.
    blocks: Vec<Band>,
    /// Per element, the column offset of the nearest set element in its own row within
    /// `RADIUS`, or `NONE`.
    row_nearest: Vec<i8>,
    /// Elements that entered or left the set since the band was found.
    stale: f64,
    /// Whether the grid of the last search wraps around its edges.
    periodic: bool,
}

/// Raw access to a grid's buffer for the band's parallel passes, whose workers write
/// disjoint elements and read none that another writes (`Extension::extend`, `fold`).
#[derive(Clone, Copy)]
struct Shared(*mut f64);

// SAFETY: only used inside `Extension::extend` and `Extension::fold`, while the buffer is
// exclusively borrowed by them; their workers touch disjoint elements (see there).
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}

impl Extension {
    /// Memory (bytes per element) the band may hold at most: an element index, its nearest
    /// set element and a squared distance per band element, and the row offsets.
    pub const BYTES_PER_ELEMENT: f64 = 10.0;

    /// Finds the band around the set {p > 0} of an `nx` x `ny` grid (row-major), wrapping
    /// around the edges where `periodic`: per row, the nearest set element in the row (two
    /// sweeps), then per element the least squared distance over the 2 `RADIUS` + 1 rows
    /// around it, in loops of selects; blocks of rows in parallel.
    pub fn rebuild(&mut self, p: &[f64], nx: usize, ny: usize, periodic: bool) {
        let r = RADIUS as isize;
        self.periodic = periodic;
        self.row_nearest.resize(nx * ny, NONE);
        self.row_nearest
            .par_chunks_mut(nx)
            .zip(p.par_chunks(nx))
            .with_min_len(ROWS_PER_TASK)
            .for_each(|(row, line)| nearest_in_row(line, row, periodic));
        self.blocks
            .resize_with(ny.div_ceil(ROWS_PER_TASK), Band::default);
        let row_nearest = &self.row_nearest;
        self.blocks
            .par_iter_mut()
            .enumerate()
            .for_each(|(b, band)| {
                band.element.clear();
                band.nearest.clear();
                band.dist2.clear();
                // per element of the row, the least key (d^2 * 16 + dy + RADIUS) over the rows
                // within reach: the nearest set element first, then the lowest row
                let mut least = vec![0i16; nx];
                for y in b * ROWS_PER_TASK..((b + 1) * ROWS_PER_TASK).min(ny) {
                    least.fill(i16::MAX);
                    for dy in -r..=r {
                        let Some(yy) = wrap(y as isize + dy, ny, periodic) else {
                            continue;
                        };
                        let row = &row_nearest[yy * nx..(yy + 1) * nx];
                        let (dy2, code) = ((dy * dy) as i16, (dy + r) as i16);
                        for (l, &o) in least.iter_mut().zip(row) {
                            // NONE (squared 16384) is capped beyond reach
                            let o2 = (o as i16 * o as i16).min(OUT_OF_REACH);
                            *l = (*l).min((o2 + dy2) * 16 + code);
                        }
                    }
                    let line = &p[y * nx..(y + 1) * nx];
                    for x in 0..nx {
                        let d2 = (least[x] / 16) as usize;
                        if d2 > RADIUS * RADIUS || line[x] > 0.0 {
                            continue;
                        }
                        let dy = (least[x] % 16) as isize - r;
                        let yy = wrap(y as isize + dy, ny, periodic).expect("a row within reach");
                        let o = row_nearest[yy * nx + x];
                        let xx = wrap(x as isize + o as isize, nx, periodic)
                            .expect("an offset within the row");
                        band.element.push((y * nx + x) as u32);
                        band.nearest.push((yy * nx + xx) as u32);
                        band.dist2.push(d2 as u8);
                    }
                }
            });
    }

    /// Runs `task` on each block of the band: all in parallel where `disjoint` (each task
    /// writes its own block's elements only); otherwise in phases whose tasks write rows no
    /// other task of the phase reaches: odd blocks, even blocks, then on a periodic grid
    /// the first block alone (which the last reaches round the edge).
    fn for_blocks(&self, disjoint: bool, task: impl Fn(&Band) + Sync + Send) {
        if disjoint {
            self.blocks.par_iter().for_each(task);
            return;
        }
        let phase = |b: usize| if b == 0 && self.periodic { 2 } else { b % 2 };
        for k in 0..3 {
            self.blocks
                .par_iter()
                .enumerate()
                .filter(|&(b, _)| phase(b) == k)
                .for_each(|(_, band)| task(band));
        }
    }

    /// Continues `g` (zero off the set {p > 0}) onto the band: E g. A block's worker
    /// writes its band elements still off the set, and reads their nearest set elements
    /// of the last search, which are in no band, so no element is read and written by
    /// different workers.
    pub fn extend(&self, p: &[f64], g: &mut [f64]) {
        let weights = &*WEIGHTS;
        let shared = Shared(g.as_mut_ptr());
        self.for_blocks(true, |band| {
            let g = shared;
            for (b, s, d2) in band.entries(p) {
                // SAFETY: b is written by this worker alone, s (in no band) by none.
                unsafe { *g.0.add(b) = weights[d2] * *g.0.add(s) };
            }
        });
    }

    /// Adds the band's values of `z` to their nearest set elements, weighted: E^T z on the
    /// set (`z` off the set is left as it was), and sets `g` back to zero on the band. A
    /// block's worker writes the set elements within `RADIUS` rows of its block, which the
    /// phases of `for_blocks` keep apart from those of the workers that run with it; band
    /// elements, which it reads, are never written in `z`.
    pub fn fold(&self, p: &[f64], z: &mut [f64], g: &mut [f64]) {
        let weights = &*WEIGHTS;
        let (zs, gs) = (Shared(z.as_mut_ptr()), Shared(g.as_mut_ptr()));
        self.for_blocks(false, |band| {
            let (z, g) = (zs, gs);
            for (b, s, d2) in band.entries(p) {
                // SAFETY: s is written by no other worker of this phase, b (a band element)
                // by none in z and by this worker alone in g.
                unsafe {
                    *z.0.add(s) += weights[d2] * *z.0.add(b);
                    *g.0.add(b) = 0.0;
                }
            }
        });
    }
}

/// `v` as an index into 0..n, wrapped round the edge where `periodic`; None off a grid
/// that does not wrap.
fn wrap(v: isize, n: usize, periodic: bool) -> Option<usize> {
    if (0..n as isize).contains(&v) {
        Some(v as usize)
    } else if periodic {
        Some(v.rem_euclid(n as isize) as usize)
    } else {
        None
    }
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// z = E^T S E g on the contact set {p > 0} of `set_count` elements (S the operator's
    /// preconditioner, g zero off the set and left so), or S g where the tuning's
    /// `residual_band` leaves the grid out. `changes` elements entered or left
    /// the set since the last call (infinite: the set is new, as at a solve's first
    /// iteration, so no band of an earlier solve or window is used); the band is found anew
    /// once those since the last search exceed `STALE_SHARE` of the set, and until then the
    /// old band serves, less the elements that entered the set.
    pub(super) fn precondition_on_set(&mut self, changes: f64, set_count: f64) {
        let (nx, ny, periodic) = (self.op.nx(), self.op.ny(), self.op.periodic());
        let band = match self.tuning.residual_band {
            ResidualBand::Off => false,
            ResidualBand::Free => !periodic,
            ResidualBand::Everywhere => true,
        };
        if !band {
            self.op.precondition(&self.g, &mut self.z);
            return;
        }
        let ext = &mut self.extension;
        ext.stale += changes;
        if ext.stale > STALE_SHARE * set_count {
            ext.rebuild(&self.p, nx, ny, periodic);
            ext.stale = 0.0;
        }
        ext.extend(&self.p, &mut self.g);
        self.op.precondition(&self.g, &mut self.z);
        self.extension.fold(&self.p, &mut self.z, &mut self.g);
    }
}

/// Writes into `out` the offset to the nearest element of the row `line` with p > 0
/// within `RADIUS` (the left one on a tie), or `NONE`; the row wraps where `periodic`. Two
/// sweeps of selects, the positions of the last set element seen before and after the row
/// (wrapped) standing in at its ends.
fn nearest_in_row(line: &[f64], out: &mut [i8], periodic: bool) {
    let n = line.len() as isize;
    let r = RADIUS as isize;
    // beyond reach of every element of the row
    let far = n + 2 * r + 1;
    let reach = r.min(n);
    let before = (n - reach..n)
        .rev()
        .find(|&k| periodic && line[k as usize] > 0.0)
        .map_or(-far, |k| k - n);
    let after = (0..reach)
        .find(|&k| periodic && line[k as usize] > 0.0)
        .map_or(2 * far, |k| k + n);
    let mut last = before;
    for (k, (o, &v)) in out.iter_mut().zip(line).enumerate() {
        let k = k as isize;
        last = if v > 0.0 { k } else { last };
        *o = if k - last <= r {
            (last - k) as i8
        } else {
            NONE
        };
    }
    let mut next = after;
    for (k, (o, &v)) in out.iter_mut().zip(line).enumerate().rev() {
        let k = k as isize;
        next = if v > 0.0 { k } else { next };
        let d = next - k;
        // NONE (-128) counts as farther than any offset within reach
        *o = if d <= r && d < -(*o as isize) {
            d as i8
        } else {
            *o
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bem::contact::tests::{polonsky_keer_only, rough_separation, solved};

    /// Every band element's nearest set element is, by brute force over the grid, at the
    /// least distance (with wrap on a periodic grid), within `RADIUS`, and every element
    /// within `RADIUS` of the set is in the band; E g and E^T y equal their sums element by
    /// element (to round-off), on grids of one to four row blocks (the parallel passes' phases,
    /// with a short last block), and <E g, y> = <g, E^T y> for g on the set and y off it.
    #[test]
    fn band_holds_the_nearest_set_elements_and_fold_is_the_transpose() {
        let weights = &*WEIGHTS;
        for (nx, ny) in [(23, 17), (29, 49), (31, 50), (12, 64), (9, 5)] {
            // a few scattered elements and patches, the same on every run
            let p: Vec<f64> = (0..nx * ny)
                .map(|i| {
                    let (x, y) = (i % nx, i / nx);
                    let patch = (x + 3 * y) % 11 < 2 && (y / 4) % 3 == 1;
                    let scattered = (i * 2654435761) % 97 < 3;
                    if patch || scattered || i == 0 {
                        1.0
                    } else {
                        0.0
                    }
                })
                .collect();
            for periodic in [false, true] {
                let case = format!("{nx}x{ny} periodic {periodic}");
                let mut e = Extension::default();
                e.rebuild(&p, nx, ny, periodic);
                let dist2 = |a: usize, b: usize| {
                    let d = |u: usize, v: usize, n: usize| {
                        let d = u.abs_diff(v);
                        if periodic {
                            d.min(n - d)
                        } else {
                            d
                        }
                    };
                    let (dx, dy) = (d(a % nx, b % nx, nx), d(a / nx, b / nx, ny));
                    dx * dx + dy * dy
                };
                let set: Vec<usize> = (0..nx * ny).filter(|&i| p[i] > 0.0).collect();
                let g: Vec<f64> = (0..nx * ny)
                    .map(|i| {
                        if p[i] > 0.0 {
                            1.0 + (i % 7) as f64
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let y: Vec<f64> = (0..nx * ny)
                    .map(|i| {
                        if p[i] > 0.0 {
                            0.0
                        } else {
                            0.5 + (i % 5) as f64
                        }
                    })
                    .collect();
                let (mut eg_ref, mut ety_ref) = (g.clone(), y.clone());
                for i in (0..nx * ny).filter(|&i| p[i] <= 0.0) {
                    let least = set.iter().map(|&s| dist2(i, s)).min().unwrap();
                    let band = &e.blocks[i / nx / ROWS_PER_TASK];
                    let k = band.element.iter().position(|&b| b as usize == i);
                    if least > RADIUS * RADIUS {
                        assert!(k.is_none(), "{case}: {i} is in the band");
                        continue;
                    }
                    let k = k.unwrap_or_else(|| panic!("{case}: {i} is not in the band"));
                    let s = band.nearest[k] as usize;
                    assert!(p[s] > 0.0);
                    assert_eq!(dist2(i, s), least, "{case}: {i}");
                    let w = (-(least as f64).sqrt() / DECAY).exp();
                    assert!((weights[band.dist2[k] as usize] - w).abs() <= 1e-15);
                    eg_ref[i] = w * g[s];
                    ety_ref[s] += w * y[i];
                }
                let mut eg = g.clone();
                e.extend(&p, &mut eg);
                let (mut ety, mut cleared) = (y.clone(), eg.clone());
                e.fold(&p, &mut ety, &mut cleared);
                assert_eq!(eg, eg_ref, "{case}");
                // the same sums, added in the phases' order
                for (a, b) in ety.iter().zip(&ety_ref) {
                    assert!((a - b).abs() <= 1e-14 * b.abs(), "{case}: {a} {b}");
                }
                let lhs: f64 = eg.iter().zip(&y).map(|(a, b)| a * b).sum();
                let rhs: f64 = set.iter().map(|&i| g[i] * ety[i]).sum();
                assert!(
                    (lhs - rhs).abs() <= 1e-12 * lhs.abs(),
                    "{case}: {lhs} {rhs}"
                );
                assert_eq!(cleared, g, "{case}");
            }
        }
    }

    /// Polonsky–Keer on a rough surface (self-affine, H 0.8, 2-20 % contact): with the
    /// residual band the free grid and the periodic cell reach the same contact as without,
    /// to the tolerance, in fewer iterations.
    #[test]
    fn the_band_keeps_the_contact_and_saves_iterations() {
        use crate::bem::contact::{Target, Tuning};
        use crate::halfspace::operator::FftOperator;
        use crate::halfspace::periodic::PeriodicOperator;

        let (n, dx) = (128, 1.0 / 128.0);
        let h = rough_separation(n, dx, 0.8, 7);
        let opts = polonsky_keer_only();
        for fraction in [0.02, 0.2] {
            // mean pressure fraction * E* rms slope / 2 (E* = 4 at G = 1)
            let target = Target::Force(fraction * 0.2 * (n as f64 * dx).powi(2));
            let run = |band, periodic: bool| {
                let tuning = Tuning {
                    residual_band: band,
                    ..Tuning::default()
                };
                if periodic {
                    let op = PeriodicOperator::new(n, n, dx).unwrap();
                    solved(ContactSolver::with_tuning(op, tuning), &h, target, &opts)
                } else {
                    let op = FftOperator::new(n, n, dx).unwrap();
                    solved(ContactSolver::with_tuning(op, tuning), &h, target, &opts)
                }
            };
            for (band, periodic) in [
                (ResidualBand::Free, false),
                (ResidualBand::Everywhere, true),
            ] {
                let ((plain, p_plain), (banded, p_band)) =
                    (run(ResidualBand::Off, periodic), run(band, periodic));
                let peak = p_plain.iter().fold(0.0f64, |m, &v| m.max(v));
                let diff = p_plain
                    .iter()
                    .zip(&p_band)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(
                    diff < 1e-8 * peak,
                    "{fraction} {periodic}: {diff} vs {peak}"
                );
                assert_eq!(
                    plain.contact_count, banded.contact_count,
                    "{fraction} {periodic}"
                );
                assert!(
                    banded.iterations < plain.iterations,
                    "{fraction} {periodic}: {} with the band, {} without",
                    banded.iterations,
                    plain.iterations
                );
            }
        }
    }

    /// A periodic cell's rough contact with the band (its fold in phases, the first block
    /// alone, the last reaching round the edge) repeats bit for bit on 1, 2 and 3 threads.
    #[test]
    fn a_banded_cell_repeats_bit_for_bit_across_thread_counts() {
        use crate::bem::contact::{Target, Tuning};
        use crate::halfspace::periodic::PeriodicOperator;

        // 100 rows: seven blocks, the last one short
        let (n, dx) = (100, 1.0 / 100.0);
        let h = rough_separation(n, dx, 0.5, 11);
        let opts = polonsky_keer_only();
        let target = Target::Force(0.05 * 0.2 * (n as f64 * dx).powi(2));
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let tuning = Tuning {
                    residual_band: ResidualBand::Everywhere,
                    ..Tuning::default()
                };
                let op = PeriodicOperator::new(n, n, dx).unwrap();
                solved(ContactSolver::with_tuning(op, tuning), &h, target, &opts)
            })
        };
        let (one, p_one) = run(1);
        let count = p_one.iter().filter(|&&p| p > 0.0).count();
        assert!(count > 100, "{count} elements in contact");
        for threads in [2, 3] {
            let (s, p) = run(threads);
            let same = p
                .iter()
                .zip(&p_one)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{threads} threads");
            assert_eq!(s.iterations, one.iterations, "{threads} threads");
        }
    }
}
