//! The public entry points: options, output frames and `render`.

use std::time::Duration;

use glam::Vec3;

use crate::camera::Camera;
use crate::error::{RasterError, Result};
use crate::pipeline;
use crate::pipeline::shade::{Out, Pixel};
use crate::pool;
use crate::scene::Scene;
use crate::shading::{ShadingMode, SpecularModel};

/// Largest supported width or height in pixels. With the ±16384-pixel guard band, 16.8
/// fixed-point coordinates then stay below 2^23 and every edge function is exact in i64.
pub const MAX_IMAGE_SIZE: u32 = 16384;

/// How to render.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels, 1..=[`MAX_IMAGE_SIZE`].
    pub width: u32,
    /// Image height in pixels, 1..=[`MAX_IMAGE_SIZE`].
    pub height: u32,
    /// Where lighting is evaluated.
    pub shading: ShadingMode,
    /// Which specular lobe.
    pub specular: SpecularModel,
    /// Linear RGB of pixels no triangle covers.
    pub background: Vec3,
    /// Skip triangles that are clockwise on screen.
    pub cull_backfaces: bool,
    /// Worker threads; `None` uses every core. Results are identical for any count.
    pub threads: Option<usize>,
    /// Use only the target's baseline instructions (SSE2 on x86-64) even where the CPU has
    /// AVX2. The image is bit-identical either way; this exists to check that, and to
    /// measure what the wider instructions buy.
    pub baseline_isa: bool,
}

impl RenderOptions {
    /// Phong shading, Blinn-Phong specular, black background, no culling, all cores.
    pub fn new(width: u32, height: u32) -> Self {
        RenderOptions {
            width,
            height,
            shading: ShadingMode::Phong,
            specular: SpecularModel::BlinnPhong,
            background: Vec3::ZERO,
            cull_backfaces: false,
            threads: None,
            baseline_isa: false,
        }
    }

    /// Checks sizes, background and thread count.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || v > MAX_IMAGE_SIZE {
                return Err(RasterError::invalid(format!(
                    "{name} must be between 1 and {MAX_IMAGE_SIZE}, got {v}"
                )));
            }
        }
        if !self.background.is_finite() {
            return Err(RasterError::invalid(format!(
                "background must be finite, got {:?}",
                self.background.to_array()
            )));
        }
        pool::check_threads(self.threads)
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// Wall time per pipeline stage of one render.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    /// Vertex transform (and Gouraud lighting).
    pub vertex: Duration,
    /// Assembly, clipping, setup, binning (and flat lighting).
    pub setup: Duration,
    /// Rasterization and shading of all tiles.
    pub raster_shade: Duration,
}

/// Counters and timings of one render.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RenderStats {
    /// Triangles submitted.
    pub triangles_in: usize,
    /// Triangles (after clipping) handed to the rasterizer.
    pub triangles_setup: usize,
    /// Triangles that crossed a clip plane and were clipped.
    pub triangles_clipped: usize,
    /// Triangles removed by back-face culling.
    pub triangles_culled: usize,
    /// Triangles dropped because a transformed coordinate overflowed to a non-finite value.
    pub triangles_dropped: usize,
    /// Point sources lit per shaded point: one per directional, point or spot light, and
    /// [`AreaLight::n_points`](crate::AreaLight::n_points) per area light.
    pub light_sources: usize,
    /// Per-stage wall times.
    pub timings: StageTimings,
}

/// Colour samples of a frame.
#[derive(Debug, Clone, PartialEq)]
pub enum ColorBuffer {
    /// `round(clamp(c, 0, 1)·255)` per channel.
    U8(Vec<u8>),
    /// Linear, unclamped.
    F32(Vec<f32>),
}

/// Which colour buffer to produce.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorFormat {
    /// 8-bit, clamped and rounded.
    U8,
    /// 32-bit float, linear and unclamped.
    F32,
}

/// A rendered image: row-major `(height, width, 3)` colour, optional depth.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGB samples, row 0 at the top.
    pub color: ColorBuffer,
    /// Eye-space depth (distance along the view axis, world units); +inf where empty.
    pub depth: Option<Vec<f32>>,
    /// What happened.
    pub stats: RenderStats,
}

/// An empty vector with room for exactly `len` values, or [`RasterError::OutOfMemory`].
fn reserve<T>(len: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| RasterError::OutOfMemory {
            bytes: len.saturating_mul(std::mem::size_of::<T>()),
        })?;
    Ok(v)
}

/// Renders `scene` seen by `camera` into newly allocated buffers.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    format: ColorFormat,
    with_depth: bool,
) -> Result<Frame> {
    options.validate()?;
    let n = options.pixel_count();
    let mut depth = if with_depth {
        Some(reserve::<f32>(n)?)
    } else {
        None
    };
    // The buffers are not zeroed: the pipeline writes every sample (at 1080p on two cores
    // the time outside the pipeline's stages fell from 0.43 to about 0.2 ms per frame).
    fn fill<P: Pixel>(
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
        n: usize,
        depth: &mut Option<Vec<f32>>,
    ) -> Result<(Vec<P>, RenderStats)> {
        let mut c = reserve::<P>(n * 3)?;
        let d = depth.as_mut().map(|d| &mut d.spare_capacity_mut()[..n]);
        let stats = run_checked(
            scene,
            camera,
            options,
            &mut c.spare_capacity_mut()[..n * 3],
            d,
        )?;
        // SAFETY: the pipeline succeeded, so it wrote all `n·3` colour samples and, when
        // asked for, all `n` depths (`pipeline::run`'s contract); both have that capacity.
        unsafe {
            c.set_len(n * 3);
            if let Some(d) = depth {
                d.set_len(n);
            }
        }
        Ok((c, stats))
    }
    let (color, stats) = match format {
        ColorFormat::U8 => {
            let (c, s) = fill::<u8>(scene, camera, options, n, &mut depth)?;
            (ColorBuffer::U8(c), s)
        }
        ColorFormat::F32 => {
            let (c, s) = fill::<f32>(scene, camera, options, n, &mut depth)?;
            (ColorBuffer::F32(c), s)
        }
    };
    Ok(Frame {
        width: options.width,
        height: options.height,
        color,
        depth,
        stats,
    })
}

/// Renders into caller-provided row-major buffers: `color` holds `height·width·3` samples
/// (`u8` or `f32`), `depth` (optional) `height·width` eye-space depths.
pub fn render_into<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    color: &mut [P],
    depth: Option<&mut [f32]>,
) -> Result<RenderStats> {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and the pipeline only ever writes
    // initialised values through these views, so the caller's slices stay initialised.
    let color = unsafe { &mut *(color as *mut [P] as *mut [Out<P>]) };
    let depth = depth.map(|d| unsafe { &mut *(d as *mut [f32] as *mut [Out<f32>]) });
    run_checked(scene, camera, options, color, depth)
}

/// Checks the options and buffer sizes, then runs the pipeline on the thread pool.
fn run_checked<P: Pixel>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    color: &mut [Out<P>],
    depth: Option<&mut [Out<f32>]>,
) -> Result<RenderStats> {
    options.validate()?;
    let n = options.pixel_count();
    if color.len() != n * 3 {
        return Err(RasterError::invalid(format!(
            "colour buffer has {} samples, expected {}x{}x3 = {}",
            color.len(),
            options.height,
            options.width,
            n * 3
        )));
    }
    if let Some(d) = &depth {
        if d.len() != n {
            return Err(RasterError::invalid(format!(
                "depth buffer has {} samples, expected {}",
                d.len(),
                n
            )));
        }
    }
    pool::run(options.threads, || {
        pipeline::run(scene, camera, options, color, depth)
    })?
}

/// Test hook: per-pixel count of covering triangles (no depth test), row-major
/// `height·width`. Watertight meshes give exactly 1 inside and 0 outside.
#[doc(hidden)]
pub fn coverage_counts(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<Vec<u32>> {
    options.validate()?;
    pool::run(options.threads, || {
        pipeline::coverage_counts(scene, camera, options)
    })?
}
