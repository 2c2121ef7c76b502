//! Shade pass: every visible pixel of a tile is shaded exactly once, from its triangle's
//! setup data, and written straight into the output rows.
//!
//! Rooms: [`store`] (output samples), [`planes`] (interpolation planes), [`runs`] (flat and
//! Gouraud), [`phong`], [`prelight`] (the lighting that flat and Gouraud do before the tile
//! stage: per face and per vertex). The shading mode and the per-pixel effects present
//! ([`crate::effects`]) are chosen once per render, so each loop carries only its own work.

mod phong;
mod planes;
mod program;

mod id_runs;
mod mixed;
pub(crate) mod prelight;
mod runs;
mod secondary;
mod store;
mod textured;

pub(crate) use mixed::{shade_mixed_tile, MixedWork};
pub(crate) use program::Program;
pub(crate) use secondary::{
    composite, fragment_mix, opaque_color, shade_secondary_tile, world as secondary_world, Collect,
    PointCache, SecondaryWork,
};
pub use store::Pixel;
pub(crate) use store::{fill_out, put, store_out, Out, RowColors, ROW_LANES};
pub(crate) use textured::{TexturedObject, TexturedScene};

use glam::Vec3;

use super::bin::Binned;
use super::isa::Isa;
use super::raster::TileBuffers;
use super::tiles::{TileRect, TILE};
use super::vertex::Vertices;
use super::Sides;
use crate::camera::Camera;
use crate::effects::FogEffect;
use crate::options::ShadingMode;
use crate::reflect::SecondaryEffect;
use crate::shadows::ShadowEffect;

/// Everything the shade pass reads, shared by all tiles.
pub(crate) struct ShadeContext<'a> {
    pub tris: &'a Binned,
    pub verts: &'a Vertices,
    pub materials: &'a [Sides],
    pub camera: &'a Camera,
    pub eye: Vec3,
    pub background: Vec3,
    /// Back faces (clockwise on screen) are lit with the flipped normal.
    pub two_sided: bool,
    /// Image width and height in pixels (the viewport of the clip coordinates).
    pub size: (f64, f64),
    /// The scene's fog, as applied per pixel.
    pub fog: Option<FogEffect>,
    /// The per-pixel stages after lighting, chosen once per render ([`Program::for_scene`]).
    pub program: Program,
    /// The scene's shadows (`None`: no light casts one, and no loop reads this).
    pub shadows: Option<ShadowEffect>,
    /// Scenes with texture maps or vertex colours: the texture stage's inputs (every mode
    /// then shades through [`shade_textured_tile`], reached from `isa::run_tile` outside the
    /// untextured tile bodies); `None` runs the untextured loops unchanged.
    pub textured: Option<TexturedScene<'a>>,
    /// The instruction set the render's tiles run on (out-of-line loops pick their copy).
    pub isa: Isa,
    /// Scenes with reflective or transparent materials or an environment background: the
    /// secondary stage's constants (every tile then runs `isa::tile_secondary`, outside
    /// the other tile bodies; the fog moves into it); `None` runs the loops unchanged.
    pub secondary: Option<SecondaryEffect>,
    /// Each object's own shading mode when a render mixes them (`shading="auto"`): every
    /// tile then runs `isa::tile_mixed`, outside the other tile bodies; `None` shades every
    /// object with the render's mode.
    pub modes: Option<&'a [ShadingMode]>,
}

impl ShadeContext<'_> {
    /// Whether the render runs on AVX2 + FMA ([`Isa::Avx2`], detected on this CPU and not
    /// turned off by `baseline_isa`): the kernels written in intrinsics (normalisation,
    /// quantisation, Phong's interpolation) then take their AVX forms, inlined into the
    /// AVX2 tile bodies.
    #[inline(always)]
    pub(crate) fn wide(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        return self.isa == Isa::Avx2;
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// Eye depth of a pixel from its stored z and interpolated 1/w, when `wanted` (depth
    /// output or fog); 0 otherwise, saving a division per pixel. `AFFINE` (screen-space
    /// weights, which sum to 1, not to 1/w): from the stored z alone.
    #[inline(always)]
    pub(super) fn eye_depth<const AFFINE: bool>(&self, wanted: bool, z: f32, inv_w: f32) -> f32 {
        if wanted {
            if AFFINE {
                self.camera.eye_depth_from_z(z)
            } else {
                self.camera.eye_depth(z, inv_w)
            }
        } else {
            0.0
        }
    }

    /// `c` seen through the fog at pixel (x, y) with eye depth `depth`. `FOG` is whether the
    /// scene has fog, fixed per render so the foggless loops carry no fog code at all.
    #[inline(always)]
    pub(super) fn fogged<const FOG: bool>(&self, c: Vec3, x: usize, y: usize, depth: f32) -> Vec3 {
        match &self.fog {
            Some(fog) if FOG => fog.apply(c, x, y, depth),
            _ => c,
        }
    }
}

/// The background colour stored once for a whole tile row.
pub(super) fn background_row<P: Pixel>(ctx: &ShadeContext<'_>) -> [P; TILE * 3] {
    let mut px = [P::default(); 3];
    P::store(&mut px, ctx.background);
    let mut row = [P::default(); TILE * 3];
    for dst in row.chunks_exact_mut(3) {
        dst.copy_from_slice(&px);
    }
    row
}

/// Fills a tile that no triangle touches with the background (and infinite depth).
#[inline(always)]
pub(crate) fn fill_background<P: Pixel>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let bg = background_row::<P>(ctx);
    for row in color.iter_mut() {
        put(row, &bg[..rect.w * 3]);
    }
    for row in depth.into_iter().flatten() {
        fill_out(row, f32::INFINITY);
    }
}

const FLAT: u8 = 0;

const GOURAUD: u8 = 1;

/// Shades one tile into its output rows (and depth rows when requested). `AFFINE`: the
/// lectures' screen-space weights ([`crate::Interpolation::Screen`]: the weight planes drop
/// the 1/w and the eye depth comes from the stored z) for Gouraud and Phong; flat
/// interpolates nothing and ignores it. The perspective loops (`AFFINE` false) are the
/// defaults' and are inlined into each instruction set's tile body (`isa.rs`).
#[inline(always)]
pub(crate) fn shade_tile<P: Pixel, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    // Flat and Gouraud: one monomorphised run loop per fog on/off (their run fast paths are
    // specialised); Phong: its effects are a per-render program, and its loop is specialised
    // only on whether that program reads the eye depth. A scene without fog pays nothing for
    // it either way.
    match (mode, ctx.fog.is_some()) {
        (ShadingMode::Flat, false) => {
            runs::shade_runs::<P, FLAT, false, false>(ctx, rect, buf, color, depth)
        }
        (ShadingMode::Flat, true) => {
            runs::shade_runs::<P, FLAT, true, false>(ctx, rect, buf, color, depth)
        }
        (ShadingMode::Gouraud, false) => {
            runs::shade_runs::<P, GOURAUD, false, AFFINE>(ctx, rect, buf, color, depth)
        }
        (ShadingMode::Gouraud, true) => {
            runs::shade_runs::<P, GOURAUD, true, AFFINE>(ctx, rect, buf, color, depth)
        }
        // Phong's per-pixel effects run as the render's program over each batch.
        // Shadows are a loop of their own (the geometric normal carried per lane), out of
        // line, so the tile bodies of scenes without them are the code they were.
        (ShadingMode::Phong, read_depth) => {
            match (
                read_depth || ctx.program.reads_depth(),
                ctx.shadows.is_some(),
            ) {
                (false, false) => {
                    phong::shade_phong::<P, false, AFFINE, false>(ctx, rect, buf, color, depth)
                }
                (true, false) => {
                    phong::shade_phong::<P, true, AFFINE, false>(ctx, rect, buf, color, depth)
                }
                (false, true) => phong_shadowed::<P, false, AFFINE>(ctx, rect, buf, color, depth),
                (true, true) => phong_shadowed::<P, true, AFFINE>(ctx, rect, buf, color, depth),
            }
        }
    }
}

/// Phong with shadows, kept out of the tile bodies (`isa.rs` inlines the rest): its cost
/// is the shadow rays and map look-ups, and the shadowless bodies keep their code and
/// inlining. Compiled for the baseline instruction set.
/// On a CPU with AVX2 and FMA (the render's [`Isa`]) it runs a copy compiled for them, as
/// do the map look-ups of `ShadowEffect::visibility` (picked by the shadow room itself).
#[inline(never)]
fn phong_shadowed<P: Pixel, const STAGES_READ_DEPTH: bool, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    #[cfg(target_arch = "x86_64")]
    if ctx.isa == Isa::Avx2 {
        // SAFETY: `Isa::Avx2` is only made by `Isa::detect` after the CPU reported AVX2 and
        // FMA, the features this copy is compiled for.
        unsafe {
            phong_shadowed_avx2::<P, STAGES_READ_DEPTH, AFFINE>(ctx, rect, buf, color, depth)
        };
        return;
    }
    phong::shade_phong::<P, STAGES_READ_DEPTH, AFFINE, true>(ctx, rect, buf, color, depth)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn phong_shadowed_avx2<P: Pixel, const STAGES_READ_DEPTH: bool, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    phong::shade_phong::<P, STAGES_READ_DEPTH, AFFINE, true>(ctx, rect, buf, color, depth)
}

/// Shades one tile of a textured scene (maps or vertex colours: [`ShadeContext::textured`]),
/// any mode. `AFFINE` as for [`shade_tile`]; `WIDE`: lit with AVX2 + FMA, which the caller
/// must have checked the CPU has.
pub(crate) fn shade_textured_tile<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let tex = ctx.textured.as_ref().expect("a textured scene");
    // Normal and bump maps: a body of its own (chosen per render), so the others keep theirs.
    if tex.perturb {
        textured::shade_textured::<P, AFFINE, true, WIDE>(ctx, tex, mode, rect, buf, color, depth);
    } else {
        textured::shade_textured::<P, AFFINE, false, WIDE>(ctx, tex, mode, rect, buf, color, depth);
    }
}
