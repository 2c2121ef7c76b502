//! Set-up triangle buffers kept from one frame for the next.
//!
//! A frame sets up about 100 bytes per triangle, in one vector per primitive chunk (96 MB
//! for a million triangles). Freed at the end of the frame, the allocator gave those pages
//! back to the OS (glibc unmaps a worker arena's extra heap once it is empty) and the next
//! frame faulted them in again, zeroed, under the process's memory-map lock. So the
//! vectors of the last frame are kept, emptied, and handed to the next frame's chunks.
//! At most one frame's worth is kept: each frame's vectors replace the previous spares, so
//! after a small frame only a small frame's memory stays.

use std::sync::Mutex;

use super::setup::SetupTri;

static SPARE: Mutex<Vec<Vec<SetupTri>>> = Mutex::new(Vec::new());

/// An empty vector with room for at least `capacity` triangles: a spare one when there is.
pub(crate) fn take(capacity: usize) -> Vec<SetupTri> {
    let spare = SPARE.lock().unwrap_or_else(|e| e.into_inner()).pop();
    match spare {
        Some(mut v) => {
            v.reserve(capacity);
            v
        }
        None => Vec::with_capacity(capacity),
    }
}

/// Keeps a finished frame's vectors (emptied) as the spares, in place of the previous ones.
pub(crate) fn give_back(vectors: impl Iterator<Item = Vec<SetupTri>>) {
    let kept: Vec<Vec<SetupTri>> = vectors
        .map(|mut v| {
            v.clear();
            v
        })
        .collect();
    let old = std::mem::replace(&mut *SPARE.lock().unwrap_or_else(|e| e.into_inner()), kept);
    drop(old); // freed outside the lock
}
