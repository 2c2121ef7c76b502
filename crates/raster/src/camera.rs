//! Look-at cameras with perspective, pinhole (pixel intrinsics) or orthographic projection.
//!
//! Conventions (OpenGL): right-handed world, the camera looks down −z in eye space, `fov_y` is
//! the full vertical angle in degrees and the aspect ratio is width / height. Depth is stored
//! reversed (near → 1, far → 0) in a [0, 1] clip range, which spreads f32 precision evenly.
//!
//! A pinhole camera ([`Intrinsics`]) uses the computer-vision convention instead for its
//! image: x right, y down, pixel (x, y) covering [x, x + 1) × [y, y + 1) with its centre at
//! (x + 0.5, y + 0.5), and a point at eye-space (X, −Y, −Z) (Z > 0 in front) seen at
//! `u = (fx·X + skew·Y + cx·Z) / Z`, `v = (fy·Y + cy·Z) / Z` (Y pointing down).

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
    /// Perspective given by pinhole intrinsics for a reference image size; see
    /// [`Intrinsics`] for how other render sizes are handled.
    Pinhole(Intrinsics),
}

/// Pinhole intrinsics `K = [[fx, skew, cx], [0, fy, cy], [0, 0, 1]]` in pixels of a
/// `width` × `height` reference image (computer-vision convention: x right, y down, pixel
/// centres at half-integers; see the module docs).
///
/// Rendering at another size scales the intrinsics by the size ratio: `fx`, `skew` and `cx`
/// by `render_width / width`, `fy` and `cy` by `render_height / height`. The same
/// normalised image is resampled, so a render with another aspect ratio stretches it
/// (the pixel aspect `fx / fy` changes); render at the reference size, or a multiple of it,
/// to keep K's meaning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics {
    /// Focal length along x, pixels, > 0.
    pub fx: f64,
    /// Focal length along y, pixels, > 0.
    pub fy: f64,
    /// Principal point x, pixels (any finite value; need not be inside the image).
    pub cx: f64,
    /// Principal point y, pixels, downwards.
    pub cy: f64,
    /// Skew `K[0][1]`, pixels (0 for rectangular pixels).
    pub skew: f64,
    /// Reference image width, pixels, ≥ 1.
    pub width: u32,
    /// Reference image height, pixels, ≥ 1.
    pub height: u32,
}

impl Intrinsics {
    /// Checks every value: finite, `fx, fy > 0`, `width, height ≥ 1`; errors name the field.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("fx", self.fx),
            ("fy", self.fy),
            ("cx", self.cx),
            ("cy", self.cy),
            ("skew", self.skew),
        ] {
            if !v.is_finite() {
                return Err(RasterError::invalid_field(
                    name,
                    format!("camera intrinsic {name} must be finite, got {v}"),
                ));
            }
        }
        for (name, v) in [("fx", self.fx), ("fy", self.fy)] {
            if v <= 0.0 {
                return Err(RasterError::invalid_field(
                    name,
                    format!("focal length {name} must be > 0 pixels, got {v}"),
                ));
            }
        }
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 {
                return Err(RasterError::invalid_field(
                    name,
                    format!("the intrinsics' reference image {name} must be >= 1 pixel, got 0"),
                ));
            }
        }
        Ok(())
    }

    /// These intrinsics for a `width` × `height` render (scaled by the size ratio; the
    /// sizes are those of a valid render, ≥ 1, and are not checked here).
    pub fn scaled_to(&self, width: u32, height: u32) -> Intrinsics {
        let sx = width as f64 / self.width as f64;
        let sy = height as f64 / self.height as f64;
        Intrinsics {
            fx: self.fx * sx,
            fy: self.fy * sy,
            cx: self.cx * sx,
            cy: self.cy * sy,
            skew: self.skew * sx,
            width,
            height,
        }
    }

    /// Eye-space `(x/d, y/d)` of the ray through normalised device coordinates (nx, ny),
    /// as `x/d = ax·nx + bx·ny + ox`, `y/d = ay·ny + oy` (d = −z, the eye depth):
    /// `(ax, bx, ox, ay, oy)`. Independent of the render size (see [`Intrinsics`]).
    fn ndc_to_ray(&self) -> (f64, f64, f64, f64, f64) {
        let (w, h) = (self.width as f64, self.height as f64);
        let ay = h / (2.0 * self.fy);
        let oy = (2.0 * self.cy - h) / (2.0 * self.fy);
        // x/d = (u − cx + skew·(y/d)) / fx with u = (nx + 1)·w/2 and y/d = −(v − cy)/fy.
        let k = self.skew / self.fx;
        let ax = w / (2.0 * self.fx);
        let ox = (w - 2.0 * self.cx) / (2.0 * self.fx) + k * oy;
        (ax, k * ay, ox, ay, oy)
    }
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

fn check_perspective_planes(near: f64, far: f64) -> Result<()> {
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
    Ok(())
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
        check_perspective_planes(near, far)?;
        Self::build(
            eye,
            target,
            up,
            Projection::Perspective { fov_y },
            near,
            far,
        )
    }

    /// A pinhole camera at `eye` looking at `target` (the optical axis; it is seen at the
    /// principal point), `up` giving the roll, projecting with the pixel intrinsics `k`.
    ///
    /// Errors as [`Camera::look_at`], and when an intrinsic is invalid
    /// ([`Intrinsics::validate`]).
    pub fn from_intrinsics(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        k: Intrinsics,
        near: f64,
        far: f64,
    ) -> Result<Self> {
        k.validate()?;
        check_perspective_planes(near, far)?;
        Self::build(eye, target, up, Projection::Pinhole(k), near, far)
    }

    /// This camera with other near and far planes, validated as its constructor does.
    pub fn with_planes(&self, near: f64, far: f64) -> Result<Self> {
        let (e, t, u) = (self.eye, self.target, self.up);
        match self.projection {
            Projection::Perspective { fov_y } => Self::look_at(e, t, u, fov_y, near, far),
            Projection::Orthographic { height } => Self::orthographic(e, t, u, height, near, far),
            Projection::Pinhole(k) => Self::from_intrinsics(e, t, u, k, near, far),
        }
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
    ///
    /// A pinhole camera ignores `aspect`: its intrinsics scale with the render size (see
    /// [`Intrinsics`]), which leaves this matrix the same for every size.
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
            Projection::Pinhole(k) => {
                // clip = (ndc · d, d) with d = −z and ndc_x = 2u/w − 1, ndc_y = 1 − 2v/h.
                let (w, h) = (k.width as f64, k.height as f64);
                DMat4::from_cols(
                    DVec4::new(2.0 * k.fx / w, 0.0, 0.0, 0.0),
                    DVec4::new(-2.0 * k.skew / w, 2.0 * k.fy / h, 0.0, 0.0),
                    DVec4::new(
                        1.0 - 2.0 * k.cx / w,
                        2.0 * k.cy / h - 1.0,
                        n / (f - n),
                        -1.0,
                    ),
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
        let (sx, kx, ox, sy, oy, ortho) = match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (fov_y.to_radians() * 0.5).tan();
                (t * aspect, 0.0, 0.0, t, 0.0, false)
            }
            Projection::Pinhole(k) => {
                let (ax, bx, ox, ay, oy) = k.ndc_to_ray();
                (ax, bx, ox, ay, oy, false)
            }
            Projection::Orthographic { height: h } => {
                (h * aspect * 0.5, 0.0, 0.0, h * 0.5, 0.0, true)
            }
        };
        EyeDistance {
            sx: sx as f32,
            kx: kx as f32,
            ox: ox as f32,
            sy: sy as f32,
            oy: oy as f32,
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
            Projection::Perspective { .. } | Projection::Pinhole(_) => {
                self.within_planes((n * f / (z * (f - n) + n)) as f32)
            }
            Projection::Orthographic { .. } => self.eye_depth(z_ndc, 1.0),
        }
    }

    /// Eye-space depth (distance along the view axis) from a stored reversed-Z value and,
    /// for perspective, the interpolated 1/w; within the near and far planes
    /// ([`Camera::within_planes`]).
    pub(crate) fn eye_depth(&self, z_ndc: f32, inv_w: f32) -> f32 {
        self.within_planes(match self.projection {
            Projection::Perspective { .. } | Projection::Pinhole(_) => 1.0 / inv_w,
            Projection::Orthographic { .. } => {
                (self.far - z_ndc as f64 * (self.far - self.near)) as f32
            }
        })
    }

    /// `depth` clamped to `[near, far]` (a NaN, which no valid input makes, becomes `near`).
    /// Every drawn surface lies between the planes (triangles are clipped to them), but a
    /// covered pixel centre can lie a snap (up to 1/512 pixel) outside its triangle, where
    /// the interpolated depth extrapolates past a triangle cut at a plane: with huge pixels
    /// (a 1 × 11 image at a 112° field of view) 0.3 % before the near plane was seen.
    #[inline(always)]
    pub(crate) fn within_planes(&self, depth: f32) -> f32 {
        depth.max(self.near as f32).min(self.far as f32)
    }
}

/// See [`Camera::eye_distance`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct EyeDistance {
    // Eye x / d = sx·nx + kx·ny + ox and y / d = sy·ny + oy (perspective; times 1 for
    // orthographic). kx, ox, oy are 0 but for an off-centre or skewed pinhole camera, and
    // adding those zeros leaves the centred cameras' distances bit-identical.
    sx: f32,
    kx: f32,
    ox: f32,
    sy: f32,
    oy: f32,
    ortho: bool,
    inv_w: f32,
    inv_h: f32,
}

impl EyeDistance {
    /// Distance from the eye to the point seen at pixel (x, y) at eye depth `depth`.
    #[inline]
    pub fn at(&self, x: usize, y: usize, depth: f32) -> f32 {
        if self.centred() {
            self.at_with::<false>(x, y, depth)
        } else {
            self.at_with::<true>(x, y, depth)
        }
    }

    /// Whether the rays are those of a centred, unskewed frustum (kx = ox = oy = 0), whose
    /// distances need no off-centre terms: [`EyeDistance::at_with::<false>`] then equals
    /// `at_with::<true>` bit for bit and costs three fewer operations per pixel.
    #[inline(always)]
    pub fn centred(&self) -> bool {
        self.kx == 0.0 && self.ox == 0.0 && self.oy == 0.0
    }

    /// [`EyeDistance::at`] with (`OFF_CENTRE`) or without the off-centre terms.
    #[inline(always)]
    pub fn at_with<const OFF_CENTRE: bool>(&self, x: usize, y: usize, depth: f32) -> f32 {
        let nx = (x as f32 + 0.5) * self.inv_w - 1.0;
        let ny = 1.0 - (y as f32 + 0.5) * self.inv_h;
        let (rx, ry) = if OFF_CENTRE {
            (
                nx * self.sx + ny * self.kx + self.ox,
                ny * self.sy + self.oy,
            )
        } else {
            (nx * self.sx, ny * self.sy)
        };
        let (ex, ey) = if self.ortho {
            (rx, ry)
        } else {
            (rx * depth, ry * depth)
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
    fn eye_depth_is_clamped_to_the_planes() {
        let c = cam();
        let (n, f) = (c.near() as f32, c.far() as f32);
        // Perspective: 1/w extrapolated past either plane.
        assert_eq!(c.eye_depth(0.0, 1.0 / (0.99 * n)), n);
        assert_eq!(c.eye_depth(0.0, 1.0 / (1.01 * f)), f);
        assert_eq!(c.eye_depth(0.0, 0.25), 4.0);
        // Reversed-Z beyond [0, 1], as the screen-space path reads it.
        assert_eq!(c.eye_depth_from_z(1.001), n);
        assert_eq!(c.eye_depth_from_z(-0.001), f);
        let o = Camera::orthographic(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            2.0,
            0.5,
            50.0,
        )
        .unwrap();
        assert_eq!(o.eye_depth(1.01, 1.0), 0.5);
        assert_eq!(o.eye_depth(-0.01, 1.0), 50.0);
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

    /// An off-centre, skewed, non-square pinhole camera for a 64 × 48 image.
    fn pinhole() -> (Camera, Intrinsics) {
        let k = Intrinsics {
            fx: 70.0,
            fy: 55.0,
            cx: 40.5,
            cy: 19.25,
            skew: 6.0,
            width: 64,
            height: 48,
        };
        let c = Camera::from_intrinsics(
            DVec3::new(0.3, 0.8, 5.0),
            DVec3::new(-0.2, 0.1, 0.0),
            DVec3::Y,
            k,
            0.5,
            50.0,
        )
        .unwrap();
        (c, k)
    }

    /// Where K puts world point `p` for camera `c` (float64, computer-vision frame).
    fn k_pixel(c: &Camera, k: &Intrinsics, p: DVec3) -> (f64, f64) {
        let e = c.view_matrix().transform_point3(p);
        let (x, y, z) = (e.x, -e.y, -e.z);
        (
            (k.fx * x + k.skew * y + k.cx * z) / z,
            (k.fy * y + k.cy * z) / z,
        )
    }

    /// Where the pipeline's viewport puts clip-space `clip` in a `w` × `h` image.
    fn window(clip: DVec4, w: f64, h: f64) -> (f64, f64) {
        (
            (clip.x / clip.w + 1.0) * 0.5 * w,
            (1.0 - clip.y / clip.w) * 0.5 * h,
        )
    }

    #[test]
    fn pinhole_projects_where_k_says_at_any_render_size() {
        let (c, k) = pinhole();
        let vp = c.projection_matrix(1.0) * c.view_matrix();
        for p in [
            DVec3::ZERO,
            DVec3::new(1.0, -0.5, 0.7),
            DVec3::new(-2.0, 1.5, -3.0),
            c.target(),
        ] {
            let (u, v) = k_pixel(&c, &k, p);
            let (sx, sy) = window(vp * p.extend(1.0), 64.0, 48.0);
            assert!((sx - u).abs() < 1e-9 && (sy - v).abs() < 1e-9, "{p}");
            // At 3× the size (and at another aspect) the scaled intrinsics hold.
            let k2 = k.scaled_to(192, 96);
            let (u2, v2) = k_pixel(&c, &k2, p);
            let (sx2, sy2) = window(vp * p.extend(1.0), 192.0, 96.0);
            assert!((sx2 - u2).abs() < 1e-9 && (sy2 - v2).abs() < 1e-9, "{p}");
        }
        // The target is on the optical axis: it is seen at the principal point.
        let (u, v) = k_pixel(&c, &k, c.target());
        assert!((u - k.cx).abs() < 1e-9 && (v - k.cy).abs() < 1e-9);
    }

    #[test]
    fn pinhole_keeps_reversed_z_and_eye_depth() {
        let (c, _) = pinhole();
        let m = c.projection_matrix(1.0);
        for (d, want) in [(0.5, 1.0), (50.0, 0.0)] {
            let clip = m * DVec4::new(0.4, -0.3, -d, 1.0);
            assert!((clip.z / clip.w - want).abs() < 1e-12 && (clip.w - d).abs() < 1e-12);
            let depth = c.eye_depth((clip.z / clip.w) as f32, (1.0 / clip.w) as f32);
            assert!((depth as f64 - d).abs() < 1e-5 * d);
        }
    }

    #[test]
    fn centred_square_pinhole_is_the_perspective_camera() {
        let (w, h) = (64u32, 48u32);
        let c = cam();
        let f = h as f64 / (2.0 * 30f64.to_radians().tan());
        let k = Intrinsics {
            fx: f,
            fy: f,
            cx: w as f64 / 2.0,
            cy: h as f64 / 2.0,
            skew: 0.0,
            width: w,
            height: h,
        };
        let p = Camera::from_intrinsics(c.eye(), c.target(), c.up(), k, c.near(), c.far()).unwrap();
        let (a, b) = (
            p.projection_matrix(9.0),
            c.projection_matrix(w as f64 / h as f64),
        );
        assert!(a.abs_diff_eq(b, 1e-12), "{a} vs {b}");
        assert_eq!(
            p.with_planes(1.0, 2.0).unwrap().projection(),
            p.projection()
        );
    }

    #[test]
    fn pinhole_eye_distance_is_the_euclidean_distance() {
        let (c, k) = pinhole();
        for (w, h) in [(64u32, 48u32), (128, 48)] {
            let ks = k.scaled_to(w, h);
            let dist = c.eye_distance(w, h);
            for (x, y, depth) in [(0usize, 0usize, 2.0f64), (63, 47, 7.5), (10, 30, 0.75)] {
                // Back-project the pixel centre through K at eye depth `depth`.
                let (u, v) = (x as f64 + 0.5, y as f64 + 0.5);
                let yc = (v - ks.cy) / ks.fy;
                let xc = (u - ks.cx - ks.skew * yc) / ks.fx;
                let want = (depth * DVec3::new(xc, yc, 1.0)).length();
                let got = dist.at(x, y, depth as f32) as f64;
                assert!((got - want).abs() < 1e-5 * want, "{x},{y}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn rejects_bad_intrinsics_naming_the_field() {
        let (c, k) = pinhole();
        let make = |k: Intrinsics| {
            Camera::from_intrinsics(c.eye(), c.target(), c.up(), k, 0.1, 10.0).unwrap_err()
        };
        let cases = [
            ("fx", Intrinsics { fx: 0.0, ..k }),
            ("fy", Intrinsics { fy: -1.0, ..k }),
            ("cx", Intrinsics { cx: f64::NAN, ..k }),
            (
                "cy",
                Intrinsics {
                    cy: f64::INFINITY,
                    ..k
                },
            ),
            (
                "skew",
                Intrinsics {
                    skew: f64::NAN,
                    ..k
                },
            ),
            ("width", Intrinsics { width: 0, ..k }),
            ("height", Intrinsics { height: 0, ..k }),
        ];
        for (field, bad) in cases {
            let e = make(bad);
            assert_eq!(e.field(), Some(field), "{e}");
            assert!(e.to_string().contains(field), "{e}");
        }
        let e = Camera::from_intrinsics(c.eye(), c.target(), c.up(), k, 0.0, 10.0).unwrap_err();
        assert_eq!(e.field(), Some("near"), "{e}");
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
