//! How to render: image size, shading mode, specular lobe, background, culling, threads.

use std::str::FromStr;

use glam::Vec3;

use crate::error::{RasterError, Result};
use crate::pool;

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
    /// Where lighting is evaluated (with [`RenderOptions::tolerance`], only where objects
    /// cannot be mixed: see there).
    pub shading: ShadingMode,
    /// `shading="auto"`: the largest RMSE (8-bit levels, against the exact surface) the
    /// shading may cost. Each object is shaded with the fastest mode (by a model of each
    /// mode's work on it) whose estimated error is within it, Phong where none is
    /// ([`crate::explain_shading`]); `None` shades every object with
    /// [`RenderOptions::shading`]. Finite and > 0.
    pub tolerance: Option<f32>,
    /// Which specular lobe.
    pub specular: SpecularModel,
    /// Linear RGB of pixels no triangle covers.
    pub background: Vec3,
    /// Skip triangles that are clockwise on screen.
    pub cull_backfaces: bool,
    /// Skip the back faces that cannot show (default `true`): those of an object whose mesh
    /// bounds solids wound outward (closed, consistently wound, each piece enclosing a
    /// positive volume), opaque, not mirrored by its transform, and lying wholly beyond the
    /// near plane (so the eye is outside it). The image is that of drawing them (up to
    /// rounding where a back face ties a front one at the silhouette); `false` draws them,
    /// for a mesh that passes through itself inside out (see docs/USER_GUIDE.md).
    pub cull_hidden: bool,
    /// Worker threads; `None` uses every core. Results are identical for any count.
    pub threads: Option<usize>,
    /// How Gouraud finds its vertex colours (ignored by flat and Phong).
    pub gouraud: GouraudMethod,
    /// How attributes are interpolated across a triangle (Gouraud colours, Phong normals and
    /// positions); flat has none.
    pub interpolation: Interpolation,
    /// Use only the target's baseline instructions (SSE2 on x86-64) even where the CPU has
    /// AVX2. The image is bit-identical either way; this exists to check that, and to
    /// measure what the wider instructions buy.
    pub baseline_isa: bool,
    /// Visibility samples per pixel: 1 (the pixel centre) or 2, 4, 8, 16 (multi-sample
    /// anti-aliasing at the standard D3D/Vulkan sample positions, [`SAMPLE_COUNTS`]). Each
    /// pixel is shaded once per visible triangle, at its centre, and the colours are
    /// averaged with the share of samples each triangle (or the background) covers.
    pub samples: u32,
    /// Render `k·width × k·height` pixels with one sample each and average each k×k block
    /// (a box filter in linear colour): the exact-but-slow anti-aliasing, 1 (off) to
    /// [`MAX_SUPERSAMPLE`]. Combines with `samples`.
    pub supersample: u32,
    /// Which triangle edges to draw as lines over the image ([`EdgeMode`]); `None` draws
    /// none and runs exactly the renderer without lines.
    pub edges: EdgeMode,
    /// Linear RGB of the lines (finite, each ≥ 0).
    pub edge_color: Vec3,
    /// Line width in pixels (finite, > 0, at most [`MAX_EDGE_WIDTH`]): a sample point
    /// within `edge_width / 2` of an edge's projected segment is covered.
    pub edge_width: f32,
    /// [`EdgeMode::Features`]: an edge between two faces whose normals differ by more than
    /// this angle (degrees, 0..=180) is a crease.
    pub edge_angle: f32,
    /// Draw the lines alone: surfaces still hide what is behind them but are painted as the
    /// background (with `alpha`, transparent). Needs `edges`.
    pub edges_only: bool,
    /// How mirrored light is found on reflective materials ([`Technique::Environment`] by
    /// default). Read only when a material has `reflectivity > 0`.
    pub reflections: Technique,
    /// How transmitted light is found on transparent materials: `None` (the default) sees
    /// what lies behind along the straight view ray (order-independent blending, no
    /// bending); `Some` bends it by Snell's law and looks it up or traces it.
    pub refractions: Option<Technique>,
    /// Secondary rays followed at most from the first surface ([`Technique::Ray`]); at the
    /// limit the environment is looked up instead. 0 ..= [`MAX_TRACE_DEPTH`].
    pub max_depth: u32,
    /// Show the scene's environment as the background (each pixel's view ray looked up)
    /// instead of [`RenderOptions::background`]; needs a scene environment.
    pub environment_background: bool,
}

/// Checks a `shading="auto"` tolerance: finite and > 0 (RMSE in 8-bit levels).
pub(crate) fn check_tolerance(tolerance: f32) -> Result<()> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(RasterError::invalid_field(
            "tolerance",
            format!("tolerance must be finite and > 0 (RMSE in 8-bit levels), got {tolerance}"),
        ));
    }
    Ok(())
}

/// Which triangle edges a render draws as lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum EdgeMode {
    /// No lines (the default).
    #[default]
    None,
    /// Every triangle edge, hidden ones too (a wireframe).
    All,
    /// Every triangle edge not hidden by a nearer surface (hidden-line removal), diagonals of
    /// flat quads included.
    Visible,
    /// Visible silhouettes (edges between a front- and a back-facing face), boundary and
    /// non-manifold edges, and creases (faces meeting at more than `edge_angle`).
    Features,
}

/// Largest [`RenderOptions::edge_width`] in pixels.
pub const MAX_EDGE_WIDTH: f32 = 256.0;

/// Default [`RenderOptions::edge_angle`] in degrees.
pub const DEFAULT_EDGE_ANGLE: f32 = 30.0;

/// How a reflection or refraction finds the light arriving along its direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Technique {
    /// One lookup of the scene's environment (or the background colour) along the
    /// direction at the first surface: other objects are not seen.
    Environment,
    /// A secondary ray through the scene's BVH (Whitted): the nearest surface it hits is
    /// lit and may reflect and refract again, up to [`RenderOptions::max_depth`].
    Ray,
}

impl FromStr for Technique {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "environment" => Ok(Technique::Environment),
            "ray" => Ok(Technique::Ray),
            _ => Err(RasterError::invalid(format!(
                "unknown technique '{s}'; expected 'environment' or 'ray'"
            ))),
        }
    }
}

/// Largest [`RenderOptions::max_depth`].
pub const MAX_TRACE_DEPTH: u32 = 32;

/// Default [`RenderOptions::max_depth`].
pub const DEFAULT_TRACE_DEPTH: u32 = 5;

/// The sample counts [`RenderOptions::samples`] accepts.
pub const SAMPLE_COUNTS: [u32; 5] = [1, 2, 4, 8, 16];

/// Largest [`RenderOptions::supersample`] factor.
pub const MAX_SUPERSAMPLE: u32 = 8;

impl RenderOptions {
    /// Phong shading, Blinn-Phong specular, black background, no back-face culling (hidden back faces of solids skipped), all cores.
    pub fn new(width: u32, height: u32) -> Self {
        RenderOptions {
            width,
            height,
            shading: ShadingMode::Phong,
            tolerance: None,
            specular: SpecularModel::BlinnPhong,
            background: Vec3::ZERO,
            cull_backfaces: false,
            cull_hidden: true,
            threads: None,
            gouraud: GouraudMethod::Normals,
            interpolation: Interpolation::Perspective,
            baseline_isa: false,
            samples: 1,
            supersample: 1,
            edges: EdgeMode::None,
            edge_color: Vec3::ZERO,
            edge_width: 1.0,
            edge_angle: DEFAULT_EDGE_ANGLE,
            edges_only: false,
            reflections: Technique::Environment,
            refractions: None,
            max_depth: DEFAULT_TRACE_DEPTH,
            environment_background: false,
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
        if !SAMPLE_COUNTS.contains(&self.samples) {
            return Err(RasterError::invalid_field(
                "samples",
                format!("samples must be 1, 2, 4, 8 or 16, got {}", self.samples),
            ));
        }
        let k = self.supersample;
        if !(1..=MAX_SUPERSAMPLE).contains(&k) {
            return Err(RasterError::invalid_field(
                "supersample",
                format!("supersample must be between 1 and {MAX_SUPERSAMPLE}, got {k}"),
            ));
        }
        let (w, h) = (self.width as u64 * k as u64, self.height as u64 * k as u64);
        if w > MAX_IMAGE_SIZE as u64 || h > MAX_IMAGE_SIZE as u64 {
            return Err(RasterError::invalid_field(
                "supersample",
                format!(
                    "supersample {k} renders {w}x{h} pixels, above the limit of \
                     {MAX_IMAGE_SIZE} per side; lower it or the image size"
                ),
            ));
        }
        self.validate_edges()?;
        if let Some(t) = self.tolerance {
            check_tolerance(t)?;
        }
        if self.max_depth > MAX_TRACE_DEPTH {
            return Err(RasterError::invalid_field(
                "max_depth",
                format!(
                    "max_depth must be between 0 and {MAX_TRACE_DEPTH}, got {}",
                    self.max_depth
                ),
            ));
        }
        pool::check_threads(self.threads)
    }

    /// Checks the line options (each error names its field).
    fn validate_edges(&self) -> Result<()> {
        let c = self.edge_color;
        if !c.is_finite() || c.min_element() < 0.0 {
            return Err(RasterError::invalid_field(
                "edge_color",
                format!(
                    "edge_color must be finite and non-negative, got {:?}",
                    c.to_array()
                ),
            ));
        }
        let w = self.edge_width;
        if !(w > 0.0 && w <= MAX_EDGE_WIDTH) {
            return Err(RasterError::invalid_field(
                "edge_width",
                format!("edge_width must be > 0 and at most {MAX_EDGE_WIDTH} pixels, got {w}"),
            ));
        }
        let a = self.edge_angle;
        if !(0.0..=180.0).contains(&a) {
            return Err(RasterError::invalid_field(
                "edge_angle",
                format!("edge_angle must be between 0 and 180 degrees, got {a}"),
            ));
        }
        if self.edges_only && self.edges == EdgeMode::None {
            return Err(RasterError::invalid_field(
                "edges_only",
                "edges_only draws the lines alone, but edges is None; give edges='all', \
                 'visible' or 'features'",
            ));
        }
        Ok(())
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// Where lighting is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadingMode {
    /// One colour per triangle: face normal, lit at the centroid.
    Flat,
    /// Lit at the vertices, colours interpolated (perspective-correct).
    Gouraud,
    /// Normals and positions interpolated, renormalised and lit per pixel.
    Phong,
}

/// Which specular lobe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecularModel {
    /// `max(n·h, 0)^f` with the half vector (OpenGL's fixed function).
    ///
    /// With `f = +inf` (the lectures' perfect mirror) `x^inf` is 1 where the float32 base
    /// `x` is ≥ 1 and 0 elsewhere, the limit of `x^f` as `f` grows: on a rasterized surface
    /// the specular term then vanishes except at a pixel whose base rounds to exactly 1.
    BlinnPhong,
    /// Phong's own `max(r·v, 0)^f`.
    Phong,
    /// Blinn-Phong scaled by `(f + 8) / 8π`, so the highlight's total energy stays about the
    /// same as the shininess changes (sharper highlights get brighter peaks). The classic
    /// form's highlight instead dims as it narrows.
    NormalizedBlinnPhong,
}

/// How Gouraud finds its vertex colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum GouraudMethod {
    /// Lit once per vertex with the vertex normal (the mesh's, or the average of its faces'
    /// unit normals): OpenGL's and the default.
    #[default]
    Normals,
    /// The lectures' "simple method": the mean of the flat-lit colours (face normal, face
    /// centroid) of the faces sharing the vertex, each face counted once, unweighted.
    FaceIntensities,
}

/// How attributes are interpolated across a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Interpolation {
    /// Perspective-correct (weights λ_k/w_k renormalised), as OpenGL: the default.
    #[default]
    Perspective,
    /// Screen-space (affine) weights λ_k, the lectures' scan-line formulas
    /// (`I = I_a + (I_b − I_a)·(x − x_a)/(x_b − x_a)` along a span). Depth output and fog still
    /// use the true eye depth (from the stored z).
    Screen,
}

impl FromStr for GouraudMethod {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "normals" => Ok(GouraudMethod::Normals),
            "face-intensities" | "face_intensities" => Ok(GouraudMethod::FaceIntensities),
            _ => Err(RasterError::invalid(format!(
                "unknown gouraud method '{s}'; expected 'normals' or 'face-intensities'"
            ))),
        }
    }
}

impl FromStr for Interpolation {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "perspective" => Ok(Interpolation::Perspective),
            "screen" => Ok(Interpolation::Screen),
            _ => Err(RasterError::invalid(format!(
                "unknown interpolation '{s}'; expected 'perspective' or 'screen'"
            ))),
        }
    }
}

impl FromStr for EdgeMode {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "none" => Ok(EdgeMode::None),
            "all" => Ok(EdgeMode::All),
            "visible" => Ok(EdgeMode::Visible),
            "features" => Ok(EdgeMode::Features),
            _ => Err(RasterError::invalid_field(
                "edges",
                format!("unknown edges mode '{s}'; expected None, 'all', 'visible' or 'features'"),
            )),
        }
    }
}

impl FromStr for ShadingMode {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "flat" => Ok(ShadingMode::Flat),
            "gouraud" => Ok(ShadingMode::Gouraud),
            "phong" => Ok(ShadingMode::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown shading mode '{s}'; expected 'flat', 'gouraud' or 'phong'"
            ))),
        }
    }
}

impl FromStr for SpecularModel {
    type Err = RasterError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "blinn" | "blinn-phong" | "blinn_phong" => Ok(SpecularModel::BlinnPhong),
            "blinn-normalized" | "blinn_normalized" | "normalized-blinn" => {
                Ok(SpecularModel::NormalizedBlinnPhong)
            }
            "phong" => Ok(SpecularModel::Phong),
            _ => Err(RasterError::invalid(format!(
                "unknown specular model '{s}'; expected 'blinn', 'phong' or 'blinn-normalized'"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names() {
        assert_eq!("Phong".parse::<ShadingMode>().unwrap(), ShadingMode::Phong);
        assert!("toon".parse::<ShadingMode>().is_err());
        assert_eq!(
            "face-intensities".parse::<GouraudMethod>().unwrap(),
            GouraudMethod::FaceIntensities
        );
        assert_eq!(
            "Screen".parse::<Interpolation>().unwrap(),
            Interpolation::Screen
        );
        assert!("affine".parse::<Interpolation>().is_err());
        assert_eq!(
            "blinn".parse::<SpecularModel>().unwrap(),
            SpecularModel::BlinnPhong
        );
    }
}
