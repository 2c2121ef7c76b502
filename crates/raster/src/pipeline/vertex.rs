//! Vertex stage: object → world → clip space. Geometry only: no material or light is read
//! here (Gouraud's vertex colours are lit afterwards by `shade::prelight`).
//!
//! Only the attributes a render reads are produced ([`Attributes`]): world positions (every
//! mode lights somewhere), world normals for Gouraud and Phong, texture coordinates and
//! vertex colours only when a material or mesh of the scene has them.

use std::mem::MaybeUninit;

use glam::{DMat4, Mat3, Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::clip::{ClipPlanes, INVALID};
use super::setup::{snap, Snapped};
#[cfg(target_arch = "x86_64")]
use super::vertex_lanes;
use crate::options::ShadingMode;
use crate::scene::Scene;

/// Post-transform vertices of every object, concatenated in submission order.
#[derive(Debug, Default)]
pub(crate) struct Vertices {
    pub clip: Vec<Vec4>,
    /// Clip-plane outcode per vertex (plus [`INVALID`]); only for the transformed vertices,
    /// not for those appended by clipping (which are snapped where they are made).
    pub outcode: Vec<u8>,
    /// Snapped screen position, depth and 1/w, valid where the outcode is 0.
    pub screen: Vec<Snapped>,
    pub world: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub color: Vec<Vec3>,
    /// Gouraud with two-sided lighting: colours lit with the flipped normal and the back material.
    pub color_back: Vec<Vec3>,
    /// Texture coordinates (textured scenes only; zero for objects without UVs).
    pub uv: Vec<Vec2>,
    /// Mesh vertex colours (scenes with any; zero for objects without).
    pub vertex_color: Vec<Vec3>,
    /// World tangents (xyz) and handedness (w), scenes with normal or bump maps only (zero
    /// for objects without UVs).
    pub tangent: Vec<Vec4>,
    /// How each vertex made by clipping blends three transformed ones (their indices and
    /// weights), so an attribute produced after clipping (a lit colour) extends to them.
    pub blends: Vec<([u32; 3], [f32; 3])>,
}

impl Vertices {
    /// Appends a vertex blended from three existing ones with weights `w` (clip-space linear,
    /// which is exact for every attribute before the perspective divide).
    pub fn push_blend(&mut self, from: &Vertices, v: [u32; 3], w: [f32; 3], clip: Vec4) {
        self.clip.push(clip);
        self.blends.push((v, w));
        if !from.world.is_empty() {
            self.world.push(blend(&from.world, v, w));
        }
        if !from.normal.is_empty() {
            self.normal.push(blend(&from.normal, v, w));
        }
        if !from.uv.is_empty() {
            let a = &from.uv;
            let uv = a[v[0] as usize] * w[0] + a[v[1] as usize] * w[1] + a[v[2] as usize] * w[2];
            self.uv.push(uv);
        }
        if !from.vertex_color.is_empty() {
            self.vertex_color.push(blend(&from.vertex_color, v, w));
        }
        if !from.tangent.is_empty() {
            let a = &from.tangent;
            let t = a[v[0] as usize] * w[0] + a[v[1] as usize] * w[1] + a[v[2] as usize] * w[2];
            self.tangent.push(t);
        }
    }

    /// Appends all of `other`.
    pub fn append(&mut self, other: &mut Vertices) {
        self.clip.append(&mut other.clip);
        self.world.append(&mut other.world);
        self.normal.append(&mut other.normal);
        self.color.append(&mut other.color);
        self.color_back.append(&mut other.color_back);
        self.uv.append(&mut other.uv);
        self.vertex_color.append(&mut other.vertex_color);
        self.tangent.append(&mut other.tangent);
        self.blends.append(&mut other.blends);
    }

    /// Extends `attr`, given for the transformed vertices, to the vertices made by clipping.
    pub fn extend_to_clipped(blends: &[([u32; 3], [f32; 3])], attr: &mut Vec<Vec3>) {
        attr.reserve_exact(blends.len());
        for &(v, w) in blends {
            let x = blend(attr, v, w);
            attr.push(x);
        }
    }
}

/// An attribute of a clip-made vertex: the clip-space-linear blend of three vertices' (exact
/// for every attribute before the perspective divide).
fn blend(a: &[Vec3], v: [u32; 3], w: [f32; 3]) -> Vec3 {
    a[v[0] as usize] * w[0] + a[v[1] as usize] * w[1] + a[v[2] as usize] * w[2]
}

/// Which per-vertex attributes a render produces.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attributes {
    pub normal: bool,
    /// Texture coordinates (a material reads a map).
    pub uv: bool,
    /// Vertex colours (a mesh has them).
    pub color: bool,
    /// Tangent frames (a material has a normal or bump map).
    pub tangent: bool,
}

impl Attributes {
    /// Positions only (world positions are always produced: clipping blends them).
    pub const NONE: Attributes = Attributes {
        normal: false,
        uv: false,
        color: false,
        tangent: false,
    };

    /// What a shading mode reads (world positions always).
    pub fn for_mode(mode: ShadingMode) -> Self {
        Attributes {
            normal: mode != ShadingMode::Flat,
            uv: false,
            color: false,
            tangent: false,
        }
    }

    /// What `mode` reads in `scene`: UVs when an object has maps, vertex colours when a
    /// lit mesh has them, tangents when a material has a normal or bump map (Phong: the
    /// other modes refuse those maps).
    pub fn for_scene(mode: ShadingMode, scene: &Scene) -> Self {
        let objects = scene.objects();
        Attributes {
            uv: objects.iter().any(|o| o.maps().is_some()),
            color: objects.iter().any(|o| o.mesh().colors().is_some()),
            tangent: mode == ShadingMode::Phong
                && objects
                    .iter()
                    .any(|o| o.maps().is_some_and(|m| m.perturbs())),
            ..Attributes::for_mode(mode)
        }
    }
}

/// Vertices per parallel work item of the transform: each array is cut into chunks of this
/// many (a 5,000-vertex model splits over several workers).
const CHUNK: usize = 1024;

/// Appends `src` to `dst`, or takes it whole when `dst` has no room yet (one object):
/// copying a million vertices' arrays into fresh ones cost a copy and the page faults of a
/// second allocation each frame.
fn adopt<T: Copy>(dst: &mut Vec<T>, src: Vec<T>) {
    if dst.capacity() == 0 {
        *dst = src;
    } else {
        dst.extend_from_slice(&src);
    }
}

/// Clip coordinates of one vertex (f64, rounded to f32), its outcode (of the rounded
/// coordinates, plus [`INVALID`]) and its snapped screen position (zero unless the
/// outcode is 0). `vertex_lanes::clip_vertices` is the same on AVX lanes.
#[inline(always)]
pub(super) fn clip_vertex(
    mvp: &DMat4,
    planes: &ClipPlanes,
    size: (f64, f64),
    p: Vec3,
) -> (Vec4, u8, Snapped) {
    let c = *mvp * p.as_dvec3().extend(1.0);
    let c32 = c.as_vec4();
    let code = if c32.is_finite() {
        planes.outcode_finite(c32)
    } else {
        INVALID
    };
    if code != 0 {
        return (c32, code, Snapped::default());
    }
    match snap(c, size.0, size.1) {
        Some(s) => (c32, 0, s),
        None => (c32, INVALID, Snapped::default()),
    }
}

/// How many leading vertices a `vertex_lanes` function did: the call (unsafe: it needs
/// AVX2) when `wide`, else none. The caller does the rest one at a time.
macro_rules! lane_prefix {
    ($wide:expr, $call:expr) => {{
        #[cfg(target_arch = "x86_64")]
        let done = match $wide {
            // SAFETY: `wide` only when the CPU has AVX2 (`Isa::detect`); each caller's
            // outputs are as long as its inputs.
            true => unsafe { $call },
            false => 0,
        };
        #[cfg(not(target_arch = "x86_64"))]
        let done = {
            let _ = $wide;
            0
        };
        done
    }};
}

/// [`clip_vertex`] of every point of `p` into the same places of `c`, `k` and `s` (as
/// long as `p`), four at a time on AVX2 when `wide`.
#[allow(clippy::too_many_arguments)]
fn clip_vertices(
    wide: bool,
    mvp: &DMat4,
    planes: &ClipPlanes,
    size: (f64, f64),
    p: &[Vec3],
    c: &mut [MaybeUninit<Vec4>],
    k: &mut [MaybeUninit<u8>],
    s: &mut [MaybeUninit<Snapped>],
) {
    let done = lane_prefix!(
        wide,
        vertex_lanes::clip_vertices(mvp, planes.guard(), size, p, c, k, s)
    );
    for (i, &v) in p.iter().enumerate().skip(done) {
        let (c32, code, snapped) = clip_vertex(mvp, planes, size, v);
        c[i].write(c32);
        k[i].write(code);
        s[i].write(snapped);
    }
}

/// World positions of every point of `p` into `o` (as long as `p`), eight at a time on AVX2
/// when `wide`.
fn world_points(wide: bool, model: &Mat4, p: &[Vec3], o: &mut [MaybeUninit<Vec3>]) {
    let done = lane_prefix!(wide, vertex_lanes::world_points(model, p, o));
    for (i, v) in p.iter().enumerate().skip(done) {
        o[i].write(model.transform_point3(*v));
    }
}

/// Unit world normals of every normal of `n` into `o` (as long as `n`; zero where a normal
/// cannot be normalised), eight at a time on AVX2 when `wide`.
fn world_normals(wide: bool, nm: &Mat3, n: &[Vec3], o: &mut [MaybeUninit<Vec3>]) {
    let done = lane_prefix!(wide, vertex_lanes::world_normals(nm, n, o));
    for (i, v) in n.iter().enumerate().skip(done) {
        o[i].write((*nm * *v).normalize_or_zero());
    }
}

/// Appends `src.len()` elements to `dst`, made in parallel chunks of [`CHUNK`] by `fill`
/// (a source chunk, the destination chunk to write) straight into `dst`'s spare room.
///
/// # Safety
/// `fill` must write every element of the destination chunk it is given.
unsafe fn extend_in_chunks<S: Sync, T: Send>(
    dst: &mut Vec<T>,
    src: &[S],
    fill: impl Fn(&[S], &mut [MaybeUninit<T>]) + Sync,
) {
    let (start, n) = (dst.len(), src.len());
    dst.reserve(n);
    dst.spare_capacity_mut()[..n]
        .par_chunks_mut(CHUNK)
        .zip(src.par_chunks(CHUNK))
        .for_each(|(d, s)| fill(s, d));
    // SAFETY: `fill` wrote the first `n` spare elements (the caller's contract).
    unsafe { dst.set_len(start + n) };
}

/// Transforms every object's vertices. `view_proj` is world → clip in f64; each object's
/// full matrix is composed in f64 and rounded once to f32. Each vertex is classified
/// against the clip planes and snapped once here, not once per triangle that uses it.
pub(crate) fn transform(
    scene: &Scene,
    view_proj: DMat4,
    attrs: Attributes,
    planes: &ClipPlanes,
    size: (f64, f64),
    wide: bool,
) -> Vertices {
    let mut out = Vertices::default();
    let total: usize = scene
        .objects()
        .iter()
        .map(|o| o.mesh().positions().len())
        .sum();
    // One object (the usual case) hands its arrays over whole (`adopt`); several are
    // appended into arrays sized once.
    if scene.objects().len() > 1 {
        out.clip.reserve_exact(total);
        out.outcode.reserve_exact(total);
        out.screen.reserve_exact(total);
    }
    out.world.reserve_exact(total);
    if attrs.normal {
        out.normal.reserve_exact(total);
    }
    for obj in scene.objects() {
        let mesh = obj.mesh();
        let pos = mesh.positions();
        let model = obj.transform();
        // Clip coordinates in f64: depth differences of 1e-6 relative (two surfaces 1e-4
        // apart at distance 100 with near = 0.001) survive into the snapped z and 1/w. The f32
        // copy only serves the (rare) clipping path.
        let mvp = view_proj * model.as_dmat4();
        let n = pos.len();
        let (mut clip, mut codes, mut screen) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        clip.spare_capacity_mut()[..n]
            .par_chunks_mut(CHUNK)
            .zip(codes.spare_capacity_mut()[..n].par_chunks_mut(CHUNK))
            .zip(screen.spare_capacity_mut()[..n].par_chunks_mut(CHUNK))
            .zip(pos.par_chunks(CHUNK))
            .for_each(|(((c, k), s), p)| clip_vertices(wide, &mvp, planes, size, p, c, k, s));
        // SAFETY: `clip_vertices` wrote every element of each chunk, so the first `n`.
        unsafe {
            clip.set_len(n);
            codes.set_len(n);
            screen.set_len(n);
        }
        adopt(&mut out.clip, clip);
        adopt(&mut out.outcode, codes);
        adopt(&mut out.screen, screen);
        // SAFETY: `world_points` writes every element of its chunk.
        unsafe {
            extend_in_chunks(&mut out.world, pos, |p, o| world_points(wide, &model, p, o));
        }
        if attrs.normal {
            let nm = obj.normal_matrix();
            let normals = mesh.vertex_normals();
            // SAFETY: `world_normals` writes every element of its chunk.
            unsafe {
                extend_in_chunks(&mut out.normal, normals, |v, o| {
                    world_normals(wide, &nm, v, o)
                });
            }
        }
        if attrs.uv {
            match mesh.uvs() {
                Some(uv) => out.uv.extend_from_slice(uv),
                None => out.uv.resize(out.uv.len() + n, Vec2::ZERO),
            }
        }
        if attrs.color {
            match mesh.colors() {
                Some(c) => out.vertex_color.extend_from_slice(c),
                None => out
                    .vertex_color
                    .resize(out.vertex_color.len() + n, Vec3::ZERO),
            }
        }
        if attrs.tangent {
            match mesh.tangents() {
                Some(t) => {
                    // Tangents follow the surface (the model matrix, not the normals'
                    // inverse transpose); a mirroring transform flips the handedness.
                    let m = glam::Mat3::from_mat4(model);
                    let flip = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
                    out.tangent.par_extend(
                        t.par_iter()
                            .with_min_len(CHUNK)
                            .map(|t| (m * t.truncate()).normalize_or_zero().extend(t.w * flip)),
                    );
                }
                None => out.tangent.resize(out.tangent.len() + n, Vec4::ZERO),
            }
        }
    }
    out
}
