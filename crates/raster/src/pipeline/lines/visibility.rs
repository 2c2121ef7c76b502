//! Hidden-line visibility of one line sample, read from the visibility buffer.
//!
//! A line sample at point `p` belongs to the edge point `q` nearest it. The buffer says
//! which triangle `O` owns `p` (the nearest surface there). The sample is drawn when:
//!
//! 1. no triangle owns `p` (nothing can hide the edge there), or
//! 2. `O` is one of the edge's own faces (it has both endpoints, after welding): the edge
//!    lies on the visible surface, whatever the depths; no depth comparison, so no
//!    stitching where the line and its surface have equal depth, or
//! 3. `O` does not hide the edge: its depth plane, extended to `q`, is not in front of the
//!    edge's depth at `q` (exact whenever `O` also covers `q`: the extension is then
//!    interpolation over `O`); or `O` shares a vertex with one of the edge's faces and, at
//!    `p`, is not in front of that face's plane (a convex neighbour of a face thinner than
//!    the line lies behind the face's plane; a concave one passes the first test). Each
//!    comparison allows [`ZPlane::tolerance`].
//!
//! The second comparison is limited to the faces' neighbours because a face's plane
//! extended off the face is meaningless for a face seen nearly edge-on (its depth slope is
//! huge): an unrelated surface in front of the edge would pass it.

use super::segments::{Segment, ZPlane};
use crate::pipeline::bin::{Binned, LOCAL_BITS};
use crate::pipeline::raster::NO_TRIANGLE;

/// What the rule needs of a triangle that owns samples.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Owner {
    id: u32,
    /// Welded ids of its (original) vertices.
    welded: [u32; 3],
    plane: Option<ZPlane>,
}

impl Owner {
    /// Triangle `id`'s welded vertices and depth plane.
    pub fn of(tris: &Binned, weld: &[u32], id: u32) -> Self {
        let t = tris.get(id);
        let v = if t.clipped {
            // A piece of a clipped triangle: adjacency is the original triangle's.
            let chunk = &tris.chunks[(id >> LOCAL_BITS) as usize];
            let local = id & ((1 << LOCAL_BITS) - 1);
            let k = chunk
                .clipped_from
                .binary_search_by_key(&local, |&(i, _)| i)
                .expect("every clipped piece is listed");
            chunk.clipped_from[k].1
        } else {
            t.v
        };
        Owner {
            id,
            welded: v.map(|i| weld[i as usize]),
            plane: ZPlane::of_snapped(t.x, t.y, t.z),
        }
    }
}

/// A one-entry cache of the last owner looked up (neighbouring samples share owners).
pub(crate) struct OwnerCache {
    last: Option<Owner>,
}

impl OwnerCache {
    pub fn new() -> Self {
        OwnerCache { last: None }
    }

    #[inline]
    fn get(&mut self, tris: &Binned, weld: &[u32], id: u32) -> Owner {
        match self.last {
            Some(o) if o.id == id => o,
            _ => {
                let o = Owner::of(tris, weld, id);
                self.last = Some(o);
                o
            }
        }
    }
}

/// Whether the line sample at `p`, nearest the edge point of parameter `t`, is visible
/// when triangle `owner` (or [`NO_TRIANGLE`]) owns `p`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn visible(
    seg: &Segment,
    p: [f64; 2],
    t: f64,
    owner: u32,
    tris: &Binned,
    weld: &[u32],
    neighbours_only: bool,
    cache: &mut OwnerCache,
) -> bool {
    if owner == NO_TRIANGLE {
        return true;
    }
    let o = cache.get(tris, weld, owner);
    if o.welded.contains(&seg.ends[0]) && o.welded.contains(&seg.ends[1]) {
        return true;
    }
    let Some(plane) = o.plane else {
        return true;
    };
    let c = &seg.capsule;
    let q = [
        c.a[0] + (c.b[0] - c.a[0]) * t,
        c.a[1] + (c.b[1] - c.a[1]) * t,
    ];
    let zq = seg.z_at(t);
    if plane.at(q) <= zq + plane.tolerance(zq) {
        return true;
    }
    let zo = plane.at(p);
    seg.ribbon.iter().flatten().any(|(r, face)| {
        let zr = r.at(p);
        (!neighbours_only || o.welded.iter().any(|v| face.contains(v)))
            && zo <= zr + r.tolerance(zr)
    })
}
