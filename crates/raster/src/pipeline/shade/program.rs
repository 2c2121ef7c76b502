//! The shade program: the per-pixel stages that run after lighting over a batch of
//! fragments, chosen once per render from what the scene uses. A stage is one variant of
//! [`Stage`] and one arm of [`Stage::run`]; the batch loop matches once per stage per batch
//! of [`LANES`](crate::lighting::LANES) pixels, so a scene pays for the stages it has and nothing for the others,
//! without a const-generic loop body per combination of effects.

use glam::Vec3;

use super::store::{Out, Pixel};
use super::ShadeContext;
use crate::effects::FogEffect;
use crate::lighting::Lanes;
use crate::pipeline::tiles::TileRect;

/// Lit fragments of one batch (at most [`LANES`](crate::lighting::LANES)), in flight through the program.
pub(crate) struct Fragments<'a> {
    /// Linear colour per lane, channel-major.
    pub color: [Lanes; 3],
    /// (row, column) in the tile of each live lane; its length is the batch's.
    pub at: &'a [(usize, usize)],
    /// Eye depth per lane (computed when a stage or the depth output needs it).
    pub depth: &'a Lanes,
    /// The tile's top-left pixel.
    pub origin: (usize, usize),
}

/// A per-pixel stage after lighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stage {
    /// Blend toward the fog colour with the distance from the eye (`crate::effects::fog`).
    Fog,
}

impl Stage {
    #[inline(always)]
    pub fn run(&self, ctx: &ShadeContext<'_>, f: &mut Fragments<'_>) {
        match self {
            Stage::Fog => {
                let Some(fog) = &ctx.fog else { return };
                if fog.centred() {
                    fog_lanes::<false>(fog, f);
                } else {
                    fog_lanes::<true>(fog, f);
                }
            }
        }
    }
}

/// Fog over the live lanes of a batch.
#[inline(always)]
fn fog_lanes<const OFF_CENTRE: bool>(fog: &FogEffect, f: &mut Fragments<'_>) {
    let (x0, y0) = f.origin;
    let [r, g, b] = &mut f.color;
    // Zipped with the live lanes, so no lane access needs a bounds check.
    let lanes = r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut());
    for (((r, g), b), (&(j, i), &d)) in lanes.zip(f.at.iter().zip(f.depth)) {
        let c = fog.apply_with::<OFF_CENTRE>(Vec3::new(*r, *g, *b), x0 + i, y0 + j, d);
        (*r, *g, *b) = (c.x, c.y, c.z);
    }
}

/// The stages a render runs, in order.
#[derive(Debug, Clone, Default)]
pub(crate) struct Program {
    stages: Vec<Stage>,
}

impl Program {
    /// The stages a scene needs: fog when it has fog.
    pub fn for_scene(fog: bool) -> Self {
        let mut stages = Vec::new();
        if fog {
            stages.push(Stage::Fog);
        }
        Program { stages }
    }
}

impl Program {
    /// Whether the program has no stage (what is lit is stored as it is).
    pub fn is_empty(&self) -> bool {
        self.stages.is_empty()
    }

    /// Whether a stage reads the fragments' eye depth.
    pub fn reads_depth(&self) -> bool {
        self.stages.iter().any(|s| match s {
            Stage::Fog => true,
        })
    }
}

/// The end of every batch path (Phong, textured): runs the render's program over a batch of
/// lit lanes (`lit`, the first `at.len()` live, at tile slots `at` with eye depths `depth`)
/// and stores each into the tile's output rows `color` (one branch per stage per batch).
#[inline(always)]
pub(super) fn finish_batch<P: Pixel>(
    ctx: &ShadeContext<'_>,
    lit: [Lanes; 3],
    at: &[(usize, usize)],
    depth: &Lanes,
    rect: TileRect,
    color: &mut [&mut [Out<P>]],
) {
    let mut frags = Fragments {
        color: lit,
        at,
        depth,
        origin: (rect.x0, rect.y0),
    };
    for stage in &ctx.program {
        stage.run(ctx, &mut frags);
    }
    P::store_lanes(color, at, &frags.color, ctx.wide());
}

impl<'a> IntoIterator for &'a Program {
    type Item = &'a Stage;
    type IntoIter = std::slice::Iter<'a, Stage>;
    fn into_iter(self) -> Self::IntoIter {
        self.stages.iter()
    }
}
