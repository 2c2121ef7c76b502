//! Area lights: a rectangle or disk modelled, as in the classic local illumination model, by a
//! collection of point sources.

use glam::Vec3;

use super::colors::SplitColors;
use super::point::PointLight;
use super::shadow::Shadows;
use crate::error::{RasterError, Result};

/// Largest `samples` per side: 64² = 4096 point sources, already far past any useful
/// accuracy for a local model, and a bound on per-pixel work.
pub const MAX_AREA_SAMPLES: u32 = 64;

/// Outline of an [`AreaLight`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AreaShape {
    /// The parallelogram `position + s·u + t·v`, `s, t ∈ [−½, ½]` (a rectangle when `u ⟂ v`).
    Rectangle,
    /// The ellipse inscribed in that parallelogram (a disk of diameter `|u|` when `u ⟂ v`
    /// and `|u| = |v|`).
    Disk,
}

/// A distributed light source: `samples²` point lights spread evenly over a rectangle or
/// disk, each carrying `1/samples²` of the colour and ambient, so the total emitted light
/// does not depend on the sample count. `samples` is the speed/accuracy knob: per-pixel cost
/// grows linearly with the number of points ([`AreaLight::n_points`]).
///
/// Rectangles put one point at the centre of each cell of a `samples × samples` grid; disks
/// use a golden-angle (Vogel) spiral of `samples²` points at equal-area radii, which covers
/// the disk evenly without a grid's rings of identical radii.
///
/// Each point is an OpenGL point light with the light's attenuation. A two-sided light
/// (default) emits equally in every direction, as the lecture model's point sources do; a
/// one-sided light emits only in front of the surface (along `u × v`), as a Lambertian
/// emitter: each point becomes a spot light with cutoff 90° and exponent 1, i.e. scaled by
/// the cosine between the normal and the direction to the shaded point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    position: Vec3,
    u: Vec3,
    v: Vec3,
    shape: AreaShape,
    samples: u32,
    one_sided: bool,
    /// RGB colour (diffuse and specular intensity before `intensity`), for the whole light.
    pub color: Vec3,
    /// Scalar multiplier of `color`.
    pub intensity: f32,
    /// The light's own ambient colour, black by default; split over the points and
    /// attenuated like the rest.
    pub ambient: Vec3,
    /// Distance attenuation `(kc, kl, kq)` applied to each point with its own distance.
    pub attenuation: [f32; 3],
    /// Diffuse and specular colours when they differ; see [`SplitColors`].
    pub split: SplitColors,
    /// Whether and how the light casts shadows (off by default).
    pub shadows: Shadows,
}

fn finite_vec(v: Vec3, what: &'static str) -> Result<Vec3> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(RasterError::invalid_field(
            what,
            format!("area light {what} must be finite, got {:?}", v.to_array()),
        ))
    }
}

impl AreaLight {
    /// An area light centred at `position`, spanned by the edge vectors `u` and `v` (finite,
    /// non-zero, not parallel), with `samples` points per side (1 to
    /// [`MAX_AREA_SAMPLES`]), white, intensity 1, two-sided, no attenuation.
    pub fn new(position: Vec3, u: Vec3, v: Vec3, shape: AreaShape, samples: u32) -> Result<Self> {
        let position = finite_vec(position, "position")?;
        let u = finite_vec(u, "u")?;
        let v = finite_vec(v, "v")?;
        // In f64: for f32 edges far from 1 (1e30, 1e-30) the f32 cross product and lengths
        // overflow or underflow (fuzzing found an accepted light whose normal was zero).
        let (ud, vd) = (u.as_dvec3(), v.as_dvec3());
        let n = ud.cross(vd);
        // Relative test: parallel or zero edges leave no area to sample (or no normal).
        // (f64 holds every product of finite f32 values: no NaN here.)
        if n.length() <= 1e-6 * ud.length() * vd.length() {
            return Err(RasterError::invalid_field(
                "v",
                format!(
                    "area light edges u={:?} and v={:?} must be non-zero and not parallel",
                    u.to_array(),
                    v.to_array()
                ),
            ));
        }
        if !(1..=MAX_AREA_SAMPLES).contains(&samples) {
            return Err(RasterError::invalid_field("samples", format!(
                "area light samples must be between 1 and {MAX_AREA_SAMPLES} per side, got {samples}"
            )));
        }
        Ok(AreaLight {
            position,
            u,
            v,
            shape,
            samples,
            one_sided: false,
            color: Vec3::ONE,
            intensity: 1.0,
            ambient: Vec3::ZERO,
            attenuation: [1.0, 0.0, 0.0],
            split: SplitColors::default(),
            shadows: Shadows::Off,
        })
    }

    /// The same light with colour `color` and `intensity` (checked like a point light's).
    pub fn with_color(self, color: Vec3, intensity: f32) -> Result<Self> {
        let p = PointLight::new(self.position, color, intensity)?;
        Ok(AreaLight {
            color: p.color,
            intensity: p.intensity,
            ..self
        })
    }

    /// The same light casting shadows as `shadows` says.
    pub fn with_shadows(mut self, shadows: Shadows) -> Self {
        self.shadows = shadows;
        self
    }
    /// The same light with its own ambient colour (finite, ≥ 0).
    pub fn with_ambient(self, ambient: Vec3) -> Result<Self> {
        let p = PointLight::new(self.position, Vec3::ONE, 1.0)?.with_ambient(ambient)?;
        Ok(AreaLight {
            ambient: p.ambient,
            ..self
        })
    }

    /// The same light with distance attenuation `(kc, kl, kq)` (checked like a point
    /// light's).
    pub fn with_attenuation(self, kc: f32, kl: f32, kq: f32) -> Result<Self> {
        let p = PointLight::new(self.position, Vec3::ONE, 1.0)?.with_attenuation(kc, kl, kq)?;
        Ok(AreaLight {
            attenuation: p.attenuation,
            ..self
        })
    }

    /// The same light with its own diffuse and/or specular colour (see [`SplitColors`]).
    pub fn with_split_colors(self, diffuse: Option<Vec3>, specular: Option<Vec3>) -> Result<Self> {
        Ok(AreaLight {
            split: SplitColors::new(diffuse, specular)?,
            ..self
        })
    }

    /// The same light emitting only on the side `u × v` points to (`true`) or on both sides.
    pub fn with_one_sided(self, one_sided: bool) -> Self {
        AreaLight { one_sided, ..self }
    }

    /// Centre.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// First edge vector.
    pub fn u(&self) -> Vec3 {
        self.u
    }

    /// Second edge vector.
    pub fn v(&self) -> Vec3 {
        self.v
    }

    /// Unit normal `u × v / |u × v|` (the emitting side of a one-sided light).
    pub fn normal(&self) -> Vec3 {
        // f64: the f32 cross product of large or tiny edges overflows or underflows.
        self.u
            .as_dvec3()
            .cross(self.v.as_dvec3())
            .normalize()
            .as_vec3()
    }

    /// Outline.
    pub fn shape(&self) -> AreaShape {
        self.shape
    }

    /// Points per side.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Number of point sources, `samples²`.
    pub fn n_points(&self) -> usize {
        (self.samples * self.samples) as usize
    }

    /// Whether only the front side (along [`AreaLight::normal`]) emits.
    pub fn one_sided(&self) -> bool {
        self.one_sided
    }

    /// The sample positions, in a fixed order (row-major grid cells, or spiral order).
    pub fn points(&self) -> Vec<Vec3> {
        let n = self.samples as usize;
        let total = n * n;
        // Positions in f64, so large lights far from the origin place points as exactly as
        // f32 can hold them.
        let (c, u, v) = (
            self.position.as_dvec3(),
            self.u.as_dvec3(),
            self.v.as_dvec3(),
        );
        match self.shape {
            AreaShape::Rectangle => (0..total)
                .map(|k| {
                    let (i, j) = (k % n, k / n);
                    let s = (i as f64 + 0.5) / n as f64 - 0.5;
                    let t = (j as f64 + 0.5) / n as f64 - 0.5;
                    (c + s * u + t * v).as_vec3()
                })
                .collect(),
            AreaShape::Disk => {
                let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
                (0..total)
                    .map(|k| {
                        // Radius sqrt((k + ½)/N) gives each point an equal share of area.
                        let r = ((k as f64 + 0.5) / total as f64).sqrt();
                        let a = k as f64 * golden;
                        (c + 0.5 * r * (a.cos() * u + a.sin() * v)).as_vec3()
                    })
                    .collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(samples: u32) -> AreaLight {
        AreaLight::new(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            AreaShape::Rectangle,
            samples,
        )
        .unwrap()
    }

    #[test]
    fn rejects_bad_geometry_and_counts() {
        let (p, x, z) = (Vec3::ZERO, Vec3::X, Vec3::Z);
        let r = AreaShape::Rectangle;
        assert!(AreaLight::new(Vec3::NAN, x, z, r, 2).is_err());
        assert!(AreaLight::new(p, Vec3::ZERO, z, r, 2).is_err());
        assert!(AreaLight::new(p, x, 3.0 * x, r, 2).is_err());
        assert!(AreaLight::new(p, x, Vec3::INFINITY, r, 2).is_err());
        assert!(AreaLight::new(p, x, z, r, 0).is_err());
        assert!(AreaLight::new(p, x, z, r, MAX_AREA_SAMPLES + 1).is_err());
        let e = AreaLight::new(p, x, x, r, 2).unwrap_err().to_string();
        assert!(e.contains("not parallel"), "{e}");
        let l = AreaLight::new(p, x, z, r, 2).unwrap();
        assert!(l.with_color(Vec3::ONE, -1.0).is_err());
        assert!(l.with_attenuation(0.0, 0.0, 0.0).is_err());
        assert!(l.with_ambient(-Vec3::ONE).is_err());
    }

    #[test]
    fn rectangle_points_are_cell_centres() {
        let pts = rect(2).points();
        let want = [
            Vec3::new(-0.5, 2.0, -0.25),
            Vec3::new(0.5, 2.0, -0.25),
            Vec3::new(-0.5, 2.0, 0.25),
            Vec3::new(0.5, 2.0, 0.25),
        ];
        assert_eq!(pts, want);
        assert_eq!(rect(1).points(), vec![Vec3::new(0.0, 2.0, 0.0)]);
        // Centroid is the centre for any count.
        for n in 1..=7 {
            let pts = rect(n).points();
            let mean = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
            assert!(
                (mean - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6,
                "{n}: {mean}"
            );
        }
    }

    #[test]
    fn disk_points_lie_inside_and_cover_evenly() {
        let d = AreaLight::new(
            Vec3::ZERO,
            2.0 * Vec3::X,
            2.0 * Vec3::Y,
            AreaShape::Disk,
            16,
        )
        .unwrap();
        let pts = d.points();
        assert_eq!(pts.len(), 256);
        assert!(pts.iter().all(|p| p.z == 0.0 && p.length() <= 1.0 + 1e-6));
        // Equal-area radii: half the points within radius sqrt(1/2).
        let inner = pts.iter().filter(|p| p.length() < 0.5f32.sqrt()).count();
        assert_eq!(inner, 128);
        let mean = pts.iter().copied().sum::<Vec3>() / 256.0;
        assert!(mean.length() < 0.01, "{mean}");
    }
}
