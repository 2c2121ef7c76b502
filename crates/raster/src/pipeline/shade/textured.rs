//! The texture stage: shading of scenes with texture maps or vertex colours, in every mode.
//!
//! Each pixel's perspective-correct (u, v) and their exact screen-space derivatives come
//! from the triangle's weight planes: with q_k = λ_k/w_k (planes over pixel coordinates) and
//! W = Σ q_k, u = Σ q_k·u_k / W, so ∂u/∂x = (Σ ∂q_k/∂x·u_k − u·∂W/∂x) / W (likewise v and
//! y). The sampler (`crate::texture`) turns them into a colour; lighting is the unit surface's
//! split terms (`Surface::unit` + `Split`): ambient A, diffuse D and specular S, per face
//! (flat, at the centroid), per vertex (Gouraud, interpolated perspective-correctly) or per
//! pixel (Phong). Each pixel is
//!
//! ```text
//! c = ke·E + ka·T_a ⊙ A + kd·T_d ⊙ D + ks·T_s ⊙ S
//! ```
//!
//! with T the maps' colours (1 without a map; `T_a` is the diffuse map unless an ambient map
//! is set), so the specular highlight is added after the texture (OpenGL's separate
//! specular colour). Vertex colours replace `ka` and `kd` (`GL_COLOR_MATERIAL`,
//! `GL_AMBIENT_AND_DIFFUSE`). Scenes without maps or vertex colours never come here.
//!
//! Normal and bump maps (Phong only) perturb each pixel's normal before it is lit, in the
//! tangent frame: N the interpolated normal (normalised), T the interpolated tangent made
//! perpendicular to N and normalised (Gram–Schmidt), B = w·N × T (w the interpolated
//! handedness's sign), and the lit normal is normalize(t_x·T + t_y·B + t_z·N) for the map's
//! tangent-space normal t ([`Maps::normal_at`], [`Maps::bump_normal`]; a normal map first,
//! then a bump map in the frame it made). Shadows keep the unperturbed normal (they are
//! geometry). That work is compiled only into the `PERTURB` body, chosen once per render
//! ([`TexturedScene::perturb`]), so textured scenes without such maps run the loop they ran.
//!
//! Pixels lit per pixel (Phong) wait in a [`Batch`] of [`LANES`] and are lit, textured and
//! stored together; where none is (flat and Gouraud, or no light reaches any surface) and
//! there is no depth output or fog, a tile goes a row at a time instead ([`textured_rows`]),
//! through the same per-pixel functions, so with the same bits.

use std::mem::MaybeUninit;

use glam::{Vec2, Vec3, Vec4};

use super::id_runs::{row_runs, Run};
use super::phong::face_normal;
use super::planes::{weight_planes, Plane, PlaneCache};
use super::prelight::{face_point, split_on, Terms3, VertexTerms};
use super::program::finish_batch;
use super::store::{fill_out, put, Out, Pixel, RowColors, ROW_LANES};
use super::{background_row, ShadeContext};
use crate::lighting::{lane, normalize_lanes, set_lane, Lanes, Split, Surface, LANES};
use crate::material::Material;
use crate::options::{ShadingMode, SpecularModel};
use crate::pipeline::raster::{TileBuffers, NO_TRIANGLE};
use crate::pipeline::setup::SetupTri;
use crate::pipeline::tiles::{TileRect, TILE};
use crate::pipeline::Sides;
use crate::texture::{Footprint, Maps, Texture};

#[cfg(target_arch = "x86_64")]
mod lean;

/// What the texture stage reads of each object, per render.
pub(crate) struct TexturedObject<'a> {
    /// Front material and the one lighting back faces (two-sided).
    pub material: [Material; 2],
    pub maps: Option<&'a Maps>,
    /// Whether the mesh has vertex colours.
    pub colors: bool,
    /// Whether a map reads the screen-space derivatives ([`Maps::reads_footprint`]):
    /// without one, the pixel loop skips them.
    pub footprint: bool,
    /// Per material (front, back): the diffuse map where the rows' register path draws it
    /// ([`lean::lean_map`]).
    #[cfg(target_arch = "x86_64")]
    lean: [Option<(&'a Texture, crate::texture::ImageLanes<'a>)>; 2],
}

impl<'a> TexturedObject<'a> {
    /// What the texture stage reads of `o` (`two_sided`: the scene lights back faces).
    pub(crate) fn new(o: &'a crate::scene::Object, two_sided: bool) -> Self {
        let material = [*o.material(), *o.material_for(true, two_sided)];
        let maps = o.maps().map(|m| &**m);
        let colors = o.mesh().colors().is_some();
        TexturedObject {
            material,
            maps,
            colors,
            footprint: maps.is_some_and(|m| m.reads_footprint()),
            #[cfg(target_arch = "x86_64")]
            lean: material.map(|m| lean::lean_map(maps, colors, &m)),
        }
    }
}

/// The texture stage's share of the shade context.
pub(crate) struct TexturedScene<'a> {
    /// Unit surfaces per object (front, back).
    pub units: &'a [Sides],
    pub objects: Vec<TexturedObject<'a>>,
    /// Whether any object has a normal or bump map (Phong): the tile body that perturbs.
    pub perturb: bool,
    /// Whether a light reaches some surface ([`Surface::lights`]): Phong then lights
    /// pixels one by one, else every mode shades flat ([`shaded_as`]).
    pub lit: bool,
    /// Gouraud: every vertex's split terms (empty in the other modes).
    pub vertex_terms: &'a VertexTerms,
}

/// The triangle being shaded.
struct Current {
    plane: [Plane; 3],
    uv: [Vec2; 3],
    vcolor: [Vec3; 3],
    /// Flat: the face's terms; Gouraud: the vertices' terms.
    terms: [Terms3; 3],
    /// Phong: vertex normals (world) and positions.
    normal: [Vec3; 3],
    pos: [Vec3; 3],
    /// Phong with shadows: the geometric normal (the shadow ray offset's direction).
    face: Vec3,
    /// Phong with normal or bump maps: vertex tangents (world) and handedness.
    tangent: [Vec4; 3],
    /// (object, back side) of the material.
    key: (u32, bool),
    /// The mode this triangle is shaded in ([`shaded_as`]).
    mode: ShadingMode,
    /// The object's [`TexturedObject::colors`] and [`TexturedObject::footprint`].
    colors: bool,
    footprint: bool,
}

impl Current {
    /// Loads triangle `id` (set-up triangle `t`) into `slot`, in place: built elsewhere and
    /// moved in, each load copied the whole entry (about 390 bytes) with a `memcpy` call.
    fn load<const AFFINE: bool, const PERTURB: bool>(
        slot: &mut MaybeUninit<Current>,
        ctx: &ShadeContext<'_>,
        tex: &TexturedScene<'_>,
        mode: ShadingMode,
        id: u32,
        t: &SetupTri,
        planes: &mut PlaneCache<[Plane; 3]>,
    ) {
        let v = t.v.map(|k| k as usize);
        let back = ctx.two_sided && !t.front;
        let verts = ctx.verts;
        let unit = &tex.units[t.object as usize][back as usize];
        let mode = shaded_as(mode, unit);
        let cur = slot.write(Current {
            plane: planes.get(id, || weight_planes::<AFFINE>(ctx, t)),
            uv: if verts.uv.is_empty() {
                [Vec2::ZERO; 3]
            } else {
                v.map(|k| verts.uv[k])
            },
            vcolor: if verts.vertex_color.is_empty() {
                [Vec3::ZERO; 3]
            } else {
                v.map(|k| verts.vertex_color[k])
            },
            terms: [Terms3::default(); 3],
            normal: [Vec3::ZERO; 3],
            pos: v.map(|k| verts.world[k]),
            face: Vec3::ZERO,
            tangent: [Vec4::ZERO; 3],
            key: (t.object, back),
            mode,
            colors: tex.objects[t.object as usize].colors,
            footprint: tex.objects[t.object as usize].footprint,
        });
        match mode {
            ShadingMode::Flat => {
                // Lit before the tile stage (`prelight::light_face_terms`), except where a
                // surface no light reaches makes Gouraud or Phong shade flat (`shaded_as`).
                cur.terms = [match ctx.tris.face_terms(id) {
                    Some(f) => *f,
                    None => light_face(ctx, unit, t, back, cur.pos),
                }; 3];
            }
            ShadingMode::Gouraud => {
                // Lit before the tile stage (`prelight::light_vertex_terms`).
                let lit = tex.vertex_terms.side(back);
                cur.terms = v.map(|k| lit[k]);
            }
            ShadingMode::Phong => {
                cur.normal = v.map(|k| verts.normal[k]);
                if ctx.shadows.is_some() {
                    cur.face = face_normal(t, &verts.world);
                }
                if PERTURB {
                    cur.tangent = v.map(|k| verts.tangent[k]);
                }
            }
        }
    }
}

/// The split terms of face `t` (world vertices `pos`), lit at its centroid with its unit
/// normal, as `prelight::light_face_terms` lights them.
#[cold]
fn light_face(
    ctx: &ShadeContext<'_>,
    unit: &Surface,
    t: &SetupTri,
    back: bool,
    pos: [Vec3; 3],
) -> Terms3 {
    let (n, centroid) = face_point(t, pos, back);
    let mut f = [Terms3::default()];
    split_on(
        ctx.wide(),
        unit,
        ctx.shadows.as_ref(),
        &[n],
        &[centroid],
        ctx.eye,
        &mut f,
    );
    f[0]
}

/// The mode a surface is shaded in. A surface no light reaches ([`Surface::lights`] empty:
/// no source, or only dark ones, which `LightSet::new` drops) is lit by its constant
/// ambient term alone ([`Surface::base`]; diffuse and specular 0), which flat computes once
/// per triangle: Phong's per-pixel normals and lighting and Gouraud's per-vertex lighting
/// and interpolation (which gives the constant back up to f32 rounding) add nothing but
/// cost, so such a surface is shaded flat in every mode, and every mode gives the same
/// picture. Normal and bump maps change only the lighting, so nothing there either.
fn shaded_as(mode: ShadingMode, unit: &Surface) -> ShadingMode {
    if unit.lights.is_empty() {
        ShadingMode::Flat
    } else {
        mode
    }
}

/// What a batch is shaded with: the render, the textured scene, the mode and the tile.
#[derive(Clone, Copy)]
struct Tile<'a, 'b> {
    ctx: &'a ShadeContext<'b>,
    tex: &'a TexturedScene<'b>,
    mode: ShadingMode,
    rect: TileRect,
}

/// Where a chunk of a run goes: tile row `j`, from tile column `s` (pixel centre row `y`;
/// tile origin column `x0`), into the batch from lane `k0`.
struct Chunk {
    j: usize,
    s: usize,
    y: f64,
    x0: usize,
    k0: usize,
}

/// One group of [`LANES`] pixels of a row of triangle `c`, centres `base + k + ½` (lane k)
/// on the row centre `y`: q_m = the weight planes there, W = Σ q_m, the perspective-correct
/// weights b_m = q_m / W and the texture coordinates they blend. Every lane is evaluated
/// (a fixed trip count, so the loops widen); the callers keep the lanes they cover.
struct Group {
    w: [f64; LANES],
    r: [f64; LANES],
    b: [[f64; LANES]; 3],
    u: [f64; LANES],
    v: [f64; LANES],
}

impl Group {
    /// A group to [`Group::set`] (all zero).
    fn zeroed() -> Self {
        Group {
            w: [0.0; LANES],
            r: [0.0; LANES],
            b: [[0.0; LANES]; 3],
            u: [0.0; LANES],
            v: [0.0; LANES],
        }
    }

    /// The group of pixels `base + k + ½` on row `y` of triangle `c`, written in place: a
    /// group returned by value was copied out of the callee's arrays into the caller's
    /// (448 bytes; callgrind put that copy at 6 % of the texture report's floor).
    #[allow(clippy::needless_range_loop)] // lane k of several arrays
    #[inline(always)]
    fn set(&mut self, c: &Current, base: f64, y: f64) {
        let pl = &c.plane;
        let by = [0, 1, 2].map(|m| pl[m][1] * y);
        let us = c.uv.map(|t| t.x as f64);
        let vs = c.uv.map(|t| t.y as f64);
        let Group { w, r, b, u, v } = self;
        for k in 0..LANES {
            let x = base + k as f64 + 0.5;
            let q = [0, 1, 2].map(|m| pl[m][0] * x + by[m] + pl[m][2]);
            w[k] = q[0] + q[1] + q[2];
            r[k] = 1.0 / w[k];
            for m in 0..3 {
                b[m][k] = q[m] * r[k];
            }
        }
        for k in 0..LANES {
            u[k] = us[0] * b[0][k] + us[1] * b[1][k] + us[2] * b[2][k];
            v[k] = vs[0] * b[0][k] + vs[1] * b[1][k] + vs[2] * b[2][k];
        }
    }

    /// The exact screen-space derivatives of (u, v) at `lanes`, into `out`:
    /// ∂(Σ q_k·a_k / W)/∂x = (Σ ∂q_k/∂x·a_k − a·∂W/∂x) / W.
    #[inline(always)]
    fn footprints(&self, c: &Current, lanes: std::ops::Range<usize>, out: &mut [Footprint]) {
        let pl = &c.plane;
        let us = c.uv.map(|t| t.x as f64);
        let vs = c.uv.map(|t| t.y as f64);
        let da =
            |a: [f64; 3], axis: usize| pl[0][axis] * a[0] + pl[1][axis] * a[1] + pl[2][axis] * a[2];
        let dw = [0, 1].map(|axis| pl[0][axis] + pl[1][axis] + pl[2][axis]);
        let (dux, dvx, duy, dvy) = (da(us, 0), da(vs, 0), da(us, 1), da(vs, 1));
        for k in lanes {
            out[k] = Footprint {
                du_dx: (dux - self.u[k] * dw[0]) * self.r[k],
                dv_dx: (dvx - self.v[k] * dw[0]) * self.r[k],
                du_dy: (duy - self.u[k] * dw[1]) * self.r[k],
                dv_dy: (dvy - self.v[k] * dw[1]) * self.r[k],
            };
        }
    }

    /// The weights in f32, what the vertex values are blended with.
    #[inline(always)]
    fn weights_f32(&self) -> [[f32; LANES]; 3] {
        self.b.map(|bm| bm.map(|x| x as f32))
    }
}

/// Three vertex values `a` blended by the weights `bf` into `lanes` of `out`, as `Vec3`
/// arithmetic does it per component: a₀·b₀ + a₁·b₁ + a₂·b₂.
#[inline(always)]
fn blend(a: [f32; 3], bf: &[[f32; LANES]; 3], lanes: std::ops::Range<usize>, out: &mut Lanes) {
    for k in lanes {
        out[k] = a[0] * bf[0][k] + a[1] * bf[1][k] + a[2] * bf[2][k];
    }
}

/// Flat and Gouraud: the split terms of `lanes` (the face's, or the vertices' blended).
#[inline(always)]
fn vertex_terms(
    c: &Current,
    bf: &[[f32; LANES]; 3],
    lanes: std::ops::Range<usize>,
    out: &mut Split,
) {
    if c.mode == ShadingMode::Gouraud {
        let tt = &c.terms;
        for ch in 0..3 {
            blend(tt.map(|x| x.a[ch]), bf, lanes.clone(), &mut out.ambient[ch]);
            blend(tt.map(|x| x.d[ch]), bf, lanes.clone(), &mut out.diffuse[ch]);
            blend(
                tt.map(|x| x.s[ch]),
                bf,
                lanes.clone(),
                &mut out.specular[ch],
            );
        }
    } else {
        face_terms(c, lanes, out);
    }
}

/// Flat: the face's split terms in `lanes` (no weights: they are the same everywhere).
#[inline(always)]
fn face_terms(c: &Current, lanes: std::ops::Range<usize>, out: &mut Split) {
    let f = &c.terms[0];
    for ch in 0..3 {
        out.ambient[ch][lanes.clone()].fill(f.a[ch]);
        out.diffuse[ch][lanes.clone()].fill(f.d[ch]);
        out.specular[ch][lanes.clone()].fill(f.s[ch]);
    }
}

/// The textured colour of every lane, `ke·Te + ka·Ta ⊙ A + kd·Td ⊙ D + ks·Ts ⊙ S` (the
/// module's doc), from the lit `terms`, the vertex colours `vcolor` (read when the object
/// has them) and the maps read at (u, v) for the first `n` lanes. Channel by channel over
/// all lanes (dead lanes compute garbage nobody stores), in the order of the per-pixel
/// expression, so each lane's value is what the per-lane `Vec3` arithmetic gave.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn textured_color(
    obj: &TexturedObject<'_>,
    m: &Material,
    terms: &Split,
    vcolor: &[Lanes; 3],
    u: &[f64; LANES],
    v: &[f64; LANES],
    fp: &[Footprint; LANES],
    n: usize,
    wide: bool,
) -> [Lanes; 3] {
    // Each map read for all lanes at once (one dispatch per map); 1 without a map.
    let read = |t: &Option<std::sync::Arc<Texture>>, out: &mut [Lanes; 3]| {
        if let Some(t) = t {
            t.sample_many(u, v, fp, n, out, wide);
        }
    };
    let mut td = [[1.0; LANES]; 3];
    let mut ts = [[1.0; LANES]; 3];
    let mut te = [[1.0; LANES]; 3];
    let mut ta = [[1.0; LANES]; 3];
    let mut own_ambient = false;
    if let Some(maps) = obj.maps {
        read(&maps.diffuse, &mut td);
        read(&maps.specular, &mut ts);
        if m.emission != Vec3::ZERO {
            read(&maps.emission, &mut te);
        }
        if maps.ambient.is_some() {
            read(&maps.ambient, &mut ta);
            own_ambient = true;
        }
    }
    let ta = if own_ambient { &ta } else { &td };
    let mut c = [[0.0; LANES]; 3];
    for ch in 0..3 {
        let (ke, ks) = (m.emission[ch], m.specular[ch]);
        let k_ad = if obj.colors {
            vcolor[ch]
        } else {
            [m.ambient[ch]; LANES]
        };
        let k_d = if obj.colors {
            vcolor[ch]
        } else {
            [m.diffuse[ch]; LANES]
        };
        for k in 0..LANES {
            c[ch][k] = ke * te[ch][k]
                + k_ad[k] * ta[ch][k] * terms.ambient[ch][k]
                + k_d[k] * td[ch][k] * terms.diffuse[ch][k]
                + ks * ts[ch][k] * terms.specular[ch][k];
        }
    }
    c
}

/// Pixels waiting to be lit and textured together, all of one material.
struct Batch {
    len: usize,
    at: [(usize, usize); LANES],
    /// Texture coordinates per lane, as lanes: a chunk's are written and read as whole
    /// vectors (as (u, v) pairs stored a lane at a time and read back as lanes by the
    /// sampler, perf put a fifth of the chunk's interpolation on those stores).
    u: [f64; LANES],
    v: [f64; LANES],
    fp: [Footprint; LANES],
    /// Channel-major lanes (as the lighting's and the stores' are), so the flush's
    /// combination is one loop per channel over all lanes.
    vcolor: [Lanes; 3],
    /// Flat and Gouraud: the interpolated terms; Phong: filled at the flush.
    terms: Split,
    /// Phong: the interpolated normal (not normalised) and position.
    n: [Lanes; 3],
    p: [Lanes; 3],
    /// Phong with shadows: each lane's geometric normal, and each source's visibility.
    g: [Lanes; 3],
    vis: Vec<Option<Lanes>>,
    /// Phong with normal or bump maps: the interpolated tangent and handedness.
    tan: [Vec4; LANES],
    depth: Lanes,
    key: (u32, bool),
    /// The chunk being taken's interpolation, written in place ([`Group::set`]).
    group: Group,
}

impl Batch {
    /// The specular exponent of each live lane: `shininess` times `map`'s value there
    /// ([`Maps::shininess_at`]).
    fn shininess(&self, map: &Texture, shininess: f32) -> Lanes {
        let mut f = [0.0; LANES];
        for (k, fk) in f.iter_mut().enumerate().take(self.len) {
            let (u, v) = (self.u[k], self.v[k]);
            *fk = Maps::shininess_at(shininess, map.sample(u, v, &self.fp[k]));
        }
        f
    }

    /// Perturbs the normals `n` (unit; flipped on back faces) of the live lanes by the
    /// object's normal and bump maps in each lane's tangent frame (see the module's doc).
    #[allow(clippy::needless_range_loop)] // lane k of several arrays
    fn perturb(&self, maps: &Maps, back: bool, n: &mut [Lanes; 3]) {
        let flip = if back { -1.0 } else { 1.0 };
        for k in 0..self.len {
            // The frame of the front face: a back face's normal is the front's, flipped.
            let nf = lane(n, k) * flip;
            let t = self.tan[k];
            let tt = (t.truncate() - nf * nf.dot(t.truncate())).normalize_or_zero();
            let w = if t.w < 0.0 { -1.0 } else { 1.0 };
            let (u, v) = (self.u[k], self.v[k]);
            let fp = &self.fp[k];
            let mut frame = (tt, nf.cross(tt) * w, nf);
            let mut out = nf;
            for (map, scale, bump) in [
                (&maps.normal, maps.normal_scale, false),
                (&maps.bump, maps.bump_scale, true),
            ] {
                let Some(map) = map else { continue };
                let ts = if bump {
                    Maps::bump_normal(map, scale, u, v, fp)
                } else {
                    Maps::normal_at(map.sample(u, v, fp), scale)
                };
                let (ft, fb, fnn) = frame;
                let p = (ft * ts.x + fb * ts.y + fnn * ts.z).normalize_or_zero();
                if p != Vec3::ZERO {
                    out = p;
                    // A bump map after a normal map: its frame turned with the normal.
                    let t2 = (ft - p * p.dot(ft)).normalize_or_zero();
                    frame = (t2, p.cross(t2) * w, p);
                }
            }
            set_lane(n, k, out * flip);
        }
    }

    /// Takes pixels `at.s ..` of tile row `at.j` (eye depths `zs`) of triangle `c` (`t`)
    /// into lanes `lanes` (`at.k0 ..`), writing their eye depths to `depth_row` if given:
    /// each lane's interpolation in lane loops over the chunk, per pixel the same
    /// operations (and so the same bits) as evaluating it alone.
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)] // lane k of several arrays
    #[inline(always)]
    fn take<const AFFINE: bool, const PERTURB: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        c: &Current,
        t: &SetupTri,
        at: &Chunk,
        lanes: std::ops::Range<usize>,
        zs: &[f32],
        want_depth: bool,
        depth_row: Option<&mut [Out<f32>]>,
    ) {
        let (lo, hi) = (lanes.start, lanes.end);
        // Pixel of lane k: at.s + (k − at.k0); its centre x is an integer plus ½ (exact:
        // small integers, so the same bits as summing in usize first). Lanes outside
        // `lo..hi` get a pixel off the chunk: the loops run over all lanes (a fixed trip
        // count, so they widen) and only `lo..hi` is kept.
        let g = &mut self.group;
        g.set(c, (at.x0 + at.s) as f64 - at.k0 as f64, at.y);
        // One loop of three stores: two `copy_from_slice` of a variable range were two
        // `memcpy` calls per chunk (6 % of a textured Phong frame's instructions).
        for k in lo..hi {
            self.u[k] = g.u[k];
            self.v[k] = g.v[k];
            self.at[k] = (at.j, at.s + k - at.k0);
        }
        if c.footprint {
            g.footprints(c, lo..hi, &mut self.fp);
        }
        let bf = g.weights_f32();
        if c.colors {
            for ch in 0..3 {
                blend(c.vcolor.map(|vc| vc[ch]), &bf, lo..hi, &mut self.vcolor[ch]);
            }
        }
        let w = &g.w;
        match c.mode {
            ShadingMode::Flat | ShadingMode::Gouraud => {
                vertex_terms(c, &bf, lo..hi, &mut self.terms);
            }
            ShadingMode::Phong => {
                for k in lo..hi {
                    let bk = [bf[0][k], bf[1][k], bf[2][k]];
                    let blend3 = |a: &[Vec3; 3]| a[0] * bk[0] + a[1] * bk[1] + a[2] * bk[2];
                    let mut n = blend3(&c.normal);
                    let len2 = n.length_squared();
                    if !(len2 > 1e-30 && len2.is_finite()) {
                        n = face_normal(t, &ctx.verts.world);
                    }
                    if ctx.two_sided && !t.front {
                        n = -n;
                    }
                    let p = blend3(&c.pos);
                    if PERTURB {
                        let tg = &c.tangent;
                        self.tan[k] = tg[0] * bk[0] + tg[1] * bk[1] + tg[2] * bk[2];
                    }
                    for ax in 0..3 {
                        self.n[ax][k] = n[ax];
                        self.p[ax][k] = p[ax];
                        self.g[ax][k] = c.face[ax];
                    }
                }
            }
        }
        for k in lo..hi {
            self.depth[k] = ctx.eye_depth::<AFFINE>(want_depth, zs[k - lo], w[k] as f32);
        }
        if let Some(d) = depth_row {
            for (k, out) in (lo..hi).zip(d) {
                out.write(self.depth[k]);
            }
        }
    }

    /// [`Batch::flush`] compiled for AVX2 + FMA when `WIDE` (the lighting's lane loops
    /// widen), for the baseline otherwise: one out-of-line copy per instruction set.
    #[inline(always)]
    fn flush_on<P: Pixel, const PERTURB: bool, const WIDE: bool>(
        &mut self,
        on: &Tile<'_, '_>,
        color: &mut [&mut [Out<P>]],
    ) {
        #[cfg(target_arch = "x86_64")]
        if WIDE {
            // SAFETY: `WIDE` is set only by the AVX2 tile body (`isa.rs`), which runs only
            // after the CPU reported AVX2 and FMA.
            unsafe { self.flush_avx2::<P, PERTURB>(on, color) };
            return;
        }
        self.flush_baseline::<P, PERTURB>(on, color);
    }

    #[inline(never)]
    fn flush_baseline<P: Pixel, const PERTURB: bool>(
        &mut self,
        on: &Tile<'_, '_>,
        color: &mut [&mut [Out<P>]],
    ) {
        self.flush::<P, PERTURB>(on, color);
    }

    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn flush_avx2<P: Pixel, const PERTURB: bool>(
        &mut self,
        on: &Tile<'_, '_>,
        color: &mut [&mut [Out<P>]],
    ) {
        self.flush::<P, PERTURB>(on, color);
    }

    #[inline(always)]
    fn flush<P: Pixel, const PERTURB: bool>(
        &mut self,
        on: &Tile<'_, '_>,
        color: &mut [&mut [Out<P>]],
    ) {
        let Tile {
            ctx,
            tex,
            mode,
            rect,
        } = *on;
        if self.len == 0 {
            return;
        }
        let (object, back) = self.key;
        let obj = &tex.objects[object as usize];
        let m = &obj.material[back as usize];
        let unit = &tex.units[object as usize][back as usize];
        if shaded_as(mode, unit) == ShadingMode::Phong {
            let mut n = [[0.0; LANES]; 3];
            normalize_lanes(&mut n, &self.n, ctx.wide());
            if let Some(s) = &ctx.shadows {
                s.visibility(&n, &self.p, &self.g, self.len, &mut self.vis);
            }
            if PERTURB {
                if let Some(maps) = obj.maps.filter(|m| m.perturbs()) {
                    self.perturb(maps, back, &mut n);
                }
            }
            // Per pixel, as untextured Phong: each shadowed light scaled by its visibility.
            let shininess_map = obj.maps.and_then(|m| m.shininess.as_ref());
            let t: Split = match (shininess_map, &ctx.shadows) {
                (None, None) => unit.terms_lanes(&n, &self.p, ctx.eye),
                (None, Some(_)) => unit.terms_lanes_visible(&n, &self.p, ctx.eye, &self.vis),
                (Some(map), _) => {
                    let f = self.shininess(map, m.shininess);
                    let mut t: Split =
                        unit.terms_lanes_shininess(&n, &self.p, ctx.eye, &self.vis, &f);
                    if unit.specular_on && unit.model == SpecularModel::NormalizedBlinnPhong {
                        // The unit surface folded the lobe's (f + 8)/8π for the material's f.
                        let base = m.shininess + 8.0;
                        for ch in &mut t.specular {
                            for (s, fk) in ch.iter_mut().zip(&f) {
                                *s *= (fk + 8.0) / base;
                            }
                        }
                    }
                    t
                }
            };
            self.terms = t;
        }
        let c = textured_color(
            obj,
            m,
            &self.terms,
            &self.vcolor,
            &self.u,
            &self.v,
            &self.fp,
            self.len,
            ctx.wide(),
        );
        finish_batch(ctx, c, &self.at[..self.len], &self.depth, rect, color);
        self.len = 0;
    }
}

/// How many loaded triangles [`shade_textured`] keeps (direct-mapped by id). With 16, the
/// tiles of textured Spot at 512 × 512 (23,424 triangles) loaded 30,190 triangles a frame
/// (Phong's 256-entry cache makes 11,945 on those frames); with 128 (an entry is about 390
/// bytes), 13,610 (callgrind's call counts).
const LOADED: usize = 128;

/// The last triangles loaded ([`Current`]), direct-mapped by id, with their weight planes:
/// rows of a tile cross the same few triangles again and again, and a load gathers the
/// planes, UVs, colours and terms of the triangle. Not a `PlaneCache<Current, LOADED>`,
/// though it repeats that mechanism (ids apart, uninitialised slots), because each way
/// tried cost instructions (callgrind, per frame, one thread): with 16 entries made by
/// value, 24 % more in the textured shade functions (Phong on textured Spot, planar UVs,
/// bilinear, 512 × 512); with 128 and an in-place `get_with`, as a field of a struct the
/// 50 KB table was copied into place per tile (`frame_cost flat 0 360 floor
/// texture=bilinear` 8.11M → 9.72M), and as a local the load's closure stayed out of
/// line (textured Spot Phong 54.12M → 55.13M).
struct Loaded {
    /// The id of each slot's triangle; [`NO_TRIANGLE`]: the slot is empty.
    ids: [u32; LOADED],
    /// Uninitialised until a load: filled with an empty entry for each tile, the table
    /// made the unlit texture floor's frame 24 % more instructions (128 `memcpy` calls a
    /// tile; callgrind, `frame_cost flat 0 360 floor texture=bilinear`).
    slots: [MaybeUninit<Current>; LOADED],
    planes: PlaneCache<[Plane; 3]>,
}

impl Loaded {
    fn new() -> Self {
        Loaded {
            ids: [NO_TRIANGLE; LOADED],
            slots: [const { MaybeUninit::uninit() }; LOADED],
            planes: PlaneCache::new(),
        }
    }

    /// Triangle `id`, loaded if it is not in the table.
    #[inline(always)]
    fn get<const AFFINE: bool, const PERTURB: bool>(
        &mut self,
        ctx: &ShadeContext<'_>,
        tex: &TexturedScene<'_>,
        mode: ShadingMode,
        id: u32,
    ) -> &Current {
        let k = id as usize % LOADED;
        // `NO_TRIANGLE` marks an empty slot, so it is never taken as loaded.
        if self.ids[k] != id || id == NO_TRIANGLE {
            let t = ctx.tris.get(id);
            Current::load::<AFFINE, PERTURB>(
                &mut self.slots[k],
                ctx,
                tex,
                mode,
                id,
                t,
                &mut self.planes,
            );
            self.ids[k] = id;
        }
        // SAFETY: `ids[k]` is `id`, not `NO_TRIANGLE`, so slot `k` was written when the id
        // was, here or by an earlier call.
        unsafe { self.slots[k].assume_init_ref() }
    }
}

/// Shades one tile of a textured scene (any mode); `WIDE`: compiled for AVX2 + FMA, its
/// batches lit with AVX2 too ([`Batch::flush_on`]). Never inlined: the untextured tile
/// bodies that branch past it keep their own code layout.
#[inline(never)]
pub(super) fn shade_textured<
    P: Pixel,
    const AFFINE: bool,
    const PERTURB: bool,
    const WIDE: bool,
>(
    ctx: &ShadeContext<'_>,
    tex: &TexturedScene<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        // SAFETY: `WIDE` is set only by the AVX2 tile body (`isa.rs`), which runs only
        // where AVX2 and FMA were detected.
        unsafe {
            shade_textured_avx2::<P, AFFINE, PERTURB>(ctx, tex, mode, rect, buf, color, depth)
        };
        return;
    }
    shade_textured_body::<P, AFFINE, PERTURB, WIDE>(ctx, tex, mode, rect, buf, color, depth);
}

/// [`shade_textured_body`] compiled for AVX2 + FMA: its per-pixel f64 interpolation (the
/// texture coordinates and their derivatives) in AVX encodings, the same operations, so the
/// same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn shade_textured_avx2<P: Pixel, const AFFINE: bool, const PERTURB: bool>(
    ctx: &ShadeContext<'_>,
    tex: &TexturedScene<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    depth: Option<&mut [&mut [Out<f32>]]>,
) {
    shade_textured_body::<P, AFFINE, PERTURB, true>(ctx, tex, mode, rect, buf, color, depth);
}

#[inline(always)]
fn shade_textured_body<P: Pixel, const AFFINE: bool, const PERTURB: bool, const WIDE: bool>(
    ctx: &ShadeContext<'_>,
    tex: &TexturedScene<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
    mut depth: Option<&mut [&mut [Out<f32>]]>,
) {
    if depth.is_none() && ctx.program.is_empty() && (mode != ShadingMode::Phong || !tex.lit) {
        return textured_rows::<P, AFFINE>(ctx, tex, mode, rect, buf, color);
    }
    let on = Tile {
        ctx,
        tex,
        mode,
        rect,
    };
    let want_depth = depth.is_some() || ctx.program.reads_depth();
    let background = background_row::<P>(ctx);
    let mut loaded = Loaded::new();
    let mut batch = Batch {
        len: 0,
        at: [(0, 0); LANES],
        u: [0.0; LANES],
        v: [0.0; LANES],
        fp: [Footprint::default(); LANES],
        vcolor: [[0.0; LANES]; 3],
        terms: Split::default(),
        n: [[0.0; LANES]; 3],
        p: [[0.0; LANES]; 3],
        g: [[0.0; LANES]; 3],
        vis: ctx
            .shadows
            .as_ref()
            .map_or(Vec::new(), |s| vec![None; s.sources()]),
        depth: [0.0; LANES],
        key: (u32::MAX, false),
        tan: [Vec4::ZERO; LANES],
        group: Group::zeroed(),
    };
    for j in 0..rect.h {
        let y = (rect.y0 + j) as f64 + 0.5;
        let zs = &buf.depth[j * TILE..j * TILE + rect.w];
        for Run { id, start: i, end } in row_runs(buf, j, rect.w) {
            if id == NO_TRIANGLE {
                put(&mut color[j][i * 3..end * 3], &background[..(end - i) * 3]);
                if let Some(d) = depth.as_deref_mut() {
                    fill_out(&mut d[j][i..end], f32::INFINITY);
                }
                continue;
            }
            let t = ctx.tris.get(id);
            let c = loaded.get::<AFFINE, PERTURB>(ctx, tex, mode, id);
            if batch.len > 0 && batch.key != c.key {
                batch.flush_on::<P, PERTURB, WIDE>(&on, color);
            }
            batch.key = c.key;
            // The run in chunks that fill the batch: a whole batch at once where the batch
            // is empty and the run has LANES pixels left (constant bounds: lane loops), the
            // rest lane by lane.
            let mut s = i;
            while s < end {
                let k0 = batch.len;
                let n = (LANES - k0).min(end - s);
                let at = Chunk {
                    j,
                    s,
                    y,
                    x0: rect.x0,
                    k0,
                };
                let dr = depth.as_deref_mut().map(|d| &mut d[j][s..s + n]);
                if n == LANES {
                    batch.take::<AFFINE, PERTURB>(
                        ctx,
                        c,
                        t,
                        &at,
                        0..LANES,
                        &zs[s..s + n],
                        want_depth,
                        dr,
                    );
                } else {
                    batch.take::<AFFINE, PERTURB>(
                        ctx,
                        c,
                        t,
                        &at,
                        k0..k0 + n,
                        &zs[s..s + n],
                        want_depth,
                        dr,
                    );
                }
                batch.len += n;
                if batch.len == LANES {
                    batch.flush_on::<P, PERTURB, WIDE>(&on, color);
                }
                s += n;
            }
        }
    }
    batch.flush_on::<P, PERTURB, WIDE>(&on, color);
}

/// Flat and Gouraud (every surface lit per face or per vertex, or by no light) without
/// depth output or fog, the common case: each tile row's colours go into a row buffer,
/// every run over whole [`LANES`] from its start (a run's last group spills into the next
/// run's pixels, which that run then overwrites), and the row is stored once, as Gouraud's
/// untextured rows are. No batch: a group's coordinates, terms and texels stay in lanes
/// from the interpolation to the row (the batch copied them in and out a lane at a time,
/// and stored each batch on its own). Per pixel the same operations as the batch path
/// ([`Group`], [`vertex_terms`], [`textured_color`]), so the same bits.
#[inline(always)]
fn textured_rows<P: Pixel, const AFFINE: bool>(
    ctx: &ShadeContext<'_>,
    tex: &TexturedScene<'_>,
    mode: ShadingMode,
    rect: TileRect,
    buf: &TileBuffers,
    color: &mut [&mut [Out<P>]],
) {
    let wide = ctx.wide();
    // Normal and bump maps need Phong, which never comes here: loaded without them.
    let mut loaded = Loaded::new();
    let bg = ctx.background.to_array();
    let mut lin: RowColors = [[0.0; ROW_LANES]; 3];
    let mut terms = Split::default();
    let mut vcolor = [[0.0; LANES]; 3];
    // Lanes past a run's end keep their last footprint (finite), as a batch's dead lanes do.
    let mut fp = [Footprint::default(); LANES];
    let mut g = Group::zeroed();
    for (j, row) in color[..rect.h].iter_mut().enumerate() {
        let y = (rect.y0 + j) as f64 + 0.5;
        for run in row_runs(buf, j, rect.w) {
            let (id, whole) = (run.id, run.whole_lanes());
            if id == NO_TRIANGLE {
                for (ch, v) in lin.iter_mut().zip(bg) {
                    ch[whole.clone()].fill(v);
                }
                continue;
            }
            let c = loaded.get::<AFFINE, false>(ctx, tex, mode, id);
            let (object, back) = c.key;
            let obj = &tex.objects[object as usize];
            let m = &obj.material[back as usize];
            #[cfg(target_arch = "x86_64")]
            if wide {
                if let Some((t, map)) = &obj.lean[back as usize] {
                    let (x0, end) = (rect.x0, run.end);
                    // SAFETY: `wide`: the render's ISA is AVX2, detected on this CPU.
                    unsafe {
                        let g = c.mode == ShadingMode::Gouraud;
                        use crate::texture::Filter;
                        use lean::{lean_groups as l, BILINEAR, NEAREST, TRILINEAR};
                        let f = match (map.filter(), g) {
                            (Filter::Nearest, false) => l::<NEAREST, false>,
                            (Filter::Nearest, true) => l::<NEAREST, true>,
                            (Filter::Bilinear, false) => l::<BILINEAR, false>,
                            (Filter::Bilinear, true) => l::<BILINEAR, true>,
                            (Filter::Trilinear, false) => l::<TRILINEAR, false>,
                            (Filter::Trilinear, true) => l::<TRILINEAR, true>,
                        };
                        f(c, m, t, map, x0, y, whole, end, &mut lin);
                    }
                    continue;
                }
            }
            // Flat: the face's terms, the same in every group of the run, filled once (per
            // group, the fill's stores were a tenth of a nearest-filtered floor's frame).
            let gouraud = c.mode == ShadingMode::Gouraud;
            if !gouraud {
                face_terms(c, 0..LANES, &mut terms);
            }
            for s in whole.step_by(LANES) {
                let live = LANES.min(run.end - s);
                g.set(c, (rect.x0 + s) as f64, y);
                if c.footprint {
                    g.footprints(c, 0..live, &mut fp);
                }
                if c.colors || gouraud {
                    let bf = g.weights_f32();
                    if c.colors {
                        for (ch, out) in vcolor.iter_mut().enumerate() {
                            blend(c.vcolor.map(|vc| vc[ch]), &bf, 0..LANES, out);
                        }
                    }
                    if gouraud {
                        vertex_terms(c, &bf, 0..LANES, &mut terms);
                    }
                }
                let out = textured_color(obj, m, &terms, &vcolor, &g.u, &g.v, &fp, live, wide);
                for (ch, o) in lin.iter_mut().zip(&out) {
                    ch[s..s + LANES].copy_from_slice(o);
                }
            }
        }
        P::store_row(&mut row[..rect.w * 3], &lin, wide);
    }
}
