//! The crate's own rayon thread pool: its size can be set at run time, and a process forked
//! from one that used it (Python's multiprocessing on Linux) builds a new one instead of
//! waiting forever for threads that the fork did not copy.

use crate::support::error::{Error, Result};
use rayon::{ThreadPool, ThreadPoolBuilder, Yield};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

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

/// How long a worker kept awake by `KeepAwake` goes on looking for work after it last found
/// some, before it leaves the pool's workers to their own idling (rayon puts an idle worker
/// to sleep after about 32 yields, tens of microseconds).
pub const AWAKE_IDLE: Duration = Duration::from_millis(2);

/// Keeps the pool's other workers looking for work while it lives, so that the next
/// parallel loop of a computation made of many short ones (an iterative solver's passes
/// and transforms, each tens to hundreds of microseconds) starts on all of them at once
/// instead of first waking sleeping threads, which on a virtual machine costs tens of
/// microseconds per loop. Each other worker runs a job that takes the pool's pending work
/// (`rayon::yield_now`) and yields its core between looks (`std::thread::yield_now`), so
/// other processes still get it; it stops when this is dropped, or `AWAKE_IDLE` after it
/// last found work. Made on a worker of a pool with one thread, or off the pool, it does
/// nothing.
pub struct KeepAwake {
    shared: Arc<Looking>,
}

/// What a `KeepAwake` shares with its jobs.
#[derive(Default)]
struct Looking {
    /// Set when the guard is dropped.
    stop: AtomicBool,
    /// Jobs looking for work now.
    count: AtomicUsize,
}

impl KeepAwake {
    /// Sets the pool's other workers looking for work until it is dropped or `AWAKE_IDLE`
    /// after they last found some (see the type).
    pub fn new() -> Self {
        Self::with_idle(AWAKE_IDLE)
    }

    /// Sets the pool's other workers looking for work until it is dropped or `idle` after
    /// they last found some.
    pub fn with_idle(idle: Duration) -> Self {
        let shared = Arc::new(Looking::default());
        if let Some(owner) = rayon::current_thread_index() {
            for _ in 1..rayon::current_num_threads() {
                let shared = Arc::clone(&shared);
                rayon::spawn(move || look_for_work(owner, idle, &shared));
            }
        }
        KeepAwake { shared }
    }

    /// Workers this guard keeps looking for work now (0 to the pool's threads less one).
    pub fn looking(&self) -> usize {
        self.shared.count.load(Ordering::Acquire)
    }
}

impl Default for KeepAwake {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for KeepAwake {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
    }
}

/// A `KeepAwake` job: takes the pool's pending work until the guard is dropped or `idle`
/// has passed without any; returns at once on the worker that made the guard (whose
/// computation, below this job on its stack, could not go on meanwhile).
fn look_for_work(owner: usize, idle: Duration, shared: &Looking) {
    if rayon::current_thread_index() == Some(owner) {
        return;
    }
    shared.count.fetch_add(1, Ordering::AcqRel);
    let mut found = Instant::now();
    while !shared.stop.load(Ordering::Acquire) {
        match rayon::yield_now() {
            Some(Yield::Executed) => found = Instant::now(),
            Some(Yield::Idle) if found.elapsed() < idle => std::thread::yield_now(),
            _ => break,
        }
    }
    shared.count.fetch_sub(1, Ordering::AcqRel);
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

    /// Polls `f` every 100 us for up to a second; whether it came true.
    fn within_a_second(f: impl Fn() -> bool) -> bool {
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(1) {
            if f() {
                return true;
            }
            std::thread::sleep(Duration::from_micros(100));
        }
        false
    }

    #[test]
    fn keep_awake_holds_the_other_workers_until_dropped_or_idle() {
        let pool = ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        pool.install(|| {
            let awake = KeepAwake::with_idle(Duration::from_secs(30));
            assert!(within_a_second(|| awake.looking() == 2));
            // the workers it holds take the pool's work: this thread only waits on a
            // channel, and the two others are inside the looking jobs, which stay
            let me = rayon::current_thread_index();
            let (tx, rx) = std::sync::mpsc::channel();
            for _ in 0..8 {
                let tx = tx.clone();
                rayon::spawn(move || tx.send(rayon::current_thread_index()).unwrap());
            }
            let ran: Vec<_> = (0..8).map(|_| rx.recv().unwrap()).collect();
            assert!(ran.iter().all(|&t| t.is_some() && t != me));
            assert_eq!(awake.looking(), 2);
            let shared = Arc::clone(&awake.shared);
            drop(awake);
            assert!(within_a_second(|| shared.count.load(Ordering::Acquire) == 0));
            // without work, they leave by themselves while the guard lives
            let idle = KeepAwake::with_idle(Duration::from_millis(200));
            assert!(within_a_second(|| idle.looking() == 2));
            assert!(within_a_second(|| idle.looking() == 0));
        });
        let single = ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        single.install(|| {
            let awake = KeepAwake::new();
            std::thread::sleep(AWAKE_IDLE);
            assert_eq!(awake.looking(), 0);
        });
        assert_eq!(KeepAwake::new().looking(), 0);
    }
}
