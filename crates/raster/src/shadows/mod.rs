//! The shadow room: for each shadow-casting light source of a render, how visible it is
//! from a batch of shaded points. Exact shadows cast a segment from each point to the light
//! through the rays room's BVH; shadow maps ([`map`]) compare depth rendered from the light.
//!
//! Shadow rays start at the shaded point moved off its surface along the triangle's
//! geometric normal (turned to the side of the shading normal) by [`ShadowEffect::offset`]:
//! `1e-4` of the scene's bounding-box diagonal (plus `1e-6` of the point's largest
//! coordinate), far above the float error of an interpolated position and far below any
//! feature a scene shows, so a surface never shadows itself by rounding and a contact
//! shadow starts at the contact.

mod exact;
mod fit;
#[cfg(test)]
mod lcg;
mod lookup;
mod map;

use glam::Vec3;

use crate::error::{RasterError, Result};
use crate::lighting::{Geometry, Lanes, LightSet, LANES};
use crate::lights::{Light, Shadows};
use crate::options::RenderOptions;
use crate::rays::Bvh;
use crate::scene::Scene;
use lookup::Points;
pub(crate) use map::DepthPass;
use map::ShadowMap;
pub(crate) use map::ViewFit;

/// Largest number of shadow-map texels a render may hold (2^28: 1 GiB of f32 depths).
pub const MAX_SHADOW_TEXELS: u64 = 1 << 28;

/// Where a source's light comes from.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Toward {
    /// A light at infinity: the unit direction toward it.
    Direction(Vec3),
    /// A light at a position.
    Position(Vec3),
}

impl Toward {
    fn of(g: &Geometry) -> Self {
        match *g {
            Geometry::Directional(d) => Toward::Direction(d),
            Geometry::Point(q) | Geometry::Spot { position: q, .. } => Toward::Position(q),
        }
    }
}

#[derive(Debug)]
enum Caster {
    Exact(Toward),
    Map(Box<ShadowMap>),
}

/// A render's shadows: one caster per shadow-casting source of its light set.
#[derive(Debug)]
pub(crate) struct ShadowEffect {
    /// Per source of the light set (same order as the surfaces' lights).
    casters: Vec<Option<Caster>>,
    bvh: Option<Bvh>,
    /// Scene-size part of the ray offset (see the module's doc).
    offset: f32,
    /// Whether the CPU has AVX2 and FMA and the render may use them: the map look-ups then
    /// run a copy compiled for them (8 lanes a vector instead of 4).
    wide: bool,
}

impl ShadowEffect {
    /// The shadows of `scene` under `set` (its prepared light set), or `None` when no light
    /// casts one. `world` holds every object's world-space vertices in scene order (the
    /// vertex stage's). The BVH is built only when a light asks for exact shadows; shadow
    /// maps are rendered here from each light, through `depth` (the pipeline's depth pass),
    /// directional ones fitted to what `view` sees (see [`ViewFit`]). `wide`: the render's
    /// instruction set is AVX2 + FMA (see [`ShadowEffect::visibility`]).
    pub fn new(
        scene: &Scene,
        set: &LightSet,
        world: &[Vec3],
        view: ViewFit<'_>,
        options: &RenderOptions,
        depth: DepthPass<'_>,
        wide: bool,
    ) -> Result<Option<Self>> {
        if !set.sources.iter().any(|s| s.shadows.on()) {
            return Ok(None);
        }
        let mut bounds = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in world.iter().filter(|p| p.is_finite()) {
            bounds = (bounds.0.min(*p), bounds.1.max(*p));
        }
        let diagonal = (bounds.1 - bounds.0).length();
        let offset = if diagonal.is_finite() {
            1e-4 * diagonal
        } else {
            0.0
        };
        let exact = set
            .sources
            .iter()
            .any(|s| matches!(s.shadows, Shadows::Exact));
        let bvh = exact.then(|| Bvh::new(world_triangles(scene, world)));
        // Each source's samples per side: an area light's points share its maps' budget.
        let sides: Vec<u32> = scene
            .lights()
            .iter()
            .flat_map(|l| match l {
                Light::Area(a) => vec![a.samples(); a.n_points()],
                _ => vec![1],
            })
            .collect();
        let mut texels = 0u64;
        let mut plans = Vec::with_capacity(set.sources.len());
        for (s, &side) in set.sources.iter().zip(&sides) {
            let plan = match s.shadows {
                Shadows::Map(settings) => {
                    let settings = map::per_point(settings, side);
                    texels += map::texels(s, &settings);
                    Some(settings)
                }
                _ => None,
            };
            plans.push(plan);
        }
        if texels > MAX_SHADOW_TEXELS {
            return Err(RasterError::invalid_field(
                "shadows",
                format!(
                    "the scene's shadow maps would need {texels} texels, more than the limit \
                     of {MAX_SHADOW_TEXELS} (1 GiB): lower their resolution or an area \
                     light's samples, or use shadows='exact'"
                ),
            ));
        }
        let mut casters = Vec::with_capacity(set.sources.len());
        for (s, plan) in set.sources.iter().zip(plans) {
            casters.push(match (s.shadows, plan) {
                (Shadows::Exact, _) => Some(Caster::Exact(Toward::of(&s.geometry))),
                (Shadows::Map(_), Some(settings)) => Some(Caster::Map(Box::new(ShadowMap::new(
                    s, settings, bounds, view, options, depth,
                )?))),
                _ => None,
            });
        }
        Ok(Some(ShadowEffect {
            casters,
            bvh,
            offset,
            wide,
        }))
    }

    /// Number of sources (the length [`ShadowEffect::visibility`] fills).
    pub fn sources(&self) -> usize {
        self.casters.len()
    }

    /// The visibility of each source from the first `live` lanes of points `p` with unit
    /// shading normals `n` and geometric normals `g` (any length, any side): `None` for a
    /// source that casts no shadow, else 0 (hidden) to 1 (lit) per lane. Map look-ups run
    /// over whole lanes ([`lookup`]), in the AVX2 copy when the render is `wide`; both
    /// copies do the same IEEE operations, so they give identical results.
    pub fn visibility(
        &self,
        n: &[Lanes; 3],
        p: &[Lanes; 3],
        g: &[Lanes; 3],
        live: usize,
        out: &mut [Option<Lanes>],
    ) {
        let pts = Points { n, p, g };
        for (caster, o) in self.casters.iter().zip(out.iter_mut()) {
            match caster {
                None => *o = None,
                // Written in place: a copy of the lanes through the stack cost 4 % of a
                // shadowed Phong frame in perf.
                Some(Caster::Map(m)) => map_lanes(m, &pts, live, o.insert([1.0; LANES]), self.wide),
                Some(Caster::Exact(toward)) => *o = Some(self.exact_lanes(*toward, &pts, live)),
            }
        }
    }

    /// Exact visibility of the first `live` lanes (1 beyond), a shadow ray each; out of
    /// line, so the map path above stays a small function.
    #[inline(never)]
    fn exact_lanes(&self, toward: Toward, pts: &Points<'_>, live: usize) -> Lanes {
        let bvh = self.bvh.as_ref().expect("built for exact shadows");
        let mut vis = [1.0; LANES];
        let at = |a: &[Lanes; 3], k: usize| Vec3::new(a[0][k], a[1][k], a[2][k]);
        for (k, v) in vis.iter_mut().enumerate().take(live) {
            let (n, p, g) = (at(pts.n, k), at(pts.p, k), at(pts.g, k));
            *v = exact::visibility(bvh, toward, n, p, g, self.offset);
        }
        vis
    }
}

/// A map's look-up of a batch, in the copy for the render's instruction set.
fn map_lanes(m: &ShadowMap, pts: &Points<'_>, live: usize, vis: &mut Lanes, wide: bool) {
    #[cfg(target_arch = "x86_64")]
    if wide {
        // SAFETY: `wide` is set only when the render's instruction set was detected as
        // AVX2 + FMA (`Isa::detect`), the features this copy is compiled for.
        unsafe { map_lanes_avx2(m, pts, live, vis) };
        return;
    }
    let _ = wide;
    m.visibility_lanes::<false>(pts, live, vis)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn map_lanes_avx2(m: &ShadowMap, pts: &Points<'_>, live: usize, vis: &mut Lanes) {
    m.visibility_lanes::<true>(pts, live, vis)
}

/// Every object's triangles in world space (the vertex stage's positions).
fn world_triangles(scene: &Scene, world: &[Vec3]) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::with_capacity(scene.triangle_count());
    let mut first = 0usize;
    for o in scene.objects() {
        let mesh = o.mesh();
        tris.extend(
            mesh.indices()
                .iter()
                .map(|t| t.map(|i| world[first + i as usize])),
        );
        first += mesh.positions().len();
    }
    tris
}
