//! What a render returns: colour and depth buffers, counters and stage timings.

use std::time::Duration;

use crate::auto_shading::ShadingEstimate;

/// Wall time per pipeline stage of one render.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    /// Vertex transform.
    pub vertex: Duration,
    /// Assembly, clipping, setup, binning, and the lighting flat and Gouraud do before the
    /// tile stage (per face, per vertex).
    pub setup: Duration,
    /// Rasterization and shading of all tiles.
    pub raster_shade: Duration,
}

/// Counters and timings of one render.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderStats {
    /// Triangles submitted.
    pub triangles_in: usize,
    /// Triangles (after clipping) handed to the rasterizer: not those of zero area, off
    /// screen, or (one sample per pixel) covering no pixel centre.
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
    /// `shading="auto"` ([`crate::RenderOptions::tolerance`]): per object in scene order,
    /// the mode used and the estimated errors; empty otherwise.
    pub shading: Vec<ShadingEstimate>,
}

/// Colour samples of a frame.
#[derive(Debug, Clone, PartialEq)]
pub enum ColorBuffer {
    /// `round(clamp(c, 0, 1)·255)` per channel.
    U8(Vec<u8>),
    /// Linear, unclamped.
    F32(Vec<f32>),
}

/// Which buffers a render produces besides the colour.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outputs {
    /// The eye-space depth ([`Frame::depth`]).
    pub depth: bool,
    /// The coverage ([`Frame::coverage`]): with the colour of a render over a black
    /// background it makes a premultiplied RGBA image.
    pub coverage: bool,
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
    /// Share of each pixel's samples that a triangle covers, in [0, 1] (0 or 1 with one
    /// sample), when asked for ([`Outputs::coverage`]).
    pub coverage: Option<Vec<f32>>,
    /// What happened.
    pub stats: RenderStats,
}
