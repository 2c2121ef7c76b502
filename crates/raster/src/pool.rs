//! Worker pools: each render leases a pool of its thread count for its duration.
//!
//! A pool serves one render at a time, so renders started at the same time from several
//! threads each get their own workers and run in parallel (one shared pool per thread count
//! made two `threads=1` renders take turns on its single worker). Pools are created on
//! first need and returned to an idle list afterwards, so a steady stream of renders
//! starts no threads. The renderer never uses rayon's global pool, so it does not fight
//! other rayon users.
//!
//! On Linux the workers of a pool with one worker per CPU the process may use are each
//! bound to their own CPU ([`placement`]): unbound, a worker woken while another was busy
//! was queued behind it on the same CPU for milliseconds on a virtual machine, so frames
//! drawn at intervals used one core (see the function).

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
        None => {
            let cpus = placement(n);
            ThreadPoolBuilder::new()
                .num_threads(n)
                .thread_name(|i| format!("shadelab-{i}"))
                .start_handler(move |i| {
                    if let Some(cpus) = &cpus {
                        bind_current_thread(cpus[i]);
                    }
                })
                .build()
                .map_err(|e| {
                    RasterError::invalid(format!("cannot start {n} worker threads: {e}"))
                })?
        }
    };
    Ok(Lease {
        n,
        pool: Some(pool),
    })
}

/// The environment variable that turns the binding of workers to CPUs off when set to `0`.
pub const PIN_THREADS_ENV: &str = "SHADELAB_PIN_THREADS";

/// The CPU each worker of a new pool of `n` is bound to: worker `i` to the `i`-th of the
/// CPUs the process may run on, when `n` is their number (`threads=None`, or the same
/// count given); otherwise `None`, left to the OS, as off Linux and when
/// [`PIN_THREADS_ENV`] is `0`.
///
/// Why: rayon wakes a sleeping worker when another one splits off work. Linux places the
/// woken thread on the waker's CPU when the other CPU looks unavailable, which a virtual
/// machine's idle virtual CPU does (the host has descheduled it), and it then waits there
/// behind the busy waker until a load balance moves it: measured on this project's
/// 2-CPU VM, after 5 to 20 ms without work the second of two rayon jobs started 2 ms late
/// (median of 50, the length of the first job), 50 to 60 µs late with the workers bound;
/// a 99,224-triangle flat frame at 512² rendered 20 ms apart took 7.5 ms on 2 threads
/// unbound (its 1-thread time) and 4.0 ms bound.
///
/// Why only a pool as large as the CPU set: processes do not know of each other, so pools
/// of fewer workers bound the same way would all land on the first CPUs (four processes
/// with `threads=4` on 16 cores would share 4 of them); a pool of every CPU puts one
/// worker on each whoever else does the same. A single worker is never bound.
pub(crate) fn placement(n: usize) -> Option<Vec<usize>> {
    if n < 2 || std::env::var(PIN_THREADS_ENV).is_ok_and(|v| v.trim() == "0") {
        return None;
    }
    allowed_cpus().filter(|cpus| cpus.len() == n)
}

/// The CPUs the process may run on (its main thread's affinity, read when a pool is made:
/// a bound worker's own would be one CPU), in order; Linux only.
#[cfg(target_os = "linux")]
fn allowed_cpus() -> Option<Vec<usize>> {
    // SAFETY: getpid has no preconditions.
    let pid = unsafe { libc::getpid() };
    affinity(pid)
}

#[cfg(not(target_os = "linux"))]
fn allowed_cpus() -> Option<Vec<usize>> {
    None
}

/// The CPUs thread `tid` may run on (0: the calling thread).
#[cfg(target_os = "linux")]
fn affinity(tid: libc::pid_t) -> Option<Vec<usize>> {
    // SAFETY: `cpu_set_t` is plain data (all-zero is the empty set); sched_getaffinity
    // writes at most `size_of::<cpu_set_t>()` bytes into it, and CPU_ISSET reads it in
    // bounds for every index below CPU_SETSIZE.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        if libc::sched_getaffinity(tid, std::mem::size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return None;
        }
        let cpus: Vec<usize> = (0..libc::CPU_SETSIZE as usize)
            .filter(|&c| libc::CPU_ISSET(c, &set))
            .collect();
        (!cpus.is_empty()).then_some(cpus)
    }
}

/// Binds the calling thread to `cpu`. A failure (a CPU taken away meanwhile) leaves the
/// thread where the OS puts it: binding only helps speed.
#[cfg(target_os = "linux")]
fn bind_current_thread(cpu: usize) {
    // SAFETY: as in `affinity`; `cpu` comes from such a set, below CPU_SETSIZE.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        let _ = libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

#[cfg(not(target_os = "linux"))]
fn bind_current_thread(_cpu: usize) {}

/// Test hook: for each worker of a pool of `threads` (leased as a render leases one), the
/// CPUs it may run on (Linux; empty lists elsewhere).
#[doc(hidden)]
pub fn worker_cpus(threads: Option<usize>) -> Result<Vec<Vec<usize>>> {
    let lease = lease(threads)?;
    let pool = lease.pool.as_ref().expect("a live lease holds its pool");
    Ok(pool.broadcast(|_| {
        #[cfg(target_os = "linux")]
        {
            affinity(0).unwrap_or_default()
        }
        #[cfg(not(target_os = "linux"))]
        {
            Vec::new()
        }
    }))
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
