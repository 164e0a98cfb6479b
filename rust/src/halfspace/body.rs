//! The surface operators of each body: the one place that builds operators, kernel tables
//! and preconditioners. A free half-space is solved by Love's coefficients through the
//! DC-FFT (`FftOperator`, preconditioned by the spectral inverse 2 |q| dx, or on small grids
//! the inverse-kernel stencil) on windows that share one kernel table; a periodic cell by its spectral kernel (`PeriodicOperator`,
//! preconditioned by the exact spectral inverse) on the whole cell, a periodic layer the
//! same way with the layer's spectral compliance (`crate::halfspace::layer`), and a free
//! grid on a layer by the DC-FFT of the layer's influence coefficients (preconditioned by
//! the layer's spectral inverse) on windows that share one table of them, as the
//! half-space's.

use crate::halfspace::influence::KernelTable;
use crate::halfspace::layer::{compliance, kernel_table, least_coefficient, FreeLayerOperator};
use crate::halfspace::operator::{FftOperator, FftPlans, SurfaceOperator};
use crate::halfspace::periodic::PeriodicOperator;
use crate::model::body::Body;
use crate::support::error::{Error, Result};
use faer::Mat;

/// The surface operator of a body (deflection in m under element pressures in Pa, at a
/// shear modulus of 1 Pa).
pub enum Operator {
    /// A free half-space (DC-FFT of Love's coefficients).
    Free(FftOperator),
    /// A periodic cell (spectral kernel, zero mean mode).
    Periodic(PeriodicOperator),
    /// A free grid on a layer (DC-FFT of the layer's influence coefficients).
    FreeLayer(FreeLayerOperator),
}

impl Body {
    /// The operator of a whole `nx` x `ny` grid of elements of side `dx` (m).
    pub fn operator(self, nx: usize, ny: usize, dx: f64) -> Result<Operator> {
        Ok(match self {
            Body::HalfSpace => Operator::Free(FftOperator::new(nx, ny, dx)?),
            Body::Periodic => Operator::Periodic(PeriodicOperator::new(nx, ny, dx)?),
            Body::Layer {
                layer,
                nu,
                periodic: true,
            } => Operator::Periodic(PeriodicOperator::with_compliance(nx, ny, dx, |q| {
                compliance(q, layer, nu)
            })?),
            Body::Layer {
                layer,
                nu,
                periodic: false,
            } => Operator::FreeLayer(FreeLayerOperator::new(nx, ny, dx, layer, nu)?),
        })
    }

    /// Memory (bytes) the operator of a whole `nx` x `ny` grid holds while a solve runs.
    pub fn operator_bytes(self, nx: usize, ny: usize) -> f64 {
        match self {
            Body::HalfSpace
            | Body::Layer {
                periodic: false, ..
            } => crate::halfspace::operator::held_bytes(nx, ny),
            Body::Periodic | Body::Layer { periodic: true, .. } => {
                crate::halfspace::periodic::BYTES_PER_ELEMENT * (nx * ny) as f64
            }
        }
    }

    /// The kernel table the windows of an `nx` x `ny` grid of side `dx` (m) share, for a
    /// body solved on windows (`Body::windows`): Love's coefficients, or a layer's
    /// (`crate::halfspace::layer::kernel_table`, which fails for elements wider than its
    /// limit); None for a periodic cell.
    pub fn window_kernel(self, nx: usize, ny: usize, dx: f64) -> Result<Option<KernelTable>> {
        Ok(match self {
            Body::HalfSpace => Some(KernelTable::new(nx, ny, dx)),
            Body::Layer {
                layer,
                nu,
                periodic: false,
            } => Some(kernel_table(nx, ny, dx, layer, nu)?),
            Body::Periodic | Body::Layer { periodic: true, .. } => None,
        })
    }

    /// A lower bound (m/Pa at G = 1, <= 0) of the body's influence coefficients at every
    /// offset, for elements of side `dx` (m): a pressure field of total force F deflects no
    /// point by less than F / dx^2 times it, so the windows of a body whose surface may rise
    /// around a load widen by that rise. 0 for the half-space, whose coefficients are
    /// positive and fall with each offset; a free layer's from its kernel's least value
    /// (`crate::halfspace::layer::least_coefficient`); 0 for a periodic cell, which has no
    /// windows.
    pub fn least_coefficient(self, dx: f64) -> f64 {
        match self {
            Body::Layer {
                layer,
                nu,
                periodic: false,
            } => least_coefficient(dx, layer, nu),
            Body::HalfSpace | Body::Periodic | Body::Layer { periodic: true, .. } => 0.0,
        }
    }

    /// The operator of a `wx` x `wy` window from the grid's kernel table `kernel`
    /// (`window_kernel`) and the FFT plans `plans` (kept by the caller across windows).
    pub fn window_operator(
        self,
        kernel: &KernelTable,
        wx: usize,
        wy: usize,
        plans: &mut FftPlans,
    ) -> Result<Operator> {
        match self {
            Body::HalfSpace => Ok(Operator::Free(FftOperator::with_kernel(
                wx, wy, kernel, plans,
            )?)),
            Body::Layer {
                layer,
                nu,
                periodic: false,
            } => Ok(Operator::FreeLayer(FreeLayerOperator::with_kernel(
                wx, wy, kernel, layer, nu, plans,
            )?)),
            Body::Periodic | Body::Layer { periodic: true, .. } => {
                Err(Error::InvalidInput(format!(
                    "a {} has no windows: its solves take the whole grid",
                    self.name()
                )))
            }
        }
    }
}

impl Operator {
    /// The sizes (x, y) of the FFT grid the operator transforms: twice the grid, padded
    /// to fast sizes, for a free surface; the cell's own for a periodic one.
    pub fn fft_size(&self) -> (usize, usize) {
        match self {
            Operator::Free(op) => op.padded(),
            Operator::Periodic(op) => (op.nx(), op.ny()),
            Operator::FreeLayer(op) => op.padded(),
        }
    }

    /// Resizes a window's operator to `wx` x `wy` elements of the same padded sizes.
    pub fn resize(&mut self, wx: usize, wy: usize) -> Result<()> {
        match self {
            Operator::Free(op) => op.resize(wx, wy),
            Operator::FreeLayer(op) => op.resize(wx, wy),
            Operator::Periodic(op) if (op.nx(), op.ny()) == (wx, wy) => Ok(()),
            Operator::Periodic(_) => Err(Error::InvalidInput(
                "a periodic cell's operator is never resized".into(),
            )),
        }
    }
}

impl SurfaceOperator for Operator {
    fn nx(&self) -> usize {
        match self {
            Operator::Free(op) => op.nx(),
            Operator::Periodic(op) => op.nx(),
            Operator::FreeLayer(op) => op.nx(),
        }
    }
    fn ny(&self) -> usize {
        match self {
            Operator::Free(op) => op.ny(),
            Operator::Periodic(op) => op.ny(),
            Operator::FreeLayer(op) => op.ny(),
        }
    }
    fn dx(&self) -> f64 {
        match self {
            Operator::Free(op) => op.dx(),
            Operator::Periodic(op) => op.dx(),
            Operator::FreeLayer(op) => op.dx(),
        }
    }
    fn apply(&mut self, p: &[f64], u: &mut [f64]) {
        match self {
            Operator::Free(op) => op.apply(p, u),
            Operator::Periodic(op) => op.apply(p, u),
            Operator::FreeLayer(op) => op.apply(p, u),
        }
    }
    fn apply_single(&mut self, p: &[f64], u: &mut [f64]) {
        match self {
            Operator::Free(op) => op.apply_single(p, u),
            Operator::Periodic(op) => op.apply_single(p, u),
            Operator::FreeLayer(op) => op.apply_single(p, u),
        }
    }
    fn add_single(&mut self, q: &[f64], u: &mut [f64]) -> bool {
        match self {
            Operator::Free(op) => op.add_single(q, u),
            Operator::Periodic(op) => op.add_single(q, u),
            Operator::FreeLayer(op) => op.add_single(q, u),
        }
    }
    fn submatrix(&mut self, idx: &[usize]) -> Result<Mat<f64>> {
        match self {
            Operator::Free(op) => op.submatrix(idx),
            Operator::Periodic(op) => op.submatrix(idx),
            Operator::FreeLayer(op) => op.submatrix(idx),
        }
    }
    fn precondition(&mut self, g: &[f64], z: &mut [f64]) {
        match self {
            Operator::Free(op) => op.precondition(g, z),
            Operator::Periodic(op) => op.precondition(g, z),
            Operator::FreeLayer(op) => op.precondition(g, z),
        }
    }
    fn add_point_loads(&mut self, idx: &[usize], values: &[f64], u: &mut [f64]) -> bool {
        match self {
            Operator::Free(op) => op.add_point_loads(idx, values, u),
            Operator::Periodic(op) => op.add_point_loads(idx, values, u),
            Operator::FreeLayer(op) => op.add_point_loads(idx, values, u),
        }
    }
    fn point_load_limit(&self) -> usize {
        match self {
            Operator::Free(op) => op.point_load_limit(),
            Operator::Periodic(op) => op.point_load_limit(),
            Operator::FreeLayer(op) => op.point_load_limit(),
        }
    }
    fn periodic(&self) -> bool {
        match self {
            Operator::Free(op) => op.periodic(),
            Operator::Periodic(op) => op.periodic(),
            Operator::FreeLayer(op) => op.periodic(),
        }
    }
}
