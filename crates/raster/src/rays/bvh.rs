//! A bounding volume hierarchy over world-space triangles, built with the surface area
//! heuristic over binned centroids, answering "is this segment blocked?" (any hit) and
//! "what does this ray hit first?" (closest hit).

use glam::Vec3;

/// Triangles per leaf at most (below this the SAH split is not tried).
const LEAF: usize = 4;
/// Centroid bins per axis for the SAH sweep.
const BINS: usize = 12;

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn merge(&mut self, o: &Aabb) {
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
    }

    fn area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A node: a leaf holds `count > 0` triangles from `first`; an inner node's children are
/// `first` and `first + 1`.
#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
}

/// The hierarchy and its triangles (reordered so every leaf's are contiguous).
#[derive(Debug, Clone)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    tris: Vec<[Vec3; 3]>,
    /// Each held triangle's index in the list it was built from.
    ids: Vec<u32>,
}

/// The first triangle a ray meets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hit {
    /// Ray parameter of the hit (`origin + t·dir`).
    pub t: f32,
    /// Index of the triangle in the list the hierarchy was built from.
    pub index: u32,
    /// Barycentric weights of the triangle's second and third corners at the hit.
    pub uv: (f32, f32),
}

impl Bvh {
    /// Builds the hierarchy over `tris`; triangles with a non-finite corner are left out
    /// (they cannot block a finite segment in any meaningful way).
    pub fn new(tris: Vec<[Vec3; 3]>) -> Self {
        let (tris, kept): (Vec<[Vec3; 3]>, Vec<u32>) = tris
            .into_iter()
            .enumerate()
            .filter(|(_, t)| t.iter().all(|p| p.is_finite()))
            .map(|(i, t)| (t, i as u32))
            .unzip();
        let mut items: Vec<(Aabb, Vec3, u32)> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let mut b = Aabb::EMPTY;
                t.iter().for_each(|p| b.grow(*p));
                (b, (t[0] + t[1] + t[2]) / 3.0, i as u32)
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len().max(1));
        nodes.push(Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        if !items.is_empty() {
            build(&mut nodes, 0, &mut items, 0);
        }
        let ids = items.iter().map(|it| kept[it.2 as usize]).collect();
        let tris = items.iter().map(|it| tris[it.2 as usize]).collect();
        Bvh { nodes, tris, ids }
    }

    /// The nearest triangle the ray `origin + t·dir` crosses at `0 < t < t_max` (edges
    /// included; among hits at exactly the same `t` the first found, the same for every call
    /// on the same hierarchy). Nodes beyond the best hit so far are skipped.
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        if self.tris.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best: Option<Hit> = None;
        let mut limit = t_max;
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !slab(&node.bounds, origin, inv, limit) {
                continue;
            }
            if node.count > 0 {
                let (a, b) = (node.first as usize, (node.first + node.count) as usize);
                for (k, t) in self.tris[a..b].iter().enumerate() {
                    if let Some((s, u, v)) = intersect(t, origin, dir, limit) {
                        limit = s;
                        best = Some(Hit {
                            t: s,
                            index: self.ids[a + k],
                            uv: (u, v),
                        });
                    }
                }
            } else if top + 2 <= stack.len() {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            } else {
                // Deeper than the stack (see `occluded`): search the subtrees directly.
                for child in [node.first, node.first + 1] {
                    if let Some(h) = self.subtree_closest(child, origin, dir, limit) {
                        limit = h.t;
                        best = Some(h);
                    }
                }
            }
        }
        best
    }

    fn subtree_closest(&self, i: u32, origin: Vec3, dir: Vec3, t_max: f32) -> Option<Hit> {
        let node = &self.nodes[i as usize];
        if node.count > 0 {
            let (a, b) = (node.first as usize, (node.first + node.count) as usize);
            let mut best = None;
            let mut limit = t_max;
            for (k, t) in self.tris[a..b].iter().enumerate() {
                if let Some((s, u, v)) = intersect(t, origin, dir, limit) {
                    limit = s;
                    best = Some(Hit {
                        t: s,
                        index: self.ids[a + k],
                        uv: (u, v),
                    });
                }
            }
            return best;
        }
        let l = self.subtree_closest(node.first, origin, dir, t_max);
        let limit = l.map_or(t_max, |h| h.t);
        self.subtree_closest(node.first + 1, origin, dir, limit)
            .or(l)
    }

    /// Number of triangles held.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether a triangle crosses the open segment `origin + t·dir`, `0 < t < t_max`
    /// (`dir` need not be unit; `inv` is its componentwise reciprocal).
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        if self.tris.is_empty() {
            return false;
        }
        let inv = dir.recip();
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !slab(&node.bounds, origin, inv, t_max) {
                continue;
            }
            if node.count > 0 {
                let (a, b) = (node.first as usize, (node.first + node.count) as usize);
                if self.tris[a..b].iter().any(|t| hits(t, origin, dir, t_max)) {
                    return true;
                }
            } else if top + 2 <= stack.len() {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            } else {
                // Deeper than the stack (cannot happen with SAH on < 2^60 triangles, but a
                // degenerate build must stay correct): test the subtree's leaves directly.
                if self.subtree_hits(node.first, origin, dir, t_max)
                    || self.subtree_hits(node.first + 1, origin, dir, t_max)
                {
                    return true;
                }
            }
        }
        false
    }

    fn subtree_hits(&self, i: u32, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let node = &self.nodes[i as usize];
        if node.count > 0 {
            let (a, b) = (node.first as usize, (node.first + node.count) as usize);
            return self.tris[a..b].iter().any(|t| hits(t, origin, dir, t_max));
        }
        self.subtree_hits(node.first, origin, dir, t_max)
            || self.subtree_hits(node.first + 1, origin, dir, t_max)
    }
}

/// Recursively splits `items` (the node `at`'s triangles, starting at `offset` in the final
/// order) by the binned SAH.
fn build(nodes: &mut Vec<Node>, at: usize, items: &mut [(Aabb, Vec3, u32)], offset: u32) {
    let mut bounds = Aabb::EMPTY;
    let mut cent = Aabb::EMPTY;
    for it in items.iter() {
        bounds.merge(&it.0);
        cent.grow(it.1);
    }
    let leaf = Node {
        bounds,
        first: offset,
        count: items.len() as u32,
    };
    if items.len() <= LEAF {
        nodes[at] = leaf;
        return;
    }
    // Best split over the three axes: cost = area_left · n_left + area_right · n_right.
    let mut best: Option<(usize, usize, f32)> = None;
    let extent = cent.max - cent.min;
    for axis in 0..3 {
        if extent[axis].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - cent.min[axis]) * scale) as usize).min(BINS - 1);
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        for it in items.iter() {
            let b = &mut bins[bin_of(it.1)];
            b.0.merge(&it.0);
            b.1 += 1;
        }
        let mut right_area = [0.0f32; BINS];
        let mut acc = (Aabb::EMPTY, 0usize);
        for i in (1..BINS).rev() {
            acc.0.merge(&bins[i].0);
            acc.1 += bins[i].1;
            right_area[i] = acc.0.area() * acc.1 as f32;
        }
        let mut left = (Aabb::EMPTY, 0usize);
        for i in 0..BINS - 1 {
            left.0.merge(&bins[i].0);
            left.1 += bins[i].1;
            let cost = left.0.area() * left.1 as f32 + right_area[i + 1];
            if left.1 > 0 && left.1 < items.len() && best.map_or(true, |b| cost < b.2) {
                best = Some((axis, i, cost));
            }
        }
    }
    let Some((axis, split, cost)) = best else {
        nodes[at] = leaf; // every centroid in one place: nothing to split
        return;
    };
    if cost >= bounds.area() * items.len() as f32 && items.len() <= 2 * LEAF {
        nodes[at] = leaf; // splitting would not pay
        return;
    }
    let scale = BINS as f32 / extent[axis];
    let mid = partition(items, |it| {
        (((it.1[axis] - cent.min[axis]) * scale) as usize).min(BINS - 1) <= split
    });
    let first = nodes.len();
    nodes.push(leaf);
    nodes.push(leaf);
    nodes[at] = Node {
        bounds,
        first: first as u32,
        count: 0,
    };
    let (l, r) = items.split_at_mut(mid);
    build(nodes, first, l, offset);
    build(nodes, first + 1, r, offset + mid as u32);
}

/// Moves the items for which `left` holds to the front; returns how many there are.
fn partition<T>(items: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

/// Ray against box over `0 ≤ t ≤ t_max` (slab test; NaN from 0·inf compares false and
/// keeps the box, which is conservative).
#[inline(always)]
fn slab(b: &Aabb, o: Vec3, inv: Vec3, t_max: f32) -> bool {
    let t0 = (b.min - o) * inv;
    let t1 = (b.max - o) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(t_max);
    near <= far || far.is_nan() || near.is_nan()
}

/// Möller–Trumbore: whether the ray hits the triangle at `0 < t < t_max` (edges included).
#[inline(always)]
fn hits(t: &[Vec3; 3], o: Vec3, d: Vec3, t_max: f32) -> bool {
    intersect(t, o, d, t_max).is_some()
}

/// Möller–Trumbore: the ray's hit of the triangle at `0 < t < t_max` (edges included) as
/// `(t, u, v)`, the barycentric weights of corners 1 and 2.
#[inline(always)]
fn intersect(t: &[Vec3; 3], o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32, f32)> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - t[0];
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let s = e2.dot(qv) * inv;
    (s > 0.0 && s < t_max).then_some((s, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<[Vec3; 3]> {
        // n×n unit quads in the plane y = 0, two triangles each.
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x, z) = (i as f32, j as f32);
                let (a, b, c, d) = (
                    Vec3::new(x, 0.0, z),
                    Vec3::new(x + 1.0, 0.0, z),
                    Vec3::new(x + 1.0, 0.0, z + 1.0),
                    Vec3::new(x, 0.0, z + 1.0),
                );
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
        t
    }

    /// `grid(n)` and `count` small tilted triangles above it, with edges `e1` and `e2` from
    /// corners `corner(k · step)`.
    fn grid_and_tilted(
        n: usize,
        count: usize,
        step: f32,
        corner: impl Fn(f32) -> Vec3,
        [e1, e2]: [Vec3; 2],
    ) -> Vec<[Vec3; 3]> {
        let mut tris = grid(n);
        for k in 0..count {
            let c = corner(k as f32 * step);
            tris.push([c, c + e1, c + e2]);
        }
        tris
    }

    /// Floats in [0, 1) from a linear congruential generator started at `seed`.
    fn uniform(mut seed: u32) -> impl FnMut() -> f32 {
        move || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    fn brute(tris: &[[Vec3; 3]], o: Vec3, d: Vec3, t_max: f32) -> bool {
        tris.iter().any(|t| hits(t, o, d, t_max))
    }

    #[test]
    fn agrees_with_brute_force() {
        let tris = grid_and_tilted(
            16,
            50,
            0.37,
            |f| {
                Vec3::new(
                    8.0 + 6.0 * f.sin(),
                    1.0 + (f * 1.3).cos().abs(),
                    8.0 + 6.0 * f.cos(),
                )
            },
            [Vec3::new(0.7, 0.2, 0.0), Vec3::new(0.0, 0.3, 0.6)],
        );
        let bvh = Bvh::new(tris.clone());
        assert_eq!(bvh.len(), tris.len());
        let mut rnd = uniform(12345);
        let mut blocked = 0;
        for _ in 0..2000 {
            let o = Vec3::new(rnd() * 16.0, rnd() * 3.0 - 0.5, rnd() * 16.0);
            let d = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 10.0;
            let want = brute(&tris, o, d, 1.0);
            assert_eq!(bvh.occluded(o, d, 1.0), want, "{o} {d}");
            blocked += want as usize;
        }
        assert!(blocked > 100 && blocked < 1900, "{blocked}");
    }

    #[test]
    fn closest_hit_agrees_with_brute_force() {
        let tris = grid_and_tilted(
            8,
            40,
            0.53,
            |f| {
                Vec3::new(
                    4.0 + 3.0 * f.sin(),
                    0.5 + (f * 1.7).cos().abs(),
                    4.0 + 3.0 * f.cos(),
                )
            },
            [Vec3::new(0.9, 0.1, 0.0), Vec3::new(0.0, 0.2, 0.8)],
        );
        let bvh = Bvh::new(tris.clone());
        let mut rnd = uniform(777);
        let mut hit = 0;
        for _ in 0..2000 {
            let o = Vec3::new(rnd() * 8.0, rnd() * 3.0 + 0.01, rnd() * 8.0);
            let d = Vec3::new(rnd() - 0.5, rnd() - 0.9, rnd() - 0.5);
            let want = tris
                .iter()
                .enumerate()
                .filter_map(|(i, t)| intersect(t, o, d, f32::INFINITY).map(|h| (h.0, i)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let got = bvh.closest(o, d, f32::INFINITY);
            match (want, got) {
                (None, None) => {}
                (Some((t, _)), Some(h)) => {
                    assert_eq!(h.t, t, "{o} {d}");
                    let (u, v) = h.uv;
                    let tri = tris[h.index as usize];
                    let p = tri[0] * (1.0 - u - v) + tri[1] * u + tri[2] * v;
                    assert!((p - (o + d * t)).length() < 1e-4);
                    hit += 1;
                }
                other => panic!("{other:?} {o} {d}"),
            }
        }
        assert!(hit > 1000, "{hit}");
    }

    #[test]
    fn segment_ends_and_degenerate_input() {
        let bvh = Bvh::new(grid(2));
        let o = Vec3::new(0.5, 1.0, 0.5);
        // Straight down to the plane: blocked only if the segment reaches it.
        assert!(bvh.occluded(o, -Vec3::Y, 2.0));
        assert!(!bvh.occluded(o, -Vec3::Y, 0.9));
        assert!(!bvh.occluded(o, Vec3::Y, 10.0));
        // Parallel to the plane, in it: no hit (det = 0), no NaN trouble.
        assert!(!bvh.occluded(Vec3::new(0.5, 0.0, 0.5), Vec3::X, 10.0));
        // Zero-area and non-finite triangles are harmless.
        let z = Vec3::ONE;
        let bad = vec![[z, z, z], [Vec3::NAN, z, Vec3::X]];
        let bvh = Bvh::new(bad);
        assert_eq!(bvh.len(), 1);
        assert!(!bvh.occluded(Vec3::ZERO, Vec3::ONE, 10.0));
        assert!(!Bvh::new(Vec::new()).occluded(Vec3::ZERO, Vec3::X, 1.0));
    }
}
