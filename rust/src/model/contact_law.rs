//! The contact law: how the indenter's surface and the body's interact across the gap
//! g = u - d + h (m). Every assumption the engines make about the sign of a contact force is
//! made here, once: hard contact carries no tension, so an MDR element presses with
//! max(d - g_i, 0) and leaves the surface when its force would turn tensile, a BEM pressure
//! is projected onto p >= 0, and a prescribed force must be >= 0.
//!
//! Adhesive laws (work of adhesion w, J/m^2) carry tension. JKR (Johnson, Kendall & Roberts
//! 1971; zero-range adhesion, any axisymmetric indenter by Heß's rule): an MDR element
//! attaches when the indenter touches it and lets go when its elongation reaches
//! sqrt(2 pi a w / E*) at contact radius a. DMT (Derjaguin, Muller & Toporov 1975): the
//! non-adhesive (hard) contact plus the constant attraction 2 pi w R of a tip of radius R
//! acting while the surfaces touch.
//!
//! Cohesive-zone laws (BEM) give the traction as a function of the gap: Maugis–Dugdale
//! (Maugis 1992) pulls with a constant stress sigma0 wherever 0 <= g <= h0 = w / sigma0; the
//! exponential law pulls with (w / rho) exp(-g / rho) at every gap (the potential
//! -w exp(-g / rho) of the Adhesion package). Both keep the hard wall g >= 0.

use crate::support::error::{check_positive, Error, Result};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How two surfaces interact in normal contact (the scene's `contact`; default `hard`).
/// Scene files write `contact = "hard"` or a table, `contact = { type = "jkr",
/// work_of_adhesion = 0.05 }`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(
    tag = "type",
    rename_all = "lowercase",
    deny_unknown_fields,
    remote = "Self"
)]
pub enum ContactLaw {
    /// Frictionless, non-adhesive contact (Signorini): gap >= 0, pressure >= 0, p g = 0.
    #[default]
    Hard,
    /// JKR adhesion of zero range: work of adhesion w (J/m^2) released where the surfaces
    /// touch; the contact edge is a crack that opens when the energy released reaches w.
    Jkr {
        /// Work of adhesion w (J/m^2), > 0.
        work_of_adhesion: f64,
        /// Cohesive stress sigma0 (Pa, > 0) of the crack tip's process zone (Dugdale), or
        /// None. On a viscoelastic body it sets the zone's length and, with the crack's
        /// speed, the time the zone's material is stretched over: the edge then lets go by
        /// the energy release rate with the creep compliance of that time
        /// (`mdr::adhesion_crack`); None keeps Heß's rule with the relaxed modulus. An
        /// elastic body does not use it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        stress: Option<f64>,
    },
    /// DMT adhesion: a hard contact plus the attraction 2 pi w R of a rounded tip of radius
    /// R while the surfaces touch (w in J/m^2).
    Dmt {
        /// Work of adhesion w (J/m^2), > 0.
        work_of_adhesion: f64,
    },
    /// Maugis–Dugdale cohesive zone (BEM): a tensile traction `stress` sigma0 (Pa) acts
    /// wherever the gap is at most h0 = w / sigma0, in contact included (TOML
    /// `type = "maugis_dugdale"`).
    #[serde(rename = "maugis_dugdale")]
    MaugisDugdale {
        /// Work of adhesion w = sigma0 h0 (J/m^2), > 0.
        work_of_adhesion: f64,
        /// Cohesive stress sigma0 (Pa), > 0.
        stress: f64,
    },
    /// Exponential cohesive law (BEM): the potential -w exp(-g / rho) per unit area, a
    /// tensile traction (w / rho) exp(-g / rho) at gap g >= 0.
    Exponential {
        /// Work of adhesion w (J/m^2), > 0.
        work_of_adhesion: f64,
        /// Decay length rho (m), > 0.
        range: f64,
    },
}

impl Serialize for ContactLaw {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            ContactLaw::Hard => s.serialize_str("hard"),
            _ => ContactLaw::serialize(self, s),
        }
    }
}

impl<'de> Deserialize<'de> for ContactLaw {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Law;
        impl<'de> Visitor<'de> for Law {
            type Value = ContactLaw;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"hard\" or a table { type = \"jkr\" | \"dmt\" | \"maugis_dugdale\" | \"exponential\", work_of_adhesion, ... }")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> std::result::Result<ContactLaw, E> {
                match v {
                    "hard" => Ok(ContactLaw::Hard),
                    "jkr" | "dmt" | "maugis_dugdale" | "exponential" => Err(E::custom(format!(
                        "contact '{v}' needs its work of adhesion: {{ type = \"{v}\", work_of_adhesion = ... }}"
                    ))),
                    other => Err(E::unknown_variant(
                        other,
                        &["hard", "jkr", "dmt", "maugis_dugdale", "exponential"],
                    )),
                }
            }
            fn visit_map<M: MapAccess<'de>>(
                self,
                m: M,
            ) -> std::result::Result<ContactLaw, M::Error> {
                let law = ContactLaw::deserialize(de::value::MapAccessDeserializer::new(m))?;
                law.validate()
                    .map_err(|e| <M::Error as de::Error>::custom(e.to_string()))?;
                Ok(law)
            }
        }
        d.deserialize_any(Law)
    }
}

impl ContactLaw {
    /// The law's name in scene files ("hard", "jkr", "dmt", "maugis_dugdale" or
    /// "exponential").
    pub fn name(self) -> &'static str {
        match self {
            ContactLaw::Hard => "hard",
            ContactLaw::Jkr { .. } => "jkr",
            ContactLaw::Dmt { .. } => "dmt",
            ContactLaw::MaugisDugdale { .. } => "maugis_dugdale",
            ContactLaw::Exponential { .. } => "exponential",
        }
    }

    /// Whether the law is a cohesive zone (traction a function of the gap; solved by BEM).
    pub fn is_cohesive(self) -> bool {
        matches!(
            self,
            ContactLaw::MaugisDugdale { .. } | ContactLaw::Exponential { .. }
        )
    }

    /// The tensile traction (Pa, >= 0) a cohesive law exerts at gap `g` (m, >= 0): sigma0
    /// for g <= h0 under Maugis–Dugdale, (w / rho) exp(-g / rho) under the exponential law;
    /// 0 for the other laws.
    pub fn traction(self, g: f64) -> f64 {
        match self {
            ContactLaw::MaugisDugdale {
                work_of_adhesion,
                stress,
            } if g <= work_of_adhesion / stress => stress,
            ContactLaw::Exponential {
                work_of_adhesion,
                range,
            } => work_of_adhesion / range * (-g.max(0.0) / range).exp(),
            _ => 0.0,
        }
    }

    /// The interaction energy per unit area (J/m^2, at most 0) of a cohesive law at gap `g`
    /// (m, at least 0), whose derivative is the traction: -sigma0 (h0 - g) for g <= h0 under
    /// Maugis–Dugdale, -w exp(-g / rho) under the exponential law; 0 for the other laws.
    pub fn potential(self, g: f64) -> f64 {
        match self {
            ContactLaw::MaugisDugdale {
                work_of_adhesion,
                stress,
            } => -stress * (work_of_adhesion / stress - g).max(0.0),
            ContactLaw::Exponential {
                work_of_adhesion,
                range,
            } => -work_of_adhesion * (-g.max(0.0) / range).exp(),
            _ => 0.0,
        }
    }

    /// The range (m) of a cohesive law: h0 = w / sigma0 (Maugis–Dugdale) or rho
    /// (exponential); 0 for the other laws.
    pub fn range(self) -> f64 {
        match self {
            ContactLaw::MaugisDugdale {
                work_of_adhesion,
                stress,
            } => work_of_adhesion / stress,
            ContactLaw::Exponential { range, .. } => range,
            _ => 0.0,
        }
    }

    /// Whether this is the default law (scene files and JSON omit it then).
    pub fn is_hard(&self) -> bool {
        matches!(self, ContactLaw::Hard)
    }

    /// Whether the law carries tension (an adhesive law).
    pub fn is_adhesive(self) -> bool {
        !self.is_hard()
    }

    /// The work of adhesion w (J/m^2); 0 for hard contact.
    pub fn work_of_adhesion(self) -> f64 {
        match self {
            ContactLaw::Hard => 0.0,
            ContactLaw::Jkr {
                work_of_adhesion, ..
            }
            | ContactLaw::Dmt { work_of_adhesion }
            | ContactLaw::MaugisDugdale {
                work_of_adhesion, ..
            }
            | ContactLaw::Exponential {
                work_of_adhesion, ..
            } => work_of_adhesion,
        }
    }

    /// Fails unless the law's parameters are valid (a work of adhesion, a cohesive stress
    /// and a range finite and > 0).
    pub fn validate(self) -> Result<()> {
        match self {
            ContactLaw::Hard => Ok(()),
            ContactLaw::MaugisDugdale { stress, .. } => {
                check_positive("contact work_of_adhesion (J/m^2)", self.work_of_adhesion())?;
                check_positive("contact stress (Pa)", stress)
            }
            ContactLaw::Exponential { range, .. } => {
                check_positive("contact work_of_adhesion (J/m^2)", self.work_of_adhesion())?;
                check_positive("contact range (m)", range)
            }
            ContactLaw::Jkr {
                stress: Some(stress),
                ..
            } => {
                check_positive("contact work_of_adhesion (J/m^2)", self.work_of_adhesion())?;
                check_positive("contact stress (Pa)", stress)
            }
            _ => check_positive("contact work_of_adhesion (J/m^2)", self.work_of_adhesion()),
        }
    }

    /// Fails on a prescribed total force (N) the law cannot carry: a tensile one under hard
    /// contact (an adhesive law carries tension up to its pull-off force).
    pub fn check_force(self, force: f64) -> Result<()> {
        match self {
            ContactLaw::Hard if force < 0.0 => Err(Error::InvalidInput(format!(
                "forces must be >= 0 (no adhesion), got {force}"
            ))),
            _ => Ok(()),
        }
    }

    /// The nearest pressure (Pa) the law admits inside the contact to `p`: max(p, 0) under
    /// hard contact and DMT (whose attraction acts outside the contact), any under JKR, and
    /// at least minus the traction at contact under a cohesive law.
    pub fn admissible(self, p: f64) -> f64 {
        match self {
            ContactLaw::Hard | ContactLaw::Dmt { .. } => p.max(0.0),
            ContactLaw::Jkr { .. } => p,
            ContactLaw::MaugisDugdale { .. } | ContactLaw::Exponential { .. } => {
                p.max(-self.traction(0.0))
            }
        }
    }

    /// The compression (m) of an MDR element whose surface lies at `g` (m) under an
    /// indenter at depth `d` (m) when it is touched: max(d - g, 0) for every law (the touch
    /// rule; an adhesive element stays attached beyond, see `detachment_elongation`).
    pub fn compression(self, d: f64, g: f64) -> f64 {
        (d - g).max(0.0)
    }

    /// The depth d (m) at which the elements of `surface` (their free surfaces, m) are
    /// compressed by `s` (m) in all, and how many touch: the MDR root of a force
    /// (s = force over the element stiffness) by the touch rule. Exact up to round-off.
    pub fn depth_for_compression(self, surface: &SortedSurface, s: f64) -> (f64, usize) {
        surface.hard_root(s)
    }

    /// The total compression (m) of the elements of `surface` under an indenter at depth
    /// `d` (m), and how many touch.
    pub fn compression_at(self, surface: &SortedSurface, d: f64) -> (f64, usize) {
        let k = surface.sorted.partition_point(|&v| v < d);
        (k as f64 * d - surface.prefix[k], k)
    }

    /// The elongation (m) at which an attached MDR element at the edge of a contact of
    /// radius `a` (m) lets go, on a body of contact modulus `e_star` (Pa): Heß's rule
    /// sqrt(2 pi a w / E*) under JKR, 0 (no tension) otherwise.
    pub fn detachment_elongation(self, a: f64, e_star: f64) -> f64 {
        match self {
            ContactLaw::Jkr {
                work_of_adhesion, ..
            } => (2.0 * PI * a * work_of_adhesion / e_star).sqrt(),
            _ => 0.0,
        }
    }

    /// The attraction (N) between the surfaces while they touch: DMT's 2 pi w R for a tip of
    /// radius `tip_radius` (m; Derjaguin's approximation), 0 for the other laws. Fails for DMT
    /// on an indenter without a rounded tip (None).
    pub fn attraction(self, tip_radius: Option<f64>) -> Result<f64> {
        match (self, tip_radius) {
            (ContactLaw::Dmt { work_of_adhesion }, Some(r)) => Ok(2.0 * PI * work_of_adhesion * r),
            (ContactLaw::Dmt { .. }, None) => Err(Error::InvalidInput(
                "contact 'dmt' needs an indenter with a rounded tip (paraboloid or sphere): its attraction 2 pi w R takes the tip radius R".into(),
            )),
            _ => Ok(0.0),
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
