//! Worker pools, one per thread count, created on first use and kept for the process.
//!
//! The renderer never uses rayon's global pool, so it does not fight other rayon users.

use std::sync::{Arc, Mutex};

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::{RasterError, Result};

/// Upper bound on worker threads.
pub const MAX_THREADS: usize = 256;

static POOLS: Mutex<Vec<(usize, Arc<ThreadPool>)>> = Mutex::new(Vec::new());

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

/// The shared pool for `threads` workers (`None`: every core).
pub(crate) fn pool(threads: Option<usize>) -> Result<Arc<ThreadPool>> {
    check_threads(threads)?;
    let n = threads.unwrap_or_else(default_threads);
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(k, _)| *k == n) {
        return Ok(p.clone());
    }
    let p = Arc::new(
        ThreadPoolBuilder::new()
            .num_threads(n)
            .thread_name(|i| format!("shadelab-{i}"))
            .build()
            .map_err(|e| RasterError::invalid(format!("cannot start {n} worker threads: {e}")))?,
    );
    pools.push((n, p.clone()));
    Ok(p)
}
