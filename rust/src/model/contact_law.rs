//! The contact law: how the indenter's surface and the body's interact across the gap
//! g = u - d + h (m). Every assumption the engines make about the sign of a contact force is
//! made here, once: hard contact carries no tension, so an MDR element presses with
//! max(d - g_i, 0) and leaves the surface when its force would turn tensile, a BEM pressure
//! is projected onto p >= 0, and a prescribed force must be >= 0. An adhesive law adds a
//! variant and its arms here.

use crate::support::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// How two surfaces interact in normal contact (the scene's `contact`; default `hard`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactLaw {
    /// Frictionless, non-adhesive contact (Signorini): gap >= 0, pressure >= 0, p g = 0.
    #[default]
    Hard,
}

impl ContactLaw {
    /// The law's name in scene files ("hard").
    pub fn name(self) -> &'static str {
        match self {
            ContactLaw::Hard => "hard",
        }
    }

    /// Whether this is the default law (scene files and JSON omit it then).
    pub fn is_hard(&self) -> bool {
        matches!(self, ContactLaw::Hard)
    }

    /// Fails on a prescribed total force (N) the law cannot carry: a tensile one under hard
    /// contact.
    pub fn check_force(self, force: f64) -> Result<()> {
        match self {
            ContactLaw::Hard if force < 0.0 => Err(Error::InvalidInput(format!(
                "forces must be >= 0 (no adhesion), got {force}"
            ))),
            ContactLaw::Hard => Ok(()),
        }
    }

    /// The nearest pressure (Pa) the law admits to `p`: max(p, 0) under hard contact.
    pub fn admissible(self, p: f64) -> f64 {
        match self {
            ContactLaw::Hard => p.max(0.0),
        }
    }

    /// The compression (m) of an MDR element whose surface lies at `g` (m) under an
    /// indenter at depth `d` (m): max(d - g, 0) under hard contact.
    pub fn compression(self, d: f64, g: f64) -> f64 {
        match self {
            ContactLaw::Hard => (d - g).max(0.0),
        }
    }

    /// The depth d (m) at which the elements of `surface` (their free surfaces, m) are
    /// compressed by `s` (m) in all, and how many touch: the MDR root of a force
    /// (s = force over the element stiffness). Exact up to round-off.
    pub fn depth_for_compression(self, surface: &SortedSurface, s: f64) -> (f64, usize) {
        match self {
            ContactLaw::Hard => surface.hard_root(s),
        }
    }

    /// The total compression (m) of the elements of `surface` under an indenter at depth
    /// `d` (m), and how many touch.
    pub fn compression_at(self, surface: &SortedSurface, d: f64) -> (f64, usize) {
        match self {
            ContactLaw::Hard => {
                let k = surface.sorted.partition_point(|&v| v < d);
                (k as f64 * d - surface.prefix[k], k)
            }
        }
    }
}

/// The free-surface heights of a foundation's elements (m), sorted, with their prefix sums:
/// what the MDR roots of a contact law search. Its buffers are reused by `refill`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SortedSurface {
    sorted: Vec<f64>,
    prefix: Vec<f64>,
}

impl SortedSurface {
    /// The surface of the elements `heights` (m).
    pub fn new(heights: &[f64]) -> Self {
        let mut s = SortedSurface::default();
        s.refill(heights);
        s
    }

    /// Replaces the heights (m) by `heights`, reusing the buffers.
    pub fn refill(&mut self, heights: &[f64]) {
        self.sorted.clear();
        self.sorted.extend_from_slice(heights);
        self.sorted.sort_unstable_by(f64::total_cmp);
        self.prefix.clear();
        self.prefix.push(0.0);
        let mut total = 0.0;
        for &v in &self.sorted {
            total += v;
            self.prefix.push(total);
        }
    }

    /// The heights in ascending order (m).
    pub fn sorted(&self) -> &[f64] {
        &self.sorted
    }

    /// Depth d with sum max(d - g_i, 0) = `s` (>= 0), and the number of heights below d:
    /// exact up to round-off, by bisection on the displaced excess. The lowest height and 0
    /// when `s` <= 0.
    fn hard_root(&self, s: f64) -> (f64, usize) {
        let (sorted, prefix) = (&self.sorted, &self.prefix);
        let n = sorted.len();
        if s <= 0.0 {
            return (sorted[0], 0);
        }
        // excess(k) = sum_{j<k} (g_(k) - g_j): what depth g_(k) displaces; increasing in k.
        let excess = |k: usize| k as f64 * sorted[k] - prefix[k];
        let k = if excess(n - 1) < s {
            n
        } else {
            let (mut lo, mut hi) = (1usize, n - 1);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if excess(mid) >= s {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            lo
        };
        ((s + prefix[k]) / k as f64, k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hard root is exact on a small profile, and compression_at inverts it.
    #[test]
    fn hard_root_and_compression_are_inverse() {
        let surface = SortedSurface::new(&[3.0, 0.0, 1.0, 2.0]);
        let law = ContactLaw::Hard;
        // d = 1.5 compresses 1.5 + 0.5 = 2.0 over two elements
        assert_eq!(law.depth_for_compression(&surface, 2.0), (1.5, 2));
        assert_eq!(law.compression_at(&surface, 1.5), (2.0, 2));
        assert_eq!(law.depth_for_compression(&surface, 0.0), (0.0, 0));
        assert_eq!(law.compression(1.5, 2.0), 0.0);
        assert!(law.check_force(-1e-300).is_err() && law.check_force(0.0).is_ok());
    }
}
