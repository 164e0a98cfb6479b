//! The contact solver's parallel passes over its work buffers: fixed chunks, so that every
//! sum is taken in the same order whatever the number of threads (results repeat bit for
//! bit). Each chunk also holds an index list of some of its elements (`Chunk::set`, in
//! increasing order): Polonsky–Keer keeps its contact set there, so that the passes that only
//! concern the set touch the set's elements alone; a sum over the list adds the same terms
//! in the same order as a sum over the whole chunk that skips the other elements.

use super::ContactSolver;
use crate::halfspace::operator::SurfaceOperator;
use rayon::prelude::*;

/// Elements per task of the solver's parallel passes.
pub(super) const PASS_CHUNK: usize = 4096;

/// Most sums one pass returns.
pub(super) const MAX_SUMS: usize = 5;

/// Listed elements below which `ContactSolver::set_sums` runs on one thread (about 50 us of
/// work, several times a wake-up of the pool's threads).
const SERIAL_SET: usize = 16384;

const _: () = assert!(PASS_CHUNK <= 1 << 16, "chunk-local indices are u16");

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
    /// Room for the chunk's index list (chunk-local indices): its first `len` entries.
    pub set: &'a mut [u16],
    /// Room for the next index list while a pass builds it from `set`.
    pub next: &'a mut [u16],
    /// Length of the index list.
    pub len: &'a mut usize,
}

impl Chunk<'_> {
    /// Appends chunk-local index `j` to the index list when `keep`, without a branch (the
    /// list has room for every element of the chunk, and `j` follows the last entry).
    #[inline(always)]
    pub fn push_if(&mut self, j: usize, keep: bool) {
        self.set[*self.len] = j as u16;
        *self.len += usize::from(keep);
    }
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// Runs `f` on fixed chunks of the work buffers in parallel and returns the sums of
    /// its results, added chunk by chunk in order.
    pub(super) fn pass_sums<const K: usize>(
        &mut self,
        f: impl Fn(&mut Chunk) -> [f64; K] + Sync,
    ) -> [f64; K] {
        self.chunk_sums(1, f)
    }

    /// `pass_sums` for an `f` that works on the index lists alone: while the lists are short,
    /// the chunks run one after the other on the calling thread, sparing the other threads'
    /// wake-up (the sums are the same).
    pub(super) fn set_sums<const K: usize>(
        &mut self,
        f: impl Fn(&mut Chunk) -> [f64; K] + Sync,
    ) -> [f64; K] {
        let listed: usize = self.set_len.iter().sum();
        let min_len = if listed < SERIAL_SET { usize::MAX } else { 1 };
        self.chunk_sums(min_len, f)
    }

    /// `pass_sums` with tasks of at least `min_len` chunks.
    fn chunk_sums<const K: usize>(
        &mut self,
        min_len: usize,
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
            .zip(self.set_list.par_chunks_mut(PASS_CHUNK))
            .zip(self.set_next.par_chunks_mut(PASS_CHUNK))
            .zip(self.set_len.par_iter_mut())
            .zip(self.partials.par_iter_mut())
            .enumerate()
            .with_min_len(min_len)
            .for_each(
                |(k, ((((((((((p, u), g), t), r), z), p_old), set), next), len), out))| {
                    let mut chunk = Chunk {
                        lo: k * PASS_CHUNK,
                        p,
                        u,
                        g,
                        t,
                        r,
                        z,
                        p_old,
                        set,
                        next,
                        len,
                    };
                    out[..K].copy_from_slice(&f(&mut chunk));
                },
            );
        let mut acc = [0.0; K];
        for part in &self.partials {
            acc.iter_mut().zip(part).for_each(|(a, v)| *a += v);
        }
        acc
    }

    /// The elements of the chunks' index lists, as indices into the work buffers, in
    /// increasing order.
    pub(super) fn listed(&self) -> impl Iterator<Item = usize> + '_ {
        self.set_len.iter().enumerate().flat_map(move |(k, &len)| {
            let lo = k * PASS_CHUNK;
            self.set_list[lo..lo + len]
                .iter()
                .map(move |&j| lo + j as usize)
        })
    }
}
