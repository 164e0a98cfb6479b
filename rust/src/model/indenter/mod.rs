//! Rigid indenters: axisymmetric ones h = f(r), with their footprints, BEM height maps and
//! MDR 1D profiles g(x) = |x| * integral_0^|x| f'(r) / sqrt(x^2 - r^2) dr (Popov & Hess);
//! the four-sided pyramid (`pyramid.rs`), exact in the BEM and an equivalent cone in MDR;
//! and height maps (`heightmap.rs`), which fix their own BEM grid and have no MDR profile.
//!
//! Lengths in m. A footprint is the part of the plane the indenter covers: a disc, a centred
//! square of edge L (whose 1D MDR indenter has half-length L / sqrt(pi), equal area), a
//! height map's rectangle, or the whole plane (unbounded).

pub mod heightmap;
pub mod profile;
pub mod pyramid;

use crate::model::grid::Grid;
use crate::support::error::{check_positive, Error, Result};
use heightmap::{not_axisymmetric, HeightMap, HeightMapTable};
use profile::{Profile, ProfileTable};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A rigid indenter: axisymmetric, a four-sided pyramid, or a height map.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum Indenter {
    /// Flat cylindrical punch: h = 0 on the disc r <= radius.
    Rod {
        /// Radius (m).
        radius: f64,
    },
    /// Paraboloid h = c r^2 (radius of curvature R = 1 / (2c)).
    Paraboloid {
        /// Curvature parameter c (1/m).
        c: f64,
        /// Side of a centred square footprint (m); absent: unbounded.
        #[serde(default)]
        edge: Option<f64>,
    },
    /// Cone h = slope r.
    Cone {
        /// Slope (dimensionless, the cotangent of the half-opening angle).
        slope: f64,
        /// Side of a centred square footprint (m); absent: unbounded.
        #[serde(default)]
        edge: Option<f64>,
    },
    /// Four-sided pyramid h = max(|x|, |y|) / tan(half_angle) (see `pyramid.rs`); MDR
    /// solves its equivalent cone.
    Pyramid {
        /// Face half-angle alpha (radians, in (0, pi/2)): between the axis and a face.
        half_angle: f64,
        /// Side of a centred square footprint (m), the pyramid's base; absent: unbounded.
        #[serde(default)]
        edge: Option<f64>,
    },
    /// Exact spherical cap h = R - sqrt(R^2 - r^2) on the open disc r < R.
    Sphere {
        /// Radius R of the sphere (m).
        radius: f64,
    },
    /// A tabulated profile (see `ProfileTable`).
    Profile(#[serde(with = "profile_serde")] Box<Profile>),
    /// A height map (see `HeightMapTable`).
    HeightMap(#[serde(with = "heightmap_serde")] Box<HeightMap>),
}

mod heightmap_serde {
    use super::{HeightMap, HeightMapTable};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(m: &HeightMap, s: S) -> Result<S::Ok, S::Error> {
        m.table().serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Box<HeightMap>, D::Error> {
        let table = HeightMapTable::deserialize(d)?;
        HeightMap::try_from(table)
            .map(Box::new)
            .map_err(|e| serde::de::Error::custom(e.message()))
    }
}

mod profile_serde {
    use super::{Profile, ProfileTable};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(p: &Profile, s: S) -> Result<S::Ok, S::Error> {
        p.table().serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Box<Profile>, D::Error> {
        let table = ProfileTable::deserialize(d)?;
        Profile::try_from(table)
            .map(Box::new)
            .map_err(|e| serde::de::Error::custom(e.to_string()))
    }
}

/// The part of the plane an indenter covers (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Footprint {
    /// A disc; `rim` tells whether points exactly on its rim belong to it.
    Disc {
        /// Radius (m).
        radius: f64,
        /// Whether the rim r = radius belongs to the footprint.
        rim: bool,
    },
    /// A centred square of side `edge` (m).
    Square {
        /// Side (m).
        edge: f64,
    },
    /// A height map's rectangle, centred.
    Rectangle {
        /// Side along x (m).
        width: f64,
        /// Side along y (m).
        length: f64,
    },
    /// The whole plane.
    Unbounded,
}

impl Footprint {
    /// Whether the point (`x`, `y`) (m) lies in the footprint.
    pub fn covers(&self, x: f64, y: f64) -> bool {
        match *self {
            Footprint::Disc { radius, rim: true } => x.hypot(y) <= radius,
            Footprint::Disc { radius, rim: false } => x.hypot(y) < radius,
            Footprint::Square { edge } => x.abs() <= 0.5 * edge && y.abs() <= 0.5 * edge,
            Footprint::Rectangle { width, length } => {
                x.abs() <= 0.5 * width && y.abs() <= 0.5 * length
            }
            Footprint::Unbounded => true,
        }
    }
}

/// Where the MDR relations seek a contact radius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reach {
    /// Within a disc footprint of this radius. With `fills` the contact fills the disc once
    /// the profile at its rim falls short; without, the profile diverges at the rim (a
    /// spherical cap), which bounds the radius from inside.
    Disc {
        /// Radius of the disc (m).
        radius: f64,
        /// Whether the contact can fill the disc.
        fills: bool,
    },
    /// From 0 up to `start` times 2^`doublings`, the bound doubling from `start`.
    Beyond {
        /// First bound of the search (m).
        start: f64,
        /// How often the bound may double.
        doublings: u32,
    },
}

/// An even 1D MDR profile g (m) at many 1D coordinates (m) at once.
pub type ProfileFn<'a> = &'a dyn Fn(&[f64]) -> Result<Vec<f64>>;

/// The MDR relations of an axisymmetric 1D profile g known only as a function (one the
/// caller evaluates), by the bisection and the quadrature `Indenter` uses.
pub struct MdrProfile<'a> {
    /// g (m) at many 1D coordinates (m) at once.
    pub profile: ProfileFn<'a>,
    /// The footprint; a square's half edge bounds the Lee–Radok contact radius.
    pub footprint: Footprint,
    /// Where contact radii are sought.
    pub reach: Reach,
}

impl MdrProfile<'_> {
    fn g(&self, x: f64) -> Result<f64> {
        Ok((self.profile)(&[x])?[0])
    }

    /// Contact radius (m) at tip depth `d` (m): g(a) = d (0 at d <= 0, where the profile
    /// is not evaluated); a filled disc caps it.
    pub fn radius_at_depth(&self, d: f64) -> Result<f64> {
        if d <= 0.0 {
            return Ok(0.0);
        }
        bisect_radius(self.reach, |a| self.g(a), d, "depth")
    }

    /// Contact radius (m) under the MDR load `s` (m^2), as `Indenter::radius_at_load` (0 at
    /// s <= 0, where the profile is not evaluated).
    pub fn radius_at_load(&self, s: f64) -> Result<f64> {
        if s <= 0.0 {
            return Ok(0.0);
        }
        bisect_radius(self.reach, |a| mdr_load(self.profile, a), s, "load")
    }

    /// Depth (m) under the MDR load `s` (m^2), as `Indenter::depth_under_load`.
    pub fn depth_under_load(&self, s: f64) -> Result<Option<f64>> {
        let fills = matches!(self.reach, Reach::Disc { fills: true, .. });
        lee_radok_depth(
            self.footprint,
            fills,
            |s| self.radius_at_load(s),
            |x| self.g(x),
            |a| mdr_load(self.profile, a),
            s,
        )
    }
}

/// integral_{-a}^{a} (g(a) - g(x)) dx (m^2) of an even 1D profile `g` by Simpson's rule on
/// 512 panels: the MDR load (F / (4 G), or I / (4 eta) for an impulse I) at contact radius
/// `a` (m).
pub fn mdr_load(g: ProfileFn<'_>, a: f64) -> Result<f64> {
    let panels = 512;
    let h = a / panels as f64;
    let mut x: Vec<f64> = (0..=panels).map(|i| i as f64 * h).collect();
    x.push(a);
    let values = g(&x)?;
    let mut integral = 0.0;
    for (i, &v) in values[..=panels].iter().enumerate() {
        let w = if i == 0 || i == panels {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        integral += w * v;
    }
    Ok(2.0 * (a * values[panels + 1] - integral * h / 3.0))
}

/// The radius a (m) with `f(a)` = `target` for an increasing f, sought within `reach`: a
/// filled disc's radius when even its rim falls short; a domain error naming the target
/// (`what`: "depth" or "load") when nothing within reach gets there.
pub fn bisect_radius(
    reach: Reach,
    f: impl Fn(f64) -> Result<f64>,
    target: f64,
    what: &str,
) -> Result<f64> {
    let reaches = |a: f64| f(a).map(|v| v >= target);
    let (mut lo, mut hi) = (0.0, 0.0);
    match reach {
        Reach::Disc { radius, fills } => {
            if fills && !reaches(radius)? {
                return Ok(radius);
            }
            hi = radius;
        }
        Reach::Beyond { start, doublings } => {
            for k in 0..=doublings {
                hi = start * 2f64.powi(k as i32);
                if reaches(hi)? {
                    break;
                }
                if k == doublings {
                    let unit = if what == "depth" { "m" } else { "m^2" };
                    let hint = if doublings == 0 {
                        ": tabulate the profile further"
                    } else {
                        ""
                    };
                    return Err(Error::Domain(format!(
                        "no contact radius up to {hi:?} m reaches {what} {target:?} {unit}{hint}"
                    )));
                }
            }
        }
    }
    loop {
        let mid = 0.5 * (lo + hi);
        if !(lo < mid && mid < hi) {
            return Ok(hi);
        }
        if f(mid)? < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

/// Lee–Radok depth (m) under the MDR load `s` (m^2): 0 without a load, else d = g(a) at the
/// contact radius a under the load; once the contact fills a disc footprint (`fills`) of
/// radius R the indenter moves on like a rod, d = g(R) + (s - s_R) / (2 R); None once the
/// contact circle is wider than half a square's edge (half a rectangle's shorter side).
fn lee_radok_depth(
    footprint: Footprint,
    fills: bool,
    radius_at_load: impl Fn(f64) -> Result<f64>,
    g: impl Fn(f64) -> Result<f64>,
    load: impl Fn(f64) -> Result<f64>,
    s: f64,
) -> Result<Option<f64>> {
    if s <= 0.0 {
        return Ok(Some(0.0));
    }
    let a = radius_at_load(s)?;
    match footprint {
        Footprint::Disc { radius, .. } if fills && a >= radius => {
            Ok(Some(g(radius)? + (s - load(radius)?) / (2.0 * radius)))
        }
        Footprint::Square { edge } if a > 0.5 * edge => Ok(None),
        Footprint::Rectangle { width, length } if a > 0.5 * width.min(length) => Ok(None),
        _ => g(a).map(Some),
    }
}

impl Indenter {
    /// Fails on non-finite or non-positive parameters.
    pub fn validate(&self) -> Result<()> {
        let edge = match *self {
            Indenter::Rod { radius } => return check_positive("rod radius", radius),
            Indenter::Sphere { radius } => return check_positive("sphere radius", radius),
            Indenter::Profile(_) | Indenter::HeightMap(_) => return Ok(()),
            Indenter::Paraboloid { c, edge } => {
                check_positive("paraboloid c", c)?;
                edge
            }
            Indenter::Cone { slope, edge } => {
                check_positive("cone slope", slope)?;
                edge
            }
            Indenter::Pyramid { half_angle, edge } => {
                pyramid::check_half_angle(half_angle)?;
                edge
            }
        };
        edge.map_or(Ok(()), |e| check_positive("footprint edge", e))
    }

    /// The footprint.
    pub fn footprint(&self) -> Footprint {
        let square = |edge: Option<f64>| {
            edge.map_or(Footprint::Unbounded, |edge| Footprint::Square { edge })
        };
        match self {
            Indenter::Rod { radius } => Footprint::Disc {
                radius: *radius,
                rim: true,
            },
            Indenter::Sphere { radius } => Footprint::Disc {
                radius: *radius,
                rim: false,
            },
            Indenter::Paraboloid { edge, .. }
            | Indenter::Cone { edge, .. }
            | Indenter::Pyramid { edge, .. } => square(*edge),
            Indenter::Profile(p) => match (p.table().radius, p.table().edge) {
                (Some(radius), _) => Footprint::Disc { radius, rim: true },
                (None, edge) => square(edge),
            },
            Indenter::HeightMap(m) => {
                let (width, length) = m.sides();
                Footprint::Rectangle { width, length }
            }
        }
    }

    /// Whether the face is flat (the rod): its contact is the whole face at every depth.
    pub fn is_flat(&self) -> bool {
        matches!(self, Indenter::Rod { .. })
    }

    /// Half the side of the smallest centred square holding the footprint (m); None when
    /// unbounded.
    pub fn half_width(&self) -> Option<f64> {
        match self.footprint() {
            Footprint::Disc { radius, .. } => Some(radius),
            Footprint::Square { edge } => Some(0.5 * edge),
            Footprint::Rectangle { width, length } => Some(0.5 * width.max(length)),
            Footprint::Unbounded => None,
        }
    }

    /// Half-length of the 1D MDR indenter (m): a disc's radius, L / sqrt(pi) for a square
    /// of side L or sqrt(W L / pi) for a rectangle (equal area); None when unbounded.
    pub fn half_length_1d(&self) -> Option<f64> {
        match self.footprint() {
            Footprint::Disc { radius, .. } => Some(radius),
            Footprint::Square { edge } => Some(edge / PI.sqrt()),
            Footprint::Rectangle { width, length } => Some((width * length / PI).sqrt()),
            Footprint::Unbounded => None,
        }
    }

    /// Height above the tip (m) at (`x`, `y`) (m) inside the footprint: the indenter's true
    /// shape, which the BEM solves.
    pub fn surface(&self, x: f64, y: f64) -> Result<f64> {
        match *self {
            Indenter::Pyramid { half_angle, .. } => Ok(pyramid::height(half_angle, x, y)),
            _ => self.height(x.hypot(y)),
        }
    }

    /// Height above the tip (m) at radius `r` (m) inside the footprint, of the axisymmetric
    /// indenter MDR solves (a pyramid's equivalent cone).
    pub fn height(&self, r: f64) -> Result<f64> {
        Ok(match self {
            Indenter::Rod { .. } => 0.0,
            Indenter::Paraboloid { c, .. } => c * r * r,
            Indenter::Cone { slope, .. } => slope * r,
            Indenter::Pyramid { half_angle, edge } => {
                pyramid::equivalent_cone(*half_angle, *edge).height(r)?
            }
            Indenter::Sphere { radius } => r * r / (radius + ((radius - r) * (radius + r)).sqrt()),
            Indenter::Profile(p) => p.height(r)?,
            Indenter::HeightMap(_) => return Err(not_axisymmetric("height h(r)")),
        })
    }

    /// Radius of curvature (m) of a rounded tip (paraboloid 1 / (2 c), sphere), which DMT's
    /// attraction takes; None for the other indenters.
    pub fn tip_radius(&self) -> Option<f64> {
        match self {
            Indenter::Paraboloid { c, .. } => Some(0.5 / c),
            Indenter::Sphere { radius } => Some(*radius),
            _ => None,
        }
    }

    /// MDR profile g (m) at 1D coordinate `x` (m), even in x.
    pub fn profile_1d(&self, x: f64) -> Result<f64> {
        let x = x.abs();
        Ok(match self {
            Indenter::Rod { .. } => 0.0,
            Indenter::Paraboloid { c, .. } => 2.0 * c * x * x,
            Indenter::Cone { slope, .. } => 0.5 * PI * slope * x,
            Indenter::Pyramid { half_angle, edge } => {
                pyramid::equivalent_cone(*half_angle, *edge).profile_1d(x)?
            }
            Indenter::Sphere { radius } => {
                if x >= *radius {
                    return Err(Error::InvalidInput(format!(
                        "sphere: the MDR profile needs |x| < radius = {radius}, got {x}"
                    )));
                }
                x * (x / radius).atanh()
            }
            Indenter::Profile(p) => p.profile_1d(x)?,
            Indenter::HeightMap(_) => return Err(not_axisymmetric("MDR profile")),
        })
    }

    /// Contact radius (m) at tip depth `d` (m): g(a) = d, for elastic and viscous media
    /// alike; a disc footprint caps it.
    pub fn radius_at_depth(&self, d: f64) -> Result<f64> {
        let d = d.max(0.0);
        Ok(match self {
            Indenter::Rod { radius } => *radius,
            Indenter::Paraboloid { c, .. } => (d / (2.0 * c)).sqrt(),
            Indenter::Cone { slope, .. } => 2.0 * d / (PI * slope),
            Indenter::Pyramid { half_angle, edge } => {
                pyramid::equivalent_cone(*half_angle, *edge).radius_at_depth(d)?
            }
            Indenter::HeightMap(_) => return Err(not_axisymmetric("contact radius")),
            _ => bisect_radius(self.reach(), |a| self.profile_1d(a), d, "depth")?,
        })
    }

    /// Contact radius (m) under the MDR load `s` = F / (4 G) or I / (4 eta) (m^2): the a
    /// with integral_{-a}^{a} (g(a) - g(x)) dx = s; a disc footprint caps it.
    pub fn radius_at_load(&self, s: f64) -> Result<f64> {
        let s = s.max(0.0);
        Ok(match self {
            Indenter::Rod { radius } => *radius,
            // 2 (g(a) a - integral_0^a g) = 8 c a^3 / 3
            Indenter::Paraboloid { c, .. } => (3.0 * s / (8.0 * c)).cbrt(),
            // 2 (k a^2 - k a^2 / 2) = k a^2, k = pi slope / 2
            Indenter::Cone { slope, .. } => (s / (0.5 * PI * slope)).sqrt(),
            Indenter::Pyramid { half_angle, edge } => {
                pyramid::equivalent_cone(*half_angle, *edge).radius_at_load(s)?
            }
            Indenter::HeightMap(_) => return Err(not_axisymmetric("contact radius")),
            _ => bisect_radius(self.reach(), |a| self.load_at_radius(a), s, "load")?,
        })
    }

    /// Lee–Radok depth (m) under the MDR load `s` (m^2; F / (4 G), or I / (4 eta) for a
    /// viscous impulse I): the monotone contact's d = g(a) at `radius_at_load`; once the
    /// contact fills a disc footprint whose rim belongs to it (the rod, a tabulated profile's
    /// disc) the indenter moves on like a rod, d = g(R) + (s - s_R) / (2 R). None once the
    /// contact circle is wider than half a square's edge, where it stops being circular.
    pub fn depth_under_load(&self, s: f64) -> Result<Option<f64>> {
        let fills = matches!(self.footprint(), Footprint::Disc { rim: true, .. });
        lee_radok_depth(
            self.footprint(),
            fills,
            |s| self.radius_at_load(s),
            |x| self.profile_1d(x),
            |a| self.load_at_radius(a),
            s,
        )
    }

    /// Heights above the tip (m) of the true shape (`surface`) over the grid of element
    /// centres `x` (nx) by `y` (ny) (m), row-major (ny, nx), and whether each centre lies
    /// in the footprint; 0 outside it.
    pub fn height_map(&self, x: &[f64], y: &[f64]) -> Result<(Vec<f64>, Vec<bool>)> {
        let footprint = self.footprint();
        let mut height = Vec::with_capacity(x.len() * y.len());
        let mut inside = Vec::with_capacity(x.len() * y.len());
        for &yi in y {
            for &xi in x {
                let covered = footprint.covers(xi, yi);
                inside.push(covered);
                height.push(if covered { self.surface(xi, yi)? } else { 0.0 });
            }
        }
        Ok((height, inside))
    }

    /// Depth (m) under the MDR load `s` (m^2) while the contact fits the footprint; None
    /// once it would leave it.
    pub fn depth_at_load(&self, s: f64) -> Result<Option<f64>> {
        let a = self.radius_at_load(s)?;
        let inside = match self.footprint() {
            Footprint::Disc { radius, .. } => a < radius,
            Footprint::Square { edge } => a < 0.5 * edge,
            Footprint::Rectangle { width, length } => a < 0.5 * width.min(length),
            Footprint::Unbounded => true,
        };
        if !inside {
            return Ok(None);
        }
        self.profile_1d(a).map(Some)
    }

    /// The MDR load at contact radius `a` (m): `mdr_load` of the profile (m^2; F / E* of a
    /// hard contact of that radius).
    pub fn load_at_radius(&self, a: f64) -> Result<f64> {
        mdr_load(
            &|x: &[f64]| x.iter().map(|&v| self.profile_1d(v)).collect(),
            a,
        )
    }

    /// Where contact radii are sought: a disc footprint (filled when its rim belongs to it),
    /// else up to a table's extent (1 m for closed forms, which never search).
    fn reach(&self) -> Reach {
        match self.footprint() {
            Footprint::Disc { radius, rim } => Reach::Disc { radius, fills: rim },
            _ => Reach::Beyond {
                start: match self {
                    Indenter::Profile(p) => p.extent(),
                    _ => 1.0,
                },
                doublings: 0,
            },
        }
    }

    /// The elements (nx, ny) of the BEM grid `bem_grid` makes for the resolution `n`: a
    /// height map's own; n x n, or for a flat face the odd 2 (n / 2) + 1 that centres an
    /// element on its axis.
    pub fn bem_shape(&self, n: usize) -> (usize, usize) {
        match self {
            Indenter::HeightMap(m) => {
                let [ny, nx] = m.shape();
                (nx, ny)
            }
            _ if self.is_flat() => (2 * (n / 2) + 1, 2 * (n / 2) + 1),
            _ => (n, n),
        }
    }

    /// BEM grid over a square of half-width `half` (m) with n elements across. A flat face
    /// gets dx = 2 half / n on a grid centred on an element ((n + 1) x (n + 1) for even n:
    /// n = 200 puts 31417 elements in a disc); a height map its own grid (n must be its
    /// `HeightMap::n`); any other indenter n x n element centres symmetric about the axis,
    /// with the heights of its true shape (`surface`: a pyramid's, not its cone's).
    pub fn bem_grid(&self, n: usize, half: f64) -> Result<Grid> {
        if let Indenter::HeightMap(m) = self {
            m.check_run(crate::model::settings::Method::Bem, n)?;
            return m.grid();
        }
        let dx = 2.0 * half / n as f64;
        let (m, _) = self.bem_shape(n);
        let offset = if self.is_flat() {
            (n / 2) as f64
        } else {
            0.5 * (n as f64 - 1.0)
        };
        let centre = |i: usize| (i as f64 - offset) * dx;
        let mut height = Vec::with_capacity(m * m);
        let mut allowed = Vec::with_capacity(m * m);
        for iy in 0..m {
            for ix in 0..m {
                let (x, y) = (centre(ix), centre(iy));
                let inside = self.footprint().covers(x, y);
                allowed.push(inside);
                height.push(if inside { self.surface(x, y)? } else { 0.0 });
            }
        }
        Grid::new(m, m, dx, height, allowed)
    }

    /// MDR profile of n elements over [-half, half] (m) and their spacing (m).
    pub fn mdr_profile(&self, n: usize, half: f64) -> Result<(Vec<f64>, f64)> {
        let dx = 2.0 * half / n as f64;
        let g = (0..n)
            .map(|i| self.profile_1d((i as f64 - 0.5 * (n as f64 - 1.0)) * dx))
            .collect::<Result<Vec<f64>>>()?;
        Ok((g, dx))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generic load integral and bisection agree with the closed forms.
    #[test]
    fn numeric_radius_matches_closed_forms() {
        let p = Indenter::Paraboloid { c: 0.7, edge: None };
        let a = p.radius_at_load(0.3).unwrap();
        let numeric = bisect_radius(p.reach(), |a| p.load_at_radius(a), 0.3, "load").unwrap();
        assert!((numeric - a).abs() < 1e-9 * a);
        let d = p.radius_at_depth(0.2).unwrap();
        let bisected = bisect_radius(p.reach(), |a| p.profile_1d(a), 0.2, "depth").unwrap();
        assert!((bisected - d).abs() < 1e-12);
    }

    /// The sphere's depth at contact radius a is (a/2) ln((R + a)/(R - a)) (MDR, exact).
    #[test]
    fn sphere_radius_at_depth_inverts_its_profile() {
        let s = Indenter::Sphere { radius: 1.5 };
        let a: f64 = 0.9;
        let d = 0.5 * a * ((1.5 + a) / (1.5 - a)).ln();
        assert!((s.radius_at_depth(d).unwrap() - a).abs() < 1e-12);
    }

    /// A pyramid's BEM grid holds its exact heights; its MDR quantities are its equivalent
    /// cone's.
    #[test]
    fn pyramid_grid_is_exact_and_its_mdr_is_the_cone() {
        let alpha: f64 = 0.6;
        let p = Indenter::Pyramid {
            half_angle: alpha,
            edge: None,
        };
        let g = p.bem_grid(8, 1.0).unwrap();
        let centre = |i: usize| (i as f64 - 3.5) * 0.25;
        for (k, &h) in g.height.iter().enumerate() {
            let (x, y) = (centre(k % 8), centre(k / 8));
            assert_eq!(h, x.abs().max(y.abs()) / alpha.tan());
        }
        let cone = pyramid::equivalent_cone(alpha, None);
        for x in [0.1, 0.7] {
            assert_eq!(p.profile_1d(x).unwrap(), cone.profile_1d(x).unwrap());
            assert_eq!(p.height(x).unwrap(), cone.height(x).unwrap());
            assert_eq!(
                p.radius_at_depth(x).unwrap(),
                cone.radius_at_depth(x).unwrap()
            );
            assert_eq!(
                p.radius_at_load(x).unwrap(),
                cone.radius_at_load(x).unwrap()
            );
        }
    }

    /// Lee–Radok depths: the paraboloid's and the cone's closed forms, a filled disc moving
    /// on like a rod (8 eta R d = J past the filling load), and None past a square's edge.
    #[test]
    fn depth_under_load_follows_lee_radok() {
        let (c, s) = (0.7, 0.3);
        let d = Indenter::Paraboloid { c, edge: None }
            .depth_under_load(s)
            .unwrap()
            .unwrap();
        // s = 8 c a^3 / 3 and d = 2 c a^2
        let a = (3.0 * s / (8.0 * c)).cbrt();
        assert!((d / (2.0 * c * a * a) - 1.0).abs() < 1e-15);
        let cone = Indenter::Cone {
            slope: 0.4,
            edge: None,
        };
        let d = cone.depth_under_load(s).unwrap().unwrap();
        assert!((d / (0.5 * PI * 0.4 * s).sqrt() - 1.0).abs() < 1e-15);
        let rod = Indenter::Rod { radius: 0.5 };
        assert_eq!(rod.depth_under_load(0.3).unwrap(), Some(0.3));
        // a paraboloid table (exact cubic) on a disc of radius 0.5: filled at s = 8 c R^3 / 3
        let r: Vec<f64> = (0..11).map(|i| 0.05 * i as f64).collect();
        let table = ProfileTable {
            h: r.iter().map(|&x| c * x * x).collect(),
            slope: Some(r.iter().map(|&x| 2.0 * c * x).collect()),
            r,
            edge: None,
            radius: Some(0.5),
        };
        let disc = Indenter::Profile(Box::new(Profile::try_from(table).unwrap()));
        let filled = 8.0 * c * 0.125 / 3.0;
        let d = disc.depth_under_load(filled + 0.2).unwrap().unwrap();
        let expected = 2.0 * c * 0.25 + 0.2 / (2.0 * 0.5);
        assert!((d / expected - 1.0).abs() < 1e-10, "{d} vs {expected}");
        let square = Indenter::Paraboloid { c, edge: Some(1.0) };
        let half_edge_load = 8.0 * c * 0.125 / 3.0;
        assert!(square
            .depth_under_load(0.99 * half_edge_load)
            .unwrap()
            .is_some());
        assert_eq!(
            square.depth_under_load(1.01 * half_edge_load).unwrap(),
            None
        );
    }

    /// A profile given as a function gets the numbers of the same indenter's own: the sphere's
    /// closed-form profile through `MdrProfile` against `Indenter::Sphere`.
    #[test]
    fn a_profile_function_gets_the_indenters_numbers() {
        let sphere = Indenter::Sphere { radius: 1.5 };
        let g =
            |x: &[f64]| -> Result<Vec<f64>> { x.iter().map(|&v| sphere.profile_1d(v)).collect() };
        let mdr = MdrProfile {
            profile: &g,
            footprint: sphere.footprint(),
            reach: Reach::Disc {
                radius: 1.5,
                fills: false,
            },
        };
        for s in [1e-4, 0.2, 3.0] {
            assert_eq!(
                mdr.radius_at_load(s).unwrap(),
                sphere.radius_at_load(s).unwrap()
            );
            assert_eq!(
                mdr.depth_under_load(s).unwrap(),
                sphere.depth_under_load(s).unwrap()
            );
        }
        assert_eq!(
            mdr.radius_at_depth(0.4).unwrap(),
            sphere.radius_at_depth(0.4).unwrap()
        );
    }

    /// An unbounded profile function that levels off is sought over 2^doublings times the
    /// start, and the error names the depth.
    #[test]
    fn an_unreachable_depth_names_it() {
        let g = |x: &[f64]| -> Result<Vec<f64>> {
            Ok(x.iter().map(|&v| 1.0 - 1.0 / (1.0 + v * v)).collect())
        };
        let mdr = MdrProfile {
            profile: &g,
            footprint: Footprint::Unbounded,
            reach: Reach::Beyond {
                start: 1.0,
                doublings: 20,
            },
        };
        let e = mdr.radius_at_depth(5.0).unwrap_err().to_string();
        assert!(e.contains("up to 1048576.0 m reaches depth 5.0 m"), "{e}");
        assert!((mdr.radius_at_depth(0.5).unwrap() - 1.0).abs() < 1e-15);
    }

    /// A rod grid of n = 200 holds the 31417 elements of the paper's BEM disc.
    #[test]
    fn rod_grid_holds_the_papers_elements() {
        let g = Indenter::Rod { radius: 1.0 }.bem_grid(200, 1.0).unwrap();
        assert_eq!(g.allowed.iter().filter(|&&a| a).count(), 31417);
    }
}
