//! The scene: what to compute (indenter, medium, loading, outputs and their times), its
//! validation and defaults and its TOML and JSON forms. `crate::run` solves it into a typed
//! `Report`. Units are SI: m, s, N, Pa, Pa s.

use super::body::{Body, Layer};
use super::contact_law::ContactLaw;
use super::{Indenter, Medium};
use crate::model::loading::{DepthHistory, ForceHistory, Loading};
use crate::support::error::{check_finite, check_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// A force (N) or depth (m) history: a constant from t = 0, or samples [t (s), value],
/// piecewise linear from t = 0 and held after the last sample.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged, expecting = "a number or a list of [t, value] pairs")]
pub enum History {
    /// A constant from t = 0.
    Constant(f64),
    /// Samples [t, value], t from 0 and increasing.
    Samples(Vec<[f64; 2]>),
}

impl History {
    /// Sample times (s) and values.
    pub fn samples(&self) -> (Vec<f64>, Vec<f64>) {
        match self {
            History::Constant(v) => (vec![0.0], vec![*v]),
            History::Samples(s) => s.iter().map(|p| (p[0], p[1])).unzip(),
        }
    }

    /// Largest value of the history.
    pub fn max(&self) -> f64 {
        self.samples()
            .1
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Value after the last sample.
    pub fn last(&self) -> f64 {
        *self.samples().1.last().unwrap_or(&f64::NAN)
    }

    /// The validated force history (N; a constant must be > 0, samples what `law` carries).
    pub fn force(&self, law: ContactLaw) -> Result<ForceHistory> {
        match self {
            History::Constant(f) => {
                check_positive("force", *f)?;
                ForceHistory::constant(*f)
            }
            History::Samples(_) => {
                let (t, f) = self.samples();
                let history = ForceHistory::piecewise_linear(t, f.clone())?;
                f.iter().try_for_each(|&v| law.check_force(v))?;
                Ok(history)
            }
        }
    }

    /// The validated depth history (m).
    pub fn depth(&self) -> Result<DepthHistory> {
        let (t, d) = self.samples();
        DepthHistory::piecewise_linear(t, d)
    }
}

/// What a scene can be asked to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Output {
    /// Tip depth d (m); always computed.
    Depth,
    /// Contact length (m) from the contact area (BEM) or the element count (MDR); always
    /// computed.
    ContactLength,
    /// Penetration rate dd/dt (m/s) of a viscous medium.
    Velocity,
    /// F / (4 eta dd/dt) (m), the paper's contact length (Eq. 23) of a viscous medium
    /// (F (1 - nu) / (2 eta dd/dt) for a Poisson ratio nu).
    StiffnessLength,
    /// Pressure field (Pa) at the field times.
    Pressure,
    /// Surface velocity field (m/s) of a viscous medium at the field times.
    SurfaceVelocity,
    /// Surface deflection field (m) at the field times.
    Deflection,
    /// Real contact area over the area of a height map (1); always computed for one.
    ContactFraction,
    /// Number of contact patches of a height map; always computed for one.
    Patches,
    /// Mean gap (m) between a height map and the deformed surface, over the map; always
    /// computed for one.
    MeanGap,
    /// Gap field (m) of a height map at the field times: height below the highest point
    /// plus deflection minus depth, zero in contact.
    Gap,
}

impl Output {
    /// Whether the output is a field (built at the field times only).
    pub fn is_field(self) -> bool {
        matches!(
            self,
            Output::Pressure | Output::SurfaceVelocity | Output::Deflection | Output::Gap
        )
    }

    /// Whether the output belongs to height maps only.
    pub fn is_height_map(self) -> bool {
        matches!(
            self,
            Output::ContactFraction | Output::Patches | Output::MeanGap | Output::Gap
        )
    }
}

/// Whether an output is a series (one value per output time) or a field (a map or a radial
/// profile at each field time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    /// One value per output time.
    Series,
    /// A map (BEM) or a radial profile (MDR) at each field time.
    Field,
}

impl OutputKind {
    /// "series" or "field".
    pub fn name(self) -> &'static str {
        match self {
            OutputKind::Series => "series",
            OutputKind::Field => "field",
        }
    }
}

impl Output {
    /// Every output, in the order the scene files' documentation lists them.
    pub const ALL: [Output; 11] = [
        Output::Depth,
        Output::ContactLength,
        Output::Velocity,
        Output::StiffnessLength,
        Output::Pressure,
        Output::SurfaceVelocity,
        Output::Deflection,
        Output::ContactFraction,
        Output::Patches,
        Output::MeanGap,
        Output::Gap,
    ];

    /// The output's name in scene files, reports and the Python package.
    pub fn name(self) -> &'static str {
        match self {
            Output::Depth => "depth",
            Output::ContactLength => "contact_length",
            Output::Velocity => "velocity",
            Output::StiffnessLength => "stiffness_length",
            Output::Pressure => "pressure",
            Output::SurfaceVelocity => "surface_velocity",
            Output::Deflection => "deflection",
            Output::ContactFraction => "contact_fraction",
            Output::Patches => "patches",
            Output::MeanGap => "mean_gap",
            Output::Gap => "gap",
        }
    }

    /// The unit of the output's values (SI), from the table `crate::model::quantities::QUANTITIES`.
    pub fn unit(self) -> &'static str {
        super::quantities::unit(self.name()).expect("every output is a quantity of the report")
    }

    /// A series or a field.
    pub fn kind(self) -> OutputKind {
        if self.is_field() {
            OutputKind::Field
        } else {
            OutputKind::Series
        }
    }

    /// Whether a scene that names no outputs computes it (`DEFAULT_OUTPUTS`).
    pub fn is_default(self) -> bool {
        DEFAULT_OUTPUTS.contains(&self)
    }
}

/// A rigid indenter pressed into a half-space: what to compute, independent of the method.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The indenter.
    pub indenter: Indenter,
    /// The half-space, or the layer's material.
    pub medium: Medium,
    /// A layer of the medium on a rigid base in place of the half-space (absent: a
    /// half-space).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<Layer>,
    /// How the indenter and the body interact (default hard contact).
    #[serde(default, skip_serializing_if = "ContactLaw::is_hard")]
    pub contact: ContactLaw,
    /// Force history (N); give this or `depth`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force: Option<History>,
    /// Depth history (m; negative holds the tip above the surface); give this or `force`.
    /// An elastic scene is solved statically at its last depth, for the force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<History>,
    /// Simulated time (s); required unless the medium is elastic (a static solve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Output times (s) in (0, duration], increasing; default five equal steps up to the
    /// duration.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub times: Option<Vec<f64>>,
    /// What to compute; default depth and contact length. Fields only when named.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outputs: Option<Vec<Output>>,
    /// Times (s) of the field outputs; default the duration. Added to the output times.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field_times: Option<Vec<f64>>,
    /// Longest time step (s) of the viscoelastic stepping; default duration / 500.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
}

/// Outputs of a scene that names none.
pub const DEFAULT_OUTPUTS: [Output; 2] = [Output::Depth, Output::ContactLength];

/// Number of default output times.
const DEFAULT_TIMES: usize = 5;

impl Scene {
    /// Parses and validates a scene from JSON text.
    pub fn from_json(text: &str) -> Result<Self> {
        let mut de = serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(&mut de)
            .map_err(|e| Error::InvalidInput(format!("scene: {}", keyed(e))))?;
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a validated scene serialises")
    }

    /// Fails unless the scene is complete and consistent; error messages name the key.
    pub fn validate(&self) -> Result<()> {
        self.indenter.validate()?;
        self.medium.validate()?;
        self.contact.validate()?;
        if let Some(layer) = &self.layer {
            layer.validate()?;
        }
        match (&self.force, &self.depth) {
            (Some(f), None) => {
                f.force(self.contact)?;
            }
            (None, Some(d)) => {
                // validated finite
                let history = d.depth()?;
                let last = d.last();
                if self.is_static() && last <= 0.0 {
                    return Err(Error::InvalidInput(format!(
                        "an elastic scene held at a depth needs a final depth > 0 (m), got {last:e}: at or above the surface it carries no force"
                    )));
                }
                let start = history.depth(0.0);
                if self.medium.has_dashpot() && start > 0.0 {
                    return Err(Error::InvalidInput(format!(
                        "a depth already there at t = 0 ({start:e} m) needs an infinite force on a medium with a dashpot: start the depth history from 0 or after t = 0"
                    )));
                }
            }
            (None, None) => {
                return Err(Error::InvalidInput(
                    "missing key 'force' (or 'depth')".into(),
                ))
            }
            (Some(_), Some(_)) => {
                return Err(Error::InvalidInput(
                    "give only one of the keys 'force' and 'depth'".into(),
                ))
            }
        }
        if let Some(dt) = self.dt {
            crate::support::error::check_finite_positive("dt", dt)?;
        }
        if self.is_static() {
            if self.duration.is_some() || self.times.is_some() || self.field_times.is_some() {
                return Err(Error::InvalidInput(
                    "an elastic scene is static: give no duration, times or field_times".into(),
                ));
            }
            return Ok(());
        }
        let duration = self.duration.ok_or_else(|| {
            Error::InvalidInput(
                "missing key 'duration' (s): the medium is time-dependent or the contact adhesive"
                    .into(),
            )
        })?;
        check_positive("duration", duration)?;
        if let Some(dt) = self.dt {
            crate::model::settings::check_steps(dt, duration, duration / dt)?;
        }
        check_times("times", &self.requested_times(), duration)?;
        check_times("field_times", &self.requested_field_times(), duration)?;
        let times = self.requested_times();
        if times.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::InvalidInput(format!(
                "times must increase, got {times:?}"
            )));
        }
        Ok(())
    }

    /// Whether the scene is one static solve: an elastic medium in hard contact (an
    /// adhesive contact follows its loading history, for its pull-off depends on it).
    pub fn is_static(&self) -> bool {
        self.medium.is_elastic() && !self.contact.is_adhesive()
    }

    /// The outputs asked for.
    pub fn outputs(&self) -> Vec<Output> {
        self.outputs
            .clone()
            .unwrap_or_else(|| DEFAULT_OUTPUTS.to_vec())
    }

    /// Whether the scene asks for `output`.
    pub fn wants(&self, output: Output) -> bool {
        self.outputs().contains(&output)
    }

    /// The body the scene presses into, decided here once: one cell of a periodic surface
    /// for a periodic height map, a free surface otherwise; of a half-space, or of the
    /// scene's layer (with the medium's Poisson ratio).
    pub fn body(&self) -> Body {
        let surface = match &self.indenter {
            Indenter::HeightMap(map) => map.body(),
            _ => Body::HalfSpace,
        };
        match self.layer {
            None => surface,
            Some(layer) => Body::Layer {
                layer,
                nu: self.medium.nu(),
                periodic: surface.is_periodic(),
            },
        }
    }

    /// Whether any field is asked for.
    pub fn wants_fields(&self) -> bool {
        self.outputs().iter().any(|o| o.is_field())
    }

    /// The loading: force or depth history.
    pub fn loading(&self) -> Result<Loading> {
        match (&self.force, &self.depth) {
            (Some(f), _) => f.force(self.contact).map(Loading::Force),
            (None, Some(d)) => d.depth().map(Loading::Depth),
            (None, None) => Err(Error::InvalidInput(
                "missing key 'force' (or 'depth')".into(),
            )),
        }
    }

    /// What a static scene (`is_static`) is solved under: its final force (N) or depth (m),
    /// held from t = 0.
    pub fn held_loading(&self) -> Result<Loading> {
        match (&self.force, &self.depth) {
            (Some(f), _) => ForceHistory::constant(f.last()).map(Loading::Force),
            (None, Some(d)) => {
                DepthHistory::piecewise_linear(vec![0.0], vec![d.last()]).map(Loading::Depth)
            }
            (None, None) => Err(Error::InvalidInput(
                "missing key 'force' (or 'depth')".into(),
            )),
        }
    }

    fn duration_or_zero(&self) -> f64 {
        self.duration.unwrap_or(0.0)
    }

    /// Output times as given, or the default: five equal steps up to the duration
    /// (numpy's `linspace(duration / 5, duration, 5)`).
    fn requested_times(&self) -> Vec<f64> {
        let duration = self.duration_or_zero();
        self.times.clone().unwrap_or_else(|| {
            let start = duration / DEFAULT_TIMES as f64;
            let step = (duration - start) / (DEFAULT_TIMES - 1) as f64;
            (0..DEFAULT_TIMES)
                .map(|k| {
                    if k == DEFAULT_TIMES - 1 {
                        duration
                    } else {
                        start + k as f64 * step
                    }
                })
                .collect()
        })
    }

    fn requested_field_times(&self) -> Vec<f64> {
        self.field_times
            .clone()
            .unwrap_or_else(|| vec![self.duration_or_zero()])
    }

    /// The field times (s): empty when no field is asked for; [0] for a static scene.
    pub fn field_times(&self) -> Vec<f64> {
        if !self.wants_fields() {
            vec![]
        } else if self.is_static() {
            vec![0.0]
        } else {
            self.requested_field_times()
        }
    }

    /// Times (s) the solvers run to: the `output_times`, each within `COINCIDENT_TIMES` of
    /// its value of the previous one merged into it.
    pub fn solved_times(&self) -> Vec<f64> {
        let mut solved: Vec<f64> = vec![];
        for t in self.output_times() {
            match solved.last() {
                Some(&prev) if t - prev <= COINCIDENT_TIMES * t => {}
                _ => solved.push(t),
            }
        }
        solved
    }

    /// For each of the `output_times`, the index of the solved time it is reported from.
    pub fn solved_from(&self) -> Vec<usize> {
        let solved = self.solved_times();
        self.output_times()
            .iter()
            .map(|&t| solved.partition_point(|&s| s <= t) - 1)
            .collect()
    }

    /// Output times (s) of the report: the requested ones plus field times not within
    /// round-off (1e-12 duration) of one of them, sorted; [0] for a static scene.
    pub fn output_times(&self) -> Vec<f64> {
        if self.is_static() {
            return vec![0.0];
        }
        let mut times = self.requested_times();
        let tol = 1e-12 * self.duration_or_zero();
        for f in self.field_times() {
            if !times.iter().any(|&t| (t - f).abs() <= tol) {
                times.push(f);
            }
        }
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }

    /// Index into `solved_times` of each field time.
    pub fn field_steps(&self) -> Vec<usize> {
        let times = self.solved_times();
        self.field_times()
            .iter()
            .map(|&f| {
                (0..times.len())
                    .min_by(|&a, &b| (times[a] - f).abs().total_cmp(&(times[b] - f).abs()))
                    .unwrap_or(0)
            })
            .collect()
    }

    /// Each field time (s) with its index into `solved_times`.
    pub fn field_points(&self) -> Vec<(f64, usize)> {
        self.field_times()
            .into_iter()
            .zip(self.field_steps())
            .collect()
    }
}

/// A deserialisation error with the dotted key it happened at: "key 'indenter.c': ...".
pub(crate) fn keyed<E: std::fmt::Display>(e: serde_path_to_error::Error<E>) -> String {
    let path = e.path().to_string();
    let inner = e.inner().to_string();
    // toml repeats the key on a second line ("in `indenter`"): the path says it already
    let inner = inner.lines().next().unwrap_or("").trim_end();
    if path == "." || path.is_empty() {
        inner.to_string()
    } else {
        format!("key '{path}': {inner}")
    }
}

/// Fails unless `times` are finite and in (0, duration].
fn check_times(name: &str, times: &[f64], duration: f64) -> Result<()> {
    if times.is_empty() {
        return Err(Error::InvalidInput(format!("{name} must not be empty")));
    }
    check_finite(name, times)?;
    if let Some(t) = times
        .iter()
        .find(|&&t| t <= 0.0 || t > duration * (1.0 + 1e-12))
    {
        return Err(Error::InvalidInput(format!(
            "{name} must lie in (0, duration = {duration}], got {t}"
        )));
    }
    let earliest = EARLIEST_TIME * duration;
    if let Some(t) = times.iter().find(|&&t| t < earliest) {
        return Err(Error::InvalidInput(format!(
            "{name}: {t:e} s is too close to the start to resolve in double precision; \
             output times must be >= {EARLIEST_TIME:e} of the duration ({earliest:e} s)"
        )));
    }
    Ok(())
}

/// Earliest output time, as a fraction of the duration: a solve at an impulse or a step
/// this much smaller than the run's own works at the edge of double precision.
pub const EARLIEST_TIME: f64 = 1e-12;

/// Output times closer than this fraction of their value to the previous one are reported
/// from the same solved state: a step that short is below what the contact solves resolve,
/// and the state changes by less than this relative amount across it.
pub const COINCIDENT_TIMES: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::medium::INCOMPRESSIBLE;
    use crate::model::{file, HeightMap, Method, RunSettings, SceneFile};

    fn viscous(indenter: Indenter) -> Scene {
        Scene {
            indenter,
            layer: None,
            contact: ContactLaw::Hard,
            medium: Medium::Viscous {
                eta: 1.0,
                nu: INCOMPRESSIBLE,
            },
            force: Some(History::Constant(1.0)),
            depth: None,
            duration: Some(5.0),
            times: None,
            outputs: None,
            field_times: None,
            dt: None,
        }
    }

    fn paraboloid() -> Scene {
        viscous(Indenter::Paraboloid {
            c: 1.0,
            edge: Some(2.56),
        })
    }

    /// The list of outputs is complete, and each name is the one scene files use.
    #[test]
    fn outputs_are_listed_once_by_their_file_names() {
        let position = |o: Output| match o {
            Output::Depth => 0,
            Output::ContactLength => 1,
            Output::Velocity => 2,
            Output::StiffnessLength => 3,
            Output::Pressure => 4,
            Output::SurfaceVelocity => 5,
            Output::Deflection => 6,
            Output::ContactFraction => 7,
            Output::Patches => 8,
            Output::MeanGap => 9,
            Output::Gap => 10,
        };
        for (k, o) in Output::ALL.into_iter().enumerate() {
            assert_eq!(position(o), k);
            assert_eq!(
                serde_json::to_string(&o).unwrap(),
                format!("\"{}\"", o.name())
            );
            assert!(!o.unit().is_empty());
        }
        assert_eq!(Output::Pressure.unit(), "Pa");
        assert_eq!(Output::Gap.kind(), OutputKind::Field);
    }

    #[test]
    fn default_times_and_field_times() {
        let mut s = paraboloid();
        assert_eq!(s.output_times(), vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert!(s.field_times().is_empty());
        s.outputs = Some(vec![Output::Depth, Output::Pressure]);
        s.field_times = Some(vec![2.5, 4.0]);
        assert_eq!(s.output_times(), vec![1.0, 2.0, 2.5, 3.0, 4.0, 5.0]);
        assert_eq!(s.field_steps(), vec![2, 4]);
    }

    /// Times within 1e-9 of their value are solved once and reported twice; a field time
    /// among them maps to the solved one.
    #[test]
    fn coincident_times_are_solved_once() {
        let mut s = paraboloid();
        s.times = Some(vec![1.0, 1.0 + 1e-10, 3.0, 3.0 + 1e-6]);
        s.outputs = Some(vec![Output::Depth, Output::Pressure]);
        s.field_times = Some(vec![1.0 + 1e-10]);
        assert_eq!(s.output_times(), vec![1.0, 1.0 + 1e-10, 3.0, 3.0 + 1e-6]);
        assert_eq!(s.solved_times(), vec![1.0, 3.0, 3.0 + 1e-6]);
        assert_eq!(s.solved_from(), vec![0, 0, 1, 2]);
        assert_eq!(s.field_steps(), vec![0]);
    }

    #[test]
    fn inconsistent_scenes_are_refused_naming_the_key() {
        let refused = |s: Scene, word: &str| {
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        };
        let mut s = paraboloid();
        s.force = None;
        refused(s, "force");
        let mut s = paraboloid();
        s.depth = Some(History::Constant(0.1));
        refused(s, "only one");
        let mut s = paraboloid();
        s.times = Some(vec![1.0, 6.0]);
        refused(s, "times");
        let mut s = paraboloid();
        s.dt = Some(1e-300);
        refused(s, "steps");
        let mut s = paraboloid();
        s.medium = Medium::Elastic {
            g: 1.0,
            nu: INCOMPRESSIBLE,
        };
        refused(s, "static");
        let mut s = paraboloid();
        s.duration = None;
        refused(s, "duration");
    }

    /// A height map's scene file names the .npy written beside it, and reads back the same
    /// scene, n included; inline heights read back too.
    #[test]
    fn height_map_scene_files_round_trip_through_their_npy() {
        let heights = vec![0.1, -0.25, 1.0 / 3.0, 2e-7, 0.0, -1.5];
        let map = HeightMap::new(2, 3, heights, 0.5, true).unwrap();
        let mut scene = viscous(Indenter::HeightMap(Box::new(map)));
        scene.medium = Medium::Elastic {
            g: 1.0,
            nu: INCOMPRESSIBLE,
        };
        scene.duration = None;
        let dir = std::env::temp_dir().join(format!("mdrvisc-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("cell.toml");
        let text = file::write(&scene, Some((Method::Bem, 3)), &path).unwrap();
        assert!(text.contains("heights = \"cell.npy\""), "{text}");
        let back = SceneFile::load(path.to_str().unwrap()).unwrap();
        assert_eq!((back.scene.clone(), back.settings.n), (scene.clone(), 3));
        let inline =
            file::to_toml(&scene, None).replace("[indenter]", "method = \"bem\"\n[indenter]");
        let parsed = SceneFile::parse(&inline, "inline").unwrap();
        assert_eq!((parsed.scene, parsed.settings.n), (scene, 3));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn scene_files_round_trip_through_toml() {
        let mut s = viscous(Indenter::Sphere { radius: 2.0 });
        s.force = Some(History::Samples(vec![[0.0, 0.0], [1.0, 0.1 + 0.2]]));
        s.outputs = Some(vec![Output::Depth, Output::Deflection]);
        s.field_times = Some(vec![1.0 / 3.0]);
        let file = SceneFile {
            scene: s,
            settings: RunSettings::new(Method::Mdr, 1001),
        };
        let back = SceneFile::parse(&file.to_toml(), "test").unwrap();
        assert_eq!(back, file);
        let json = Scene::from_json(&file.scene.to_json()).unwrap();
        assert_eq!(json, file.scene);
    }
}
