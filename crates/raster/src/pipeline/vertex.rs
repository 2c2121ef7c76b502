//! Vertex stage: object → world → clip space. Geometry only: no material or light is read
//! here (Gouraud's vertex colours are lit afterwards by `shade::prelight`).
//!
//! Only the attributes a render reads are produced ([`Attributes`]): world positions (every
//! mode lights somewhere), world normals for Gouraud and Phong, texture coordinates and
//! vertex colours only when a material or mesh of the scene has them.

use glam::{DMat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::clip::ClipPlanes;
use super::setup::{snap, Snapped};
use crate::options::ShadingMode;
use crate::scene::Scene;

/// Outcode bit of a vertex whose snapped coordinates are unusable (non-finite).
pub(crate) const INVALID: u8 = 0x80;

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

/// Fewest vertices per parallel work item of the transform (a 5,000-vertex model splits over
/// several workers).
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

/// Transforms every object's vertices. `view_proj` is world → clip in f64; each object's
/// full matrix is composed in f64 and rounded once to f32. Each vertex is classified
/// against the clip planes and snapped once here, not once per triangle that uses it.
pub(crate) fn transform(
    scene: &Scene,
    view_proj: DMat4,
    attrs: Attributes,
    planes: &ClipPlanes,
    size: (f64, f64),
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
        let (clip, (codes, screen)): (Vec<Vec4>, (Vec<u8>, Vec<Snapped>)) = pos
            .par_iter()
            .with_min_len(CHUNK)
            .map(|p| {
                let c = mvp * p.as_dvec3().extend(1.0);
                let c32 = c.as_vec4();
                let code = if c32.is_finite() {
                    planes.outcode_finite(c32)
                } else {
                    INVALID
                };
                if code != 0 {
                    return (c32, (code, Snapped::default()));
                }
                match snap(c, size.0, size.1) {
                    Some(s) => (c32, (0, s)),
                    None => (c32, (INVALID, Snapped::default())),
                }
            })
            .unzip();
        adopt(&mut out.clip, clip);
        adopt(&mut out.outcode, codes);
        adopt(&mut out.screen, screen);
        out.world.par_extend(
            pos.par_iter()
                .with_min_len(CHUNK)
                .map(|p| model.transform_point3(*p)),
        );
        if attrs.normal {
            let nm = obj.normal_matrix();
            out.normal.par_extend(
                mesh.vertex_normals()
                    .par_iter()
                    .with_min_len(CHUNK)
                    .map(|n| (nm * *n).normalize_or_zero()),
            );
        }
        let n = pos.len();
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
