//! Passes over the prepared geometry: the colour pass (visibility, then shading, into the
//! user's buffers), the depth-only pass (visibility alone: a shadow map's pass) and the
//! coverage test hook. Each is the same vertex, primitive, binning and raster stages; they
//! differ in what a tile does with its visibility buffer.

use rayon::prelude::*;

use super::lines::{LinePass, LineScratch, TileRows};
use super::raster;
use super::shade::{put, Out, Pixel, Program, ShadeContext, TexturedObject, TexturedScene};
use super::{isa, prepare, tiles, Needs};
use crate::camera::{Camera, Projection};
use crate::effects::FogEffect;
use crate::error::{RasterError, Result};
use crate::frame::RenderStats;
use crate::options::{EdgeMode, Interpolation, RenderOptions, ShadingMode};
use crate::reflect::SecondaryEffect;
use crate::scene::Scene;

/// The row-major output buffers of a colour pass: `height·width·3` colour samples and,
/// when asked for, `height·width` depths and coverages.
pub(crate) struct Buffers<'a, P> {
    pub color: &'a mut [Out<P>],
    pub depth: Option<&'a mut [Out<f32>]>,
    pub coverage: Option<&'a mut [Out<f32>]>,
}

/// Per-tile row lists of an optional single-channel output (`None` for every tile when the
/// output is not wanted).
fn tile_rows<T>(
    buf: Option<&mut [T]>,
    w: usize,
    h: usize,
    tiles: usize,
) -> Vec<Option<Vec<&mut [T]>>> {
    match buf {
        Some(b) => tiles::split_rows(b, w, h, 1)
            .into_iter()
            .map(Some)
            .collect(),
        None => (0..tiles).map(|_| None).collect(),
    }
}

/// Runs the whole pipeline into caller-provided row-major buffers. On success every sample
/// of the colour, depth and coverage buffers has been written (tiles cover the image, and
/// each tile writes every pixel of its rows: background or shaded). `modes`: each object's
/// own shading mode (`shading="auto"` mixing modes; `options.shading` is then the most
/// accurate of them); `None` shades every object with `options.shading`.
pub(crate) fn color_pass<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    modes: Option<&[ShadingMode]>,
    out: Buffers<'_, P>,
) -> Result<RenderStats> {
    let secondary_wanted = SecondaryEffect::wanted(scene, options);
    if secondary_wanted {
        check_secondary(scene, options)?;
    }
    let mut prep = prepare(scene, camera, options, Needs::Color, modes)?;
    // Phong reads them per pixel, and the texture stage where it lights (every mode); the
    // untextured flat and Gouraud have used them already (prelight).
    let shadows = match options.shading {
        ShadingMode::Phong => prep.shadows.take(),
        _ if !prep.units.is_empty() => prep.shadows.take(),
        _ => None,
    };
    let (w, h) = (options.width as usize, options.height as usize);
    let rects = tiles::tile_rects(w, h);
    let mut color_rows = tiles::split_rows(out.color, w, h, 3);
    let mut depth_rows = tile_rows(out.depth, w, h, rects.len());
    let mut coverage_rows = tile_rows(out.coverage, w, h, rects.len());
    let isa = isa::Isa::detect(options.baseline_isa);
    let screen = options.interpolation == Interpolation::Screen;
    let fog = scene
        .fog()
        .map(|f| FogEffect::new(*f, camera.eye_distance(options.width, options.height)));
    // With the secondary stage the fog comes after the mix, in that stage.
    let (fog, secondary) = if secondary_wanted {
        let world = &prep.verts.world[..prep.verts.world.len().min(scene_vertices(scene))];
        (
            None,
            Some(SecondaryEffect::new(scene, camera, options, world, fog)),
        )
    } else {
        (fog, None)
    };
    let shade_ctx = ShadeContext {
        tris: &prep.tris,
        verts: &prep.verts,
        materials: &prep.materials,
        camera,
        eye: prep.eye,
        background: options.background,
        two_sided: scene.two_sided(),
        size: (options.width as f64, options.height as f64),
        fog,
        program: Program::for_scene(fog.is_some()),
        shadows,
        textured: (!prep.units.is_empty()).then(|| TexturedScene {
            units: &prep.units,
            objects: scene
                .objects()
                .iter()
                .map(|o| TexturedObject::new(o, scene.two_sided()))
                .collect(),
            perturb: options.shading == crate::options::ShadingMode::Phong
                && scene
                    .objects()
                    .iter()
                    .any(|o| o.maps().is_some_and(|m| m.perturbs())),
            lit: prep.units.iter().flatten().any(|u| !u.lights.is_empty()),
            vertex_terms: &prep.vertex_terms,
        }),
        secondary,
        isa,
        modes,
    };
    if options.edges != EdgeMode::None {
        // Lines: a tile closure of its own, chosen once per render, so a render without
        // them runs the closure below exactly as before.
        let lines = LinePass::new(scene, camera, options, &prep.tris, &prep.verts);
        let modes = (options.shading, screen, options.samples);
        rects
            .par_iter()
            .zip(color_rows.par_iter_mut())
            .zip(depth_rows.par_iter_mut())
            .zip(coverage_rows.par_iter_mut())
            .enumerate()
            .for_each_init(
                || (isa::Workspace::new(options.samples), LineScratch::new()),
                |(work, scratch), (i, (((rect, crows), drows), vrows))| {
                    let rows = TileRows {
                        color: crows,
                        depth: drows.as_deref_mut(),
                        coverage: vrows.as_deref_mut(),
                    };
                    lines.run_tile(isa, &shade_ctx, modes, work, scratch, i, *rect, rows);
                },
            );
        let mut stats = prep.stats;
        stats.timings.raster_shade = prep.t_start.elapsed();
        return Ok(stats);
    }
    rects
        .par_iter()
        .zip(color_rows.par_iter_mut())
        .zip(depth_rows.par_iter_mut())
        .zip(coverage_rows.par_iter_mut())
        .enumerate()
        .for_each_init(
            || isa::Workspace::new(options.samples),
            |work, (i, (((rect, crows), drows), vrows))| {
                let job = isa::TileJob {
                    index: i,
                    rect: *rect,
                    color: crows,
                    depth: drows.as_deref_mut(),
                };
                let (mode, samples) = (options.shading, options.samples);
                isa::run_tile(isa, &shade_ctx, mode, screen, samples, work, job);
                if let Some(rows) = vrows {
                    // After the tile's work, from its visibility (outside the tile bodies,
                    // so a render without this output runs them unchanged).
                    let empty = prep.tris.tile_is_empty(i);
                    work.write_coverage(*rect, empty, rows);
                }
            },
        );
    let mut stats = prep.stats;
    stats.timings.raster_shade = prep.t_start.elapsed();
    Ok(stats)
}

/// Every object's vertex count, summed (the vertex stage's positions before clip-made ones).
fn scene_vertices(scene: &Scene) -> usize {
    scene
        .objects()
        .iter()
        .map(|o| o.mesh().positions().len())
        .sum()
}

/// Combinations the secondary stage does not support yet, refused with the field to change.
fn check_secondary(scene: &Scene, options: &RenderOptions) -> Result<()> {
    if options.environment_background && scene.environment().is_none() {
        return Err(RasterError::invalid_field(
            "background",
            "background='environment' needs a scene environment (Scene(environment=...))",
        ));
    }
    if let Some(env) = scene.environment() {
        let m = env.max_value();
        if m > crate::pipeline::MAX_RADIANCE {
            return Err(RasterError::invalid_field(
                "intensity",
                format!(
                    "the environment reaches {m:.3e} (intensity x largest texel), beyond the \
                     {:e} that float32 colours can safely hold",
                    crate::pipeline::MAX_RADIANCE
                ),
            ));
        }
    }
    Ok(())
}

/// Depth-only pass: the visibility of every pixel, written as its window depth (reversed-Z:
/// 1 at the near plane, 0 at the far plane; −1, below every depth, where no triangle is),
/// row-major; or with `eye` as its eye depth ([`Camera::eye_depth_from_z`]; infinite where
/// no triangle is), converted as each tile's rows are written. Every pixel is written. No
/// material or light is read and nothing is shaded: this is the pass a shadow map renders
/// from a light.
pub(crate) fn depth_pass(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    depth: &mut [Out<f32>],
    eye: bool,
) -> Result<RenderStats> {
    let prep = prepare(scene, camera, options, Needs::Geometry, None)?;
    let (w, h) = (options.width as usize, options.height as usize);
    let rects = tiles::tile_rects(w, h);
    let mut rows = tiles::split_rows(depth, w, h, 1);
    let isa = isa::Isa::detect(options.baseline_isa);
    rects
        .par_iter()
        .zip(rows.par_iter_mut())
        .enumerate()
        // A tile of depths per worker: the depth pass reads no ids.
        .for_each_init(DepthTileBuf::default, |buf, (i, (rect, rows))| {
            let job = DepthTile {
                index: i,
                rect: *rect,
                camera: eye.then_some(camera),
            };
            #[cfg(target_arch = "x86_64")]
            if isa == isa::Isa::Avx2 {
                // SAFETY: `Isa::Avx2` is only made by `Isa::detect` after the CPU reported
                // AVX2 and FMA, the features this copy is compiled for.
                unsafe { depth_tile_avx2(&prep.tris, &job, buf, rows) };
                return;
            }
            depth_tile(&prep.tris, &job, buf, rows);
        });
    let mut stats = prep.stats;
    stats.timings.raster_shade = prep.t_start.elapsed();
    Ok(stats)
}

/// A tile's depths, reused from tile to tile by a worker of the depth pass.
struct DepthTileBuf(Box<[f32; tiles::TILE * tiles::TILE]>);

impl Default for DepthTileBuf {
    fn default() -> Self {
        DepthTileBuf(Box::new([raster::EMPTY_DEPTH; tiles::TILE * tiles::TILE]))
    }
}

/// One tile of the depth pass: its index and rectangle, and the camera whose eye depths are
/// written (`None`: window depths).
struct DepthTile<'a> {
    index: usize,
    rect: tiles::TileRect,
    camera: Option<&'a Camera>,
}

/// Rasterizes one tile of the depth pass and writes its rows.
#[inline(always)]
fn depth_tile(
    tris: &super::bin::Binned,
    job: &DepthTile<'_>,
    buf: &mut DepthTileBuf,
    rows: &mut [&mut [Out<f32>]],
) {
    raster::rasterize_depth_tile(tris, job.index, job.rect, &mut buf.0);
    for (j, row) in rows.iter_mut().enumerate() {
        let z = &buf.0[j * tiles::TILE..j * tiles::TILE + job.rect.w];
        match job.camera {
            Some(camera) => put_eye_depths(camera, row, z),
            None => put(row, z),
        }
    }
}

/// [`depth_tile`] compiled for AVX2 + FMA (the same operations: identical depths).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn depth_tile_avx2(
    tris: &super::bin::Binned,
    job: &DepthTile<'_>,
    buf: &mut DepthTileBuf,
    rows: &mut [&mut [Out<f32>]],
) {
    depth_tile(tris, job, buf, rows)
}

/// Writes the eye depths of the window depths `z` into `row` (as `eye_depth_from_z`, the
/// projection's case chosen once per row).
#[inline(always)]
fn put_eye_depths(camera: &Camera, row: &mut [Out<f32>], z: &[f32]) {
    let (n, f) = (camera.near(), camera.far());
    let perspective = !matches!(camera.projection(), Projection::Orthographic { .. });
    for (d, &z) in row.iter_mut().zip(z) {
        let v = if z < 0.0 {
            f32::INFINITY
        } else if perspective {
            (n * f / (z as f64 * (f - n) + n)) as f32
        } else {
            (f - z as f64 * (f - n)) as f32
        };
        debug_assert!(z < 0.0 || v == camera.eye_depth_from_z(z));
        d.write(v);
    }
}

/// Test hook: how many triangles cover each pixel centre (no depth test), row-major.
pub(crate) fn coverage_counts(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<Vec<u32>> {
    let prep = prepare(scene, camera, options, Needs::Geometry, None)?;
    let (w, h) = (options.width as usize, options.height as usize);
    struct Counter<'a> {
        counts: &'a mut [u32],
        rect: tiles::TileRect,
        width: usize,
    }
    impl raster::SpanSink for Counter<'_> {
        fn span(&mut self, s: raster::Span) {
            for slot in s.start..s.start + s.len {
                self.pixel(slot, 0.0, s.id);
            }
        }

        fn pixel(&mut self, slot: usize, _: f32, _: u32) {
            let x = self.rect.x0 + slot % tiles::TILE;
            let y = self.rect.y0 + slot / tiles::TILE;
            self.counts[y * self.width + x] += 1;
        }
    }
    let mut counts = vec![0u32; w * h];
    for (i, rect) in tiles::tile_rects(w, h).into_iter().enumerate() {
        let mut counter = Counter {
            counts: &mut counts,
            rect,
            width: w,
        };
        raster::for_each_span(prep.tris.tile(i), rect, &mut counter);
    }
    Ok(counts)
}
