//! The lighting done before the tile stage. Untextured geometry, whose colour needs no
//! map: Gouraud lights every vertex (then extends the colours to the vertices clipping made,
//! by their blends), flat lights every set-up triangle once (a clipped triangle's pieces
//! share the colour of the original). Textured geometry: the split terms (ambient, diffuse,
//! specular) the texture stage weighs by the maps, per vertex for Gouraud
//! ([`light_vertex_terms`]) and per set-up triangle for flat ([`light_face_terms`]). All
//! evaluate [`LANES`] points at a time.

use glam::Vec3;
use rayon::prelude::*;

use crate::lighting::{lane, normalize_lanes, Folded, Lanes, Split, Surface, LANES};
use crate::pipeline::bin::Chunk;
use crate::pipeline::setup::SetupTri;
use crate::pipeline::vertex::Vertices;
use crate::pipeline::Sides;
use crate::scene::Scene;
use crate::shadows::ShadowEffect;

/// The colours of the first `live` of [`LANES`] points (unit normals `n`), each
/// shadow-casting light's diffuse and specular scaled by its visibility from the point:
/// flat and Gouraud find visibility where they light (face centroids, vertices), so their
/// shadows are as coarse as their shading (Phong's are per pixel). The normal stands in for
/// the geometric one (the ray offset's direction).
#[inline(always)]
fn lit(
    surface: &Surface,
    shadows: Option<&ShadowEffect>,
    n: &[Lanes; 3],
    p: &[Lanes; 3],
    live: usize,
    eye: Vec3,
) -> [Lanes; 3] {
    match shadows {
        None => surface.shade_lanes(n, p, eye),
        Some(s) => lit_shadowed(surface, s, n, p, live, eye),
    }
}

/// [`lit`] with shadows, out of line so the shadowless loops stay as they were.
#[cold]
#[inline(never)]
fn lit_shadowed(
    surface: &Surface,
    shadows: &ShadowEffect,
    n: &[Lanes; 3],
    p: &[Lanes; 3],
    live: usize,
    eye: Vec3,
) -> [Lanes; 3] {
    let mut vis = vec![None; shadows.sources()];
    shadows.visibility(n, p, n, live, &mut vis);
    surface.terms_lanes_visible::<Folded>(n, p, eye, &vis).0
}

/// Fewest vertices lit per parallel work item: small enough that a 5,000-vertex model is
/// lit by two workers (with 4,096 its one item ran on one), large enough that rayon's
/// per-item cost stays below a percent.
const CHUNK: usize = 1024;

/// How [`light_vertices`] lights one batch of up to [`LANES`] vertices.
struct VertexLanes<'a> {
    surface: &'a Surface,
    shadows: Option<&'a ShadowEffect>,
    /// 1, or −1 for the back side's colours (flipped normals).
    flip: f32,
    eye: Vec3,
}

impl VertexLanes<'_> {
    /// The colours `o` of the vertices at `p` with normals `n` (all of the same length).
    #[inline(always)]
    fn light(&self, p: &[Vec3], n: &[Vec3], o: &mut [Vec3]) {
        let mut nl = [[0.0; LANES]; 3];
        let mut pl = [[0.0; LANES]; 3];
        for (k, (p, n)) in p.iter().zip(n).enumerate() {
            let n = *n * self.flip;
            for ax in 0..3 {
                nl[ax][k] = n[ax];
                pl[ax][k] = p[ax];
            }
        }
        let c = lit(self.surface, self.shadows, &nl, &pl, p.len(), self.eye);
        for (k, o) in o.iter_mut().enumerate() {
            *o = Vec3::new(c[0][k], c[1][k], c[2][k]);
        }
    }

    /// [`VertexLanes::light`] compiled for AVX2 + FMA: the lighting's lane loops widen, with
    /// the same bits (no fused multiply-adds are formed; see `isa.rs`).
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn light_avx2(&self, p: &[Vec3], n: &[Vec3], o: &mut [Vec3]) {
        self.light(p, n, o);
    }
}

/// Gouraud (by vertex normals, the default): the lit colour of every vertex (`verts.color`) and, under two-sided lighting,
/// the colour lit with the flipped normal and the back material (`verts.color_back`). Reads
/// the world positions and normals of the transformed vertices and drops them afterwards
/// (the tile stage interpolates colours only) unless `keep_geometry` (a later stage reads
/// them: lines, reflections and transparency). `wide`: the CPU has AVX2 and FMA (the
/// lighting runs in their lanes, with the same bits).
///
/// Only the vertices in `used` (indexed like the transformed vertices) are lit, eight lanes
/// at a time: a group of lanes none of which is used is skipped and its colours left at
/// zero, which no drawn triangle reads (culled back faces and triangles covering no pixel
/// centre leave many vertices unused; each lit one gets the same bits either way).
#[allow(clippy::too_many_arguments)]
pub(crate) fn light_vertices(
    scene: &Scene,
    verts: &mut Vertices,
    surfaces: &[Sides],
    eye: Vec3,
    shadows: Option<&ShadowEffect>,
    keep_geometry: bool,
    wide: bool,
    used: &[bool],
) {
    #[cfg(not(target_arch = "x86_64"))]
    let _ = wide;
    let two_sided = scene.two_sided();
    let mut first = 0;
    let mut color = Vec::with_capacity(verts.clip.len());
    let mut color_back = Vec::new();
    for (obj, [front, back]) in scene.objects().iter().zip(surfaces) {
        let n = obj.mesh().positions().len();
        let (pos, normals) = (
            &verts.world[first..first + n],
            &verts.normal[first..first + n],
        );
        // Each work item writes its lanes' colours straight into its slice of the output (a
        // flat-mapped iterator of single colours paid an iterator step per vertex).
        let used = &used[first..first + n];
        let light = |flip: f32, out: &mut Vec<Vec3>| {
            let surface = if flip > 0.0 { front } else { back };
            let start = out.len();
            out.resize(start + n, Vec3::ZERO);
            out[start..]
                .par_chunks_mut(LANES)
                .zip(pos.par_chunks(LANES))
                .zip(normals.par_chunks(LANES))
                .zip(used.par_chunks(LANES))
                .with_min_len(CHUNK / LANES)
                .for_each(|(((o, p), n), u)| {
                    if !u.contains(&true) {
                        return;
                    }
                    let lanes = VertexLanes {
                        surface,
                        shadows,
                        flip,
                        eye,
                    };
                    #[cfg(target_arch = "x86_64")]
                    if wide {
                        // SAFETY: `wide` is true only when the CPU reported AVX2 and FMA
                        // (`Isa::detect`, by the caller).
                        unsafe { lanes.light_avx2(p, n, o) };
                        return;
                    }
                    lanes.light(p, n, o);
                });
        };
        light(1.0, &mut color);
        if two_sided {
            light(-1.0, &mut color_back);
        }
        first += n;
    }
    finish_vertex_colors(verts, color, color_back, two_sided, keep_geometry);
}

/// Extends the vertex colours to the clip-made vertices, stores them, and drops the world
/// positions and normals unless `keep_geometry` (the tile stage interpolates colours only).
fn finish_vertex_colors(
    verts: &mut Vertices,
    mut color: Vec<Vec3>,
    mut color_back: Vec<Vec3>,
    two_sided: bool,
    keep_geometry: bool,
) {
    Vertices::extend_to_clipped(&verts.blends, &mut color);
    if two_sided {
        Vertices::extend_to_clipped(&verts.blends, &mut color_back);
    }
    verts.color = color;
    verts.color_back = color_back;
    if !keep_geometry {
        verts.world = Vec::new();
        verts.normal = Vec::new();
    }
}

/// Gouraud by the lectures' "simple method" ([`crate::GouraudMethod::FaceIntensities`]):
/// every face of the mesh is lit as flat lights it (its unit normal
/// `normalize((p1 − p0) × (p2 − p0))` at its centroid; zero for a degenerate face), and a
/// vertex's colour is the unweighted mean of the colours of the faces that use it (a face
/// naming the vertex twice counts once). A vertex no face uses is never drawn and gets
/// black. Two-sided: the same with the flipped normals and the back material.
/// `keep_geometry` as for [`light_vertices`].
pub(crate) fn light_vertices_by_faces(
    scene: &Scene,
    verts: &mut Vertices,
    surfaces: &[Sides],
    eye: Vec3,
    shadows: Option<&ShadowEffect>,
    keep_geometry: bool,
) {
    let two_sided = scene.two_sided();
    let mut first = 0;
    let mut color = Vec::with_capacity(verts.clip.len());
    let mut color_back = Vec::new();
    for (obj, [front, back]) in scene.objects().iter().zip(surfaces) {
        let n = obj.mesh().positions().len();
        let pos = &verts.world[first..first + n];
        let faces = obj.mesh().indices();
        let light = |surface: &crate::lighting::Surface, flip: f32| -> Vec<Vec3> {
            let lit: Vec<Vec3> = faces
                .par_chunks(LANES)
                .with_min_len(CHUNK / LANES)
                .flat_map_iter(|group| {
                    let mut raw = [[0.0; LANES]; 3];
                    let mut p = [[0.0; LANES]; 3];
                    for (k, f) in group.iter().enumerate() {
                        let [a, b, c] = f.map(|v| pos[v as usize]);
                        let nrm = (b - a).cross(c - a) * flip;
                        let centroid = (a + b + c) / 3.0;
                        for ax in 0..3 {
                            raw[ax][k] = nrm[ax];
                            p[ax][k] = centroid[ax];
                        }
                    }
                    let mut nl = [[0.0; LANES]; 3];
                    normalize_lanes(&mut nl, &raw, surface.wide());
                    let c = lit(surface, shadows, &nl, &p, group.len(), eye);
                    (0..group.len()).map(move |k| Vec3::new(c[0][k], c[1][k], c[2][k]))
                })
                .collect();
            // Sums in f64 so the mean does not depend on the order of a large fan.
            let mut sum = vec![glam::DVec3::ZERO; n];
            let mut count = vec![0u32; n];
            for (f, c) in faces.iter().zip(&lit) {
                let [a, b, d] = *f;
                for (i, v) in [a, b, d].into_iter().enumerate() {
                    if f[..i].contains(&v) {
                        continue;
                    }
                    sum[v as usize] += c.as_dvec3();
                    count[v as usize] += 1;
                }
            }
            sum.iter()
                .zip(&count)
                .map(|(s, &k)| {
                    if k == 0 {
                        Vec3::ZERO
                    } else {
                        (*s / k as f64).as_vec3()
                    }
                })
                .collect()
        };
        color.extend(light(front, 1.0));
        if two_sided {
            color_back.extend(light(back, -1.0));
        }
        first += n;
    }
    finish_vertex_colors(verts, color, color_back, two_sided, keep_geometry);
}

/// Flat: the colour of every set-up triangle of `chunk` (`t.flat`), lit with the face normal
/// at the centroid; back faces under two-sided lighting with the flipped normal and the back
/// material. `world` holds the transformed vertices' world positions.
pub(crate) fn light_faces(
    chunk: &mut Chunk,
    world: &[Vec3],
    surfaces: &[Sides],
    eye: Vec3,
    two_sided: bool,
    shadows: Option<&ShadowEffect>,
) {
    let sides = &surfaces[chunk.object as usize];
    let tris = &mut chunk.tris;
    // Two-sided lighting lights back faces with the flipped normal and their material.
    let side = |t: &SetupTri| two_sided && !t.front;
    for back in [false, true] {
        let surface = &sides[back as usize];
        let todo: Vec<usize> = (0..tris.len())
            .filter(|&i| !tris[i].clipped && side(&tris[i]) == back)
            .collect();
        for group in todo.chunks(LANES) {
            let mut raw = [[0.0; LANES]; 3];
            let mut p = [[0.0; LANES]; 3];
            for (k, &i) in group.iter().enumerate() {
                let t = &tris[i];
                let [a, b, c] = t.v.map(|v| world[v as usize]);
                // Setup swapped two vertices of front faces; undo it for the true normal.
                let n = if t.front {
                    (c - a).cross(b - a)
                } else {
                    (b - a).cross(c - a)
                };
                let n = if back { -n } else { n };
                let centroid = (a + b + c) / 3.0;
                for ax in 0..3 {
                    raw[ax][k] = n[ax];
                    p[ax][k] = centroid[ax];
                }
            }
            let mut n = [[0.0; LANES]; 3];
            normalize_lanes(&mut n, &raw, surface.wide());
            let c = lit(surface, shadows, &n, &p, group.len(), eye);
            for (k, &i) in group.iter().enumerate() {
                tris[i].flat = Vec3::new(c[0][k], c[1][k], c[2][k]);
            }
        }
    }
    // Pieces of a clipped triangle: the original triangle's colour, lit once (the side of
    // its first piece decides), shared by its consecutive pieces.
    let mut last: Option<([u32; 3], Vec3)> = None;
    for &(i, v) in &chunk.clipped_from {
        let t = &mut tris[i as usize];
        let color = match last {
            Some((lv, c)) if lv == v => c,
            _ => {
                let flip = two_sided && !t.front;
                let [a, b, c] = v.map(|i| world[i as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                let n = if flip { -n } else { n };
                let centroid = (a + b + c) / 3.0;
                let surface = &sides[flip as usize];
                match shadows {
                    None => surface.shade(n, centroid, eye),
                    Some(_) => {
                        let splat = |v: Vec3| [[v.x; LANES], [v.y; LANES], [v.z; LANES]];
                        let c = lit(surface, shadows, &splat(n), &splat(centroid), 1, eye);
                        Vec3::new(c[0][0], c[1][0], c[2][0])
                    }
                }
            }
        };
        t.flat = color;
        last = Some((v, color));
    }
}

/// Split lighting terms of one point (ambient, diffuse, specular), which the texture stage
/// weighs by the maps' colours.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Terms3 {
    pub a: Vec3,
    pub d: Vec3,
    pub s: Vec3,
}

/// The split terms `out[k]` of up to [`LANES`] points (unit normals `n`, positions `p`) lit
/// by `unit`, each shadow-casting light's diffuse and specular scaled by its visibility from
/// the point (as [`lit`]: the normal stands in for the geometric one).
#[inline(always)]
fn split_lanes(
    unit: &Surface,
    shadows: Option<&ShadowEffect>,
    n: &[Vec3],
    p: &[Vec3],
    eye: Vec3,
    out: &mut [Terms3],
) {
    let mut nl = [[0.0; LANES]; 3];
    let mut pl = [[0.0; LANES]; 3];
    for (k, (n, p)) in n.iter().zip(p).enumerate() {
        for ax in 0..3 {
            nl[ax][k] = n[ax];
            pl[ax][k] = p[ax];
        }
    }
    let t: Split = match shadows {
        None => unit.terms_lanes(&nl, &pl, eye),
        Some(s) => {
            let mut vis = vec![None; s.sources()];
            s.visibility(&nl, &pl, &nl, n.len(), &mut vis);
            unit.terms_lanes_visible(&nl, &pl, eye, &vis)
        }
    };
    for (k, o) in out.iter_mut().enumerate().take(n.len()) {
        *o = Terms3 {
            a: lane(&t.ambient, k),
            d: lane(&t.diffuse, k),
            s: lane(&t.specular, k),
        };
    }
}

/// [`split_lanes`] compiled for AVX2 + FMA: the lighting's lane loops widen, with the same
/// bits (no fused multiply-adds are formed; see `isa.rs`).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn split_lanes_avx2(
    unit: &Surface,
    shadows: Option<&ShadowEffect>,
    n: &[Vec3],
    p: &[Vec3],
    eye: Vec3,
    out: &mut [Terms3],
) {
    split_lanes(unit, shadows, n, p, eye, out);
}

/// [`split_lanes`], compiled for AVX2 + FMA where `wide` (the CPU reported both:
/// `Isa::detect`, by the caller).
#[inline(always)]
pub(crate) fn split_on(
    wide: bool,
    unit: &Surface,
    shadows: Option<&ShadowEffect>,
    n: &[Vec3],
    p: &[Vec3],
    eye: Vec3,
    out: &mut [Terms3],
) {
    #[cfg(target_arch = "x86_64")]
    if wide {
        // SAFETY: `wide` is true only when the CPU reported AVX2 and FMA.
        unsafe { split_lanes_avx2(unit, shadows, n, p, eye, out) };
        return;
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = wide;
    split_lanes(unit, shadows, n, p, eye, out);
}

/// The unit normal and the centroid of set-up triangle `t` (world vertices `pos`), the
/// normal flipped for the `back` side: where flat lights a face.
#[inline]
pub(crate) fn face_point(t: &SetupTri, pos: [Vec3; 3], back: bool) -> (Vec3, Vec3) {
    let [a, b, c] = pos;
    // Setup swapped two vertices of front faces; undo it for the true normal.
    let n = if t.front {
        (c - a).cross(b - a)
    } else {
        (b - a).cross(c - a)
    };
    let n = if back { -n } else { n }.normalize_or_zero();
    (n, (a + b + c) / 3.0)
}

/// Textured Gouraud's vertex lighting: the split terms of every vertex (`front`) and, under
/// two-sided lighting, those lit with the flipped normal and the back unit surface (`back`),
/// indexed like the vertices (clip-made ones included). The texture stage reads a
/// triangle's three when it loads it, instead of lighting them there: a vertex was lit once
/// per triangle that uses it and again each time a tile re-loaded the triangle, about
/// eight times per vertex on a mesh.
#[derive(Default)]
pub(crate) struct VertexTerms {
    pub front: Vec<Terms3>,
    pub back: Vec<Terms3>,
}

impl VertexTerms {
    /// The terms of one side.
    #[inline]
    pub fn side(&self, back: bool) -> &[Terms3] {
        if back {
            &self.back
        } else {
            &self.front
        }
    }
}

/// Lights [`VertexTerms`] for the textured Gouraud: each object's vertices with its unit
/// surfaces (`units`, [`Surface::unit`]), as the texture stage lit them per triangle
/// (same bits: each point's lanes are independent of the others'). Only the transformed
/// vertices in `used` are lit ([`LANES`] at a time, a group with none used is skipped and
/// left at zero, which no drawn triangle reads), and every clip-made vertex, with the
/// surfaces of the object it was blended from. A side whose surface no light reaches is
/// not lit at all: the texture stage shades it flat (`shaded_as`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn light_vertex_terms(
    scene: &Scene,
    verts: &Vertices,
    units: &[Sides],
    eye: Vec3,
    shadows: Option<&ShadowEffect>,
    wide: bool,
    used: &[bool],
) -> VertexTerms {
    let two_sided = scene.two_sided();
    // Each object's first vertex, then the count of transformed vertices.
    let mut first = Vec::with_capacity(scene.objects().len() + 1);
    first.push(0usize);
    for o in scene.objects() {
        first.push(first.last().copied().unwrap_or(0) + o.mesh().positions().len());
    }
    let transformed = first.last().copied().unwrap_or(0);
    let total = verts.world.len();
    let light = |side: usize| -> Vec<Terms3> {
        let flip = if side == 0 { 1.0 } else { -1.0 };
        let mut out = vec![Terms3::default(); total];
        let group = |unit: &Surface, p: &[Vec3], n: &[Vec3], o: &mut [Terms3]| {
            vertex_group(wide, unit, shadows, flip, p, n, eye, o)
        };
        for (oi, sides) in units.iter().enumerate() {
            let unit = &sides[side];
            if unit.lights.is_empty() {
                continue;
            }
            let r = first[oi]..first[oi + 1];
            out[r.clone()]
                .par_chunks_mut(LANES)
                .zip(verts.world[r.clone()].par_chunks(LANES))
                .zip(verts.normal[r.clone()].par_chunks(LANES))
                .zip(used[r].par_chunks(LANES))
                .with_min_len(CHUNK / LANES)
                .for_each(|(((o, p), n), u)| {
                    if u.contains(&true) {
                        group(unit, p, n, o);
                    }
                });
        }
        // Clip-made vertices (few: those of triangles crossing the near or guard planes),
        // each with its object's surface.
        for (i, (from, _)) in verts.blends.iter().enumerate() {
            let v = transformed + i;
            let oi = first.partition_point(|&f| f <= from[0] as usize) - 1;
            let unit = &units[oi][side];
            if !unit.lights.is_empty() {
                group(
                    unit,
                    &verts.world[v..v + 1],
                    &verts.normal[v..v + 1],
                    &mut out[v..v + 1],
                );
            }
        }
        out
    };
    VertexTerms {
        front: light(0),
        back: if two_sided { light(1) } else { Vec::new() },
    }
}

/// One lane group of [`light_vertex_terms`]: up to [`LANES`] vertices, their normals `n`
/// scaled by `flip` (−1: the back side). A function, not a closure of the caller: as a
/// closure calling [`split_on`], test binaries of the dev profile failed to link
/// ("undefined hidden symbol" for the closure, rust-lld, rustc 1.95).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn vertex_group(
    wide: bool,
    unit: &Surface,
    shadows: Option<&ShadowEffect>,
    flip: f32,
    p: &[Vec3],
    n: &[Vec3],
    eye: Vec3,
    o: &mut [Terms3],
) {
    let mut nf = [Vec3::ZERO; LANES];
    for (f, n) in nf.iter_mut().zip(n) {
        *f = *n * flip;
    }
    split_on(wide, unit, shadows, &nf[..n.len()], p, eye, o);
}

/// Textured flat's face lighting: the split terms of every set-up triangle of `chunk`
/// (`chunk.face_terms`), each lit at its centroid with its unit normal (flipped, with the
/// back unit surface, for a back face under two-sided lighting), [`LANES`] faces at a
/// time. The texture stage lit each face when it loaded it, once per tile that re-loaded it
/// and one face per lane group; the same points give the same bits here. A piece of a
/// clipped triangle is lit as its own face (as the texture stage did). `world` holds every
/// vertex's world position, clip-made ones included.
pub(crate) fn light_face_terms(
    chunk: &mut Chunk,
    world: &[Vec3],
    units: &[Sides],
    eye: Vec3,
    two_sided: bool,
    shadows: Option<&ShadowEffect>,
    wide: bool,
) {
    let sides = &units[chunk.object as usize];
    let tris = &chunk.tris;
    let mut out = vec![Terms3::default(); tris.len()];
    let side = |t: &SetupTri| two_sided && !t.front;
    for back in [false, true] {
        let unit = &sides[back as usize];
        let todo: Vec<usize> = (0..tris.len())
            .filter(|&i| side(&tris[i]) == back)
            .collect();
        for group in todo.chunks(LANES) {
            let mut n = [Vec3::ZERO; LANES];
            let mut p = [Vec3::ZERO; LANES];
            for (k, &i) in group.iter().enumerate() {
                let t = &tris[i];
                (n[k], p[k]) = face_point(t, t.v.map(|v| world[v as usize]), back);
            }
            let (n, p) = (&n[..group.len()], &p[..group.len()]);
            let mut o = [Terms3::default(); LANES];
            split_on(wide, unit, shadows, n, p, eye, &mut o);
            for (k, &i) in group.iter().enumerate() {
                out[i] = o[k];
            }
        }
    }
    chunk.face_terms = out;
}
