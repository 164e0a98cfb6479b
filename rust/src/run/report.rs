//! What a run computed and how: series at the output times, fields at the field times, and
//! the run's own numbers (resolution, steps, solves, iterations, residual, wall time,
//! warnings). Units: SI (see `UNITS`).

use crate::model::settings::Method;
use crate::model::Scene;
use serde::Serialize;

/// The unit of each quantity of a report.
pub const UNITS: [(&str, &str); 25] = [
    ("t", "s"),
    ("depth", "m"),
    ("contact_length", "m"),
    ("area", "m^2"),
    ("zone_area", "m^2"),
    ("zone_length", "m"),
    ("force", "N"),
    ("velocity", "m/s"),
    ("stiffness_length", "m"),
    ("central_pressure", "Pa"),
    ("contact_fraction", "1"),
    ("patches", "1"),
    ("mean_gap", "m"),
    ("dx", "m"),
    ("wall_time", "s"),
    ("pull_off_force", "N"),
    ("pull_off_depth", "m"),
    ("pull_off_time", "s"),
    ("jump_in", "s"),
    ("jump_out", "s"),
    ("pressure", "Pa"),
    ("surface_velocity", "m/s"),
    ("deflection", "m"),
    ("gap", "m"),
    ("x, y, r", "m"),
];

/// Fields at one time. BEM fields are (ny, nx) row-major maps over element centres `x`,
/// `y`; MDR fields are radial profiles at radii `r` (inverse transforms of the 1D fields).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct FieldSet {
    /// Time (s); 0 for a static scene.
    pub t: f64,
    /// Element-centre x (m) of BEM maps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub x: Option<Vec<f64>>,
    /// Element-centre y (m) of BEM maps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub y: Option<Vec<f64>>,
    /// Radii (m) of MDR profiles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r: Option<Vec<f64>>,
    /// Pressure (Pa).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pressure: Option<Vec<f64>>,
    /// Surface velocity (m/s); for a BEM flat punch over `x_extended` on both axes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface_velocity: Option<Vec<f64>>,
    /// Element centres (m) of the grid extended around a flat punch, both axes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub x_extended: Option<Vec<f64>>,
    /// Surface deflection (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub deflection: Option<Vec<f64>>,
    /// Gap (m) between a height map and the deformed surface: height below the highest
    /// point plus deflection minus depth; zero in contact up to the solver's tolerance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gap: Option<Vec<f64>>,
}

/// What a run reports. Series have one entry per output time; quantities a run did not
/// compute are None.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The method.
    pub method: Method,
    /// Resolution asked for: BEM elements across the footprint, MDR elements.
    pub n: usize,
    /// Element size (m).
    pub dx: f64,
    /// BEM grid (ny, nx); None for MDR.
    pub grid_shape: Option<[usize; 2]>,
    /// Time integration: "implicit", "explicit", "one solve" (a flat punch), "static"
    /// (elastic) or "viscoelastic" (exact exponential steps).
    pub integrator: String,
    /// Output times (s); [0] for a static scene.
    pub t: Vec<f64>,
    /// Tip depth (m).
    pub depth: Vec<f64>,
    /// Contact length (m): 2 sqrt(area / pi) (BEM) or the contact's element count times dx
    /// (MDR).
    pub contact_length: Vec<f64>,
    /// Contact area (m^2) (BEM).
    pub area: Option<Vec<f64>>,
    /// Area (m^2) of the contact and the adhesive zone around it, the elements within the
    /// law's range (BEM under a cohesive-zone law).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone_area: Option<Vec<f64>>,
    /// Outer diameter of the adhesive zone (m): 2 sqrt(zone_area / pi), as `contact_length`
    /// is of the contact (BEM under a cohesive-zone law).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone_length: Option<Vec<f64>>,
    /// Force on the indenter (N): prescribed or computed.
    pub force: Vec<f64>,
    /// Penetration rate dd/dt (m/s), viscous medium.
    pub velocity: Option<Vec<f64>>,
    /// F / (4 eta dd/dt) (m), the paper's contact length, viscous medium (F (1 - nu) /
    /// (2 eta dd/dt) for a Poisson ratio nu: 4 eta is the contact viscosity 2 eta / (1 - nu)).
    pub stiffness_length: Option<Vec<f64>>,
    /// Pressure at the centre of a flat punch (Pa).
    pub central_pressure: Option<Vec<f64>>,
    /// Real contact area over the area of the height map (1).
    pub contact_fraction: Option<Vec<f64>>,
    /// Number of contact patches of a height map (4-connected components of the contact).
    pub patches: Option<Vec<usize>>,
    /// Mean gap (m) between a height map and the deformed surface, over the map.
    pub mean_gap: Option<Vec<f64>>,
    /// Whether the contact covers the whole indenter.
    pub saturated: Option<Vec<bool>>,
    /// Whether the contact reached the outermost ring of the BEM grid.
    pub at_edge: Option<Vec<bool>>,
    /// Fields at the field times.
    pub fields: Vec<FieldSet>,
    /// Pull-off of an adhesive contact: the force (N, tensile: negative) it carried in its
    /// last state before it first let go.
    pub pull_off_force: Option<f64>,
    /// Depth (m) of the pull-off's state.
    pub pull_off_depth: Option<f64>,
    /// Time (s) of the pull-off's state.
    pub pull_off_time: Option<f64>,
    /// Times (s) of the steps at which an adhesive contact formed already carrying tension
    /// (DMT's touch); empty when none did, None under hard contact.
    pub jump_in: Option<Vec<f64>>,
    /// Times (s) of the steps at which an adhesive contact that carried tension let go;
    /// empty when none did, None under hard contact.
    pub jump_out: Option<Vec<f64>>,
    /// Time steps taken.
    pub steps: usize,
    /// Contact solves.
    pub solves: usize,
    /// Solver iterations in all.
    pub iterations: usize,
    /// The static contact solver used: "polonsky-keer" or "active-set".
    pub solver: Option<String>,
    /// Window (y0, x0, rows, columns) of the grid the last static solve ran on.
    pub window: Option<[usize; 4]>,
    /// Iterations of each grid level of a static BEM solve, coarsest first and the solved
    /// grid last (one entry without nested levels); they sum to `iterations`.
    pub level_iterations: Option<Vec<usize>>,
    /// Largest final relative residual of the contact solves.
    pub residual: f64,
    /// Wall time of the run (s).
    pub wall_time: f64,
    /// What the caller should know about the result's accuracy.
    pub warnings: Vec<String>,
}

/// Contacts narrower than this many elements are flagged as under-resolved.
pub const MIN_CONTACT_ELEMENTS: f64 = 10.0;

impl Report {
    /// The report at the output times `t` (s), entry k of each series taken from the solved
    /// output `from[k]`.
    pub fn expand(&mut self, t: Vec<f64>, from: &[usize]) {
        fn pick<T: Copy>(v: &mut Vec<T>, from: &[usize]) {
            *v = from.iter().map(|&k| v[k]).collect();
        }
        pick(&mut self.depth, from);
        pick(&mut self.contact_length, from);
        pick(&mut self.force, from);
        for v in [
            &mut self.area,
            &mut self.zone_area,
            &mut self.zone_length,
            &mut self.velocity,
            &mut self.stiffness_length,
            &mut self.central_pressure,
            &mut self.contact_fraction,
            &mut self.mean_gap,
        ]
        .into_iter()
        .flatten()
        {
            pick(v, from);
        }
        if let Some(v) = &mut self.patches {
            pick(v, from);
        }
        for v in [&mut self.saturated, &mut self.at_edge]
            .into_iter()
            .flatten()
        {
            pick(v, from);
        }
        self.t = t;
    }

    /// Flags output times whose contact spans fewer than `MIN_CONTACT_ELEMENTS` elements (but
    /// some: no contact, after separation, is resolved at any n). A height map's contact is
    /// measured patch by patch: the diameter of the disc of a patch's mean area; its grid
    /// is the map's own, so the advice is to sample the map finer, not to refine n.
    pub fn check_resolution(&mut self) {
        let span = |k: usize| -> f64 {
            match (&self.patches, &self.contact_fraction, self.grid_shape) {
                (Some(patches), Some(fraction), Some([ny, nx])) if patches[k] > 0 => {
                    let elements = fraction[k] * (nx * ny) as f64 / patches[k] as f64;
                    2.0 * (elements / std::f64::consts::PI).sqrt()
                }
                (Some(_), Some(_), Some(_)) => 0.0,
                _ => self.contact_length[k] / self.dx,
            }
        };
        let thin: Vec<usize> = (0..self.t.len())
            .filter(|&k| {
                let elements = span(k);
                elements > 0.0 && elements < MIN_CONTACT_ELEMENTS
            })
            .collect();
        let (Some(&first), Some(&last)) = (thin.first(), thin.last()) else {
            return;
        };
        let min = thin.iter().map(|&k| span(k)).fold(f64::INFINITY, f64::min);
        let when = if thin.len() == 1 {
            format!("at t = {} s", self.t[first])
        } else {
            format!(
                "at {} output times from t = {} s to {} s",
                thin.len(),
                self.t[first],
                self.t[last]
            )
        };
        let method = self.method.name().to_uppercase();
        self.warnings.push(if self.patches.is_some() {
            format!(
                "{method}: the contact patches span fewer than {MIN_CONTACT_ELEMENTS} elements on average (min {min:.1}) {when}; a rough contact's area converges slowly with the map's sampling: expect errors of several percent in the area (check on a map sampled finer)"
            )
        } else {
            format!(
                "{method}: the contact spans fewer than {MIN_CONTACT_ELEMENTS} elements (min {min:.1}) {when}; its edge is resolved to an element, so expect errors {} there (refine n)",
                if min > 2.0 {
                    // a length of m elements is within one element of the true m - 1 or more
                    format!("up to about {:.0} %", 100.0 / (min - 1.0))
                } else {
                    "above 100 %".to_string()
                }
            )
        });
    }

    /// One line: method, resolution, steps, solves, iterations, residual, wall time.
    pub fn summary(&self) -> String {
        format!(
            "{} n={} dx={:.4e} m steps={} solves={} iterations={} residual={:.2e} wall={:.3} s",
            self.method.name().to_uppercase(),
            self.n,
            self.dx,
            self.steps,
            self.solves,
            self.iterations,
            self.residual,
            self.wall_time
        )
    }

    /// A text table of the series, headed by `name` and the summary.
    pub fn table(&self, name: &str) -> String {
        let mut out = format!("{name} — {}\n", self.summary());
        if let Some(p0) = &self.central_pressure {
            out += &format!("  central pressure p0 = {:.6} Pa\n", p0[p0.len() - 1]);
        }
        if let (Some(f), Some(d), Some(t)) =
            (self.pull_off_force, self.pull_off_depth, self.pull_off_time)
        {
            out += &format!("  pull-off force {f:.8e} N at depth {d:.8e} m, t = {t} s\n");
        }
        for (name, times) in [("jump-in", &self.jump_in), ("jump-out", &self.jump_out)] {
            if let Some(times) = times.as_ref().filter(|v| !v.is_empty()) {
                out += &format!("  {name} at t = {times:?} s\n");
            }
        }
        let numbers = |v: &[f64]| v.iter().map(|x| format!("{x:>14.8}")).collect();
        let mut columns: Vec<(&str, Vec<String>)> = vec![
            ("t [s]", numbers(&self.t)),
            ("d [m]", numbers(&self.depth)),
            ("l [m]", numbers(&self.contact_length)),
            ("F [N]", numbers(&self.force)),
        ];
        if let Some(v) = &self.velocity {
            columns.push(("dd/dt [m/s]", numbers(v)));
        }
        if let Some(v) = &self.stiffness_length {
            columns.push(("l_F [m]", numbers(v)));
        }
        if let Some(v) = &self.zone_length {
            columns.push(("l_zone [m]", numbers(v)));
        }
        if let (Some(area), Some(fraction), Some(patches), Some(gap)) = (
            &self.area,
            &self.contact_fraction,
            &self.patches,
            &self.mean_gap,
        ) {
            let scientific = |v: &[f64]| v.iter().map(|x| format!("{x:>14.6e}")).collect();
            columns.push(("A [m^2]", scientific(area)));
            columns.push(("A/A0", numbers(fraction)));
            columns.push((
                "patches",
                patches.iter().map(|p| format!("{p:>14}")).collect(),
            ));
            columns.push(("mean gap [m]", scientific(gap)));
        }
        out += "  ";
        out += &columns
            .iter()
            .map(|(h, _)| format!("{h:>14}"))
            .collect::<Vec<_>>()
            .join(" ");
        out += "\n";
        for k in 0..self.t.len() {
            out += "  ";
            out += &columns
                .iter()
                .map(|(_, v)| v[k].as_str())
                .collect::<Vec<_>>()
                .join(" ");
            out += "\n";
        }
        for w in &self.warnings {
            out += &format!("  warning: {w}\n");
        }
        out
    }

    /// The report as one JSON entry of a run document: `{"scene": name, "input": the
    /// scene, "n": .., "result": the report, "units": {...}}`.
    pub fn document(&self, name: &str, scene: &Scene) -> serde_json::Value {
        let units: serde_json::Map<String, serde_json::Value> = UNITS
            .iter()
            .map(|(k, u)| (k.to_string(), serde_json::Value::String(u.to_string())))
            .collect();
        serde_json::json!({
            "scene": name,
            "input": scene,
            "result": self,
            "units": units,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::quantities::{unit, QUANTITIES};

    /// The document's units (`UNITS`, the coordinates x, y, r as one entry) are those of
    /// `QUANTITIES`, every quantity with a unit among them but the flat punch's extended
    /// axis.
    #[test]
    fn document_units_are_the_quantities_units() {
        let mut named = vec![];
        for (names, u) in UNITS {
            for name in names.split(", ") {
                assert_eq!(unit(name), Some(u), "{name}");
                named.push(name);
            }
        }
        for (name, u, _) in QUANTITIES {
            assert_eq!(
                !u.is_empty() && name != "x_extended",
                named.contains(&name),
                "{name}"
            );
        }
    }
}
