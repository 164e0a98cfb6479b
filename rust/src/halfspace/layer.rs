//! The surface compliance of an elastic layer of thickness h on a rigid base, per
//! wavevector: the periodic operator of a layered cell multiplies by it where a half-space's
//! multiplies by 1 / (2 |q|).
//!
//! A surface pressure p cos(q x) on a layer 0 <= z <= h (z into the layer, shear modulus G,
//! Poisson ratio nu, no shear traction on the surface) is a plane-strain problem in the
//! direction of q. Navier's equations with the x-dependence cos / sin(q x) have the general
//! solution (A + B z) e^(qz) + (C + D z) e^(-qz) (the two-dimensional Papkovich–Neuber
//! solution, Johnson, Contact Mechanics, 1985, §2.8); the four constants follow from the
//! surface's two tractions and the base's two conditions:
//!
//! - bonded (u_x = u_z = 0 at z = h):
//!   u_z(0) / u_half = [kappa sinh 2t - 2t] / [kappa cosh 2t + 2 t^2 + (1 + kappa^2) / 2],
//! - frictionless (u_z = 0 and no shear traction at z = h):
//!   u_z(0) / u_half = [cosh 2t - 1] / [sinh 2t + 2t],
//!
//! with t = |q| h, kappa = 3 - 4 nu and the half-space's u_half = p (1 - nu) / (G |q|). These
//! are the rigid-substrate case of the layered half-space's kernels (Li & Chou, Int. J.
//! Solids Struct. 34, 1997; Persson, J. Phys.: Condens. Matter 24, 2012, for a
//! bonded layer). The tests below solve the four boundary conditions numerically and check
//! the limits: the half-space for t -> infinity, and for t -> 0 confined compression
//! u = p h (1 - 2 nu) / (2 G (1 - nu)) (bonded, nu < 1/2), u = p q^2 h^3 / (3 G) (bonded,
//! incompressible: the layer squeezes out sideways like a lubricating film and stiffens as
//! 1/h^3), and plane-strain compression u = p h (1 - nu) / (2 G) (frictionless).
//!
//! The ratio depends on nu, not only through the contact modulus: the layer's symbol at the
//! medium's incompressible equivalent G' = G / (2 (1 - nu)) (the operators' G = 1) is
//! ratio(|q| h, nu) / (2 |q|). Numerically, the ratio is evaluated with e^(-2t) in place of
//! the growing exponentials for t >= 1 (no overflow at any thickness, the half-space's
//! exponentially small correction kept), and for t < 1 the bonded numerator is summed as
//! (kappa - 1) sinh 2t + (sinh 2t - 2t) with the second term's series, so that the
//! incompressible thin layer (kappa = 1, a numerator of order t^3) keeps full relative
//! precision.

use crate::halfspace::influence::{quarter_kernel, KernelTable};
use crate::halfspace::operator::{FftOperator, FftPlans, SpectralInverse, SurfaceOperator};
use crate::model::body::{Base, Layer};
use crate::support::error::{check_positive, Error, Result};
use faer::Mat;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// |q| h above which the ratio is 1 to round-off (its correction, below
/// 7 t^2 e^(-2t), is under 1e-30 there).
const THICK: f64 = 40.0;

/// The layer's surface compliance over the half-space's, u_z(0) / (p (1 - nu) / (G |q|)),
/// at t = |q| h for Poisson ratio `nu` and base `base`: 0 at t = 0, 1 as t -> infinity.
pub fn compliance_ratio(t: f64, nu: f64, base: Base) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    if t > THICK {
        return 1.0;
    }
    match base {
        Base::Frictionless => {
            // [cosh 2t - 1] / [sinh 2t + 2t], both over e^(2t) / 2
            let e = (-2.0 * t).exp();
            let rise = -(-2.0 * t).exp_m1();
            rise * rise / (4.0 * t * e - (-4.0 * t).exp_m1())
        }
        Base::Bonded => {
            let kappa = 3.0 - 4.0 * nu;
            if t < 1.0 {
                let x = 2.0 * t;
                let numerator = (kappa - 1.0) * x.sinh() + sinh_minus_x(x);
                numerator / (kappa * x.cosh() + 2.0 * t * t + 0.5 * (1.0 + kappa * kappa))
            } else {
                let e = (-2.0 * t).exp();
                let numerator = -kappa * (-4.0 * t).exp_m1() - 4.0 * t * e;
                let denominator = kappa * (1.0 + e * e) + (4.0 * t * t + 1.0 + kappa * kappa) * e;
                numerator / denominator
            }
        }
    }
}

/// sinh x - x for 0 <= x < 2 by its series x^3/3! + x^5/5! + ... (relative round-off).
fn sinh_minus_x(x: f64) -> f64 {
    let (x2, mut term, mut sum) = (x * x, x * x * x / 6.0, 0.0);
    let mut n = 3.0;
    while term > 1e-17 * sum || sum == 0.0 {
        sum += term;
        term *= x2 / ((n + 1.0) * (n + 2.0));
        n += 2.0;
        if term == 0.0 {
            break;
        }
    }
    sum
}

/// The layer's spectral surface compliance (m/Pa at the incompressible-equivalent shear
/// modulus G' = 1 Pa, as the half-space's 1 / (2 |q|)) at wavenumber `q` (1/m), Poisson
/// ratio `nu`: ratio(|q| h, nu) / (2 |q|); at q = 0 its limit, the uniform compliance
/// h (1 - 2 nu) / (4 (1 - nu)^2) (bonded) or h / 4 (frictionless).
pub fn compliance(q: f64, layer: Layer, nu: f64) -> f64 {
    let h = layer.thickness;
    if q > 0.0 {
        compliance_ratio(q * h, nu, layer.base) / (2.0 * q)
    } else {
        match layer.base {
            Base::Bonded => h * (1.0 - 2.0 * nu) / (4.0 * (1.0 - nu) * (1.0 - nu)),
            Base::Frictionless => 0.25 * h,
        }
    }
}

/// Radius, in thicknesses, beyond which a layer's influence coefficients are taken as zero:
/// the layer's kernel decays like e^(-y r / h), y the smallest imaginary part of a pole of
/// ratio(s) / s (0.739 for the incompressible bonded layer, the slowest; 0.913 at nu = 0.3,
/// 1.19 at nu = 0; 2.11 frictionless), so it has fallen below 1e-16 of its scale there.
pub const REACH: f64 = 50.0;

/// Spacing, in thicknesses, of the tabulated correction kernel (cubic interpolation
/// between; the coefficients' sum is then exact to 1e-8, the tests).
const SPACING: f64 = 0.0125;

/// |q| h up to which the correction's Hankel transform is integrated: its integrand,
/// ratio - 1, is below 7 t^2 e^(-2t) < 1e-18 beyond.
const T_MAX: f64 = 25.0;

/// Width in |q| h of the 8-point Gauss–Legendre panels of the Hankel transform (a phase
/// change of REACH times it, 2.5 rad, per panel at most).
const PANEL: f64 = 0.05;

/// Largest element side of a free grid on a layer, in thicknesses: the correction varies
/// on the scale of the thickness, and each element's integral takes up to 20 x 20 points.
pub const MAX_ELEMENT: f64 = 8.0;

/// Gauss–Legendre nodes and weights of order `m` on [-1/2, 1/2] (weights summing to 1), by
/// Newton's iteration on the Legendre polynomial.
pub(crate) fn gauss_legendre(m: usize) -> Vec<(f64, f64)> {
    (0..m)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (m as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=m {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                derivative = m as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (0.5 * x, 1.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// Correction tables by (nu's bits, base).
type Tables = HashMap<(u64, Base), Arc<Vec<f64>>>;

/// The correction kernel of a layer of unit thickness, G(rho) = (1 / 4 pi) integral over
/// t of (ratio(t) - 1) J0(t rho) dt, at rho = i SPACING up to past REACH: the surface
/// deflection of a unit point force on the layer minus the half-space's 1 / (4 pi rho)
/// (G' = 1); a layer of thickness h has G(r / h) / h. One table per (nu, base), cached for
/// the process.
fn correction_table(nu: f64, base: Base) -> Arc<Vec<f64>> {
    static CACHE: OnceLock<Mutex<Tables>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let key = (nu.to_bits(), base);
    if let Some(table) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return table.clone();
    }
    let gauss = gauss_legendre(8);
    let panels = (T_MAX / PANEL).round() as usize;
    let nodes: Vec<(f64, f64)> = (0..panels)
        .flat_map(|k| {
            let start = k as f64 * PANEL;
            gauss.iter().map(move |&(x, w)| {
                let t = start + (x + 0.5) * PANEL;
                (t, w * PANEL * (compliance_ratio(t, nu, base) - 1.0))
            })
        })
        .collect();
    let count = (REACH / SPACING).ceil() as usize + 3;
    let values: Vec<f64> = (0..count)
        .into_par_iter()
        .map(|i| {
            let rho = i as f64 * SPACING;
            nodes
                .iter()
                .map(|&(t, w)| w * libm::j0(t * rho))
                .sum::<f64>()
                / (4.0 * std::f64::consts::PI)
        })
        .collect();
    let table = Arc::new(values);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, table.clone());
    table
}

/// G(rho) from the table by cubic Lagrange interpolation through the four nearest nodes
/// (G is even in rho), rho < REACH.
fn interpolate(table: &[f64], rho: f64) -> f64 {
    let u = rho / SPACING;
    let i = (u.floor() as usize).min(table.len() - 3);
    let s = u - i as f64;
    let at = |j: isize| table[j.unsigned_abs()];
    let i = i as isize;
    let (a, b, c, d) = (at(i - 1), at(i), at(i + 1), at(i + 2));
    // Lagrange through the nodes at s = -1, 0, 1, 2
    let (sm, s1, s2) = (s + 1.0, s - 1.0, s - 2.0);
    -s * s1 * s2 / 6.0 * a + sm * s1 * s2 / 2.0 * b - sm * s * s2 / 2.0 * c + sm * s * s1 / 6.0 * d
}

/// The influence coefficients of a layer for offsets kx < nx, ky < ny of a grid of
/// elements of side `dx` (m): deflection (m at G' = 1) at an element's centre under a unit
/// pressure on the element (kx, ky) away. Love's coefficients of the half-space plus the
/// correction kernel (`correction_table`, a Hankel transform of the layer's compliance
/// minus the half-space's) integrated over the element by m x m Gauss–Legendre points
/// (m = 4 + ceil(2 dx / h), up to 20); zero beyond `REACH` thicknesses. Accuracy: the
/// coefficients sum to the layer's uniform compliance within 1e-8 of it (the cubic
/// interpolation of the table dominates); the element quadrature integrates a function
/// smooth on the scale h >= dx / 8. The correction table is computed once per (nu, base)
/// in the process (16 M Bessel evaluations), the coefficients once per operator. Fails for
/// elements larger than `MAX_ELEMENT` thicknesses.
pub fn kernel_table(nx: usize, ny: usize, dx: f64, layer: Layer, nu: f64) -> Result<KernelTable> {
    let h = layer.thickness;
    if dx > MAX_ELEMENT * h {
        return Err(Error::InvalidInput(format!(
            "a layer {h:e} m thick needs elements of at most {MAX_ELEMENT} thicknesses, got dx = {dx:e} m: refine the grid (larger n)"
        )));
    }
    let table = correction_table(nu, layer.base);
    let m = (4 + (2.0 * dx / h).ceil() as usize).min(20);
    let points = gauss_legendre(m);
    let mut values = quarter_kernel(nx, ny, dx);
    values
        .par_chunks_mut(nx.max(1))
        .enumerate()
        .for_each(|(ky, row)| {
            for (kx, v) in row.iter_mut().enumerate() {
                let near = |k: usize| ((k as f64 - 0.5).max(0.0)) * dx;
                if near(kx).hypot(near(ky)) > REACH * h {
                    *v = 0.0;
                    continue;
                }
                let mut sum = 0.0;
                for &(x, wx) in &points {
                    for &(y, wy) in &points {
                        let r = ((kx as f64 + x) * dx).hypot((ky as f64 + y) * dx);
                        let rho = r / h;
                        let g = if rho < REACH {
                            interpolate(&table, rho) / h
                        } else {
                            -1.0 / (4.0 * std::f64::consts::PI * r)
                        };
                        sum += wx * wy * g;
                    }
                }
                *v += sum * dx * dx;
            }
        });
    Ok(KernelTable::from_values(nx, ny, dx, values))
}

/// Margin on the least point-kernel value of `least_coefficient`: the minimum is taken over
/// the table's nodes (SPACING apart, a relative error of order 1e-4 near a smooth minimum)
/// and an element's coefficient is a quadrature of the kernel over it.
const LEAST_MARGIN: f64 = 1.05;

/// A lower bound (m/Pa at G' = 1, <= 0) of a layer's influence coefficients
/// (`kernel_table`) at every offset, for elements of side `dx` (m): dx^2 times the least
/// value of the point kernel 1 / (4 pi r) + G(r / h) / h (negative where the surface rises
/// around a load: 0.0107 / h at its lowest, r = 1.12 h, for the incompressible bonded layer;
/// 0.0013 / h at nu = 0.3; 0.0009 / h frictionless), with a 5 % margin; 0 where the kernel
/// is nowhere negative. An element's coefficient is the kernel's integral over it, at least
/// dx^2 times its least value; so a pressure field of total force F deflects no point by
/// less than F / dx^2 times this bound: the most the surface rises anywhere.
pub fn least_coefficient(dx: f64, layer: Layer, nu: f64) -> f64 {
    let table = correction_table(nu, layer.base);
    let lowest = table
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, g)| 1.0 / (4.0 * std::f64::consts::PI * i as f64 * SPACING) + g)
        .fold(0.0f64, f64::min);
    LEAST_MARGIN * lowest * dx * dx / layer.thickness
}

/// The surface operator of a free (non-periodic) grid, or of a window of one, on a layer:
/// the DC-FFT of the layer's influence coefficients (`kernel_table`), dense submatrices from
/// the same coefficients, and the layer's spectral inverse (`SpectralInverse` of the layer's
/// continuum compliance, `compliance`) as the conjugate gradients' preconditioner. Where the
/// layer is thin against a wavelength its compliance falls below the half-space's (to
/// q^2 h^3 / 3 for the incompressible bonded layer), which the half-space's preconditioners,
/// flat or growing like |q| at long waves, do not see.
pub struct FreeLayerOperator {
    fft: FftOperator,
    table: KernelTable,
    layer: Layer,
    nu: f64,
    inverse: Option<Box<SpectralInverse>>,
}

impl FreeLayerOperator {
    /// The operator of an `nx` x `ny` grid of elements of side `dx` (m) on `layer` of
    /// Poisson ratio `nu`.
    pub fn new(nx: usize, ny: usize, dx: f64, layer: Layer, nu: f64) -> Result<Self> {
        check_positive("element size dx", dx)?;
        let table = kernel_table(nx, ny, dx, layer, nu)?;
        Self::with_kernel(nx, ny, &table, layer, nu, &mut FftPlans::default())
    }

    /// The operator of an `nx` x `ny` grid (a window) from the layer's coefficients `table`
    /// of a grid that covers it (`kernel_table`, shared by the windows of a grid) and a plan
    /// cache; it keeps the table's part that covers `nx` x `ny` for dense submatrices.
    pub fn with_kernel(
        nx: usize,
        ny: usize,
        table: &KernelTable,
        layer: Layer,
        nu: f64,
        plans: &mut FftPlans,
    ) -> Result<Self> {
        let fft = FftOperator::with_kernel(nx, ny, table, plans)?;
        let own = if table.extent() == (nx, ny) {
            table.clone()
        } else {
            let values = (0..nx * ny).map(|i| table.get(i % nx, i / nx)).collect();
            KernelTable::from_values(nx, ny, table.dx(), values)
        };
        Ok(FreeLayerOperator {
            fft,
            table: own,
            layer,
            nu,
            inverse: None,
        })
    }

    /// The padded FFT sizes (x, y).
    pub fn padded(&self) -> (usize, usize) {
        self.fft.padded()
    }

    /// Makes this the operator of an `nx` x `ny` window with the same padded sizes, within
    /// the grid it was made for (`FftOperator::resize`).
    pub fn resize(&mut self, nx: usize, ny: usize) -> Result<()> {
        self.fft.resize(nx, ny)?;
        self.inverse = None;
        Ok(())
    }
}

impl SurfaceOperator for FreeLayerOperator {
    fn nx(&self) -> usize {
        self.fft.nx()
    }
    fn ny(&self) -> usize {
        self.fft.ny()
    }
    fn dx(&self) -> f64 {
        self.fft.dx()
    }
    fn apply(&mut self, p: &[f64], u: &mut [f64]) {
        self.fft.apply(p, u);
    }
    fn apply_single(&mut self, p: &[f64], u: &mut [f64]) {
        self.fft.convolve_single(p, u);
    }
    fn add_single(&mut self, q: &[f64], u: &mut [f64]) -> bool {
        self.fft.add_convolved_single(q, u);
        true
    }
    /// Entries K[i, j] = the layer's coefficient at the offset of element i from j.
    fn submatrix(&mut self, idx: &[usize]) -> Result<Mat<f64>> {
        let nx = self.nx();
        let table = &self.table;
        Ok(Mat::from_fn(idx.len(), idx.len(), |i, j| {
            let (a, b) = (idx[i], idx[j]);
            table.get((a % nx).abs_diff(b % nx), (a / nx).abs_diff(b / nx))
        }))
    }
    /// Direct summation of the layer's coefficients in real space, as the half-space's
    /// operator does (the same padded circulant kernel).
    fn add_point_loads(&mut self, idx: &[usize], values: &[f64], u: &mut [f64]) -> bool {
        self.fft.add_point_loads(idx, values, u)
    }
    fn point_load_limit(&self) -> usize {
        self.fft.point_load_limit()
    }
    /// The layer's spectral inverse (`SpectralInverse`), made on first use per grid size.
    fn precondition(&mut self, g: &[f64], z: &mut [f64]) {
        let (nx, ny, dx, layer, nu) = (self.nx(), self.ny(), self.dx(), self.layer, self.nu);
        self.inverse
            .get_or_insert_with(|| {
                Box::new(SpectralInverse::of_kernel(
                    nx,
                    ny,
                    dx,
                    &mut FftPlans::default(),
                    |q| compliance(q, layer, nu),
                ))
            })
            .apply(g, z);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// u_z(0) / (p (1 - nu) / (G q)) of the layer by solving the four boundary conditions
    /// of the general plane-strain solution numerically (G = q = 1, thickness t, p = 1):
    /// u_z = (a + b z) e^z + (c + d z) e^-z, u_x = (c + d z - kappa d) e^-z -
    /// (a + b z + kappa b) e^z (x-dependences cos, sin), nu < 1/2.
    fn solved_ratio(t: f64, nu: f64, base: Base) -> f64 {
        let kappa = 3.0 - 4.0 * nu;
        let lambda = 2.0 * nu / (1.0 - 2.0 * nu);
        // [u_z, u_x, sigma_zz, sigma_xz] at depth z of the solution with constants c
        let fields = |c: [f64; 4], z: f64| {
            let [a, b, cc, d] = c;
            let (ep, em) = (z.exp(), (-z).exp());
            let w = (a + b * z) * ep + (cc + d * z) * em;
            let dw = (a + b + b * z) * ep + (d - cc - d * z) * em;
            let u = (cc + d * z - kappa * d) * em - (a + b * z + kappa * b) * ep;
            let du = (d - cc - d * z + kappa * d) * em - (a + b * z + kappa * b + b) * ep;
            [w, u, lambda * (u + dw) + 2.0 * dw, du - w]
        };
        let rows = |c: [f64; 4]| {
            let (top, bottom) = (fields(c, 0.0), fields(c, t));
            match base {
                Base::Bonded => [top[2], top[3], bottom[0], bottom[1]],
                Base::Frictionless => [top[2], top[3], bottom[0], bottom[3]],
            }
        };
        let mut m = [[0.0; 5]; 4];
        for j in 0..4 {
            let mut unit = [0.0; 4];
            unit[j] = 1.0;
            for (i, v) in rows(unit).into_iter().enumerate() {
                m[i][j] = v;
            }
        }
        m[0][4] = -1.0; // sigma_zz(0) = -p
        for col in 0..4 {
            let pivot = (col..4)
                .max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))
                .unwrap();
            m.swap(col, pivot);
            for row in 0..4 {
                if row != col {
                    let f = m[row][col] / m[col][col];
                    let pivot_row = m[col];
                    for (v, p) in m[row].iter_mut().zip(pivot_row).skip(col) {
                        *v -= f * p;
                    }
                }
            }
        }
        let c = [0, 1, 2, 3].map(|i| m[i][4] / m[i][i]);
        fields(c, 0.0)[0] / (1.0 - nu)
    }

    /// The closed forms agree with the numerically solved boundary conditions for both
    /// bases, several Poisson ratios and thicknesses (measured to 2.8e-13 relative).
    #[test]
    fn the_ratio_solves_the_layer_boundary_value_problem() {
        for base in [Base::Bonded, Base::Frictionless] {
            for nu in [-0.5, 0.0, 0.3, 0.45, 0.499] {
                for t in [0.05, 0.3, 0.9, 1.0, 1.7, 4.0, 8.0] {
                    let (closed, solved) =
                        (compliance_ratio(t, nu, base), solved_ratio(t, nu, base));
                    assert!(
                        (closed / solved - 1.0).abs() < 1e-10,
                        "{base:?} nu {nu} t {t}: {closed} vs {solved}"
                    );
                }
            }
        }
    }

    /// Thick layers: the ratio tends to 1 with the leading correction
    /// (4 t^2 + 4 t + 1 + kappa^2) e^(-2t) / kappa (bonded) and (4 t + 2) e^(-2t) (frictionless),
    /// from the closed forms' expansions in e^(-2t); no overflow at any thickness.
    #[test]
    fn thick_layers_are_half_spaces() {
        for nu in [0.0, 0.3, 0.5] {
            let kappa = 3.0 - 4.0 * nu;
            for t in [15.0f64, 25.0] {
                let e = (-2.0 * t).exp();
                let bonded = 1.0 - compliance_ratio(t, nu, Base::Bonded);
                let expected = (4.0 * t * t + 4.0 * t + 1.0 + kappa * kappa) * e / kappa;
                assert!(
                    (bonded - expected).abs() <= 1e-3 * expected + 2.3e-16,
                    "{t}: {bonded}"
                );
                let free = 1.0 - compliance_ratio(t, nu, Base::Frictionless);
                let expected = (4.0 * t + 2.0) * e;
                assert!(
                    (free - expected).abs() <= 1e-3 * expected + 2.3e-16,
                    "{t}: {free}"
                );
            }
            for t in [1e3, 1e300, f64::INFINITY] {
                assert_eq!(compliance_ratio(t, nu, Base::Bonded), 1.0);
                assert_eq!(compliance_ratio(t, nu, Base::Frictionless), 1.0);
            }
        }
    }

    /// Thin layers: confined compression h (1 - 2 nu) / (2 G (1 - nu)) (bonded), the
    /// squeeze film q^2 h^3 / (3 G) of the incompressible bonded layer (ratio 2 t^3 / 3
    /// (1 + O(t^2)), kept to full relative precision down to t = 1e-6), and plane-strain
    /// compression h (1 - nu) / (2 G) (frictionless), each to O(t^2).
    #[test]
    fn thin_layers_have_their_asymptotics() {
        for t in [1e-2, 1e-4, 1e-6] {
            for nu in [-0.5, 0.0, 0.3, 0.45] {
                let confined = t * (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu) * (1.0 - nu));
                let bonded = compliance_ratio(t, nu, Base::Bonded);
                assert!(
                    (bonded / confined - 1.0).abs() < 10.0 * t * t / (1.0 - 2.0 * nu),
                    "{nu} {t}"
                );
                let free = compliance_ratio(t, nu, Base::Frictionless);
                assert!((free / (0.5 * t) - 1.0).abs() < 2.0 * t * t, "{nu} {t}");
            }
            let film = compliance_ratio(t, 0.5, Base::Bonded);
            assert!(
                (film / (2.0 * t * t * t / 3.0) - 1.0).abs() < 2.0 * t * t,
                "{t}: {film}"
            );
        }
        // the compliance itself: at G' = 1 (G = 2 (1 - nu)) the film's is q^2 h^3 / 3 at nu = 1/2
        let layer = Layer {
            thickness: 1e-3,
            base: Base::Bonded,
        };
        let q = 1.0;
        let u = compliance(q, layer, 0.5);
        assert!((u / (q * q * 1e-9 / 3.0) - 1.0).abs() < 1e-5, "{u}");
        // and at q = 0 the uniform limits, continuous with q -> 0
        for (base, nu) in [
            (Base::Bonded, 0.3),
            (Base::Frictionless, 0.3),
            (Base::Bonded, 0.5),
        ] {
            let layer = Layer {
                thickness: 2.0,
                base,
            };
            let (zero, small) = (compliance(0.0, layer, nu), compliance(1e-7, layer, nu));
            assert!(
                (zero - small).abs() <= 1e-12 * layer.thickness,
                "{base:?} {nu}"
            );
        }
    }

    /// The incompressible bonded ratio is continuous in nu at 1/2 and across the switch of
    /// evaluation at t = 1 (the two forms agree to 1e-15 there).
    #[test]
    fn the_evaluation_is_continuous() {
        for nu in [0.3, 0.5] {
            let below = compliance_ratio(1.0 - 1e-12, nu, Base::Bonded);
            let at = compliance_ratio(1.0, nu, Base::Bonded);
            assert!((below - at).abs() < 1e-11, "{nu}: {below} vs {at}");
        }
        for t in [0.5, 3.0] {
            let (half, near) = (
                compliance_ratio(t, 0.5, Base::Bonded),
                compliance_ratio(t, 0.5 - 1e-9, Base::Bonded),
            );
            assert!((half / near - 1.0).abs() < 1e-5, "{t}: {half} vs {near}");
        }
    }
}

#[cfg(test)]
mod contact_tests {
    //! Contacts on periodic layer cells against independent references: the operator on a
    //! harmonic pressure, the periodic half-space for a thick layer, the Winkler foundation
    //! of a thin layer, the elastic layer through Lee–Radok for a viscoelastic one.

    use super::*;
    use crate::bem::contact::Target;
    use crate::bem::static_contact::{solve, StaticContact, StaticRequest};
    use crate::halfspace::operator::{padded_size, SurfaceOperator};
    use crate::halfspace::periodic::mean_separation;
    use crate::model::body::Body;
    use crate::model::grid::Grid;
    use crate::model::settings::SolverOptions;
    use crate::support::monitor::Silent;
    use std::f64::consts::PI;

    fn layer(thickness: f64, base: Base) -> Layer {
        Layer { thickness, base }
    }

    fn cell_body(layer: Layer, nu: f64) -> Body {
        Body::Layer {
            layer,
            nu,
            periodic: true,
        }
    }

    /// A harmonic pressure cos(q . x) on a periodic layer cell gives
    /// u = ratio(|q| h) cos(q . x) / (2 |q|) to round-off, for both bases, compressible and
    /// incompressible, thin and thick against the wavelength (measured 4.7e-14 of the amplitude).
    #[test]
    fn a_harmonic_pressure_gives_the_layer_response() {
        let (nx, ny, dx) = (32, 24, 0.1);
        let (lx, ly) = (nx as f64 * dx, ny as f64 * dx);
        for base in [Base::Bonded, Base::Frictionless] {
            for nu in [0.0, 0.3, 0.5] {
                for h in [0.02, 0.4, 5.0] {
                    let body = cell_body(layer(h, base), nu);
                    let mut op = body.operator(nx, ny, dx).unwrap();
                    for (kx, ky) in [(1i64, 0i64), (3, -2), (16, 0), (5, 7)] {
                        let (qx, qy) = (2.0 * PI * kx as f64 / lx, 2.0 * PI * ky as f64 / ly);
                        let phase =
                            |i: usize| qx * (i % nx) as f64 * dx + qy * (i / nx) as f64 * dx;
                        let p: Vec<f64> = (0..nx * ny).map(|i| phase(i).cos()).collect();
                        let mut u = vec![0.0; nx * ny];
                        op.apply(&p, &mut u);
                        let q = qx.hypot(qy);
                        let amp = compliance_ratio(q * h, nu, base) / (2.0 * q);
                        for (i, v) in u.iter().enumerate() {
                            assert!(
                                (v - amp * phase(i).cos()).abs() < 1e-13 * amp,
                                "{base:?} nu {nu} h {h} ({kx},{ky})"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Westergaard's wavy surface h(x) = g (1 - cos(2 pi x)) on an n x 4 cell of one
    /// wavelength (1 m, g = 0.01 m) on `body`.
    fn wavy(n: usize, body: Body) -> Grid {
        let (g, ny, dx) = (0.01, 4, 1.0 / n as f64);
        let h = (0..n * ny)
            .map(|i| {
                let x = ((i % n) as f64 - (n / 2) as f64 + 0.5) * dx;
                g * (1.0 - (2.0 * PI * x).cos())
            })
            .collect();
        Grid {
            body,
            ..Grid::new(n, ny, dx, h, vec![true; n * ny]).unwrap()
        }
    }

    fn tight() -> SolverOptions {
        SolverOptions {
            tol: 1e-12,
            ..SolverOptions::default()
        }
    }

    /// The static solve (G' = 1 Pa times 1 / `compliance`) of `grid` under `force` (N), with
    /// its deflection.
    fn solved(grid: &Grid, compliance: f64, force: f64) -> StaticContact {
        let req = StaticRequest {
            deflection: true,
            ..StaticRequest::to(Target::Force(force))
        };
        solve(grid, compliance, req, &tight(), &mut Silent).unwrap()
    }

    /// Force balance (the pressures sum to the force) and the contact conditions: p >= 0,
    /// gap = h + u - d >= 0 everywhere and 0 where p > 0, to `tol` of the amplitude.
    fn check_contact(grid: &Grid, s: &StaticContact, force: f64) {
        let area = grid.dx * grid.dx;
        let total: f64 = s.pressure.iter().sum::<f64>() * area;
        assert!(
            (total / force - 1.0).abs() < 1e-12,
            "force {total} vs {force}"
        );
        let u = s.deflection.as_deref().unwrap();
        let g = 0.01;
        for (i, ((h, u), p)) in grid.height.iter().zip(u).zip(&s.pressure).enumerate() {
            let gap = h + u - s.summary.depth;
            assert!(*p >= 0.0, "p[{i}] = {p}");
            assert!(gap >= -1e-9 * g, "gap[{i}] = {gap}");
            if *p > 0.0 {
                assert!(gap.abs() < 1e-8 * g, "gap[{i}] = {gap} in contact");
            }
        }
    }

    /// A layer 1000 contact half-widths thick is the periodic half-space: the wavy surface's
    /// depth and pressures at half of Westergaard's full-contact pressure agree to 1e-6
    /// (the layer's correction, below 7 t^2 e^(-2t) at the longest wave's t = 2 pi h, is
    /// far below round-off), for both bases and any nu; force balance and gap >= 0 hold.
    #[test]
    fn a_thick_layer_is_the_half_space() {
        let n = 128;
        let force = 0.5 * PI * 4.0 * 0.01 * 4.0 / n as f64;
        let half = solved(&wavy(n, Body::Periodic), 1.0, force);
        // the contact half-width at this load is lambda / 4
        for base in [Base::Bonded, Base::Frictionless] {
            for nu in [0.0, 0.5] {
                let grid = wavy(n, cell_body(layer(1000.0 * 0.25, base), nu));
                let s = solved(&grid, 1.0, force);
                check_contact(&grid, &s, force);
                assert!((s.summary.depth / half.summary.depth - 1.0).abs() < 1e-6);
                let pmax = half.pressure.iter().fold(0.0f64, |m, &p| m.max(p));
                for (a, b) in s.pressure.iter().zip(&half.pressure) {
                    assert!((a - b).abs() < 1e-6 * pmax);
                }
            }
        }
    }

    /// The Winkler foundation of a thin layer with the periodic cell's zero mean mode:
    /// p = max(0, pbar + (d - h) / w), w the layer's uniform compliance, d fixed by the mean
    /// pressure pbar (bisection); returns d.
    fn winkler_depth(height: &[f64], w: f64, pbar: f64) -> f64 {
        let mean = |d: f64| {
            height
                .iter()
                .map(|h| (pbar + (d - h) / w).max(0.0))
                .sum::<f64>()
                / height.len() as f64
        };
        let (mut lo, mut hi) = (-1.0, 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mean(mid) < pbar {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// Thin layers: the mean separation of the wavy surface tends to the Winkler
    /// foundation's, with the foundation modulus of confined compression (bonded, nu = 0.3)
    /// or of plane-strain compression (frictionless); force balance and gap >= 0 hold. The
    /// bonded error falls like h^2 (by more than 3.5 each time the thickness halves;
    /// measured 4.0 .. 4.5, 9e-5 at h = lambda / 200), the frictionless one like h^4, its
    /// ratio's t^2 term cancelling (by more than 12 from h = 0.32 lambda to 0.16 lambda;
    /// measured 18; at 0.08 lambda it is 2.6e-6, where the contact edge's grid-scale waves,
    /// |q| h = 2.6 at the Nyquist wavevector, set a floor of 1e-4).
    #[test]
    fn thin_layers_are_winkler_foundations() {
        let n = 512;
        let nu = 0.3;
        for (base, thicknesses, rate) in [
            (Base::Bonded, vec![0.04, 0.02, 0.01, 0.005], 3.5),
            (Base::Frictionless, vec![0.32, 0.16], 12.0),
        ] {
            let mut errors = vec![];
            for h in thicknesses {
                let l = layer(h, base);
                let grid = wavy(n, cell_body(l, nu));
                let w = compliance(0.0, l, nu);
                // half the full-contact mean pressure g / w of the foundation
                let pbar = 0.5 * 0.01 / w;
                let force = pbar * 4.0 / n as f64;
                let s = solved(&grid, 1.0, force);
                check_contact(&grid, &s, force);
                let exact = winkler_depth(&grid.height, w, pbar);
                let sep = mean_separation(&grid.height, s.summary.depth);
                let reference = mean_separation(&grid.height, exact);
                errors.push((sep / reference - 1.0).abs());
            }
            assert!(errors[errors.len() - 1] < 0.02, "{base:?}: {errors:?}");
            for pair in errors.windows(2) {
                assert!(pair[0] / pair[1] > rate, "{base:?}: {errors:?}");
            }
        }
    }

    /// Creep of the wavy surface on a thin incompressible bonded layer (h = lambda / 20) of a
    /// standard solid (G_inf = 1 Pa, G_1 = 3 Pa, tau = 0.5 s) under a constant force: by
    /// Lee–Radok (the contact grows) the depth at t is the elastic layer's under the force
    /// with compliance J(t), computed by static solves independent of the stepping.
    /// The contact grows from 5.5 % to 8.6 % of the cell; measured relative errors of the
    /// mean separation up to 1.0e-8 (dt = 0.005 s, n = 256).
    #[test]
    fn viscoelastic_creep_on_a_layer_follows_lee_radok() {
        use crate::bem::viscoelastic::run_bem;
        use crate::model::loading::{ForceHistory, Loading};
        use crate::model::medium::rheology::Rheology;
        use crate::stepping::Request;
        let (g_inf, g1, tau) = (1.0, 3.0, 0.5);
        let j = |t: f64| {
            1.0 / g_inf
                + (1.0 / (g_inf + g1) - 1.0 / g_inf) * (-g_inf * t / ((g_inf + g1) * tau)).exp()
        };
        let n = 256;
        let grid = wavy(n, cell_body(layer(0.05, Base::Bonded), 0.5));
        let force = 0.004 * 4.0 / n as f64;
        let medium = Rheology::new(g_inf, vec![(g1, tau)], 0.0).unwrap();
        let loading = Loading::Force(ForceHistory::constant(force).unwrap());
        let times = [0.01, 0.1, 0.5, 1.0, 2.0, 5.0];
        let request = Request {
            times: &times,
            dt: 0.005,
            fields_at: &[],
            field_rates: false,
        };
        let s = run_bem(&grid, &medium, &loading, &request, &tight(), &mut Silent).unwrap();
        for (k, &t) in s.t.iter().enumerate() {
            let elastic = solved(&grid, j(t), force);
            let (sep, exact) = (
                mean_separation(&grid.height, s.depth[k]),
                mean_separation(&grid.height, elastic.summary.depth),
            );
            assert!(
                (sep / exact - 1.0).abs() < 1e-7,
                "t = {t}: {sep} vs {exact}"
            );
        }
    }

    /// The free grid's influence coefficients of a layer summed over the plane are the
    /// deflection under a uniform pressure, the layer's uniform compliance:
    /// h (1 - 2 nu) / (4 (1 - nu)^2) (bonded), h / 4 (frictionless), and 0 for the
    /// incompressible bonded layer, whose volume is conserved (the surface rises around a
    /// load as much as it sinks under it). Measured to 7.4e-9 of the compliance (of the
    /// centre coefficient for the incompressible layer) at dx = h / 4 and dx = 2 h; the
    /// error falls 15-fold when the table's spacing halves (cubic interpolation).
    #[test]
    fn free_coefficients_sum_to_the_uniform_compliance() {
        for dx in [0.25, 2.0] {
            let n = (REACH / dx).ceil() as usize + 2;
            for (base, nu) in [
                (Base::Bonded, 0.3),
                (Base::Frictionless, 0.3),
                (Base::Bonded, 0.5),
            ] {
                let l = layer(1.0, base);
                let table = kernel_table(n, n, dx, l, nu).unwrap();
                let weight = |k: usize| if k == 0 { 1.0 } else { 2.0 };
                let mut sum = 0.0;
                for ky in 0..n {
                    for kx in 0..n {
                        sum += weight(kx) * weight(ky) * table.get(kx, ky);
                    }
                }
                let expected = compliance(0.0, l, nu);
                let scale = expected.max(table.get(0, 0));
                assert!(
                    (sum - expected).abs() < 1e-7 * scale,
                    "{base:?} {nu}: {sum} vs {expected}"
                );
            }
        }
    }

    /// An isolated contact on a thin incompressible bonded layer (h = 0.02 m, contact
    /// radius 1.4 h = 7 elements, element 0.2 h) is the same on a free grid and on a periodic cell
    /// 50 thicknesses wide: the layer's kernel has fallen to 4e-7 at the cell's half-width,
    /// and it integrates to zero (C(0) = 0), so the periodic cell's mean plane is the free
    /// surface's far field and the depths agree; the two kernels differ only at the element
    /// scale (spectral against element-integrated), as on the half-space (`static_contact`'s
    /// isolated Hertz contact). Measured: the same 164 contact elements, depths 1.1e-3
    /// apart, pressures within 7.0e-3 of the peak and 5.1e-3 apart in the L1 norm. On the free grid: force balance, p >= 0, gap >= 0
    /// where the surface rises around the contact (its lowest deflection is negative).
    #[test]
    fn free_and_periodic_grids_agree_on_an_isolated_contact() {
        let (n, dx, radius) = (256, 1.0 / 256.0, 1.0);
        let c = n as f64 / 2.0 - 0.5;
        let r = |i: usize| (((i % n) as f64 - c) * dx).hypot(((i / n) as f64 - c) * dx);
        let h: Vec<f64> = (0..n * n).map(|i| r(i).powi(2) / (2.0 * radius)).collect();
        let l = layer(0.02, Base::Bonded);
        let grid = |periodic| Grid {
            body: Body::Layer {
                layer: l,
                nu: 0.5,
                periodic,
            },
            ..Grid::new(n, n, dx, h.clone(), vec![true; n * n]).unwrap()
        };
        let force = 2e-4;
        let free_grid = grid(false);
        let free = solved(&free_grid, 1.0, force);
        let per = solved(&grid(true), 1.0, force);
        let u = free.deflection.as_deref().unwrap();
        assert!(u.iter().fold(0.0f64, |m, &v| m.min(v)) < 0.0);
        let area = dx * dx;
        assert!((free.pressure.iter().sum::<f64>() * area / force - 1.0).abs() < 1e-12);
        let depth = free.summary.depth;
        for (i, ((h, u), p)) in free_grid
            .height
            .iter()
            .zip(u)
            .zip(&free.pressure)
            .enumerate()
        {
            let gap = h + u - depth;
            assert!(
                *p >= 0.0 && gap >= -1e-9 * depth,
                "element {i}: p {p}, gap {gap}"
            );
            if *p > 0.0 {
                assert!(
                    gap.abs() < 1e-8 * depth,
                    "element {i}: gap {gap} in contact"
                );
            }
        }
        let in_contact = |s: &StaticContact| s.pressure.iter().filter(|&&p| p > 0.0).count();
        let peak = free.pressure.iter().fold(0.0f64, |m, &p| m.max(p));
        let (mut worst, mut l1, mut norm) = (0.0f64, 0.0, 0.0);
        for (a, b) in free.pressure.iter().zip(&per.pressure) {
            worst = worst.max((a - b).abs());
            l1 += (a - b).abs();
            norm += a.abs();
        }
        assert_eq!(in_contact(&free), in_contact(&per));
        assert!((per.summary.depth / depth - 1.0).abs() < 2e-3);
        assert!(worst < 1e-2 * peak && l1 < 7e-3 * norm);
    }

    /// Point loads summed in real space (`add_point_loads`) give the FFT convolution's
    /// deflection on a layer, whose kernel changes sign (bonded, incompressible, h = 2 dx),
    /// on the whole grid and on a window of it.
    #[test]
    fn point_loads_match_the_convolution_on_a_layer() {
        let l = layer(2.0, Base::Bonded);
        let (nx, ny) = (23, 17);
        let mut op = FreeLayerOperator::new(nx, ny, 1.0, l, 0.5).unwrap();
        let same_padding = |n: usize| {
            (1..n)
                .rev()
                .find(|&w| padded_size(w) != padded_size(n))
                .map_or(n, |w| w + 1)
        };
        let window = (same_padding(nx), same_padding(ny));
        assert!(window.0 * window.1 < nx * ny);
        for (wx, wy) in [(nx, ny), window] {
            op.resize(wx, wy).unwrap();
            let idx = [0, 5 * wx + 7, wx * wy - 1, 3 * wx + wx - 1];
            let values = [1.0, -0.4, 2.5, 0.7];
            let mut p = vec![0.0; wx * wy];
            idx.iter().zip(&values).for_each(|(&i, &v)| p[i] = v);
            let mut convolved = vec![0.0; wx * wy];
            op.apply(&p, &mut convolved);
            let mut summed = vec![0.0; wx * wy];
            assert!(op.add_point_loads(&idx, &values, &mut summed));
            let scale = convolved.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(convolved.iter().any(|&v| v < 0.0));
            for (a, b) in convolved.iter().zip(&summed) {
                assert!((a - b).abs() < 1e-12 * scale, "{a} vs {b}");
            }
        }
        assert!(op.point_load_limit() > 0);
    }

    /// `least_coefficient` bounds a layer's influence coefficients from below at every
    /// offset, for elements from h / 8 to 8 h wide (both bases, nu = 0, 0.3, 0.5), and is
    /// tight for small elements (within its 5 % margin and the table's sampling of the
    /// kernel's minimum: below 1.1 times the least coefficient at dx = h / 8); every kernel
    /// here dips below zero somewhere (the surface rises around a load).
    #[test]
    fn least_coefficient_bounds_the_coefficients() {
        for (base, nu) in [
            (Base::Bonded, 0.5),
            (Base::Bonded, 0.3),
            (Base::Bonded, 0.0),
            (Base::Frictionless, 0.3),
        ] {
            let l = layer(1.0, base);
            for dx in [0.125f64, 0.5, 2.0, 8.0] {
                let n = (12.0 / dx).ceil() as usize + 2;
                let table = kernel_table(n, n, dx, l, nu).unwrap();
                let lowest = (0..n * n)
                    .map(|i| table.get(i % n, i / n))
                    .fold(f64::INFINITY, f64::min);
                let least = least_coefficient(dx, l, nu);
                assert!(least <= lowest, "{base:?} {nu} dx {dx}: {least} > {lowest}");
                if dx == 0.125 {
                    assert!(
                        lowest < 0.0 && least > 1.1 * lowest,
                        "{base:?} {nu}: {least} vs {lowest}"
                    );
                }
            }
        }
    }

    /// A paraboloid (R = 1) pressed into a thin layer (h = 0.1, contact radius about 3 h) on a
    /// free grid: the solve on a window (force control with a depth bound, depth control)
    /// gives the whole grid's solution (`solve_whole`, every element free to touch) to the
    /// solver's tolerance, on a window smaller than the grid; the window of the viscous
    /// stepping (`Window::around_contact` with the body's least coefficient) holds the whole
    /// grid's contact. On the incompressible bonded layer the surface bulges around the
    /// contact, which reaches beyond the indenter's intersection with the undeformed
    /// surface {h <= d}: the window that depth control starts from is widened by the rise
    /// under the solved force.
    #[test]
    fn windows_on_a_layer_give_the_whole_grid_solution() {
        use crate::bem::static_contact::solve_whole;
        use crate::bem::window::Window;
        let (n, dx) = (48, 0.02);
        let c = n as f64 / 2.0 - 0.5;
        let h: Vec<f64> = (0..n * n)
            .map(|i| {
                0.5 * (((i % n) as f64 - c) * dx)
                    .hypot(((i / n) as f64 - c) * dx)
                    .powi(2)
            })
            .collect();
        for nu in [0.5, 0.3] {
            let body = Body::Layer {
                layer: layer(0.1, Base::Bonded),
                nu,
                periodic: false,
            };
            let grid = Grid {
                body,
                ..Grid::new(n, n, dx, h.clone(), vec![true; n * n]).unwrap()
            };
            // the half-space's Hertz depth at the force, an upper bound of the layer's
            let force = 0.05f64;
            let hertz = (3.0 * force / 16.0).powf(2.0 / 3.0);
            let whole = solve_whole(
                &grid,
                1.0,
                Target::Force(force),
                false,
                &tight(),
                &mut Silent,
            )
            .unwrap();
            let depth = whole.summary.depth;
            for (target, bound) in [
                (Target::Force(force), Some(1.05 * hertz)),
                (Target::Depth(depth), None),
            ] {
                let req = StaticRequest {
                    depth_bound: bound,
                    ..StaticRequest::to(target)
                };
                let s = solve(&grid, 1.0, req, &tight(), &mut Silent).unwrap();
                assert!(
                    s.window.wx < n && s.window.wy < n,
                    "nu {nu}: {:?}",
                    s.window
                );
                let peak = whole.pressure.iter().fold(0.0f64, |m, &p| m.max(p));
                assert!((s.summary.depth / depth - 1.0).abs() < 1e-9, "nu {nu}");
                assert!((s.summary.force / force - 1.0).abs() < 1e-9, "nu {nu}");
                for (a, b) in s.pressure.iter().zip(&whole.pressure) {
                    assert!((a - b).abs() < 1e-8 * peak, "nu {nu}: {a} vs {b}");
                }
            }
            let wider = (0..n * n).any(|i| whole.pressure[i] > 0.0 && h[i] > depth);
            assert_eq!(wider, nu == 0.5, "nu {nu}");
            let window = Window::around_contact(
                n,
                n,
                &h,
                &grid.allowed,
                1.05 * hertz,
                force,
                &kernel_table(n, n, dx, grid.body.layer().unwrap(), nu).unwrap(),
                body.least_coefficient(dx),
            );
            let (wx, wy) = (
                window.x0..window.x0 + window.wx,
                window.y0..window.y0 + window.wy,
            );
            for (i, &p) in whole.pressure.iter().enumerate() {
                assert!(p == 0.0 || (wx.contains(&(i % n)) && wy.contains(&(i / n))));
            }
        }
    }
}
