//! The crate's own rayon thread pool: its size can be set at run time, and a process forked
//! from one that used it (Python's multiprocessing on Linux) builds a new one instead of
//! waiting forever for threads that the fork did not copy.

use crate::support::error::{Error, Result};
use rayon::{ThreadPool, ThreadPoolBuilder};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Threads asked for; 0: rayon's default (`RAYON_NUM_THREADS`, else the available cores).
static THREADS: AtomicUsize = AtomicUsize::new(0);

/// The pool, the process it was built in, and the thread count it was built for.
static POOL: Mutex<Option<(u32, usize, Arc<ThreadPool>)>> = Mutex::new(None);

/// Worker threads per available core that a pool may have at most: more only adds
/// switching, and a count of millions would exhaust the machine's threads.
pub const THREADS_PER_CORE: usize = 8;

/// The largest thread count `set_num_threads` takes: `THREADS_PER_CORE` times the
/// available cores.
pub fn max_threads() -> usize {
    THREADS_PER_CORE * std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Sets the number of worker threads of computations started from now on (`n` in
/// 1..=`max_threads()`), or back to rayon's default (`None`: `RAYON_NUM_THREADS`, else the
/// available cores).
pub fn set_num_threads(n: Option<usize>) -> Result<()> {
    let most = max_threads();
    match n {
        Some(k) if k == 0 || k > most => Err(Error::InvalidInput(format!(
            "the number of threads must be >= 1 and at most {most} ({THREADS_PER_CORE} per core), got {k}"
        ))),
        _ => {
            THREADS.store(n.unwrap_or(0), Ordering::Relaxed);
            Ok(())
        }
    }
}

/// The pool computations run on: built on first use, and again after a fork or a change of
/// the thread count.
pub fn get() -> Result<Arc<ThreadPool>> {
    let threads = THREADS.load(Ordering::Relaxed);
    let pid = std::process::id();
    let mut slot = POOL.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((built_in, built_for, pool)) = slot.as_ref() {
        if *built_in == pid && *built_for == threads {
            return Ok(Arc::clone(pool));
        }
    }
    if let Some((built_in, _, stale)) = slot.take() {
        if built_in != pid {
            // its threads were not copied by the fork: dropping it would wait on them
            std::mem::forget(stale);
        }
    }
    let pool = Arc::new(
        ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("mdrvisc-{i}"))
            .build()
            .map_err(|e| Error::InvalidInput(format!("cannot start the thread pool: {e}")))?,
    );
    *slot = Some((pid, threads, Arc::clone(&pool)));
    Ok(pool)
}

/// Worker threads of the pool.
pub fn num_threads() -> Result<usize> {
    get().map(|p| p.current_num_threads())
}

/// Runs `f` on a worker of the pool and waits for it (in place when already on a worker of
/// any rayon pool, where waiting for a job of the same pool could deadlock).
pub fn run<T: Send>(f: impl FnOnce() -> T + Send) -> Result<T> {
    if rayon::current_thread_index().is_some() {
        return Ok(f());
    }
    Ok(get()?.install(f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thread_count_can_be_set_and_reset() {
        set_num_threads(Some(1)).unwrap();
        assert_eq!(num_threads().unwrap(), 1);
        assert_eq!(run(rayon::current_num_threads).unwrap(), 1);
        set_num_threads(Some(2)).unwrap();
        assert_eq!(num_threads().unwrap(), 2);
        assert!(set_num_threads(Some(0)).is_err());
        set_num_threads(None).unwrap();
    }
}
