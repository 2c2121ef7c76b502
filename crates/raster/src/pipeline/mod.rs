//! The render pipeline, one file per stage:
//!
//! 1. [`vertex`]: object → world → clip space (parallel over vertices);
//! 2. primitive stage (here): assemble, clip ([`clip`]), snap and set up ([`setup`]) triangles
//!    (parallel over fixed-size triangle chunks, results kept in submission order);
//! 3. [`bin`]: sort triangle ids into 64×64 screen tiles;
//! 4. per tile, in parallel: [`raster`] (visibility: depth + triangle id) then [`shade`]
//!    (each visible pixel shaded once, written straight into the output rows of [`tiles`]).

pub(crate) mod bin;
pub(crate) mod clip;
mod cull;
pub(crate) mod isa;
mod lines;
mod passes;
pub(crate) mod raster;
mod recycle;
pub(crate) mod samples;
mod secondary_samples;
pub(crate) mod setup;
pub mod shade;
pub(crate) mod tiles;
pub(crate) mod vertex;
mod vertex_lanes;

pub(crate) use passes::{color_pass, coverage_counts, depth_pass, Buffers};

use std::time::Instant;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::camera::Camera;
use crate::error::{RasterError, Result};
use crate::frame::RenderStats;
use crate::lighting::{check_mirror, LightSet, Surface};
use crate::material::Material;
use crate::options::{EdgeMode, GouraudMethod, RenderOptions, ShadingMode, Technique};
use crate::reflect::SecondaryEffect;
use crate::scene::Scene;
use crate::shadows::ShadowEffect;
use bin::{Binned, Bins, Chunk};
use clip::{ClipPlanes, INVALID};
use setup::{Setup, Snapped};
use shade::prelight;
use vertex::{Attributes, Vertices};

/// Marks a vertex index that refers to a chunk's clip-generated vertices (fixed up on merge).
const EXTRA_BIT: u32 = 1 << 31;
/// Most triangles per primitive-stage work item. Clipping makes at most 7 triangles of one,
/// so a chunk's output fits the 16 local id bits.
const TRI_CHUNK: usize = 8192;
/// Fewest triangles per work item when a small scene is split finer ([`chunk_len`]).
const MIN_CHUNK: usize = 1024;
/// Work items per worker thread a scene is split into, where chunks stay above [`MIN_CHUNK`].
const CHUNKS_PER_THREAD: usize = 4;

/// Triangles per primitive-stage work item for `triangles` on `threads` workers: [`TRI_CHUNK`]
/// on one thread and for big scenes; smaller for small scenes so that every worker gets
/// several (Spot's 23k triangles made 3 chunks, which 2 threads set up in 0.77 of one
/// thread's time). Triangles keep their order whatever the split, so the pictures do not
/// depend on it (only the internal triangle ids do).
fn chunk_len(triangles: usize, threads: usize) -> usize {
    if threads <= 1 {
        return TRI_CHUNK;
    }
    triangles
        .div_ceil(CHUNKS_PER_THREAD * threads)
        .clamp(MIN_CHUNK, TRI_CHUNK)
}

struct ChunkOut {
    chunk: Chunk,
    extra: Vertices,
    clipped: usize,
    culled: usize,
    dropped: usize,
}

/// What the primitive stage reads: geometry only.
struct PrimitiveContext<'a> {
    verts: &'a Vertices,
    planes: ClipPlanes,
    options: &'a RenderOptions,
    tiles: (usize, usize),
    /// Per object: whether setup skips its back faces ([`cull`]).
    cull: Vec<bool>,
}

impl PrimitiveContext<'_> {
    fn assemble(&self, object: u32, first_vertex: u32, indices: &[[u32; 3]]) -> ChunkOut {
        let (w, h) = (self.options.width, self.options.height);
        let (wf, hf) = (w as f64, h as f64);
        let mut out = ChunkOut {
            chunk: Chunk {
                tris: recycle::take(indices.len()),
                bins: Bins::default(),
                object,
                clipped_from: Vec::new(),
                face_terms: Vec::new(),
            },
            extra: Vertices::default(),
            clipped: 0,
            culled: 0,
            dropped: 0,
        };
        let mut bins = bin::BinBuilder::new(self.tiles.0, self.tiles.1, indices.len());
        let params = SetupParams {
            object,
            size: (w, h),
            cull: self.cull[object as usize],
            margin: samples::margin(self.options.samples),
        };
        for idx in indices {
            let v = idx.map(|i| i + first_vertex);
            let codes = v.map(|i| self.verts.outcode[i as usize]);
            if (codes[0] | codes[1] | codes[2]) & INVALID != 0 {
                out.dropped += 1;
                continue;
            }
            if codes[0] & codes[1] & codes[2] != 0 {
                continue; // entirely outside one plane
            }
            let mask = codes[0] | codes[1] | codes[2];
            if mask == 0 {
                let s = v.map(|i| self.verts.screen[i as usize]);
                push_setup(params, s, v, None, &mut out, &mut bins);
                continue;
            }
            let c: [Vec4; 3] = v.map(|i| self.verts.clip[i as usize]);
            let poly = self.planes.clip(c, mask);
            if poly.len() < 3 {
                continue;
            }
            out.clipped += 1;
            let mut ids = Vec::with_capacity(poly.len());
            let mut snapped = Vec::with_capacity(poly.len());
            for (pos, wts) in &poly {
                let id = match wts.iter().position(|&x| x == 1.0) {
                    Some(k) if wts.iter().filter(|&&x| x == 0.0).count() == 2 => v[k],
                    _ => {
                        let local = out.extra.clip.len() as u32;
                        out.extra
                            .push_blend(self.verts, v, wts.map(|x| x as f32), pos.as_vec4());
                        local | EXTRA_BIT
                    }
                };
                ids.push(id);
                snapped.push(setup::snap(*pos, wf, hf));
            }
            let Some(s) = snapped.into_iter().collect::<Option<Vec<_>>>() else {
                out.dropped += 1;
                continue;
            };
            for k in 1..poly.len() - 1 {
                let vv = [ids[0], ids[k], ids[k + 1]];
                push_setup(
                    params,
                    [s[0], s[k], s[k + 1]],
                    vv,
                    Some(v),
                    &mut out,
                    &mut bins,
                );
            }
        }
        out.chunk.bins = bins.finish();
        out
    }
}

/// What setup reads of the render, the same for every triangle of a chunk.
#[derive(Clone, Copy)]
struct SetupParams {
    object: u32,
    size: (u32, u32),
    cull: bool,
    margin: i64,
}

/// Sets up one triangle and bins it; a piece of a clipped triangle (`clipped_from` is the
/// original's vertices) is marked and remembers its original. Inlined into the assembly loop
/// (as a closure called from two places it was an out-of-line call per triangle that
/// reloaded its captures and spilled every register).
#[inline(always)]
fn push_setup(
    p: SetupParams,
    s: [Snapped; 3],
    vv: [u32; 3],
    clipped_from: Option<[u32; 3]>,
    out: &mut ChunkOut,
    bins: &mut bin::BinBuilder,
) {
    match setup::setup(s, vv, p.object, p.size, p.cull, p.margin) {
        Setup::Draw(mut t) => {
            if let Some(v) = clipped_from {
                t.clipped = true;
                let i = out.chunk.tris.len() as u32;
                out.chunk.clipped_from.push((i, v));
            }
            bins.push(&t);
            out.chunk.tris.push(t);
        }
        Setup::Culled => out.culled += 1,
        Setup::Skip => {}
    }
}

/// An object's prepared materials for its front faces (`[0]`) and the faces lit as back
/// faces under two-sided lighting (`[1]`, the front one again without a back material).
pub(crate) type Sides = [Surface; 2];

/// Geometry ready for the tile stage: transformed vertices and binned, set-up triangles.
pub(crate) struct Prepared {
    pub verts: Vertices,
    pub tris: Binned,
    pub materials: Vec<Sides>,
    /// Textured scenes only (else empty): every object's unit surfaces
    /// ([`Surface::unit`]), whose split terms the texture stage weighs per point.
    pub units: Vec<Sides>,
    /// Textured Gouraud only (else empty): every vertex's split terms.
    pub vertex_terms: prelight::VertexTerms,
    pub eye: Vec3,
    /// The scene's shadows (colour passes whose lights cast them).
    pub shadows: Option<ShadowEffect>,
    pub stats: RenderStats,
    t_start: Instant,
}

/// What a pass needs of the scene beyond its geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Needs {
    /// Geometry only (depth and coverage passes): no material or light is read.
    Geometry,
    /// Lit colour: surfaces prepared, and flat or Gouraud lit before the tile stage.
    Color,
}

/// Vertex, primitive and binning stages (and, for colour, the surfaces and the lighting
/// flat and Gouraud do before the tile stage).
pub(crate) fn prepare(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    needs: Needs,
    modes: Option<&[ShadingMode]>,
) -> Result<Prepared> {
    let t_start = Instant::now();
    let (w, h) = (options.width as usize, options.height as usize);
    let mut stats = RenderStats {
        triangles_in: scene.triangle_count(),
        light_sources: scene.light_source_count(),
        ..RenderStats::default()
    };
    let total_vertices: usize = scene
        .objects()
        .iter()
        .map(|o| o.mesh().positions().len())
        .sum();
    if total_vertices >= EXTRA_BIT as usize {
        return Err(RasterError::invalid(format!(
            "the scene has {total_vertices} vertices; at most 2^31 - 1 are supported"
        )));
    }
    let chunk = chunk_len(stats.triangles_in, rayon::current_num_threads());
    let chunk_count: usize = scene
        .objects()
        .iter()
        .map(|o| o.mesh().triangle_count().div_ceil(chunk))
        .sum();
    if chunk_count >= (1 << (32 - bin::LOCAL_BITS)) - 1 {
        return Err(RasterError::invalid(format!(
            "the scene has {} triangles; at most {} are supported",
            stats.triangles_in,
            ((1usize << (32 - bin::LOCAL_BITS)) - 2) * chunk
        )));
    }
    let eye = camera.eye().as_vec3();
    let view_proj = camera.projection_matrix(w as f64 / h as f64) * camera.view_matrix();
    let light_set = LightSet::new(scene.lights());
    // Whether this render's lane loops may use AVX2 + FMA (those outside the tile bodies:
    // vertex lighting, shadow look-ups, the lighting's out-of-line loops).
    let wide = isa::Isa::detect(options.baseline_isa) != isa::Isa::Baseline;
    let viewer = |pm: Surface| {
        let pm = pm.with_wide_lanes(wide);
        if scene.local_viewer() {
            pm
        } else {
            pm.with_infinite_viewer((camera.eye() - camera.target()).as_vec3())
        }
    };
    let prepare_material = |m: &Material| {
        viewer(Surface::folded(
            m,
            scene.ambient(),
            &light_set,
            options.specular,
        ))
    };
    let two_sided = scene.two_sided();
    let lit = needs == Needs::Color;
    // Maps or vertex colours anywhere: the whole scene takes the textured shade path.
    let textured = lit && scene.objects().iter().any(|o| o.is_textured());
    if textured
        && options.shading == ShadingMode::Gouraud
        && options.gouraud == GouraudMethod::FaceIntensities
    {
        return Err(RasterError::invalid_field(
            "gouraud",
            "gouraud='face-intensities' does not support textures or vertex colours; use \
             gouraud='normals' (the default)",
        ));
    }
    if textured && options.shading != ShadingMode::Phong {
        // Maps that act before lighting need per-pixel lighting (flat and Gouraud light at
        // faces and vertices, where a per-pixel exponent or normal cannot enter).
        let per_pixel = |m: &crate::texture::Maps| -> Option<(&'static str, &'static str)> {
            if m.shininess.is_some() {
                Some((
                    "shininess_map",
                    "a shininess map varies the specular exponent",
                ))
            } else if m.normal.is_some() {
                Some(("normal_map", "a normal map varies the normal"))
            } else if m.bump.is_some() {
                Some(("bump_map", "a bump map varies the normal"))
            } else {
                None
            }
        };
        for (i, o) in scene.objects().iter().enumerate() {
            if let Some((field, what)) = o.maps().and_then(|m| per_pixel(m)) {
                return Err(RasterError::invalid_field(
                    field,
                    format!(
                        "object {i}: {what} per pixel and needs per-pixel lighting: use \
                         shading='phong' (flat and Gouraud light at faces and vertices)"
                    ),
                ));
            }
        }
    }
    let units: Vec<Sides> = scene
        .objects()
        .iter()
        .filter(|_| textured)
        .map(|o| {
            let unit = |m: &Material| {
                viewer(Surface::unit(
                    m,
                    scene.ambient(),
                    &light_set,
                    options.specular,
                ))
            };
            [unit(o.material()), unit(o.material_for(true, two_sided))]
        })
        .collect();
    if lit {
        for o in scene.objects() {
            check_mirror(o.material(), options.specular)?;
            check_mirror(o.material_for(true, two_sided), options.specular)?;
        }
    }
    let materials: Vec<Sides> = scene
        .objects()
        .iter()
        .filter(|_| lit)
        .map(|o| {
            let front = prepare_material(o.material());
            let back_material = o.material_for(true, two_sided);
            let back = if back_material == o.material() {
                front.clone()
            } else {
                prepare_material(back_material)
            };
            [front, back]
        })
        .collect();
    check_dynamic_range(scene, &materials)?;
    check_textured_range(scene, &units)?;
    let planes = ClipPlanes::new(options.width, options.height);
    let mut verts = vertex::transform(
        scene,
        view_proj,
        if lit {
            Attributes::for_scene(options.shading, scene)
        } else {
            Attributes::NONE
        },
        &planes,
        (w as f64, h as f64),
        wide,
    );
    // Shadows: the BVH or the maps, before flat and Gouraud light (they read them).
    let shadows = match lit && scene.lights().iter().any(|l| l.shadows().on()) {
        true => ShadowEffect::new(
            scene,
            &light_set,
            &verts.world[..total_vertices],
            // Only Phong shades at visible points alone: flat and Gouraud light face centres
            // and vertices (which may lie off the view), ray hits may lie anywhere. With
            // `shading="auto"` every object must be Phong.
            (modes.map_or(options.shading == ShadingMode::Phong, |m| {
                m.iter().all(|&x| x == ShadingMode::Phong)
            }) && options.reflections != Technique::Ray
                && options.refractions != Some(Technique::Ray))
            .then_some(camera),
            options,
            &|cam, opts, out| depth_pass(scene, cam, opts, out, true).map(|_| ()),
            wide,
        )?,
        false => None,
    };
    let t_vertex = Instant::now();

    // Primitive stage (assembly, clipping, setup, per-chunk binning) over fixed chunks.
    // Per object, its chunks and whether setup skips its back faces (from the outcodes of
    // its transformed vertices).
    let mut work = Vec::with_capacity(chunk_count);
    let mut cull = Vec::with_capacity(scene.objects().len());
    let mut first_vertex = 0u32;
    for (oi, obj) in scene.objects().iter().enumerate() {
        for part in obj.mesh().indices().chunks(chunk) {
            work.push((oi as u32, first_vertex, part));
        }
        let n = obj.mesh().positions().len();
        let codes = &verts.outcode[first_vertex as usize..first_vertex as usize + n];
        cull.push(cull::skips_back_faces(obj, codes, options, two_sided));
        first_vertex += n as u32;
    }
    let ctx = PrimitiveContext {
        verts: &verts,
        planes,
        options,
        tiles: tiles::tile_counts(w, h),
        cull,
    };
    // Each object's mode: the render's, or its own (`shading="auto"` mixing modes).
    let mode_of = |object: u32| modes.map_or(options.shading, |m| m[object as usize]);
    // Textured flat lights its faces' split terms in the tile stage.
    let flat_lit = lit && !textured;
    let mut outs: Vec<ChunkOut> = work
        .par_iter()
        .map(|&(oi, fv, idx)| {
            let mut out = ctx.assemble(oi, fv, idx);
            // Flat faces are lit as each chunk is set up, while its triangles are still in
            // cache (a second pass over all chunks re-read ~10 MB for 100k triangles and
            // made setup ~3 ms slower at 1080p), and from the transformed vertices only:
            // the clip-made ones have not joined yet.
            if flat_lit && mode_of(oi) == ShadingMode::Flat {
                prelight::light_faces(
                    &mut out.chunk,
                    &verts.world,
                    &materials,
                    eye,
                    two_sided,
                    shadows.as_ref(),
                );
            }
            out
        })
        .collect();
    // Clip-generated vertices go after the transformed ones, chunk by chunk.
    let mut offset = verts.clip.len() as u32;
    let mut extras = Vertices::default();
    for out in &mut outs {
        if !out.extra.clip.is_empty() {
            for t in &mut out.chunk.tris {
                for v in &mut t.v {
                    if *v & EXTRA_BIT != 0 {
                        *v = offset + (*v & !EXTRA_BIT);
                    }
                }
            }
            offset += out.extra.clip.len() as u32;
            extras.append(&mut out.extra);
        }
        stats.triangles_clipped += out.clipped;
        stats.triangles_culled += out.culled;
        stats.triangles_dropped += out.dropped;
    }
    verts.append(&mut extras);
    let gouraud = match modes {
        Some(m) => m.contains(&ShadingMode::Gouraud),
        None => options.shading == ShadingMode::Gouraud,
    };
    if lit && gouraud && !textured {
        // Gouraud's vertex lighting drops the world positions and normals it no longer
        // needs, unless lines, the secondary stage or Phong objects in the same frame read
        // them after this.
        let phong_too = modes.is_some_and(|m| m.contains(&ShadingMode::Phong));
        let keep =
            phong_too || options.edges != EdgeMode::None || SecondaryEffect::wanted(scene, options);
        match options.gouraud {
            GouraudMethod::Normals => {
                let used = used_vertices(&outs, &verts.blends, total_vertices);
                prelight::light_vertices(
                    scene,
                    &mut verts,
                    &materials,
                    eye,
                    shadows.as_ref(),
                    keep,
                    wide,
                    &used,
                )
            }
            GouraudMethod::FaceIntensities => prelight::light_vertices_by_faces(
                scene,
                &mut verts,
                &materials,
                eye,
                shadows.as_ref(),
                keep,
            ),
        }
    }
    // Textured Gouraud lights its vertices' split terms (the texture stage weighs them by
    // the maps) and keeps the world positions and normals (it reads them too).
    let vertex_terms = if lit && gouraud && textured {
        let used = used_vertices(&outs, &verts.blends, total_vertices);
        prelight::light_vertex_terms(scene, &verts, &units, eye, shadows.as_ref(), wide, &used)
    } else {
        prelight::VertexTerms::default()
    };
    // Textured flat lights its faces' split terms, now that the clip-made vertices have
    // joined (a clipped piece is lit as its own face).
    if lit && textured && options.shading == ShadingMode::Flat {
        outs.par_iter_mut().for_each(|o| {
            prelight::light_face_terms(
                &mut o.chunk,
                &verts.world,
                &units,
                eye,
                two_sided,
                shadows.as_ref(),
                wide,
            )
        });
    }
    let tris = Binned {
        chunks: outs.into_iter().map(|o| o.chunk).collect(),
    };
    stats.triangles_setup = tris.len();
    let t_setup = Instant::now();
    stats.timings.vertex = t_vertex - t_start;
    stats.timings.setup = t_setup - t_vertex;
    Ok(Prepared {
        verts,
        tris,
        materials,
        units,
        vertex_terms,
        eye,
        shadows,
        stats,
        t_start: t_setup,
    })
}

/// Which of the `total` transformed vertices the set-up triangles use, directly or through
/// a clip-made vertex's blend (Gouraud lights only those).
fn used_vertices(outs: &[ChunkOut], blends: &[([u32; 3], [f32; 3])], total: usize) -> Vec<bool> {
    use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
    let used: Vec<AtomicBool> = (0..total).map(|_| AtomicBool::new(false)).collect();
    // Stores of `true` only: the result is the same whatever the order.
    outs.par_iter().for_each(|o| {
        for t in &o.chunk.tris {
            for &v in &t.v {
                if let Some(u) = used.get(v as usize) {
                    u.store(true, Relaxed);
                }
            }
        }
    });
    for (from, _) in blends {
        for &v in from {
            used[v as usize].store(true, Relaxed);
        }
    }
    used.into_iter().map(AtomicBool::into_inner).collect()
}

/// Largest colour value the lighting of a scene may reach. Far below `f32::MAX`
/// (3.4·10³⁸), so Gouraud interpolation and fog, which never exceed their inputs by more
/// than rounding, stay finite too.
pub const MAX_RADIANCE: f64 = 1e37;

/// [`check_dynamic_range`] for textured objects: each unit surface's bound times the largest
/// coefficient a map or vertex colour can make (`ka·Ta`, `kd·Td`, `ks·Ts`), plus the
/// emission times its map's largest value.
fn check_textured_range(scene: &Scene, units: &[Sides]) -> Result<()> {
    for (i, (o, sides)) in scene.objects().iter().zip(units).enumerate() {
        let tmax = |t: Option<&std::sync::Arc<crate::texture::Texture>>| {
            t.map_or(1.0, |t| t.max_value() as f64)
        };
        let maps = o.maps().map(|m| &**m);
        let (td, ta, ts, te) = match maps {
            Some(m) => (
                tmax(m.diffuse.as_ref()),
                tmax(m.ambient_or_diffuse()),
                tmax(m.specular.as_ref()),
                tmax(m.emission.as_ref()),
            ),
            None => (1.0, 1.0, 1.0, 1.0),
        };
        let vmax = o
            .mesh()
            .colors()
            .map(|c| c.iter().map(|v| v.max_element() as f64).fold(0.0, f64::max));
        for (side, m) in [
            (0, o.material()),
            (1, o.material_for(true, scene.two_sided())),
        ] {
            let (ka, kd) = match vmax {
                Some(v) => (v, v),
                None => (
                    m.ambient.max_element() as f64,
                    m.diffuse.max_element() as f64,
                ),
            };
            let k = (ka * ta)
                .max(kd * td)
                .max(m.specular.max_element() as f64 * ts);
            let bound = sides[side].max_value() * k + m.emission.max_element() as f64 * te;
            if bound > MAX_RADIANCE || bound.is_nan() {
                return Err(RasterError::invalid(format!(
                    "object {i}: its textured lighting can reach {bound:.3e}, beyond the \
                     {MAX_RADIANCE:e} that float32 colours can safely hold; scale down light \
                     intensities, material colours or texture values"
                )));
            }
        }
    }
    Ok(())
}

/// Refuses scenes whose lighting could overflow f32: an overflowed term is `inf`, and
/// `inf · 0` (a zero fog factor, barycentric or spot factor) is NaN.
fn check_dynamic_range(scene: &Scene, materials: &[Sides]) -> Result<()> {
    for (i, sides) in materials.iter().enumerate() {
        // Front and back materials (the back one is the front one again without its own).
        let bound = sides[0].max_value().max(sides[1].max_value());
        if bound > MAX_RADIANCE || bound.is_nan() {
            return Err(RasterError::invalid(format!(
                "object {i}: its lighting can reach {bound:.3e}, beyond the {MAX_RADIANCE:e} \
                 that float32 colours can safely hold; scale down light intensities or \
                 material colours"
            )));
        }
    }
    if let Some(fog) = scene.fog() {
        let c = fog.color().max_element() as f64;
        if c > MAX_RADIANCE {
            return Err(RasterError::invalid(format!(
                "fog color {c:.3e} is beyond the {MAX_RADIANCE:e} that float32 colours can \
                 safely hold"
            )));
        }
    }
    Ok(())
}
