//! Look-at cameras with perspective or orthographic projection.
//!
//! Conventions (OpenGL): right-handed world, the camera looks down −z in eye space, `fov_y` is
//! the full vertical angle in degrees and the aspect ratio is width / height. Depth is stored
//! reversed (near → 1, far → 0) in a [0, 1] clip range, which spreads f32 precision evenly.

use glam::{DMat4, DVec3, DVec4};

use crate::error::{RasterError, Result};

/// How eye space is projected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view in degrees.
    Perspective {
        /// Full vertical angle, degrees, in (0, 180).
        fov_y: f64,
    },
    /// Orthographic with a view volume `height` world units tall (width = height · aspect).
    Orthographic {
        /// Vertical extent of the view volume, world units, > 0.
        height: f64,
    },
}

/// A camera: where it is, where it looks, and how it projects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    projection: Projection,
    near: f64,
    far: f64,
}

fn check_vec(name: &'static str, v: DVec3) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(RasterError::invalid_field(
            name,
            format!("camera {name} must be finite, got {:?}", v.to_array()),
        ))
    }
}

impl Camera {
    /// A perspective camera at `eye` looking at `target`, with `up` giving the roll.
    ///
    /// Errors when a value is non-finite, `eye == target`, `up` is parallel to the view
    /// direction, `fov_y` is outside (0, 180) or not `0 < near < far`.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y: f64,
        near: f64,
        far: f64,
    ) -> Result<Self> {
        if !(fov_y.is_finite() && fov_y > 0.0 && fov_y < 180.0) {
            return Err(RasterError::invalid_field(
                "fov_y",
                format!("fov_y must be in (0, 180) degrees, got {fov_y}"),
            ));
        }
        if !(near.is_finite() && far.is_finite() && near > 0.0 && far > near) {
            let field = if near.is_finite() && near > 0.0 {
                "far"
            } else {
                "near"
            };
            return Err(RasterError::invalid_field(
                field,
                format!(
                "a perspective camera needs 0 < near < far (finite), got near={near}, far={far}"
            ),
            ));
        }
        Self::build(
            eye,
            target,
            up,
            Projection::Perspective { fov_y },
            near,
            far,
        )
    }

    /// An orthographic camera; `height` is the vertical extent of the view in world units.
    ///
    /// Errors as [`Camera::look_at`], and when `height <= 0` or not `near < far`.
    pub fn orthographic(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        height: f64,
        near: f64,
        far: f64,
    ) -> Result<Self> {
        if !(height.is_finite() && height > 0.0) {
            return Err(RasterError::invalid_field(
                "height",
                format!("orthographic height must be > 0, got {height}"),
            ));
        }
        if !(near.is_finite() && far.is_finite() && far > near) {
            let field = if near.is_finite() { "far" } else { "near" };
            return Err(RasterError::invalid_field(
                field,
                format!(
                    "an orthographic camera needs near < far (finite), got near={near}, far={far}"
                ),
            ));
        }
        Self::build(
            eye,
            target,
            up,
            Projection::Orthographic { height },
            near,
            far,
        )
    }

    fn build(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        projection: Projection,
        near: f64,
        far: f64,
    ) -> Result<Self> {
        check_vec("eye", eye)?;
        check_vec("target", target)?;
        check_vec("up", up)?;
        let forward = target - eye;
        if forward.length_squared() == 0.0 || !forward.length_squared().is_normal() {
            return Err(RasterError::invalid_field(
                "target",
                "camera eye and target must be distinct points",
            ));
        }
        let side = forward.normalize().cross(up);
        if up.length_squared() == 0.0 || side.length() < 1e-9 * up.length() {
            return Err(RasterError::invalid_field(
                "up",
                format!(
                    "camera up {:?} must not be zero or parallel to the view direction",
                    up.to_array()
                ),
            ));
        }
        Ok(Camera {
            eye,
            target,
            up,
            projection,
            near,
            far,
        })
    }

    /// The eye position in world space.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The point looked at.
    pub fn target(&self) -> DVec3 {
        self.target
    }

    /// The up hint.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The projection kind.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// Near plane distance along the view axis.
    pub fn near(&self) -> f64 {
        self.near
    }

    /// Far plane distance along the view axis.
    pub fn far(&self) -> f64 {
        self.far
    }

    /// World → eye (OpenGL `gluLookAt`).
    pub fn view_matrix(&self) -> DMat4 {
        DMat4::look_at_rh(self.eye, self.target, self.up)
    }

    /// Eye → clip, reversed-Z with a [0, 1] depth range: `z_ndc` is 1 at `near`, 0 at `far`.
    pub fn projection_matrix(&self, aspect: f64) -> DMat4 {
        let (n, f) = (self.near, self.far);
        match self.projection {
            Projection::Perspective { fov_y } => {
                let s = 1.0 / (fov_y.to_radians() * 0.5).tan();
                DMat4::from_cols(
                    DVec4::new(s / aspect, 0.0, 0.0, 0.0),
                    DVec4::new(0.0, s, 0.0, 0.0),
                    DVec4::new(0.0, 0.0, n / (f - n), -1.0),
                    DVec4::new(0.0, 0.0, n * f / (f - n), 0.0),
                )
            }
            Projection::Orthographic { height } => DMat4::from_cols(
                DVec4::new(2.0 / (height * aspect), 0.0, 0.0, 0.0),
                DVec4::new(0.0, 2.0 / height, 0.0, 0.0),
                DVec4::new(0.0, 0.0, 1.0 / (f - n), 0.0),
                DVec4::new(0.0, 0.0, f / (f - n), 1.0),
            ),
        }
    }

    /// Per-render constants turning a pixel centre and its eye depth into the Euclidean
    /// distance from the eye (for fog): see [`EyeDistance::at`].
    pub(crate) fn eye_distance(&self, width: u32, height: u32) -> EyeDistance {
        let aspect = width as f64 / height as f64;
        let (sx, sy, ortho) = match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (fov_y.to_radians() * 0.5).tan();
                (t * aspect, t, false)
            }
            Projection::Orthographic { height: h } => (h * aspect * 0.5, h * 0.5, true),
        };
        EyeDistance {
            sx: sx as f32,
            sy: sy as f32,
            ortho,
            inv_w: 2.0 / width as f32,
            inv_h: 2.0 / height as f32,
        }
    }

    /// Eye-space depth from the stored reversed-Z value alone (for screen-space
    /// interpolation, whose weights carry no 1/w): perspective inverts
    /// `z = n(f − d) / ((f − n)·d)`, i.e. `d = n·f / (z·(f − n) + n)`; orthographic as
    /// [`Camera::eye_depth`].
    pub(crate) fn eye_depth_from_z(&self, z_ndc: f32) -> f32 {
        let (n, f, z) = (self.near, self.far, z_ndc as f64);
        match self.projection {
            Projection::Perspective { .. } => (n * f / (z * (f - n) + n)) as f32,
            Projection::Orthographic { .. } => self.eye_depth(z_ndc, 1.0),
        }
    }

    /// Eye-space depth (distance along the view axis) from a stored reversed-Z value and,
    /// for perspective, the interpolated 1/w.
    pub(crate) fn eye_depth(&self, z_ndc: f32, inv_w: f32) -> f32 {
        match self.projection {
            Projection::Perspective { .. } => 1.0 / inv_w,
            Projection::Orthographic { .. } => {
                (self.far - z_ndc as f64 * (self.far - self.near)) as f32
            }
        }
    }
}

/// See [`Camera::eye_distance`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct EyeDistance {
    sx: f32,
    sy: f32,
    ortho: bool,
    inv_w: f32,
    inv_h: f32,
}

impl EyeDistance {
    /// Distance from the eye to the point seen at pixel (x, y) at eye depth `depth`.
    #[inline]
    pub fn at(&self, x: usize, y: usize, depth: f32) -> f32 {
        let nx = (x as f32 + 0.5) * self.inv_w - 1.0;
        let ny = 1.0 - (y as f32 + 0.5) * self.inv_h;
        let (ex, ey) = if self.ortho {
            (nx * self.sx, ny * self.sy)
        } else {
            (nx * self.sx * depth, ny * self.sy * depth)
        };
        (ex * ex + ey * ey + depth * depth).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::look_at(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            60.0,
            0.5,
            50.0,
        )
        .unwrap()
    }

    #[test]
    fn eye_depth_from_z_inverts_the_projection() {
        let c = cam();
        let vp = c.projection_matrix(1.5) * c.view_matrix();
        for d in [c.near(), 0.7, 1.0, 3.3, 20.0, c.far()] {
            let clip = vp * DVec4::new(0.0, 0.0, 5.0 - d, 1.0);
            let z = (clip.z / clip.w) as f32;
            let got = c.eye_depth_from_z(z) as f64;
            let want = c.eye_depth(z, (1.0 / clip.w) as f32) as f64;
            assert!((got - d).abs() <= 1e-5 * d * (1.0 + d), "d {d}: {got}");
            assert!(
                (got - want).abs() <= 1e-5 * d * (1.0 + d),
                "d {d}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn reversed_z_maps_near_to_one_far_to_zero() {
        let c = cam();
        let vp = c.projection_matrix(1.5) * c.view_matrix();
        let at = |d: f64| {
            let clip = vp * DVec4::new(0.0, 0.0, 5.0 - d, 1.0);
            (clip.z / clip.w, clip.w)
        };
        let (zn, wn) = at(0.5);
        let (zf, wf) = at(50.0);
        assert!((zn - 1.0).abs() < 1e-12 && (wn - 0.5).abs() < 1e-12);
        assert!(zf.abs() < 1e-12 && (wf - 50.0).abs() < 1e-12);
    }

    #[test]
    fn orthographic_depth_round_trips() {
        let c = Camera::orthographic(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            2.0,
            1.0,
            9.0,
        )
        .unwrap();
        let vp = c.projection_matrix(1.0) * c.view_matrix();
        let clip = vp * DVec4::new(0.3, 0.9, 1.0, 1.0); // eye depth 4
        assert!((clip.y - 0.9).abs() < 1e-12);
        assert!((c.eye_depth(clip.z as f32, 1.0) - 4.0).abs() < 1e-5);
    }

    #[test]
    fn rejects_bad_cameras() {
        let z = DVec3::ZERO;
        assert!(Camera::look_at(z, z, DVec3::Y, 45.0, 0.1, 10.0).is_err());
        assert!(Camera::look_at(DVec3::Z, z, DVec3::Z, 45.0, 0.1, 10.0).is_err());
        assert!(Camera::look_at(DVec3::Z, z, DVec3::Y, 180.0, 0.1, 10.0).is_err());
        assert!(Camera::look_at(DVec3::Z, z, DVec3::Y, 45.0, 0.0, 10.0).is_err());
        assert!(Camera::look_at(DVec3::Z, z, DVec3::Y, 45.0, 1.0, 1.0).is_err());
        assert!(
            Camera::look_at(DVec3::new(f64::NAN, 0.0, 0.0), z, DVec3::Y, 45.0, 0.1, 1.0).is_err()
        );
        assert!(Camera::orthographic(DVec3::Z, z, DVec3::Y, 0.0, 0.1, 10.0).is_err());
    }
}
