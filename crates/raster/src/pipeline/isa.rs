//! Instruction-set dispatch for the per-tile work (visibility, then shading).
//!
//! The tile body is compiled twice: for the target's baseline (SSE2 on x86-64) and, on
//! x86-64, for AVX2 + FMA, picked once per render from the CPU it runs on. Most hot loops
//! are written as plain lane loops that the compiler vectorises, so AVX2 doubles their width
//! with no code of its own; the few it did not keep whole (the depth window, normalisation,
//! u8 quantisation, Phong's interpolation) are written in intrinsics, with an AVX form the
//! AVX2 bodies inline when the render's ISA is AVX2 (`ShadeContext::wide`). Rust never contracts `a·b + c` into a fused multiply-add and
//! every lane operation is IEEE-exact, so both variants give bit-identical images (tested).

use super::raster::{self, TileBuffers, NO_TRIANGLE};
use super::samples::{self, SampleTarget};
use super::secondary_samples::{shade_secondary_samples, SecondarySamplesWork};
use super::shade::{self, Out, Pixel, ShadeContext};
use super::tiles::{TileRect, TILE};
use crate::options::ShadingMode;

/// The instruction set a render's tiles run on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Isa {
    /// What every CPU of the target has.
    Baseline,
    /// x86-64 with AVX2 and FMA (detected at run time).
    #[cfg(target_arch = "x86_64")]
    Avx2,
}

impl Isa {
    /// The best instruction set this CPU supports, or the baseline when `baseline_only`.
    pub fn detect(baseline_only: bool) -> Isa {
        #[cfg(target_arch = "x86_64")]
        if !baseline_only
            && std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
        {
            return Isa::Avx2;
        }
        let _ = baseline_only;
        Isa::Baseline
    }
}

/// One tile's inputs and outputs.
pub(crate) struct TileJob<'a, 'b, P> {
    pub index: usize,
    pub rect: TileRect,
    pub color: &'a mut [&'b mut [Out<P>]],
    pub depth: Option<&'a mut [&'b mut [Out<f32>]]>,
}

/// A worker's per-tile buffers: the single-sample visibility buffer and the multi-sample
/// target (empty with one sample).
pub(crate) struct Workspace {
    pub buf: TileBuffers,
    pub target: SampleTarget,
    /// The secondary stage's buffers (empty until a secondary tile needs them).
    pub secondary: shade::SecondaryWork,
    /// The same with several samples per pixel (empty until such a tile needs them).
    pub secondary_samples: SecondarySamplesWork,
    /// The mixed-mode buffers (empty until a tile mixes modes).
    pub mixed: shade::MixedWork,
}

impl Workspace {
    /// Buffers for `samples` per pixel.
    pub fn new(samples: u32) -> Self {
        Workspace {
            buf: TileBuffers::new(),
            target: SampleTarget::new(samples),
            secondary: shade::SecondaryWork::default(),
            secondary_samples: SecondarySamplesWork::default(),
            mixed: shade::MixedWork::default(),
        }
    }

    /// Writes the coverage of the tile just rendered (`empty`: no triangle touched it, so
    /// the buffers hold another tile's visibility) into its rows: the share of each pixel's
    /// samples that a triangle owns.
    pub fn write_coverage(&self, rect: TileRect, empty: bool, rows: &mut [&mut [Out<f32>]]) {
        if empty {
            for row in rows.iter_mut() {
                shade::fill_out(&mut row[..rect.w], 0.0);
            }
        } else if self.target.is_multi() {
            self.target.write_coverage(rect, rows);
        } else {
            for (j, row) in rows.iter_mut().enumerate() {
                let ids = &self.buf.id[j * TILE..j * TILE + rect.w];
                for (o, &id) in row.iter_mut().zip(ids) {
                    o.write(if id == NO_TRIANGLE { 0.0 } else { 1.0 });
                }
            }
        }
    }
}

/// Rasterizes and shades one tile with the instruction set `isa`, or with `screen`
/// (screen-space interpolation) on the baseline; with `samples > 1` through the multi-sample
/// target (`samples.rs`), in bodies of their own.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_tile<P: Pixel>(
    isa: Isa,
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    samples: u32,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    if samples > 1 {
        if ctx.secondary.is_some() {
            // The secondary stage on the multi-sample target: a body of its own, so the
            // multi-sample bodies below compile as without it.
            // Screen-space weights stay on the baseline instructions, as `tile_screen`.
            match isa {
                _ if screen && mode != ShadingMode::Flat => {
                    tile_secondary_samples(ctx, mode, screen, work, job)
                }
                Isa::Baseline => tile_secondary_samples(ctx, mode, screen, work, job),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: as for `tile_avx2` below.
                Isa::Avx2 => unsafe { tile_secondary_samples_avx2(ctx, mode, screen, work, job) },
            }
            return;
        }
        multi_sample_tile(isa, ctx, mode, screen, &mut work.target, job);
        return;
    }
    if ctx.secondary.is_some() {
        // Reflections, refraction, transparency, environment background: a tile body of
        // its own, so the bodies below compile as without them.
        match isa {
            _ if screen && mode != ShadingMode::Flat => {
                tile_secondary(ctx, mode, screen, work, job)
            }
            Isa::Baseline => tile_secondary(ctx, mode, screen, work, job),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as for `tile_avx2` below.
            Isa::Avx2 => unsafe { tile_secondary_avx2(ctx, mode, screen, work, job) },
        }
        return;
    }
    let buf = &mut work.buf;
    if ctx.textured.is_some() {
        // Maps or vertex colours: a tile body of its own, so the untextured ones below stay
        // as they were (their code, and their instruction counts, unchanged).
        match isa {
            Isa::Baseline => tile_textured(ctx, mode, screen, buf, job),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as for `tile_avx2` below.
            Isa::Avx2 => unsafe { tile_textured_avx2(ctx, mode, screen, buf, job) },
        }
        return;
    }
    if let Some(modes) = ctx.modes {
        // Objects with their own modes (`shading="auto"`): a body of its own, so the
        // bodies below compile as without it.
        tile_mixed(isa, ctx, modes, screen, work, job);
        return;
    }
    if screen && mode != ShadingMode::Flat {
        // Screen-space interpolation (the lectures' variant): a body of its own, so the
        // default bodies below compile exactly as without it.
        tile_screen(ctx, mode, buf, job);
        return;
    }
    match isa {
        Isa::Baseline => tile_baseline(ctx, mode, buf, job),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Isa::Avx2` is only ever made by `detect` after the CPU reported AVX2 and
        // FMA, the features `tile_avx2` is compiled for.
        Isa::Avx2 => unsafe { tile_avx2(ctx, mode, buf, job) },
    }
}

fn tile_baseline<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    tile::<P, false, false>(ctx, mode, buf, job);
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn tile_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    tile::<P, false, true>(ctx, mode, buf, job);
}

/// The tile body of Gouraud and Phong with screen-space weights, for the baseline
/// instruction set only (so both instruction sets give the same bits trivially), kept out of
/// line so the default bodies compile as without it.
#[inline(never)]
fn tile_screen<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    tile::<P, true, false>(ctx, mode, buf, job);
}

/// Multi-sample tiles (`samples.rs`), dispatched like the single-sample ones; kept out of
/// line so the default bodies compile as without them.
#[inline(never)]
fn multi_sample_tile<P: Pixel>(
    isa: Isa,
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    target: &mut SampleTarget,
    job: TileJob<'_, '_, P>,
) {
    if ctx.tris.tile_is_empty(job.index) {
        shade::fill_background(ctx, job.rect, job.color, job.depth);
        return;
    }
    if screen && mode != ShadingMode::Flat {
        samples_body::<P, true, false>(ctx, mode, target, job);
        return;
    }
    match isa {
        Isa::Baseline => samples_body::<P, false, false>(ctx, mode, target, job),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `run_tile`: `Isa::Avx2` exists only on CPUs with AVX2 and FMA.
        Isa::Avx2 => unsafe { samples_avx2(ctx, mode, target, job) },
    }
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn samples_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    target: &mut SampleTarget,
    job: TileJob<'_, '_, P>,
) {
    samples_body::<P, false, true>(ctx, mode, target, job);
}

/// `WIDE`: on AVX2 + FMA (the caller checked), which textured layers are then shaded with.
#[inline(always)]
fn samples_body<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    target: &mut SampleTarget,
    job: TileJob<'_, '_, P>,
) {
    let (index, rect) = (job.index, job.rect);
    samples::sample_tile::<P, AFFINE, WIDE>(ctx, mode, index, rect, target, job.color, job.depth);
}

/// The tile body of scenes with the secondary stage, for the baseline instruction set.
#[inline(never)]
fn tile_secondary<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    secondary_body::<P, false>(ctx, mode, screen, work, job);
}

/// The same on AVX2 + FMA: its rays and look-ups are scalar, but the opaque layer's local
/// colour is shaded by the lane loops (and `floor` and the like are single instructions,
/// not calls); Rust fuses no multiply-add unasked, so the bits are the baseline's.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn tile_secondary_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    secondary_body::<P, true>(ctx, mode, screen, work, job);
}

#[inline(always)]
fn secondary_body<P: Pixel, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    let (buf, sec) = (&mut work.buf, &mut work.secondary);
    let (i, rect) = (job.index, job.rect);
    if screen && mode != ShadingMode::Flat {
        shade::shade_secondary_tile::<P, true, WIDE>(
            ctx, mode, i, rect, buf, sec, job.color, job.depth,
        );
    } else {
        shade::shade_secondary_tile::<P, false, WIDE>(
            ctx, mode, i, rect, buf, sec, job.color, job.depth,
        );
    }
}

/// The tile body of scenes with the secondary stage and several samples per pixel
/// (`secondary_samples.rs`), for the baseline instruction set.
#[inline(never)]
fn tile_secondary_samples<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    secondary_samples_body::<P, false>(ctx, mode, screen, work, job);
}

/// The same on AVX2 + FMA (as [`tile_secondary_avx2`]).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn tile_secondary_samples_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    secondary_samples_body::<P, true>(ctx, mode, screen, work, job);
}

#[inline(always)]
fn secondary_samples_body<P: Pixel, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    let (target, sec) = (&mut work.target, &mut work.secondary_samples);
    let (i, rect) = (job.index, job.rect);
    if screen && mode != ShadingMode::Flat {
        shade_secondary_samples::<P, true, WIDE>(
            ctx, mode, i, rect, target, sec, job.color, job.depth,
        );
    } else {
        shade_secondary_samples::<P, false, WIDE>(
            ctx, mode, i, rect, target, sec, job.color, job.depth,
        );
    }
}

/// The tile body of textured scenes for the baseline instruction set, kept out of line so
/// the default bodies compile as without it.
#[inline(never)]
fn tile_textured<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    textured_body::<P, false>(ctx, mode, screen, buf, job);
}

/// The same for AVX2 + FMA: the rasteriser and the lane loops of the lighting widen (the
/// sampling stays scalar).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn tile_textured_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    textured_body::<P, true>(ctx, mode, screen, buf, job);
}

/// `WIDE`: on AVX2 + FMA (the caller checked).
#[inline(always)]
fn textured_body<P: Pixel, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    screen: bool,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    if ctx.tris.tile_is_empty(job.index) {
        shade::fill_background(ctx, job.rect, job.color, job.depth);
        return;
    }
    raster::rasterize_tile_on::<WIDE>(ctx.tris, job.index, job.rect, buf);
    // Flat interpolates nothing, so screen-space weights matter only for the others.
    if screen && mode != ShadingMode::Flat {
        shade::shade_textured_tile::<P, true, WIDE>(ctx, mode, job.rect, buf, job.color, job.depth);
    } else {
        shade::shade_textured_tile::<P, false, WIDE>(
            ctx, mode, job.rect, buf, job.color, job.depth,
        );
    }
}

/// Tiles of a render whose objects have their own modes (`shade/mixed.rs`), dispatched per
/// instruction set like the default bodies; out of line so those compile as without it.
#[inline(never)]
fn tile_mixed<P: Pixel>(
    isa: Isa,
    ctx: &ShadeContext<'_>,
    modes: &[ShadingMode],
    screen: bool,
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    if ctx.tris.tile_is_empty(job.index) {
        shade::fill_background(ctx, job.rect, job.color, job.depth);
        return;
    }
    if screen {
        mixed_body::<P, true>(ctx, modes, work, job);
        return;
    }
    match isa {
        Isa::Baseline => mixed_body::<P, false>(ctx, modes, work, job),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `run_tile`: `Isa::Avx2` exists only on CPUs with AVX2 and FMA.
        Isa::Avx2 => unsafe { mixed_avx2(ctx, modes, work, job) },
    }
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn mixed_avx2<P: Pixel>(
    ctx: &ShadeContext<'_>,
    modes: &[ShadingMode],
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    mixed_body::<P, false>(ctx, modes, work, job);
}

#[inline(always)]
fn mixed_body<P: Pixel, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    modes: &[ShadingMode],
    work: &mut Workspace,
    job: TileJob<'_, '_, P>,
) {
    let (buf, mixed) = (&mut work.buf, &mut work.mixed);
    raster::rasterize_tile(ctx.tris, job.index, job.rect, buf);
    shade::shade_mixed_tile::<P, AFFINE>(ctx, modes, job.rect, buf, mixed, job.color, job.depth);
}

/// The tile body; always inlined, so each variant above compiles all of it for its own
/// instruction set (the passes it calls are `#[inline(always)]` down to the lane loops).
#[inline(always)]
fn tile<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    buf: &mut TileBuffers,
    job: TileJob<'_, '_, P>,
) {
    if ctx.tris.tile_is_empty(job.index) {
        // Nothing to clear, rasterize or look up: common around a centred model.
        shade::fill_background(ctx, job.rect, job.color, job.depth);
        return;
    }
    raster::rasterize_tile_on::<WIDE>(ctx.tris, job.index, job.rect, buf);
    shade::shade_tile::<P, AFFINE>(ctx, mode, job.rect, buf, job.color, job.depth);
}
