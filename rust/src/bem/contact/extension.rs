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
//! The band is found again after every step that changed the set, and
//! `Tuning::residual_band` says on which grids it is used. The band is held per block of
//! rows as lists of its elements, so that the search and both passes run on the blocks in
//! parallel (E^T in phases of blocks that reach no common row). The search works on the
//! set's bits, 64 elements to a word: the rows' bits widened along the row and combined over
//! the seven rows around each row give the band's words, and each band element takes the
//! first of `OFFSETS` (nearest first) that holds a set element. On the solved contact sets of
//! rough 512^2 cells (H 0.3 and 0.8, 2-20 % contact) it takes 0.35-2.0 ms on one thread, where
//! the search by row sweeps and seven-row minima it replaced took 1.0-2.9 ms for the same
//! band; the passes take 0.1-0.2 ms, against about 1 ms for S's FFT pair. With the older
//! search the band was found again only after a tenth of the set had changed, since a
//! search at every change cost more than the iterations it saved; with this one, on
//! `benchmarks/bench_rough.py`'s cells, a search at every change takes 5-8 % fewer
//! iterations at 512^2 (the finest level 2 fewer at 2048^2 and 4096^2) in the same time
//! (`benchmarks/bench_rough_builds.py`).

use super::{ContactSolver, ResidualBand};
use crate::halfspace::operator::SurfaceOperator;
use rayon::prelude::*;

/// Largest distance (elements) of a band element from its nearest set element.
pub const RADIUS: usize = 3;

/// Decay length (elements) of the continuation's weight exp(-d / DECAY).
pub const DECAY: f64 = 2.0;

/// Rows of the grid per block of the band (a parallel task of its search and passes); at
/// least 2 `RADIUS` + 1, so that blocks two apart never reach the same row.
const ROWS_PER_TASK: usize = 16;

/// The offsets (dy, dx) within `RADIUS` of an element, nearest first, then by row and by
/// column: the first one that holds a set element names the element's nearest.
const OFFSETS: [(isize, isize); 28] = [
    (-1, 0),
    (0, -1),
    (0, 1),
    (1, 0),
    (-1, -1),
    (-1, 1),
    (1, -1),
    (1, 1),
    (-2, 0),
    (0, -2),
    (0, 2),
    (2, 0),
    (-2, -1),
    (-2, 1),
    (-1, -2),
    (-1, 2),
    (1, -2),
    (1, 2),
    (2, -1),
    (2, 1),
    (-2, -2),
    (-2, 2),
    (2, -2),
    (2, 2),
    (-3, 0),
    (0, -3),
    (0, 3),
    (3, 0),
];

const _: () = assert!(
    RADIUS == 3,
    "OFFSETS and the rows widened by 2 and 3 in the band's search are those of RADIUS 3"
);

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
    /// The entries off the set {p > 0} (all of them where the set's changes were counted
    /// in full; a guard, so that the set's own values are never overwritten): (element,
    /// nearest set element, squared distance).
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
    /// The set as bit rows, and those rows widened by `RADIUS` and by 2 elements.
    masks: SetMasks,
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
    /// set element and a squared distance per band element (9), and the set's three bit
    /// rows with their margins (under 0.4).
    pub const BYTES_PER_ELEMENT: f64 = 10.0;

    /// Finds the band around the set {p > 0} of an `nx` x `ny` grid (row-major), wrapping
    /// around the edges where `periodic`: the set's bit rows, widened along the rows and
    /// combined over the 2 `RADIUS` + 1 rows around each row, give the band's elements a word
    /// of 64 at a time; each band element then takes the first of `OFFSETS` that holds a
    /// set element. Rows in parallel, then blocks of rows.
    pub fn rebuild(&mut self, p: &[f64], nx: usize, ny: usize, periodic: bool) {
        self.periodic = periodic;
        self.masks.build(p, nx, ny, periodic);
        self.blocks
            .resize_with(ny.div_ceil(ROWS_PER_TASK), Band::default);
        let masks = &self.masks;
        let r = RADIUS as isize;
        self.blocks
            .par_iter_mut()
            .enumerate()
            .for_each(|(b, band)| {
                band.element.clear();
                band.nearest.clear();
                band.dist2.clear();
                let mut near = vec![0u64; masks.words];
                for y in b * ROWS_PER_TASK..((b + 1) * ROWS_PER_TASK).min(ny) {
                    // elements within RADIUS of the set: dx^2 + dy^2 <= 9 takes |dx| <= 3, 2,
                    // 2, 0 at |dy| = 0, 1, 2, 3
                    near.copy_from_slice(masks.row(&masks.wide3, y));
                    for dy in 1..=r {
                        let plane = if dy == r { &masks.set } else { &masks.wide2 };
                        for yy in [y as isize - dy, y as isize + dy] {
                            if let Some(yy) = wrap(yy, ny, periodic) {
                                for (w, &v) in near.iter_mut().zip(masks.row(plane, yy)) {
                                    *w |= v;
                                }
                            }
                        }
                    }
                    // the set's rows from y - RADIUS to y + RADIUS, None off the grid
                    let around: [Option<usize>; 2 * RADIUS + 1] =
                        std::array::from_fn(|i| wrap(y as isize + i as isize - r, ny, periodic));
                    let on = masks.row(&masks.set, y);
                    for k in 0..masks.words {
                        let all = near[k] & !on[k] & masks.body[k];
                        if all == 0 {
                            continue;
                        }
                        // the words k - 1, k, k + 1 of the set's rows around y (zero off the
                        // grid), then per bit of word k the first of OFFSETS that holds a set
                        // element
                        let near_words = around.map(|yy| {
                            yy.map_or([0; 3], |yy| {
                                let row = masks.row(&masks.set, yy);
                                let before = k.checked_sub(1).map_or(0, |j| row[j]);
                                [before, row[k], row.get(k + 1).copied().unwrap_or(0)]
                            })
                        });
                        // the index into OFFSETS of each bit's first, as five bit planes
                        let (mut left, mut first) = (all, [0u64; 5]);
                        for (i, &(dy, dx)) in OFFSETS.iter().enumerate() {
                            let hit = shifted(&near_words[(dy + r) as usize], 1, dx) & left;
                            left &= !hit;
                            for (b, plane) in first.iter_mut().enumerate() {
                                *plane |= hit & 0u64.wrapping_sub((i >> b) as u64 & 1);
                            }
                        }
                        debug_assert_eq!(
                            left, 0,
                            "every band element has a set element within reach"
                        );
                        let mut rest = all;
                        while rest != 0 {
                            let bit = rest.trailing_zeros() as usize;
                            rest &= rest - 1;
                            let i =
                                (0..5).fold(0, |i, b| i | ((first[b] >> bit & 1) as usize) << b);
                            let (dy, dx) = OFFSETS[i];
                            let x = 64 * k + bit - RADIUS;
                            let yy = around[(dy + r) as usize].expect("a row within reach");
                            // a set bit off a grid that does not wrap is never set
                            let xx =
                                wrap(x as isize + dx, nx, periodic).expect("a column of the grid");
                            band.element.push((y * nx + x) as u32);
                            band.nearest.push((yy * nx + xx) as u32);
                            band.dist2.push((dx * dx + dy * dy) as u8);
                        }
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
    /// whenever the set changed.
    pub(super) fn precondition_on_set(&mut self, changes: f64) {
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
        if changes > 0.0 {
            ext.rebuild(&self.p, nx, ny, periodic);
        }
        ext.extend(&self.p, &mut self.g);
        self.op.precondition(&self.g, &mut self.z);
        self.extension.fold(&self.p, &mut self.z, &mut self.g);
    }
}

/// A grid's contact set as rows of bits, each row with `RADIUS` elements more on either
/// side (the other edge's elements where the grid wraps, none where it does not), so that
/// a shift along the row by up to `RADIUS` needs no wrap of its own.
#[derive(Default)]
struct SetMasks {
    /// Words (64 elements) per row.
    words: usize,
    /// The set's bits: element x of a row at bit x + `RADIUS`.
    set: Vec<u64>,
    /// Bits within 2 elements along the row of a set element.
    wide2: Vec<u64>,
    /// Bits within `RADIUS` elements along the row of a set element.
    wide3: Vec<u64>,
    /// The bits of a row that stand for its own elements (not its margins).
    body: Vec<u64>,
}

impl SetMasks {
    /// The bit rows of the set {p > 0} of an `nx` x `ny` grid and their widened copies.
    fn build(&mut self, p: &[f64], nx: usize, ny: usize, periodic: bool) {
        let words = (nx + 2 * RADIUS).div_ceil(64);
        self.words = words;
        self.body.clear();
        self.body
            .extend((0..words).map(|k| bits_in(k, RADIUS, RADIUS + nx)));
        for plane in [&mut self.set, &mut self.wide2, &mut self.wide3] {
            plane.clear();
            plane.resize(words * ny, 0);
        }
        self.set
            .par_chunks_mut(words)
            .zip(self.wide2.par_chunks_mut(words))
            .zip(self.wide3.par_chunks_mut(words))
            .zip(p.par_chunks(nx))
            .with_min_len(ROWS_PER_TASK)
            .for_each(|(((set, wide2), wide3), line)| {
                for (c, chunk) in line.chunks(64).enumerate() {
                    let m = chunk
                        .iter()
                        .enumerate()
                        .fold(0u64, |m, (i, &v)| m | u64::from(v > 0.0) << i);
                    let at = 64 * c + RADIUS;
                    set[at / 64] |= m << (at % 64);
                    if at % 64 != 0 && m >> (64 - at % 64) != 0 {
                        set[at / 64 + 1] |= m >> (64 - at % 64);
                    }
                }
                if periodic {
                    for k in 0..RADIUS {
                        let left = (k as isize - RADIUS as isize).rem_euclid(nx as isize);
                        let right = RADIUS + nx + k;
                        set[k / 64] |= u64::from(line[left as usize] > 0.0) << (k % 64);
                        set[right / 64] |= u64::from(line[k % nx] > 0.0) << (right % 64);
                    }
                }
                widen(set, wide2, 2);
                widen(set, wide3, RADIUS);
            });
    }

    /// Row `y` of a plane.
    fn row<'a>(&self, plane: &'a [u64], y: usize) -> &'a [u64] {
        &plane[y * self.words..(y + 1) * self.words]
    }
}

/// The bits of word `k` at positions from `start` to `end` (exclusive) of a row.
fn bits_in(k: usize, start: usize, end: usize) -> u64 {
    let (lo, hi) = (
        start.clamp(64 * k, 64 * k + 64),
        end.clamp(64 * k, 64 * k + 64),
    );
    if hi == lo {
        0
    } else {
        (u64::MAX >> (64 - (hi - lo))) << (lo - 64 * k)
    }
}

/// Word `k` of the bit row `row` moved by `dx` positions: its bit e is the row's bit
/// 64 k + e + dx (zero beyond the row).
fn shifted(row: &[u64], k: usize, dx: isize) -> u64 {
    let s = dx.unsigned_abs() as u32;
    match dx.cmp(&0) {
        std::cmp::Ordering::Equal => row[k],
        std::cmp::Ordering::Greater => row[k] >> s | row.get(k + 1).map_or(0, |&w| w << (64 - s)),
        std::cmp::Ordering::Less => {
            row[k] << s | k.checked_sub(1).map_or(0, |j| row[j] >> (64 - s))
        }
    }
}

/// Writes into `out` the bit row `row` widened by `reach` bits either way: a bit is set
/// where `row` has one within `reach` positions.
fn widen(row: &[u64], out: &mut [u64], reach: usize) {
    for (k, o) in out.iter_mut().enumerate() {
        *o = (-(reach as isize)..=reach as isize).fold(0, |m, dx| m | shifted(row, k, dx));
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
    /// with a short last block) and rows of one to three words of the set's bits, and
    /// <E g, y> = <g, E^T y> for g on the set and y off it.
    #[test]
    fn band_holds_the_nearest_set_elements_and_fold_is_the_transpose() {
        let weights = &*WEIGHTS;
        for (nx, ny) in [
            (23, 17),
            (29, 49),
            (31, 50),
            (12, 64),
            (9, 5),
            (61, 9),
            (130, 21),
        ] {
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

    /// `OFFSETS` holds every offset within `RADIUS` but the element's own, once, ordered by
    /// squared distance, then row, then column (the order the band's nearest set elements
    /// are chosen in).
    #[test]
    fn offsets_are_every_offset_within_reach_nearest_first() {
        let r = RADIUS as isize;
        let mut all: Vec<(isize, isize)> = (-r..=r)
            .flat_map(|dy| (-r..=r).map(move |dx| (dy, dx)))
            .filter(|&(dy, dx)| (1..=r * r).contains(&(dy * dy + dx * dx)))
            .collect();
        all.sort_by_key(|&(dy, dx)| (dy * dy + dx * dx, dy, dx));
        assert_eq!(OFFSETS.to_vec(), all);
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
