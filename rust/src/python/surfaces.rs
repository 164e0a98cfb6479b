//! Bindings of the random-surface generator: numpy height maps out.

use super::monitor::{to_pyerr, PyMonitor};
use crate::model::surfaces::{self, Roughness, SelfAffine};
use crate::support::error::Error;
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;

/// A Gaussian self-affine height map (m, shape (ny, nx), zero mean, periodic) of Hurst
/// exponent `hurst`, elements of side `dx` (m), scaled to exactly one of `rms_height` (m)
/// or `rms_slope` (spectral), with optional roll-off and short-cutoff wavelengths (m), from
/// the seed `seed`: bit for bit the same on every machine (`surfaces::self_affine`).
#[pyfunction]
#[pyo3(signature = (nx, ny, dx, hurst, rms_height=None, rms_slope=None, rolloff=None, short_cutoff=None, seed=0))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn self_affine<'py>(
    py: Python<'py>,
    nx: usize,
    ny: usize,
    dx: f64,
    hurst: f64,
    rms_height: Option<f64>,
    rms_slope: Option<f64>,
    rolloff: Option<f64>,
    short_cutoff: Option<f64>,
    seed: u64,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let roughness = match (rms_height, rms_slope) {
        (Some(h), None) => Roughness::RmsHeight(h),
        (None, Some(s)) => Roughness::RmsSlope(s),
        _ => {
            return Err(to_pyerr(
                py,
                Error::InvalidInput("give exactly one of rms_height and rms_slope".into()),
            ))
        }
    };
    let surface = SelfAffine {
        nx,
        ny,
        dx,
        hurst,
        rolloff,
        short_cutoff,
        roughness,
    };
    let heights = PyMonitor::new(None).run(py, |monitor| {
        surfaces::self_affine(&surface, seed, &monitor.stop())
    })?;
    heights.into_pyarray(py).reshape([ny, nx])
}
