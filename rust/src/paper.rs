//! The scenes of the paper (Kürschner & Filippov 2012): the flat rod of its Section 5 and the
//! paraboloids of its Section 6, with the paper's resolutions. The binary's `paper` command
//! and the Python package's `mdrvisc.paper` both run these.

use crate::model::contact_law::ContactLaw;
use crate::model::medium::INCOMPRESSIBLE;
use crate::model::{History, Indenter, Medium, Method, Output, RunSettings, Scene};

/// Curvature parameters c (1/m) of the paraboloids of Section 6.
pub const CURVATURES: [f64; 5] = [0.05, 0.2, 1.0, 5.0, 20.0];
/// Edge of the paraboloids' square footprint (m).
pub const EDGE: f64 = 2.56;
/// Force on every indenter (N).
pub const FORCE: f64 = 1.0;
/// Viscosity of the half-space (Pa s).
pub const ETA: f64 = 1.0;
/// Radius of the rod (m).
pub const ROD_RADIUS: f64 = 1.0;
/// Simulated time of the paraboloids (s).
pub const DURATION: f64 = 5.0;

/// Resolutions of one run of the comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resolutions {
    /// BEM rod: elements across the diameter (200: the paper's 31417 in the disc).
    pub rod_bem: usize,
    /// MDR rod elements.
    pub rod_mdr: usize,
    /// BEM paraboloid grid side.
    pub paraboloid_bem: usize,
    /// MDR paraboloid elements.
    pub paraboloid_mdr: usize,
}

/// The paper's resolutions, or coarse ones that run in seconds (`quick`).
pub fn resolutions(quick: bool) -> Resolutions {
    if quick {
        Resolutions {
            rod_bem: 50,
            rod_mdr: 4097,
            paraboloid_bem: 65,
            paraboloid_mdr: 4097,
        }
    } else {
        Resolutions {
            rod_bem: 200,
            rod_mdr: 66049,
            paraboloid_bem: 257,
            paraboloid_mdr: 66049,
        }
    }
}

/// Section 5: a flat rod pressed by 1 N into a viscous half-space for 1 s, with its
/// pressure and surface velocity.
pub fn rod() -> Scene {
    Scene {
        indenter: Indenter::Rod { radius: ROD_RADIUS },
        contact: ContactLaw::Hard,
        medium: Medium::Viscous {
            eta: ETA,
            nu: INCOMPRESSIBLE,
        },
        force: Some(History::Constant(FORCE)),
        depth: None,
        duration: Some(1.0),
        times: Some(vec![1.0]),
        outputs: Some(vec![
            Output::Depth,
            Output::ContactLength,
            Output::Velocity,
            Output::Pressure,
            Output::SurfaceVelocity,
        ]),
        field_times: None,
        dt: None,
    }
}

/// Section 6: a paraboloid h = c r^2 on the 2.56 m square, 1 N for 5 s, with the paper's
/// contact length F / (4 eta dd/dt).
pub fn paraboloid(c: f64) -> Scene {
    Scene {
        indenter: Indenter::Paraboloid {
            c,
            edge: Some(EDGE),
        },
        contact: ContactLaw::Hard,
        medium: Medium::Viscous {
            eta: ETA,
            nu: INCOMPRESSIBLE,
        },
        force: Some(History::Constant(FORCE)),
        depth: None,
        duration: Some(DURATION),
        times: None,
        outputs: Some(vec![
            Output::Depth,
            Output::ContactLength,
            Output::StiffnessLength,
        ]),
        field_times: None,
        dt: None,
    }
}

/// Every run of the comparison: a name, the scene and how it is solved.
pub fn scenes(quick: bool) -> Vec<(String, Scene, RunSettings)> {
    let n = resolutions(quick);
    let mut out = vec![];
    for (method, size) in [(Method::Bem, n.rod_bem), (Method::Mdr, n.rod_mdr)] {
        out.push((
            format!("rod a={ROD_RADIUS}"),
            rod(),
            RunSettings::new(method, size),
        ));
    }
    for c in CURVATURES {
        for (method, size) in [
            (Method::Bem, n.paraboloid_bem),
            (Method::Mdr, n.paraboloid_mdr),
        ] {
            out.push((
                format!("paraboloid c={c}"),
                paraboloid(c),
                RunSettings::new(method, size),
            ));
        }
    }
    out
}
