//! The contact solver's parallel passes over its work buffers: fixed chunks, so that every
//! sum is taken in the same order whatever the number of threads (results repeat bit for
//! bit).

use super::ContactSolver;
use crate::halfspace::operator::SurfaceOperator;
use rayon::prelude::*;

/// Elements per task of the solver's parallel passes.
pub(super) const PASS_CHUNK: usize = 4096;

/// Most sums one pass returns.
pub(super) const MAX_SUMS: usize = 5;

/// One chunk of the solver's work buffers, starting at element `lo`.
pub(super) struct Chunk<'a> {
    pub lo: usize,
    pub p: &'a mut [f64],
    pub u: &'a mut [f64],
    pub g: &'a mut [f64],
    pub t: &'a mut [f64],
    pub r: &'a mut [f64],
    pub z: &'a mut [f64],
    pub p_old: &'a mut [f64],
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// Runs `f` on fixed chunks of the work buffers in parallel and returns the sums of
    /// its results, added chunk by chunk in order.
    pub(super) fn pass_sums<const K: usize>(
        &mut self,
        f: impl Fn(&mut Chunk) -> [f64; K] + Sync,
    ) -> [f64; K] {
        const { assert!(K <= MAX_SUMS) };
        self.p
            .par_chunks_mut(PASS_CHUNK)
            .zip(self.u.par_chunks_mut(PASS_CHUNK))
            .zip(self.g.par_chunks_mut(PASS_CHUNK))
            .zip(self.t.par_chunks_mut(PASS_CHUNK))
            .zip(self.r.par_chunks_mut(PASS_CHUNK))
            .zip(self.z.par_chunks_mut(PASS_CHUNK))
            .zip(self.p_old.par_chunks_mut(PASS_CHUNK))
            .zip(self.partials.par_iter_mut())
            .enumerate()
            .for_each(|(k, (((((((p, u), g), t), r), z), p_old), out))| {
                let mut chunk = Chunk {
                    lo: k * PASS_CHUNK,
                    p,
                    u,
                    g,
                    t,
                    r,
                    z,
                    p_old,
                };
                out[..K].copy_from_slice(&f(&mut chunk));
            });
        let mut acc = [0.0; K];
        for part in &self.partials {
            acc.iter_mut().zip(part).for_each(|(a, v)| *a += v);
        }
        acc
    }
}
