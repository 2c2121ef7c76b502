//! Worker pools: each render leases a pool of its thread count for its duration.
//!
//! A pool serves one render at a time, so renders started at the same time from several
//! threads each get their own workers and run in parallel (one shared pool per thread count
//! made two `threads=1` renders take turns on its single worker). Pools are created on
//! first need and returned to an idle list afterwards, so a steady stream of renders
//! starts no threads. The renderer never uses rayon's global pool, so it does not fight
//! other rayon users.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::{RasterError, Result};

/// Upper bound on worker threads.
pub const MAX_THREADS: usize = 256;

/// Idle pools kept per thread count; more concurrent renders than this start pools that
/// are dropped (their threads exit) when the render ends.
const MAX_IDLE_PER_SIZE: usize = 8;

/// Idle pools: (thread count, the id of the process that started the pool, pool).
static IDLE: Mutex<Vec<(usize, u32, ThreadPool)>> = Mutex::new(Vec::new());

/// Validates a requested thread count.
pub(crate) fn check_threads(threads: Option<usize>) -> Result<()> {
    match threads {
        Some(0) => Err(RasterError::invalid(
            "threads must be >= 1 (or None for all cores)",
        )),
        Some(n) if n > MAX_THREADS => Err(RasterError::invalid(format!(
            "threads must be <= {MAX_THREADS}, got {n}"
        ))),
        _ => Ok(()),
    }
}

/// The number of threads `None` stands for.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A pool held by one render; it goes back to the idle list when dropped.
struct Lease {
    n: usize,
    pool: Option<ThreadPool>,
}

impl Drop for Lease {
    fn drop(&mut self) {
        if let Some(pool) = self.pool.take() {
            let mut idle = IDLE.lock().unwrap_or_else(|e| e.into_inner());
            if idle.iter().filter(|(k, _, _)| *k == self.n).count() < MAX_IDLE_PER_SIZE {
                idle.push((self.n, std::process::id(), pool));
            }
        }
    }
}

fn lease(threads: Option<usize>) -> Result<Lease> {
    check_threads(threads)?;
    let n = threads.unwrap_or_else(default_threads);
    let pid = std::process::id();
    let idle = {
        let mut idle = IDLE.lock().unwrap_or_else(|e| e.into_inner());
        // A forked child inherits the list but not the pools' threads: a job sent to such a
        // pool would wait forever (a ProcessPoolExecutor forked after a render hung). Those
        // pools are forgotten, never dropped: dropping would signal threads that are not
        // there.
        let mut i = 0;
        while i < idle.len() {
            if idle[i].1 == pid {
                i += 1;
            } else {
                std::mem::forget(idle.swap_remove(i).2);
            }
        }
        idle.iter()
            .position(|(k, _, _)| *k == n)
            .map(|i| idle.swap_remove(i).2)
    };
    let pool = match idle {
        Some(p) => p,
        None => ThreadPoolBuilder::new()
            .num_threads(n)
            .thread_name(|i| format!("shadelab-{i}"))
            .build()
            .map_err(|e| RasterError::invalid(format!("cannot start {n} worker threads: {e}")))?,
    };
    Ok(Lease {
        n,
        pool: Some(pool),
    })
}

/// Runs `f` on a pool of `threads` workers (`None`: every core) that no other render uses
/// meanwhile.
pub(crate) fn run<R: Send>(threads: Option<usize>, f: impl FnOnce() -> R + Send) -> Result<R> {
    let lease = lease(threads)?;
    let pool = lease.pool.as_ref().expect("a live lease holds its pool");
    Ok(pool.install(|| {
        let _in_flight = InFlight::enter();
        f()
    }))
}

// Test hook: how many renders are running on pool workers right now, the most seen at
// once, and an optional rendezvous that holds each render until that many run together.
static IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);
static MAX_IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);
static RENDEZVOUS: Mutex<(usize, Duration)> = Mutex::new((0, Duration::ZERO));
static ARRIVED: Condvar = Condvar::new();

struct InFlight;

impl InFlight {
    fn enter() -> Self {
        let now = IN_FLIGHT.fetch_add(1, Ordering::SeqCst) + 1;
        MAX_IN_FLIGHT.fetch_max(now, Ordering::SeqCst);
        let guard = RENDEZVOUS.lock().unwrap_or_else(|e| e.into_inner());
        let (want, timeout) = *guard;
        if want > 1 {
            ARRIVED.notify_all();
            // Waits until `want` renders have been in flight together (the high-water mark,
            // so a render that finished first does not strand the others), or gives up after
            // the timeout (the renders then simply ran one after the other).
            let _unused = ARRIVED
                .wait_timeout_while(guard, timeout, |_| {
                    MAX_IN_FLIGHT.load(Ordering::SeqCst) < want
                })
                .unwrap_or_else(|e| e.into_inner());
        }
        InFlight
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        IN_FLIGHT.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Test hook: resets the in-flight high-water mark and makes every render wait (up to
/// `timeout`) on its workers until `renders` renders are in flight together (`renders <= 1`
/// turns the rendezvous off). Returns nothing; read the result with [`max_in_flight`].
#[doc(hidden)]
pub fn set_rendezvous(renders: usize, timeout: Duration) {
    *RENDEZVOUS.lock().unwrap_or_else(|e| e.into_inner()) = (renders, timeout);
    MAX_IN_FLIGHT.store(IN_FLIGHT.load(Ordering::SeqCst), Ordering::SeqCst);
}

/// Test hook: the most renders seen running on pool workers at the same time since the
/// last [`set_rendezvous`].
#[doc(hidden)]
pub fn max_in_flight() -> usize {
    MAX_IN_FLIGHT.load(Ordering::SeqCst)
}
