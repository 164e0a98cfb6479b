//! MDR on a layer on a rigid base: the incremental (Mossakovskii) formulation with the
//! layer's flat-punch stiffness.
//!
//! Pressing a frictionless axisymmetric contact of radius a a little deeper is pressing a
//! flat punch of radius a: dF/dd = k(a) exactly, on any linear elastic body, with k the
//! body's flat-punch stiffness. On a layer of thickness h, k(a) = 2 E* a phi(a / h; nu,
//! base) (E* the medium's contact modulus; phi = 1 on the half-space), and
//! F(d) = integral of k(a(d')) dd'. Integrated by parts with the MDR profile g1 (d = g1(a)),
//! F = integral from 0 to a of k'(x) (d - g1(x)) dx: the half-space's MDR foundation with
//! its elements at |x| stiffened by (x phi(x / h))' — the foundation of the layered MDR
//! (Li & Popov, Machines 11, 2023, 474, with k from BEM). Viscoelastic media of constant
//! Poisson ratio take the same foundation, each element hereditary as on the half-space.
//!
//! phi is exact (to the quadrature's 1e-10): the Fredholm equation of the second kind of a
//! punch on a layer (Cooke–Lebedev; Hayes et al., J. Appl. Mech. 39, 1972, solve the
//! same), written with the layer's spectral compliance ratio R(t) (`halfspace::layer`). A
//! pressure p whose Hankel transform is integral_0^a psi(s) cos(xi s) ds gives the surface
//! deflection (2 / E*) integral_0^r psi_1(t) / sqrt(r^2 - t^2) dt, psi_1 = psi + K psi,
//! K(t, s) = (1 / pi h) [M((t - s) / h) + M((t + s) / h)], M(x) = integral_0^inf (R(u) - 1)
//! cos(u x) du; a flat punch (deflection d for r < a) has psi_1 = E* d / pi, and with
//! psi = (E* d / pi) f(t / a):
//! f(tau) + (chi / pi) integral_0^1 [M(chi (tau - sigma)) + M(chi (tau + sigma))] f(sigma)
//! dsigma = 1, chi = a / h, phi = integral_0^1 f. The operator is symmetric and positive
//! (the layer's compliance is positive), so Gauss–Legendre Nyström with a Cholesky solve.
//!
//! The contact radius follows from the same equation: an indenter of MDR profile g1 gives
//! psi_1 = (E* / pi) (d - g1(t)), and the pressure has no square-root singularity at the
//! edge where psi(a) = 0, which fixes d(a) (`depth_at_radius`). MDR's profile on the layer
//! is then that d(|x|) in place of g1(x) (`layered_profile`): the foundation's force is the
//! layer's exact elastic force, up to the elements' discretisation. (The half-space's rule
//! d = g1(a) is not: to first order in a / h a layer adds a uniform deflection to the
//! half-space's under the same force, so the contact radius at a given force is Hertz's,
//! and the half-space's rule at a given depth undercuts a sphere's first-order correction
//! by a quarter.)
//!
//! Viscoelastic media: the weighted, hereditary foundation is Lee–Radok's solution for a
//! growing contact (F(t) = integral G(t - s) dF_e(d(s)), F_e the elastic layer's force);
//! for a receding one each element keeps the half-space MDR's rule (it leaves the contact
//! when its force would turn tensile), Ting's solution with the layer's profile.

use crate::halfspace::layer::{compliance_ratio, gauss_legendre};
use crate::mdr::foundation::Fields1D;
use crate::model::body::{Base, Layer};
use crate::model::loading::Loading;
use crate::model::medium::rheology::{Rheology, StepRules};
use crate::stepping::{jumps_at_start, step_times, Request, Series, Trail};
use crate::support::error::{check_positive, Error, Result};
use crate::support::monitor::Monitor;
use faer::linalg::solvers::Solve;
use faer::{ColRef, Mat, Side};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Largest contact radius, in thicknesses, of the punch stiffness's table: a contact
/// reaching beyond it is refused.
pub const CHI_MAX: f64 = 8.0;

/// Spacing in chi = a / h of the tabulated punch stiffness (cubic interpolation between).
const CHI_STEP: f64 = 0.02;

/// Spacing in x of the tabulated M(x) (cubic interpolation between).
const M_STEP: f64 = 0.004;

/// u up to which M's cosine transform is integrated (R - 1 < 7 u^2 e^(-2u) < 1e-18 beyond).
const U_MAX: f64 = 25.0;

/// Width in u of the 8-point Gauss–Legendre panels of M's transform (a phase change of at
/// most 2 CHI_MAX times it, 0.8 rad, per panel).
const PANEL: f64 = 0.05;

/// Cubic Lagrange interpolation of `table` (nodes at i `step`, x >= 0) through the four
/// nearest nodes; at the first interval through the nodes at -1 ..= 2 of an `even`
/// function (mirrored), else through 0 ..= 3.
fn interpolate(table: &[f64], step: f64, x: f64, even: bool) -> f64 {
    let u = x / step;
    let first = if even { 0 } else { 1 };
    let i = (u.floor() as usize).clamp(first, table.len() - 3);
    let s = u - i as f64;
    let at = |j: isize| table[j.unsigned_abs()];
    let i = i as isize;
    let (a, b, c, d) = (at(i - 1), at(i), at(i + 1), at(i + 2));
    let (sm, s1, s2) = (s + 1.0, s - 1.0, s - 2.0);
    -s * s1 * s2 / 6.0 * a + sm * s1 * s2 / 2.0 * b - sm * s * s2 / 2.0 * c + sm * s * s1 / 6.0 * d
}

/// M(x) = integral_0^U_MAX (R(u) - 1) cos(u x) du at x = i M_STEP up to past 2 CHI_MAX.
fn m_table(nu: f64, base: Base) -> Vec<f64> {
    let gauss = gauss_legendre(8);
    let panels = (U_MAX / PANEL).round() as usize;
    let nodes: Vec<(f64, f64)> = (0..panels)
        .flat_map(|k| {
            let start = k as f64 * PANEL;
            gauss.iter().map(move |&(x, w)| {
                let u = start + (x + 0.5) * PANEL;
                (u, w * PANEL * (compliance_ratio(u, nu, base) - 1.0))
            })
        })
        .collect();
    let count = (2.0 * CHI_MAX / M_STEP).ceil() as usize + 3;
    (0..count)
        .map(|i| {
            let x = i as f64 * M_STEP;
            nodes.iter().map(|&(u, w)| w * (u * x).cos()).sum()
        })
        .collect()
}

/// The punch equation's Nyström system at contact radius chi thicknesses: Gauss–Legendre
/// points on [0, 1] and the Cholesky factor of the symmetrised matrix
/// sqrt(w_i) (delta_ij + w_j K(tau_i, tau_j)) / sqrt(w_j).
struct Nystrom {
    chi: f64,
    points: Vec<(f64, f64)>,
    llt: faer::linalg::solvers::Llt<f64>,
}

impl Nystrom {
    fn new(m: &[f64], chi: f64) -> Result<Self> {
        let nodes = nodes_for(chi);
        let points: Vec<(f64, f64)> = gauss_legendre(nodes)
            .into_iter()
            .map(|(x, w)| (x + 0.5, w))
            .collect();
        let a = Mat::from_fn(nodes, nodes, |i, j| {
            let ((ti, wi), (tj, wj)) = (points[i], points[j]);
            let k = kernel(m, chi, ti, tj) * (wi * wj).sqrt();
            if i == j {
                1.0 + k
            } else {
                k
            }
        });
        let llt = a.llt(Side::Lower).map_err(|e| {
            Error::Domain(format!(
                "the layer's punch equation at a / h = {chi} is not positive definite: {e:?}"
            ))
        })?;
        Ok(Nystrom { chi, points, llt })
    }

    /// The solution f at the points of f + K f = `rhs` (rhs at the points).
    fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let scaled: Vec<f64> = rhs
            .iter()
            .zip(&self.points)
            .map(|(r, &(_, w))| r * w.sqrt())
            .collect();
        let y = self.llt.solve(ColRef::from_slice(&scaled));
        (0..rhs.len())
            .map(|j| y[j] / self.points[j].1.sqrt())
            .collect()
    }

    /// The solution's integral over [0, 1].
    fn integral(&self, f: &[f64]) -> f64 {
        f.iter().zip(&self.points).map(|(v, &(_, w))| v * w).sum()
    }

    /// The solution at the edge tau = 1 by Nyström's extension, rhs(1) - integral K(1, s) f(s).
    fn at_edge(&self, m: &[f64], rhs_edge: f64, f: &[f64]) -> f64 {
        rhs_edge
            - f.iter()
                .zip(&self.points)
                .map(|(v, &(t, w))| w * kernel(m, self.chi, 1.0, t) * v)
                .sum::<f64>()
    }
}

/// The punch equation's kernel (chi / pi) [M(chi (tau - sigma)) + M(chi (tau + sigma))].
fn kernel(m: &[f64], chi: f64, tau: f64, sigma: f64) -> f64 {
    chi / std::f64::consts::PI
        * (interpolate(m, M_STEP, (chi * (tau - sigma)).abs(), true)
            + interpolate(m, M_STEP, chi * (tau + sigma), true))
}

/// Nyström points for contact radius chi thicknesses: the kernel varies on the scale
/// 1 / chi of tau (Gauss–Legendre converges exponentially; doubling them changes phi by
/// under 1e-12, the tests).
fn nodes_for(chi: f64) -> usize {
    24 + (12.0 * chi).ceil() as usize
}

/// A layer's punch stiffness table for one (Poisson ratio, base): phi(chi).
struct Tables {
    phi: Vec<f64>,
}

/// Tables by (nu's bits, base).
type Cache = HashMap<(u64, Base), Arc<Tables>>;

/// M(x) tables by (nu's bits, base).
type MCache = HashMap<(u64, Base), Arc<Vec<f64>>>;

/// M(x) of a layer of Poisson ratio `nu` on `base` (`m_table`), computed once for the
/// process: all that the contact radius at a depth needs (`depth_at_radius`), without the
/// punch stiffness's table.
fn m_cached(nu: f64, base: Base) -> Arc<Vec<f64>> {
    static CACHE: OnceLock<Mutex<MCache>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let key = (nu.to_bits(), base);
    if let Some(m) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return m.clone();
    }
    let m = Arc::new(m_table(nu, base));
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, m.clone());
    m
}

/// The tables of a layer of Poisson ratio `nu` on `base`, computed once for the process.
fn tables(nu: f64, base: Base) -> Result<Arc<Tables>> {
    static CACHE: OnceLock<Mutex<Cache>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let key = (nu.to_bits(), base);
    if let Some(t) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(t.clone());
    }
    let m = m_cached(nu, base);
    let count = (CHI_MAX / CHI_STEP).round() as usize + 3;
    let phi = (0..count)
        .into_par_iter()
        .map(|i| {
            let chi = i as f64 * CHI_STEP;
            if chi == 0.0 {
                return Ok(1.0);
            }
            let system = Nystrom::new(&m, chi)?;
            let ones = vec![1.0; system.points.len()];
            Ok(system.integral(&system.solve(&ones)))
        })
        .collect::<Result<Vec<f64>>>()?;
    let t = Arc::new(Tables { phi });
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, t.clone());
    Ok(t)
}

/// The flat-punch stiffness of a layer over the half-space's, phi(a / h) = k(a) / (2 E* a),
/// tabulated for 0 <= a / h <= CHI_MAX once per (Poisson ratio, base) for the process.
#[derive(Clone)]
pub struct PunchStiffness {
    tables: Arc<Tables>,
}

impl PunchStiffness {
    /// The table of a layer of Poisson ratio `nu` (-1 < nu <= 0.5) on `base` (computed on
    /// first use: 400 Nyström solves).
    pub fn new(nu: f64, base: Base) -> Result<Self> {
        Ok(PunchStiffness {
            tables: tables(nu, base)?,
        })
    }

    /// phi at contact radius `chi` = a / h thicknesses (|chi| <= CHI_MAX), a function of |chi|.
    pub fn phi(&self, chi: f64) -> f64 {
        interpolate(&self.tables.phi, CHI_STEP, chi.abs(), false)
    }
}

/// The depth (m) at which a contact of radius `a` (m) on `layer` has no singular pressure
/// at its edge, for the MDR profile `g1` (m, of |x|): with psi solving the punch equation
/// for the right side (E* / pi) (d - g1(a tau)), psi(1) = 0, so d = u(1) / f(1) with
/// f + K f = 1 and u + K u = g1(a tau). The half-space's d = g1(a) when h -> infinity.
pub fn depth_at_radius(
    g1: &(dyn Fn(f64) -> Result<f64> + Sync),
    a: f64,
    layer: Layer,
    nu: f64,
) -> Result<f64> {
    let m = m_cached(nu, layer.base);
    let chi = a / layer.thickness;
    if chi == 0.0 {
        return g1(0.0);
    }
    let system = Nystrom::new(&m, chi)?;
    let rhs = system
        .points
        .iter()
        .map(|&(tau, _)| g1(a * tau))
        .collect::<Result<Vec<f64>>>()?;
    let ones = vec![1.0; rhs.len()];
    let (u, f) = (system.solve(&rhs), system.solve(&ones));
    Ok(system.at_edge(&m, g1(a)?, &u) / system.at_edge(&m, 1.0, &f))
}

/// The force (N, at E* = 1 Pa) of a contact of radius `a` (m) at depth `d` (m) on `layer`,
/// MDR profile `g1`: 2 pi integral_0^a psi = 2 a integral_0^1 (d f - u) (`depth_at_radius`'s
/// f and u): the exact elastic force of the layer, independent of MDR's foundation.
pub fn force_at_radius(
    g1: &(dyn Fn(f64) -> Result<f64> + Sync),
    a: f64,
    d: f64,
    layer: Layer,
    nu: f64,
) -> Result<f64> {
    let m = m_cached(nu, layer.base);
    let system = Nystrom::new(&m, a / layer.thickness)?;
    let rhs = system
        .points
        .iter()
        .map(|&(tau, _)| Ok(d - g1(a * tau)?))
        .collect::<Result<Vec<f64>>>()?;
    Ok(2.0 * a * system.integral(&system.solve(&rhs)))
}

/// MDR's profile on a layer: at each element centre x_i = (i - (n - 1) / 2) dx (m) the depth
/// at which the contact reaches |x_i| (`depth_at_radius`), so that the weighted foundation
/// (`element_weights`) has the layer's exact contact radius; beyond `CHI_MAX` thicknesses
/// the half-space's g1 (those elements' weights are NaN: a contact reaching them is refused).
pub fn layered_profile(
    g1: &(dyn Fn(f64) -> Result<f64> + Sync),
    n: usize,
    dx: f64,
    layer: Layer,
    nu: f64,
) -> Result<Vec<f64>> {
    check_positive("element spacing dx", dx)?;
    let half = n / 2;
    let upper: Vec<f64> = (half..n)
        .into_par_iter()
        .map(|i| {
            let x = ((i as f64 - 0.5 * (n as f64 - 1.0)) * dx).abs();
            if x > CHI_MAX * layer.thickness {
                g1(x)
            } else {
                depth_at_radius(g1, x, layer, nu)
            }
        })
        .collect::<Result<Vec<f64>>>()?;
    // element i and n - 1 - i sit at opposite x
    Ok((0..n).map(|i| upper[i.max(n - 1 - i) - half]).collect())
}

/// MDR on a layer as a half-space's foundation: the layered foundation (`layered_profile`
/// weighted by `element_weights`) in the coordinate xi = x phi(x / h), where its elements'
/// weights are uniform. Returns the half profile at xi_j = (j + 1/2) dxi (j < n), the depth
/// d(x(xi_j)) at which the contact reaches x, and dxi (m), for a half profile reaching
/// `half` (m): any half-space MDR engine (elements 4 dxi G' each, counted twice) then gives
/// the layer's forces and depths, its contact lengths in xi. Fails beyond `CHI_MAX`
/// thicknesses.
pub fn half_space_equivalent(
    g1: &(dyn Fn(f64) -> Result<f64> + Sync),
    n: usize,
    half: f64,
    layer: Layer,
    nu: f64,
) -> Result<(Vec<f64>, f64)> {
    check_positive("half length", half)?;
    let h = layer.thickness;
    if half > CHI_MAX * h {
        return Err(Error::Domain(format!(
            "MDR on a layer reaches {CHI_MAX} thicknesses ({:e} m), got a profile {half:e} m long: the contact is too wide for the layer's punch table; fit a thicker layer or smaller depths",
            CHI_MAX * h
        )));
    }
    if n == 0 {
        return Err(Error::InvalidInput("the 1D profile has no elements".into()));
    }
    let punch = PunchStiffness::new(nu, layer.base)?;
    let stretch = |x: f64| x * punch.phi(x / h);
    let dxi = stretch(half) / n as f64;
    let profile = (0..n)
        .into_par_iter()
        .map(|j| {
            let xi = (j as f64 + 0.5) * dxi;
            // x phi(x / h) increases with x (the punch stiffens as it widens): bisection
            let (mut lo, mut hi) = (0.0, half);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if stretch(mid) < xi {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo <= 1e-15 * half {
                    break;
                }
            }
            depth_at_radius(g1, 0.5 * (lo + hi), layer, nu)
        })
        .collect::<Result<Vec<f64>>>()?;
    Ok((profile, dxi))
}

/// The stiffness weights of MDR elements of spacing `dx` (m) centred on
/// x_i = (i - (n - 1) / 2) dx on `layer` of Poisson ratio `nu`: element i's stiffness over
/// the half-space's, (K(x_hi) - K(x_lo)) / dx with K(x) = |x| phi(|x| / h) (both ends on one
/// side of 0; their sum where the element spans it). 1 on a thick layer; NaN beyond
/// `CHI_MAX` thicknesses.
pub fn element_weights(n: usize, dx: f64, layer: Layer, nu: f64) -> Result<Vec<f64>> {
    check_positive("element spacing dx", dx)?;
    let h = layer.thickness;
    let punch = PunchStiffness::new(nu, layer.base)?;
    let big_k = |x: f64| {
        let chi = x.abs() / h;
        if chi > CHI_MAX {
            f64::NAN
        } else {
            x.abs() * punch.phi(chi)
        }
    };
    Ok((0..n)
        .map(|i| {
            let x = (i as f64 - 0.5 * (n as f64 - 1.0)) * dx;
            let (lo, hi) = (x - 0.5 * dx, x + 0.5 * dx);
            let k = if lo >= 0.0 {
                big_k(hi) - big_k(lo)
            } else if hi <= 0.0 {
                big_k(lo) - big_k(hi)
            } else {
                big_k(hi) + big_k(lo)
            };
            k / dx
        })
        .collect())
}

/// The contact of weighted elements at relaxed surface heights `surface` (m): the depth d
/// (m) at which sum over surface_i < d of weight_i (d - surface_i) = `s` (m), s > 0.
fn depth_for_compression(surface: &[f64], weights: &[f64], s: f64, order: &mut Vec<usize>) -> f64 {
    order.clear();
    order.extend(0..surface.len());
    order.sort_unstable_by(|&a, &b| surface[a].total_cmp(&surface[b]));
    let (mut w, mut ws) = (0.0, 0.0);
    for (k, &i) in order.iter().enumerate() {
        w += weights[i];
        ws += weights[i] * surface[i];
        let d = (s + ws) / w;
        match order.get(k + 1) {
            Some(&next) if d > surface[next] => continue,
            _ => return d,
        }
    }
    f64::NAN
}

/// MDR on a layer: hard contact of the 1D profile `g` (m, spacing dx m, centred as
/// `element_weights` says) with elements weighted by `weights` (`element_weights`) of a
/// viscoelastic `medium` (G' at the incompressible equivalent; the half-space's element is
/// 4 dx G'), under `loading`, output as `request` says (no fields). Fails where the contact
/// reaches an element beyond the punch table (NaN weight).
pub fn run_mdr_layer(
    g: &[f64],
    dx: f64,
    weights: &[f64],
    medium: &Rheology,
    loading: &Loading,
    request: &Request,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    check_positive("element spacing dx", dx)?;
    let n = g.len();
    if n == 0 || weights.len() != n {
        return Err(Error::InvalidInput(
            "the 1D profile needs elements and one weight per element".into(),
        ));
    }
    request.check()?;
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => g.iter().copied().fold(f64::INFINITY, f64::min),
    };
    let mut depths = Trail::new(vec![start]);
    let m = medium.internal();
    let (mut w, mut q) = (vec![0.0; n], vec![0.0; n * m]);
    let mut surface = vec![0.0; n];
    let mut order = Vec::with_capacity(n);
    let mut out = Series::default();
    let mut t_prev = 0.0;
    let mut rules = StepRules::new(medium);
    for (s, &(t, output)) in steps.iter().enumerate() {
        let h = t - t_prev;
        let rule = rules.at(h);
        let c = 4.0 * dx * rule.g_eff;
        for i in 0..n {
            surface[i] = g[i] - rule.history(w[i], &q[i * m..(i + 1) * m]) / rule.g_eff;
        }
        let (depth, force) = match loading {
            Loading::Depth(hist) => {
                let d = hist.depth(t);
                let compression: f64 = (0..n)
                    .filter(|&i| surface[i] < d)
                    .map(|i| weights[i] * (d - surface[i]))
                    .sum();
                (d, c * compression)
            }
            Loading::Force(hist) => {
                let f = hist.force(t);
                if f < 0.0 {
                    return Err(Error::InvalidInput(format!(
                        "hard contact takes no tensile force, got {f} N at t = {t} s"
                    )));
                }
                let d = if f == 0.0 {
                    surface.iter().copied().fold(f64::INFINITY, f64::min)
                } else {
                    depth_for_compression(&surface, weights, f / c, &mut order)
                };
                (d, f)
            }
        };
        let mut count = 0;
        for i in 0..n {
            let w_new = if surface[i] < depth {
                if weights[i].is_nan() {
                    return Err(Error::Domain(format!(
                        "the contact on the layer reached {CHI_MAX} thicknesses at t = {t} s: MDR's punch stiffness is tabulated up to there; solve by BEM"
                    )));
                }
                count += 1;
                depth - g[i]
            } else {
                surface[i] - g[i]
            };
            rule.advance(w[i], w_new, &mut q[i * m..(i + 1) * m]);
            w[i] = w_new;
        }
        if force.is_nan() || depth.is_nan() {
            return Err(Error::Domain(format!(
                "the contact on the layer reached {CHI_MAX} thicknesses at t = {t} s: MDR's punch stiffness is tabulated up to there; solve by BEM"
            )));
        }
        if h == 0.0 {
            depths = Trail::new(vec![depth]);
        }
        let mut rate = [0.0];
        depths.rate(t, &[depth], &mut rate);
        if output {
            out.t.push(t);
            out.depth.push(depth);
            out.force.push(force);
            out.contact_length.push(count as f64 * dx);
            out.saturated.push(count == n);
            out.velocity.push(rate[0]);
            out.iterations.push(0);
        }
        if h > 0.0 {
            depths.push(t, &[depth]);
        }
        out.steps = s + 1;
        monitor.progress("time steps", s + 1, steps.len())?;
        t_prev = t;
    }
    Ok(out)
}

#[cfg(test)]
#[path = "layer_tests.rs"]
mod tests;
