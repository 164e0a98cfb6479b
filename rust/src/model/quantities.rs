//! The quantities a run reports, decided once: every series, number, shape, coordinate and
//! field of a report with its unit (SI) and kind. The report's JSON, the outputs a scene may
//! ask for and the Python `Result` all read this table.

/// What a quantity of a report is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuantityKind {
    /// One value per output time.
    Series,
    /// One number or label of the run.
    Scalar,
    /// A tuple of integers (a grid's shape, a window).
    Shape,
    /// A field at a field time: a map (BEM) or a radial profile (MDR).
    Field,
    /// The positions a field is given at.
    Coordinate,
    /// Times of the events of a run, any number of them (jumps of an adhesive contact).
    Events,
}

impl QuantityKind {
    /// "series", "scalar", "shape", "field", "coordinate" or "events".
    pub fn name(self) -> &'static str {
        match self {
            QuantityKind::Series => "series",
            QuantityKind::Scalar => "scalar",
            QuantityKind::Shape => "shape",
            QuantityKind::Field => "field",
            QuantityKind::Coordinate => "coordinate",
            QuantityKind::Events => "events",
        }
    }
}

/// Every quantity of a `Report` and its `FieldSet`s but the fields list and the warnings:
/// name, unit (SI; empty for counts, flags and labels) and kind. Each kind in the order the
/// Python `Result` lists it.
pub const QUANTITIES: [(&str, &str, QuantityKind); 41] = [
    ("t", "s", QuantityKind::Series),
    ("depth", "m", QuantityKind::Series),
    ("contact_length", "m", QuantityKind::Series),
    ("force", "N", QuantityKind::Series),
    ("area", "m^2", QuantityKind::Series),
    ("zone_area", "m^2", QuantityKind::Series),
    ("zone_length", "m", QuantityKind::Series),
    ("velocity", "m/s", QuantityKind::Series),
    ("stiffness_length", "m", QuantityKind::Series),
    ("central_pressure", "Pa", QuantityKind::Series),
    ("contact_fraction", "1", QuantityKind::Series),
    ("patches", "1", QuantityKind::Series),
    ("mean_gap", "m", QuantityKind::Series),
    ("saturated", "", QuantityKind::Series),
    ("at_edge", "", QuantityKind::Series),
    ("method", "", QuantityKind::Scalar),
    ("n", "", QuantityKind::Scalar),
    ("dx", "m", QuantityKind::Scalar),
    ("integrator", "", QuantityKind::Scalar),
    ("steps", "", QuantityKind::Scalar),
    ("solves", "", QuantityKind::Scalar),
    ("iterations", "", QuantityKind::Scalar),
    ("residual", "", QuantityKind::Scalar),
    ("wall_time", "s", QuantityKind::Scalar),
    ("solver", "", QuantityKind::Scalar),
    ("pull_off_force", "N", QuantityKind::Scalar),
    ("pull_off_depth", "m", QuantityKind::Scalar),
    ("pull_off_time", "s", QuantityKind::Scalar),
    ("grid_shape", "", QuantityKind::Shape),
    ("window", "", QuantityKind::Shape),
    ("level_iterations", "", QuantityKind::Shape),
    ("jump_in", "s", QuantityKind::Events),
    ("jump_out", "s", QuantityKind::Events),
    ("x", "m", QuantityKind::Coordinate),
    ("y", "m", QuantityKind::Coordinate),
    ("r", "m", QuantityKind::Coordinate),
    ("x_extended", "m", QuantityKind::Coordinate),
    ("pressure", "Pa", QuantityKind::Field),
    ("surface_velocity", "m/s", QuantityKind::Field),
    ("deflection", "m", QuantityKind::Field),
    ("gap", "m", QuantityKind::Field),
];

/// The unit of the report quantity `name` (`QUANTITIES`), None for an unknown name.
pub fn unit(name: &str) -> Option<&'static str> {
    QUANTITIES
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, u, _)| *u)
}
