//! The secondary stage (reflections, refractions, order-independent transparency, the
//! environment background) on the multi-sample target: `samples = N > 1` in a scene with
//! [`ShadeContext::secondary`].
//!
//! The rules of the multi-sample path hold (`samples.rs`): coverage and depth per sample,
//! shading (and here every secondary ray and environment lookup) once per pixel per visible
//! triangle at the pixel centre, a resolve weighted by coverage in linear colour. Per tile:
//!
//! 1. **Opaque visibility per sample**: every triangle except the
//!    [`Kind::Blended`] objects', at each sample position; the samples of each pixel are
//!    grouped by owner into layers.
//! 2. **Each layer's colour**: the mode's loops shade the layer (its local colour); then, per
//!    pixel the layer covers, the secondary stage's opaque colour (the environment where no
//!    triangle is, the mix at an optical surface, the fog), exactly as with one sample.
//! 3. **Transparent fragments per sample**: the blended triangles are rasterized at each
//!    sample position, and a fragment is kept at a sample when it is in front of that
//!    sample's opaque depth. The fragments of a pixel are sorted by (sample, depth at the
//!    sample nearest first, triangle id). Each distinct triangle's mix is computed once per
//!    pixel (at the centre, cached), and the front-to-back blend is done **per sample** over
//!    that sample's own opaque colour: the exact per-sample composite, so a transparent
//!    surface covering part of a pixel, or two crossing inside it, weigh each sample by what
//!    is really in front of it there.
//! 4. **Resolve**: without fragments, `Σ count·colour / N` over the layers; with them,
//!    `Σ composite / N` over the samples, equal composites summed as `count·value` so that a
//!    pixel whose samples all see the same surfaces keeps exactly its single-sample colour
//!    (N is a power of two). Stored once into the user's rows.

use glam::Vec3;

use super::raster;
use super::samples::{self, SampleTarget};
use super::shade::{self, Collect, Out, Pixel, ShadeContext};
use super::tiles::{TileRect, TILE};
use crate::options::ShadingMode;
use crate::reflect::Kind;

/// A transparent fragment at one sample, in front of that sample's opaque surface.
#[derive(Debug, Clone, Copy)]
struct SampleFragment {
    /// `slot · 16 + sample` (a tile has 4096 slots, a pixel at most 16 samples).
    key: u32,
    /// Window depth at the sample.
    z: f32,
    id: u32,
}

/// Bits of [`SampleFragment::key`] that hold the sample.
const SAMPLE_BITS: u32 = 4;

/// A worker's buffers for multi-sample secondary tiles (allocated on first use).
#[derive(Default)]
pub(crate) struct SecondarySamplesWork {
    /// One layer's local colours, as the shading loops write them (row-major RGB).
    local: Vec<Out<f32>>,
    /// Each used layer's opaque colour per pixel, layer-major.
    layer: Vec<Vec3>,
    frags: Vec<SampleFragment>,
    /// The current pixel's fragment mixes by triangle: (id, adds, lets through).
    mixes: Vec<(u32, Vec3, f32)>,
}

/// One tile of a scene with the secondary stage at `N = target.per_pixel() > 1` samples.
/// `AFFINE` as for [`shade::shade_tile`], `WIDE` as for [`shade::shade_textured_tile`]
/// (inlined into each instruction set's body, `isa.rs`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn shade_secondary_samples<P: Pixel, const AFFINE: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    mode: ShadingMode,
    index: usize,
    rect: TileRect,
    target: &mut SampleTarget,
    work: &mut SecondarySamplesWork,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    let sec = ctx
        .secondary
        .as_ref()
        .expect("a scene with the secondary stage");
    let blended = |id: u32| sec.kinds[ctx.tris.get(id).object as usize] == Kind::Blended;
    let n = target.per_pixel();
    // 1. Opaque visibility per sample, grouped into layers.
    if sec.any_blended {
        target.rasterize_where(ctx.tris, index, rect, |t| {
            sec.kinds[t.object as usize] != Kind::Blended
        });
    } else {
        target.rasterize_where(ctx.tris, index, rect, |_| true);
    }
    let used = target.layer(ctx, rect);
    // 2. Each layer's local colour, then its opaque colour where it covers samples.
    let SecondarySamplesWork {
        local,
        layer,
        frags,
        mixes,
    } = work;
    local.resize(TILE * TILE * 3, Out::new(0.0));
    if layer.len() < used * TILE * TILE {
        layer.resize(used * TILE * TILE, Vec3::ZERO);
    }
    let world = shade::secondary_world(ctx, mode);
    let mut cache = shade::PointCache::new();
    let mut depth = depth;
    for k in 0..used {
        let buf = target.layer_buffer(k);
        let mut rows: Vec<&mut [Out<f32>]> = local
            .chunks_mut(TILE * 3)
            .take(rect.h)
            .map(|r| &mut r[..rect.w * 3])
            .collect();
        // Layer 0 covers every pixel (a triangle or the background): it alone writes the
        // depth output, the opaque majority surface's, as without the secondary stage.
        let layer_depth = if k == 0 { depth.take() } else { None };
        if ctx.textured.is_some() {
            shade::shade_textured_tile::<f32, AFFINE, WIDE>(
                ctx,
                mode,
                rect,
                buf,
                &mut rows,
                layer_depth,
            );
        } else {
            shade::shade_tile::<f32, AFFINE>(ctx, mode, rect, buf, &mut rows, layer_depth);
        }
        let colors = &mut layer[k * TILE * TILE..(k + 1) * TILE * TILE];
        for (j, row) in rows.iter().enumerate() {
            for i in 0..rect.w {
                let slot = j * TILE + i;
                if target.layer_count(k, slot) == 0 {
                    continue;
                }
                // SAFETY: the shading loops wrote every sample of the rows they were given.
                let local = unsafe {
                    Vec3::new(
                        row[i * 3].assume_init(),
                        row[i * 3 + 1].assume_init(),
                        row[i * 3 + 2].assume_init(),
                    )
                };
                let (id, z) = (buf.id[slot], buf.depth[slot]);
                let (x, y) = (rect.x0 + i, rect.y0 + j);
                colors[slot] = shade::opaque_color::<AFFINE>(
                    ctx, sec, &world, mode, id, z, local, x, y, &mut cache,
                );
            }
        }
    }
    // 3. Transparent fragments per sample, sorted per pixel by sample, then depth.
    frags.clear();
    if sec.any_blended {
        for (s, offset) in samples::offsets(n).enumerate() {
            let tris = ctx.tris.tile(index).filter(|&(id, _)| blended(id));
            let sample = s as u32;
            let mut sink = Collect {
                opaque: &target.sample_buffer(s).depth[..],
                frags,
                make: |slot, z, id| SampleFragment {
                    key: ((slot as u32) << SAMPLE_BITS) | sample,
                    z,
                    id,
                },
            };
            raster::for_each_span_at(tris, rect, offset, &mut sink);
        }
        frags.sort_unstable_by(|a, b| {
            a.key
                .cmp(&b.key)
                .then(b.z.total_cmp(&a.z))
                .then(a.id.cmp(&b.id))
        });
    }
    // 4. The resolve.
    let inv_n = 1.0 / n as f32;
    let mut next = 0;
    for (j, out) in color.iter_mut().enumerate().take(rect.h) {
        for i in 0..rect.w {
            let slot = j * TILE + i;
            let (x, y) = (rect.x0 + i, rect.y0 + j);
            let first = next;
            while next < frags.len() && (frags[next].key >> SAMPLE_BITS) as usize == slot {
                next += 1;
            }
            let sum = if next == first {
                // Layers of a pixel are 0..m, each with its count.
                let mut acc = Vec3::ZERO;
                for k in 0..used {
                    let count = target.layer_count(k, slot);
                    if count == 0 {
                        break;
                    }
                    let v = count as f32 * layer[k * TILE * TILE + slot];
                    acc = if k == 0 { v } else { acc + v };
                }
                acc
            } else {
                mixes.clear();
                // Distinct per-sample composites and how many samples gave each.
                let mut values = [(Vec3::ZERO, 0u8); 16];
                let mut m = 0;
                let mut f = first;
                for s in 0..n {
                    let owner = target.sample_buffer(s).id[slot];
                    let k = (0..used)
                        .position(|k| {
                            target.layer_count(k, slot) > 0
                                && target.layer_buffer(k).id[slot] == owner
                        })
                        .expect("every sample's owner has a layer");
                    let opaque = layer[k * TILE * TILE + slot];
                    let start = f;
                    while f < next && (frags[f].key & ((1 << SAMPLE_BITS) - 1)) as usize == s {
                        f += 1;
                    }
                    let layers = frags[start..f].iter().map(|fr| {
                        if let Some(&(_, a, t)) = mixes.iter().find(|m| m.0 == fr.id) {
                            return (a, t);
                        }
                        // Once per pixel per triangle, at the centre (its depth there for
                        // the fog, as with one sample).
                        let tri = ctx.tris.get(fr.id);
                        let z = if sec.fog.is_some() {
                            samples::centre_depth(tri, x, y)
                        } else {
                            0.0
                        };
                        let (a, t) = shade::fragment_mix::<AFFINE>(
                            ctx, sec, &world, mode, fr.id, z, x, y, &mut cache,
                        );
                        mixes.push((fr.id, a, t));
                        (a, t)
                    });
                    let c = shade::composite(layers, opaque);
                    match values[..m].iter_mut().find(|v| v.0 == c) {
                        Some(v) => v.1 += 1,
                        None => {
                            values[m] = (c, 1);
                            m += 1;
                        }
                    }
                }
                let mut acc = values[0].1 as f32 * values[0].0;
                for &(c, count) in &values[1..m] {
                    acc += count as f32 * c;
                }
                acc
            };
            shade::store_out(&mut out[i * 3..i * 3 + 3], sum * inv_n);
        }
    }
}
