//! The sampler room: textures and how they are read at a point. It knows nothing of lighting
//! or of the pipeline: a [`Texture`] answers "which colour at (u, v), seen with these
//! screen-space derivatives".
//!
//! Conventions (OpenGL's): UV (0, 0) is the bottom-left of the image; texel (i, j) (column
//! i, row j from the top of the image) has its centre at u = (i + 0.5)/W,
//! v = 1 − (j + 0.5)/H. Filtering is exactly OpenGL 4.6 §8.14–8.15 (see [`sample`]); the
//! level of detail comes from the exact derivatives the caller passes ([`Footprint`]).
//!
//! Rooms: [`image`] (linear texels and the mip pyramid), [`wrap`] (repeat, clamp, mirror),
//! [`sample`] (nearest, bilinear, trilinear), [`procedural`] (checker, grid, stripes, noise),
//! [`decode`] (image files through the `image` crate).

mod decode;
mod image;
// The only user, the textured rows' register path, is x86-64 only.
#[cfg(target_arch = "x86_64")]
mod lanes_avx2;
mod procedural;
mod sample;
mod wrap;

use std::sync::Arc;

use glam::{DVec2, Vec3};

pub use self::image::{srgb_to_linear, Image, MAX_TEXEL_VALUE, MAX_TEXTURE_SIZE};
#[cfg(target_arch = "x86_64")]
pub(crate) use lanes_avx2::{F64x8, ImageLanes};
pub use procedural::Procedural;
pub use sample::{Filter, Footprint, MAX_ANISOTROPY};
pub use wrap::Wrap;

use crate::error::Result;

/// A texture: an image with its filter and wrap modes, or a procedural pattern evaluated at
/// each point.
#[derive(Debug, Clone)]
pub struct Texture {
    source: Source,
    /// (u, v) → (u, v)·scale + offset before sampling (MTL's `-s` and `-o`).
    uv_scale: DVec2,
    uv_offset: DVec2,
    /// The file it was loaded from and whether it was decoded as sRGB (for writing it back).
    file: Option<(std::path::PathBuf, bool)>,
}

#[derive(Debug, Clone)]
enum Source {
    Image {
        image: Arc<Image>,
        filter: Filter,
        wrap: [Wrap; 2],
        /// Probes along the footprint's major axis, 1 (isotropic) to [`MAX_ANISOTROPY`].
        aniso: u32,
    },
    Procedural(Procedural),
}

impl Texture {
    /// An image texture sampled with `filter`, wrapped per axis with `wrap` (u, v).
    pub fn from_image(image: Arc<Image>, filter: Filter, wrap: [Wrap; 2]) -> Self {
        Texture {
            source: Source::Image {
                image,
                filter,
                wrap,
                aniso: 1,
            },
            uv_scale: DVec2::ONE,
            uv_offset: DVec2::ZERO,
            file: None,
        }
    }

    /// A procedural texture (no image, evaluated where it is sampled).
    pub fn procedural(p: Procedural) -> Self {
        Texture {
            source: Source::Procedural(p),
            uv_scale: DVec2::ONE,
            uv_offset: DVec2::ZERO,
            file: None,
        }
    }

    /// The same texture read at (u, v)·`scale` + `offset` (finite; MTL's `-s` and `-o`).
    pub fn with_uv_transform(self, scale: DVec2, offset: DVec2) -> Self {
        Texture {
            uv_scale: scale,
            uv_offset: offset,
            ..self
        }
    }

    /// Decodes an image file (PNG, JPEG, 16-bit PNG...): see [`Image::load`].
    pub fn load(
        path: impl AsRef<std::path::Path>,
        filter: Filter,
        wrap: [Wrap; 2],
        srgb: bool,
    ) -> Result<Self> {
        let image = decode::load(path.as_ref(), srgb)?;
        let mut t = Texture::from_image(Arc::new(image), filter, wrap);
        t.file = Some((path.as_ref().to_path_buf(), srgb));
        Ok(t)
    }

    /// An image already decoded from `path` (linear, not sRGB), shared by several
    /// textures (MTL maps naming one file).
    pub(crate) fn load_shared(
        image: Arc<Image>,
        path: std::path::PathBuf,
        filter: Filter,
        wrap: [Wrap; 2],
    ) -> Self {
        let mut t = Texture::from_image(image, filter, wrap);
        t.file = Some((path, false));
        t
    }

    /// The same texture recording `path` (decoded as sRGB when `srgb`) as its source, for
    /// writers that name files (scene files, pickles); nothing is read.
    pub fn with_file(mut self, path: std::path::PathBuf, srgb: bool) -> Self {
        self.file = Some((path, srgb));
        self
    }

    /// The file an image texture was loaded from (as given to [`Texture::load`]) and whether
    /// it was decoded as sRGB; `None` for textures made from memory or procedural ones.
    pub fn file(&self) -> Option<(&std::path::Path, bool)> {
        self.file.as_ref().map(|(p, s)| (p.as_path(), *s))
    }

    /// The same image texture with anisotropic filtering of up to `aniso` probes (1, the
    /// default, is off; at most [`MAX_ANISOTROPY`]); see `sample::sample` for the
    /// definition. Procedural textures ignore it (they are not filtered).
    pub fn with_anisotropy(mut self, aniso: u32) -> Result<Self> {
        if !(1..=MAX_ANISOTROPY).contains(&aniso) {
            return Err(crate::error::RasterError::invalid_field(
                "anisotropy",
                format!("anisotropy must be 1 (off) to {MAX_ANISOTROPY}, got {aniso}"),
            ));
        }
        if let Source::Image { aniso: a, .. } = &mut self.source {
            *a = aniso;
        }
        Ok(self)
    }

    /// The anisotropy (1 for procedural textures).
    pub fn anisotropy(&self) -> u32 {
        match &self.source {
            Source::Image { aniso, .. } => *aniso,
            Source::Procedural(_) => 1,
        }
    }

    /// An upper bound on every channel the texture returns.
    pub fn max_value(&self) -> f32 {
        match &self.source {
            Source::Image { .. } => MAX_TEXEL_VALUE,
            Source::Procedural(p) => p.max_value(),
        }
    }

    /// The (scale, offset) applied to (u, v) before sampling.
    pub fn uv_transform(&self) -> (DVec2, DVec2) {
        (self.uv_scale, self.uv_offset)
    }

    /// The image, if this is an image texture.
    pub fn image(&self) -> Option<&Arc<Image>> {
        match &self.source {
            Source::Image { image, .. } => Some(image),
            Source::Procedural(_) => None,
        }
    }

    /// The filter (procedural textures report [`Filter::Nearest`]: evaluated at the point).
    pub fn filter(&self) -> Filter {
        match &self.source {
            Source::Image { filter, .. } => *filter,
            Source::Procedural(_) => Filter::Nearest,
        }
    }

    /// The wrap modes (u, v).
    pub fn wrap(&self) -> [Wrap; 2] {
        match &self.source {
            Source::Image { wrap, .. } => *wrap,
            Source::Procedural(_) => [Wrap::Repeat; 2],
        }
    }

    /// The procedural pattern, if this is one.
    pub fn pattern(&self) -> Option<&Procedural> {
        match &self.source {
            Source::Procedural(p) => Some(p),
            Source::Image { .. } => None,
        }
    }

    /// Whether [`Texture::sample`] reads its footprint argument (mipmapped or anisotropic
    /// image textures); for the others the caller may skip computing the derivatives.
    pub fn reads_footprint(&self) -> bool {
        match &self.source {
            Source::Image { filter, aniso, .. } => Footprint::read_by(*filter, *aniso),
            Source::Procedural(_) => false,
        }
    }

    /// The linear RGB colour at `(u, v)` with the footprint `fp` (the exact derivatives of
    /// u and v along the screen's x and y). Non-finite coordinates read as 0.
    #[inline]
    pub fn sample(&self, u: f64, v: f64, fp: &Footprint) -> Vec3 {
        let (s, o) = (self.uv_scale, self.uv_offset);
        let (u, v) = (finite_or_zero(u * s.x + o.x), finite_or_zero(v * s.y + o.y));
        let scaled = scale_footprint(fp, s);
        let fp = &scaled;
        match &self.source {
            Source::Image {
                image,
                filter,
                wrap,
                aniso,
            } => sample::sample(image, *filter, *wrap, *aniso, u, v, fp),
            Source::Procedural(p) => p.eval(u, v),
        }
    }
}

impl Texture {
    /// [`Texture::sample`] at the first `n` of the points (`(u[k], v[k])` seen with `fp[k]`, into
    /// lane `k` of the channel-major `out`; lanes from `n` on may be overwritten; `n` is
    /// at most `N`), the same values: the source and filter are dispatched once for all of
    /// them, and the image filters read all the points' texels at once
    /// (`sample::nearest_lanes`, `bilinear_lanes`, `trilinear_lanes`; with anisotropy,
    /// `sample::anisotropic_lanes` reads each round of probes so). The points past `n`
    /// may hold anything (they are computed on and dropped: whole-width lane loops). `wide`:
    /// the render's ISA is AVX2 (detected on this CPU); the texels are then read with one
    /// 16-byte load each (`sample::fetch`).
    #[inline(always)]
    pub fn sample_many<const N: usize>(
        &self,
        u: &[f64; N],
        v: &[f64; N],
        fp: &[Footprint; N],
        n: usize,
        out: &mut [[f32; N]; 3],
        wide: bool,
    ) {
        let n = n.min(N);
        let (s, o) = (self.uv_scale, self.uv_offset);
        let at = || (lanes(u, s.x, o.x), lanes(v, s.y, o.y));
        match &self.source {
            Source::Image {
                image,
                filter: Filter::Nearest,
                wrap,
                aniso: 0 | 1,
            } => {
                let (u, v) = at();
                sample::nearest_lanes(&image.levels()[0], *wrap, &u, &v, n, out, wide);
            }
            Source::Image {
                image,
                filter: Filter::Bilinear,
                wrap,
                aniso: 0 | 1,
            } => {
                let (u, v) = at();
                sample::bilinear_lanes(&image.levels()[0], *wrap, &u, &v, n, out, wide);
            }
            Source::Image {
                image,
                filter: Filter::Trilinear,
                wrap,
                aniso: 0 | 1,
            } => {
                // As `sample`: the footprint scaled with the coordinates, then λ.
                let (w, h) = (image.width(), image.height());
                let (u, v) = at();
                let scaled = std::array::from_fn(|k| scale_footprint(&fp[k], s));
                let lambda = sample::lod_lanes(&scaled, n, w, h);
                sample::trilinear_lanes(image.levels(), *wrap, &u, &v, &lambda, n, out, wide);
            }
            Source::Image {
                image,
                filter,
                wrap,
                aniso,
            } => {
                let (u, v) = at();
                let scaled = std::array::from_fn(|k| scale_footprint(&fp[k], s));
                let (f, a) = (*filter, *aniso);
                sample::anisotropic_lanes(image, f, *wrap, a, &u, &v, &scaled, n, out, wide);
            }
            Source::Procedural(_) => {
                for (k, fp) in fp.iter().enumerate().take(n) {
                    put_lane(out, k, self.sample(u[k], v[k], fp));
                }
            }
        }
    }
}

/// The coordinates `c` scaled by `s` and offset by `o`, non-finite ones 0, as
/// [`Texture::sample`] takes one (all `N` lanes: a loop of fixed length, which vectorises).
#[inline(always)]
fn lanes<const N: usize>(c: &[f64; N], s: f64, o: f64) -> [f64; N] {
    c.map(|c| finite_or_zero(c * s + o))
}

/// Writes `c` into lane `k` of channel-major lanes.
#[inline(always)]
fn put_lane<const N: usize>(out: &mut [[f32; N]; 3], k: usize, c: Vec3) {
    (out[0][k], out[1][k], out[2][k]) = (c.x, c.y, c.z);
}

/// The footprint of coordinates scaled by `s` (itself when `s` is 1, bit for bit).
#[inline(always)]
fn scale_footprint(fp: &Footprint, s: DVec2) -> Footprint {
    if s == DVec2::ONE {
        return *fp;
    }
    Footprint {
        du_dx: fp.du_dx * s.x,
        dv_dx: fp.dv_dx * s.y,
        du_dy: fp.du_dy * s.x,
        dv_dy: fp.dv_dy * s.y,
    }
}

/// `x`, or 0 where it is NaN or infinite (a select, no branch: lane loops of it widen).
#[inline(always)]
fn finite_or_zero(x: f64) -> f64 {
    let finite = x.abs() < f64::INFINITY;
    f64::from_bits(x.to_bits() & (finite as u64).wrapping_neg())
}

/// The texture maps of a material; each colour multiplies its coefficient per point.
/// `ambient` defaults to `diffuse` (as in MTL) when it is not given. `normal` and `bump`
/// perturb the shading normal instead (per-pixel lighting only: [`Maps::perturbs`]).
#[derive(Debug, Clone)]
pub struct Maps {
    /// Multiplies the diffuse reflectance `kd`.
    pub diffuse: Option<Arc<Texture>>,
    /// Multiplies the ambient reflectance `ka` (the diffuse map when `None`).
    pub ambient: Option<Arc<Texture>>,
    /// Multiplies the specular reflectance `ks`.
    pub specular: Option<Arc<Texture>>,
    /// Multiplies the emission `ke`.
    pub emission: Option<Arc<Texture>>,
    /// Multiplies the shininess (the mean of the texel's r, g, b: [`Maps::shininess_at`]);
    /// per-pixel lighting (Phong) only.
    pub shininess: Option<Arc<Texture>>,
    /// A tangent-space normal map: texel (r, g, b) is the normal
    /// (2r − 1, 2g − 1, 2b − 1) in the frame (tangent, bitangent, normal)
    /// ([`crate::generate_tangents`]); Phong only.
    pub normal: Option<Arc<Texture>>,
    /// Multiplies the normal map's x and y (glTF's `normalTexture.scale`); finite.
    pub normal_scale: f32,
    /// A height map (the mean of r, g, b), its gradient taken by central differences in
    /// texture space ([`Maps::bump_normal`]); Phong only.
    pub bump: Option<Arc<Texture>>,
    /// The height of a texel value 1, in UV units; finite.
    pub bump_scale: f32,
}

impl Default for Maps {
    fn default() -> Self {
        Maps {
            diffuse: None,
            ambient: None,
            specular: None,
            emission: None,
            shininess: None,
            normal: None,
            normal_scale: 1.0,
            bump: None,
            bump_scale: 1.0,
        }
    }
}

impl Maps {
    /// Whether no map is set.
    pub fn is_empty(&self) -> bool {
        self.diffuse.is_none()
            && self.ambient.is_none()
            && self.specular.is_none()
            && self.emission.is_none()
            && self.shininess.is_none()
            && self.normal.is_none()
            && self.bump.is_none()
    }

    /// Refuses a non-finite `normal_scale` or `bump_scale` (the error names the field).
    pub fn check_scales(&self) -> Result<()> {
        for (name, x) in [
            ("normal_scale", self.normal_scale),
            ("bump_scale", self.bump_scale),
        ] {
            if !x.is_finite() {
                return Err(crate::error::RasterError::invalid_field(
                    name,
                    format!("{name} must be finite, got {x}"),
                ));
            }
        }
        Ok(())
    }

    /// Whether any map reads the footprint it is sampled with ([`Texture::reads_footprint`]).
    pub fn reads_footprint(&self) -> bool {
        [
            &self.diffuse,
            &self.ambient,
            &self.specular,
            &self.emission,
            &self.shininess,
            &self.normal,
            &self.bump,
        ]
        .into_iter()
        .flatten()
        .any(|t| t.reads_footprint())
    }

    /// Whether a map perturbs the shading normal (normal or bump map).
    pub fn perturbs(&self) -> bool {
        self.normal.is_some() || self.bump.is_some()
    }

    /// The tangent-space normal a normal-map texel `t` encodes, x and y scaled by `scale`:
    /// (s·(2r − 1), s·(2g − 1), 2b − 1), not normalised (a texel (0.5, 0.5, 1) gives
    /// exactly (0, 0, 1)).
    #[inline]
    pub fn normal_at(t: Vec3, scale: f32) -> Vec3 {
        let n = t * 2.0 - Vec3::ONE;
        Vec3::new(n.x * scale, n.y * scale, n.z)
    }

    /// The tangent-space normal of the height field `scale·h(u, v)` over the UV plane,
    /// (−scale·∂h/∂u, −scale·∂h/∂v, 1) (not normalised), with the gradient by central
    /// differences of `height` (the mean of r, g, b) at (u ± δu, v) and (u, v ± δv): one
    /// texel of level 0 for image textures, 1/1024 for procedural ones. A constant map gives
    /// exactly (0, 0, 1).
    pub fn bump_normal(map: &Texture, scale: f32, u: f64, v: f64, fp: &Footprint) -> Vec3 {
        let (du, dv) = match map.image() {
            Some(img) => (1.0 / img.width() as f64, 1.0 / img.height() as f64),
            None => (1.0 / 1024.0, 1.0 / 1024.0),
        };
        let h = |u: f64, v: f64| {
            let t = map.sample(u, v, fp);
            ((t.x + t.y + t.z) / 3.0) as f64
        };
        let hu = (h(u + du, v) - h(u - du, v)) / (2.0 * du);
        let hv = (h(u, v + dv) - h(u, v - dv)) / (2.0 * dv);
        let s = scale as f64;
        Vec3::new((-s * hu) as f32, (-s * hv) as f32, 1.0)
    }

    /// The specular exponent at a point whose shininess map reads `t`: `shininess × (r + g +
    /// b)/3`, with an infinite or overflowing product the perfect mirror's `f32::MAX` (as an
    /// infinite shininess is lit) and a NaN-free result for every texel in [0, 1e6].
    #[inline]
    pub fn shininess_at(shininess: f32, t: Vec3) -> f32 {
        let f = shininess * ((t.x + t.y + t.z) / 3.0);
        if f.is_nan() {
            0.0 // inf × 0: a zero map value
        } else {
            f.min(f32::MAX)
        }
    }

    /// The map that weighs the ambient term: its own, else the diffuse map.
    pub fn ambient_or_diffuse(&self) -> Option<&Arc<Texture>> {
        self.ambient.as_ref().or(self.diffuse.as_ref())
    }
}

impl PartialEq for Maps {
    /// The same textures (by identity: two loads of one file are two textures).
    fn eq(&self, other: &Self) -> bool {
        let same = |a: &Option<Arc<Texture>>, b: &Option<Arc<Texture>>| match (a, b) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        same(&self.diffuse, &other.diffuse)
            && same(&self.ambient, &other.ambient)
            && same(&self.specular, &other.specular)
            && same(&self.emission, &other.emission)
            && same(&self.shininess, &other.shininess)
            && same(&self.normal, &other.normal)
            && same(&self.bump, &other.bump)
            && self.normal_scale.to_bits() == other.normal_scale.to_bits()
            && self.bump_scale.to_bits() == other.bump_scale.to_bits()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_or_zero_keeps_finite_values_bit_for_bit() {
        for x in [
            0.0,
            -0.0,
            1.5,
            -2.25,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            5e-324,
        ] {
            assert_eq!(finite_or_zero(x).to_bits(), x.to_bits(), "{x}");
        }
        for x in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(finite_or_zero(x).to_bits(), 0, "{x}");
        }
    }
}
