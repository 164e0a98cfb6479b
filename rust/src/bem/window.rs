//! Rectangular sub-grids ("windows") that hold everything a step can touch, so that a solve
//! runs on the smallest FFT grid that represents it exactly, and a cache of solvers per
//! padded FFT size so that plans, buffers and kernel spectra are made once per size, not
//! once per step or window (`SolverPool`, which solves on the whole grid where the body has
//! no windows).

use crate::bem::contact::ContactSolver;
use crate::halfspace::body::Operator;
use crate::halfspace::influence::KernelTable;
use crate::halfspace::operator::{padded_size, FftPlans, SurfaceOperator};
use crate::model::body::Body;
use crate::support::error::{check_positive, Error, Result};
use std::collections::HashMap;

/// A sub-grid with origin (x0, y0) and size wx x wy inside a grid `nx` x `ny`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    /// Grid width.
    pub nx: usize,
    /// Grid height.
    pub ny: usize,
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// Columns.
    pub wx: usize,
    /// Rows.
    pub wy: usize,
}

impl Window {
    /// The whole grid.
    pub fn full(nx: usize, ny: usize) -> Self {
        Window {
            nx,
            ny,
            x0: 0,
            y0: 0,
            wx: nx,
            wy: ny,
        }
    }

    /// The bounding box of the elements where `inside` holds, grown by `margin` elements and
    /// clipped to the grid; the whole grid when nothing is inside.
    pub fn around(nx: usize, ny: usize, margin: usize, inside: impl Fn(usize) -> bool) -> Self {
        let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (usize::MAX, 0, usize::MAX, 0);
        for i in (0..nx * ny).filter(|&i| inside(i)) {
            let (x, y) = (i % nx, i / nx);
            x_lo = x_lo.min(x);
            x_hi = x_hi.max(x);
            y_lo = y_lo.min(y);
            y_hi = y_hi.max(y);
        }
        if x_lo == usize::MAX {
            return Window::full(nx, ny);
        }
        let span = |lo: usize, hi: usize, n: usize| {
            let lo = lo.saturating_sub(margin);
            let hi = (hi + margin).min(n - 1);
            (lo, hi - lo + 1)
        };
        let (x0, wx) = span(x_lo, x_hi, nx);
        let (y0, wy) = span(y_lo, y_hi, ny);
        Window {
            nx,
            ny,
            x0,
            y0,
            wx,
            wy,
        }
    }

    /// The window (margin 2) around the elements that can touch while the rigid body's
    /// approach is at most `bound` (m): allowed elements whose separation `sep` (m) plus a
    /// lower bound of the deflection that the new load adds is <= bound. The load adds
    /// `load` (m^3: compliance times force, 1/G F or dI/eta) spread over some elements of
    /// the set that can touch; `least` (m/Pa at G = 1, <= 0) bounds the coefficients at every
    /// offset from below (`Body::least_coefficient`), so that no point sinks by less than
    /// load / dx^2 times it: the set is {sep - rise <= bound}, rise = -load least / dx^2 the
    /// most the surface can rise (0 on a half-space). Within it, the deflection at x is at
    /// least load / dx^2 times the least coefficient at the offsets from x to the set's
    /// bounding box, all at most the offset to the box's corner farthest from x: Love's
    /// coefficients fall with each offset, so for `least` = 0 that is the coefficient to the
    /// corner; otherwise the least coefficient over the offsets up to the corner in both
    /// directions (a running minimum over the box). `table` must cover the box. The whole
    /// grid when nothing can touch; the window around that set when nothing passes the
    /// tighter test (the bound is then below the depth, which the solve will show).
    #[allow(clippy::too_many_arguments)]
    pub fn around_contact(
        nx: usize,
        ny: usize,
        sep: &[f64],
        allowed: &[bool],
        bound: f64,
        load: f64,
        table: &KernelTable,
        least: f64,
    ) -> Self {
        let scale = load / (table.dx() * table.dx());
        let rise = -scale * least.min(0.0);
        let can = |i: usize| allowed[i] && sep[i] - rise <= bound;
        let outer = Window::around(nx, ny, 0, can);
        if outer.is_full() {
            return Window::around(nx, ny, 2, can);
        }
        let (wx, wy) = (outer.wx, outer.wy);
        let floor = (least < 0.0).then(|| {
            let mut floor = vec![0.0; wx * wy];
            for ky in 0..wy {
                for kx in 0..wx {
                    let mut v = table.get(kx, ky);
                    if kx > 0 {
                        v = v.min(floor[ky * wx + kx - 1]);
                    }
                    if ky > 0 {
                        v = v.min(floor[(ky - 1) * wx + kx]);
                    }
                    floor[ky * wx + kx] = v;
                }
            }
            floor
        });
        let lowest = |kx: usize, ky: usize| match &floor {
            Some(f) => f[ky * wx + kx],
            None => table.get(kx, ky),
        };
        let (x_hi, y_hi) = (outer.x0 + wx - 1, outer.y0 + wy - 1);
        let far = |v: usize, lo: usize, hi: usize| (v - lo).max(hi - v);
        let tight = |i: usize| {
            let (x, y) = (i % nx, i / nx);
            can(i)
                && sep[i] + scale * lowest(far(x, outer.x0, x_hi), far(y, outer.y0, y_hi)) <= bound
        };
        if (0..nx * ny).any(tight) {
            Window::around(nx, ny, 2, tight)
        } else {
            Window::around(nx, ny, 2, can)
        }
    }

    /// Whether `other`, a window of the same grid, lies inside this one.
    pub fn contains(&self, other: &Window) -> bool {
        other.x0 >= self.x0
            && other.y0 >= self.y0
            && other.x0 + other.wx <= self.x0 + self.wx
            && other.y0 + other.wy <= self.y0 + self.wy
    }

    /// Whether the window is the whole grid.
    pub fn is_full(&self) -> bool {
        self.wx == self.nx && self.wy == self.ny
    }

    /// Grid index of window element `j`.
    pub fn to_grid(&self, j: usize) -> usize {
        (self.y0 + j / self.wx) * self.nx + self.x0 + j % self.wx
    }

    /// Copies the window's part of `full` into `out` (cleared first).
    pub fn gather<T: Copy>(&self, full: &[T], out: &mut Vec<T>) {
        out.clear();
        for r in 0..self.wy {
            let s = (self.y0 + r) * self.nx + self.x0;
            out.extend_from_slice(&full[s..s + self.wx]);
        }
    }

    /// Writes window values `win` into `full`, and zero everywhere else.
    pub fn scatter(&self, win: &[f64], full: &mut [f64]) {
        full.fill(0.0);
        for r in 0..self.wy {
            let s = (self.y0 + r) * self.nx + self.x0;
            full[s..s + self.wx].copy_from_slice(&win[r * self.wx..(r + 1) * self.wx]);
        }
    }
}

/// The contact solvers of one grid's runs, on its body: for a body solved on windows, one
/// solver per padded FFT size, made on first use from the grid's kernel table (computed
/// once) and resized to each window of the same padded sizes, so that a run plans,
/// allocates and transforms a kernel once per padded size; for a body solved whole, one
/// solver of the whole grid.
pub struct SolverPool {
    body: Body,
    nx: usize,
    ny: usize,
    dx: f64,
    kernel: Option<KernelTable>,
    least: f64,
    plans: FftPlans,
    solvers: HashMap<(usize, usize), ContactSolver<Operator>>,
}

impl SolverPool {
    /// An empty pool for an `nx` x `ny` grid of elements of side `dx` (m) on `body`.
    pub fn new(body: Body, nx: usize, ny: usize, dx: f64) -> Result<Self> {
        check_positive("element size dx", dx)?;
        Ok(SolverPool {
            body,
            nx,
            ny,
            dx,
            kernel: body.window_kernel(nx, ny, dx)?,
            least: body.least_coefficient(dx),
            plans: FftPlans::default(),
            solvers: HashMap::new(),
        })
    }

    /// The window that holds every allowed element whose separation `sep` (m) plus the
    /// least deflection a load `load` (m^3: compliance times force) adds is at most `bound`
    /// (m), widened by the most the body's surface can rise under the load
    /// (`Window::around_contact`); the whole grid on a body solved whole.
    pub fn contact_window(&self, sep: &[f64], allowed: &[bool], bound: f64, load: f64) -> Window {
        match &self.kernel {
            Some(k) => {
                Window::around_contact(self.nx, self.ny, sep, allowed, bound, load, k, self.least)
            }
            None => Window::full(self.nx, self.ny),
        }
    }

    /// The window of a fixed contact set `set` (for flat-punch solves on it); the whole grid
    /// on a body solved whole.
    pub fn set_window(&self, set: &[bool]) -> Window {
        match &self.kernel {
            Some(_) => Window::around(self.nx, self.ny, 0, |i| set[i]),
            None => Window::full(self.nx, self.ny),
        }
    }

    /// A new operator of the whole grid.
    pub fn whole(&mut self) -> Result<Operator> {
        match &self.kernel {
            Some(k) => self
                .body
                .window_operator(k, self.nx, self.ny, &mut self.plans),
            None => self.body.operator(self.nx, self.ny, self.dx),
        }
    }

    /// The solver for a `wx` x `wy` window (its pressure zeroed when it was resized). A padded
    /// size's solver is made for the largest window of that size the grid holds, so that
    /// resizing it never allocates.
    pub fn get(&mut self, wx: usize, wy: usize) -> Result<&mut ContactSolver<Operator>> {
        use std::collections::hash_map::Entry;
        let Some(kernel) = &self.kernel else {
            if (wx, wy) != (self.nx, self.ny) {
                return Err(Error::InvalidInput(format!(
                    "a {} body of {} x {} elements is solved whole, not on a {wx} x {wy} window",
                    self.body.name(),
                    self.nx,
                    self.ny
                )));
            }
            return match self.solvers.entry((wx, wy)) {
                Entry::Occupied(e) => Ok(e.into_mut()),
                Entry::Vacant(e) => Ok(e.insert(ContactSolver::new(
                    self.body.operator(self.nx, self.ny, self.dx)?,
                ))),
            };
        };
        let (mx, my) = (padded_size(wx), padded_size(wy));
        let solver = match self.solvers.entry((mx, my)) {
            Entry::Occupied(e) => e.into_mut(),
            Entry::Vacant(e) => {
                let (cx, cy) = (
                    (mx / 2 + 1).min(self.nx).max(wx),
                    (my / 2 + 1).min(self.ny).max(wy),
                );
                e.insert(ContactSolver::new(self.body.window_operator(
                    kernel,
                    cx,
                    cy,
                    &mut self.plans,
                )?))
            }
        };
        if (solver.operator().nx(), solver.operator().ny()) != (wx, wy) {
            solver.resize(wx, wy)?;
        }
        Ok(solver)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::halfspace::operator::FftOperator;

    #[test]
    fn window_round_trip() {
        let (nx, ny) = (40, 30);
        let w = Window::around(nx, ny, 2, |i| i == 5 * nx + 7 || i == 12 * nx + 20);
        assert!(w.x0 <= 5 && w.x0 + w.wx > 22 && w.y0 <= 3 && w.y0 + w.wy > 14);
        let full: Vec<f64> = (0..nx * ny).map(|i| i as f64).collect();
        let mut part = vec![];
        w.gather(&full, &mut part);
        assert_eq!(part.len(), w.wx * w.wy);
        for (j, v) in part.iter().enumerate() {
            assert_eq!(*v, w.to_grid(j) as f64);
        }
        let mut back = vec![0.0; nx * ny];
        w.scatter(&part, &mut back);
        assert_eq!(back[w.to_grid(3)], full[w.to_grid(3)]);
    }

    /// The contact of a paraboloid pressed with force F lies inside the window that
    /// `around_contact` gives for a bound above its depth, which is tighter than the window
    /// around {h <= bound}; and coefficients fall with each offset, as its bound assumes.
    #[test]
    fn contact_window_holds_the_contact_and_is_tighter() {
        use crate::bem::contact::Target;
        use crate::model::settings::SolverOptions;
        use crate::support::monitor::Silent;
        let (n, dx, force) = (120, 0.02, 0.05);
        let c = (n as f64 - 1.0) / 2.0;
        let h: Vec<f64> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 - c, (i / n) as f64 - c);
                (x * x + y * y) * dx * dx / 20.0
            })
            .collect();
        let allowed = vec![true; n * n];
        let mut solver = ContactSolver::new(FftOperator::new(n, n, dx).unwrap());
        let s = solver
            .solve(
                &h,
                &allowed,
                1.0,
                Target::Force(force),
                false,
                0.0,
                &SolverOptions::default(),
                &mut Silent,
            )
            .unwrap();
        let table = KernelTable::new(n, n, dx);
        let bound = 1.02 * s.depth;
        let plain = Window::around(n, n, 2, |i| h[i] <= bound);
        let tight = Window::around_contact(n, n, &h, &allowed, bound, force, &table, 0.0);
        assert!(tight.wx + 4 <= plain.wx, "{tight:?} vs {plain:?}");
        let inside = |w: &Window, i: usize| {
            let (x, y) = (i % n, i / n);
            x >= w.x0 + 2 && x + 2 < w.x0 + w.wx && y >= w.y0 + 2 && y + 2 < w.y0 + w.wy
        };
        for (i, &p) in solver.pressure().iter().enumerate() {
            assert!(
                p == 0.0 || inside(&tight, i),
                "element {i} in contact outside {tight:?}"
            );
        }
        for k in 0..n - 1 {
            assert!(table.get(k + 1, 3) < table.get(k, 3) && table.get(3, k + 1) < table.get(3, k));
        }
    }

    /// Windows of the same padded size share one solver, resized to each; another padded
    /// size gets its own.
    #[test]
    fn pool_shares_a_solver_per_padded_size() {
        let mut pool = SolverPool::new(Body::HalfSpace, 257, 257, 0.01).unwrap();
        for (w, pads) in [(150, 320), (160, 320), (145, 288), (155, 320)] {
            let solver = pool.get(w, w).unwrap();
            let Operator::Free(op) = solver.operator() else {
                panic!("a free half-space's window operator")
            };
            assert_eq!(op.padded(), (pads, pads));
            assert_eq!(
                (solver.operator().nx(), solver.pressure().len()),
                (w, w * w)
            );
        }
        assert_eq!(pool.solvers.len(), 2);
    }
}
