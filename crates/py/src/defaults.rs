//! What `render` fills in when the user left it out: near/far planes fitted to the scene's
//! bounds for the camera's eye, and a light rig that moves with the camera for scenes
//! without lights. Both are pure functions of the scene and camera, applied to the render's
//! own copy of the scene, so the user's objects are never changed.

use std::borrow::Cow;

use glam::{DMat4, DVec3, Vec3};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use shadelab_raster as core;

use crate::camera::PyCamera;
use crate::errors::to_py;

/// A 4x4 matrix as a float64 NumPy array (rows are the matrix rows).
pub fn mat_to_numpy(py: Python<'_>, m: DMat4) -> Bound<'_, PyArray2<f64>> {
    Array2::from_shape_vec((4, 4), m.transpose().to_cols_array().to_vec())
        .expect("16 values")
        .into_pyarray(py)
}

/// The world-space axis-aligned bounds of every object (each mesh's box, transformed), or
/// None for a scene without objects.
pub fn world_bounds(scene: &core::Scene) -> Option<(DVec3, DVec3)> {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for o in scene.objects() {
        let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for p in o.mesh().positions() {
            a = a.min(*p);
            b = b.max(*p);
        }
        if a.x > b.x {
            continue;
        }
        let m = o.transform().as_dmat4();
        for i in 0..8 {
            let corner = DVec3::new(
                f64::from(if i & 1 == 0 { a.x } else { b.x }),
                f64::from(if i & 2 == 0 { a.y } else { b.y }),
                f64::from(if i & 4 == 0 { a.z } else { b.z }),
            );
            let w = m.transform_point3(corner);
            lo = lo.min(w);
            hi = hi.max(w);
        }
    }
    (lo.x <= hi.x && lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// Smallest near/far ratio a fitted perspective near plane may have: the reversed-Z float
/// depth keeps about the same relative precision at any distance, so a small ratio costs
/// little, and it keeps geometry right in front of an eye inside the scene's box.
const MIN_NEAR_RATIO: f64 = 1e-5;

/// `camera` with the planes it leaves to `render` fitted to `scene`: from just in front of
/// the nearest to just behind the farthest corner of the scene's box, along the view axis.
/// A scene without objects, or entirely behind the eye, keeps the placeholder planes.
pub fn fit_planes(camera: &PyCamera, scene: &core::Scene) -> PyResult<core::Camera> {
    let c = camera.inner;
    if !(camera.fit_near || camera.fit_far) {
        return Ok(c);
    }
    let Some((lo, hi)) = world_bounds(scene) else {
        return Ok(c);
    };
    let forward = (c.target() - c.eye()).normalize();
    let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let z = (corner - c.eye()).dot(forward);
        zmin = zmin.min(z);
        zmax = zmax.max(z);
    }
    // A margin so that faces lying exactly on the box are not clipped by rounding.
    let pad = 0.01 * (zmax - zmin) + 1e-6 * (zmax.abs() + zmin.abs()) + 1e-9;
    let (mut near, mut far) = (c.near(), c.far());
    match c.projection() {
        core::Projection::Perspective { .. } | core::Projection::Pinhole(_) => {
            if camera.fit_far {
                if zmax + pad <= 0.0 {
                    return Ok(c); // all behind the eye: nothing to fit
                }
                far = zmax + pad;
            }
            if camera.fit_near {
                near = (zmin - pad).max(far * MIN_NEAR_RATIO);
            }
            if near >= far {
                // The one plane given lies beyond the other's fitted place.
                if camera.fit_near {
                    near = far * MIN_NEAR_RATIO;
                } else {
                    far = near * 2.0;
                }
            }
            c.with_planes(near, far).map_err(to_py)
        }
        core::Projection::Orthographic { .. } => {
            if camera.fit_far {
                far = zmax + pad;
            }
            if camera.fit_near {
                near = zmin - pad;
            }
            if near >= far {
                let gap = (zmax - zmin).max(1.0);
                if camera.fit_near {
                    near = far - gap;
                } else {
                    far = near + gap;
                }
            }
            c.with_planes(near, far).map_err(to_py)
        }
    }
}

/// The default light rig as (elevation, azimuth, intensity), angles in degrees in the
/// camera's frame: elevation up from the view axis, azimuth to the right. A headlight
/// from the eye keeps every visible face lit; a key light from the upper left and a weaker
/// fill from the lower right give the shape (the key-to-fill ratio of about 2 is the
/// photographer's and PyVista's light kit's choice).
pub const LIGHT_RIG: [(f64, f64, f32); 3] =
    [(0.0, 0.0, 0.35), (45.0, -35.0, 0.55), (-25.0, 50.0, 0.25)];

/// The rig's white directional lights for `camera`, in world space.
pub fn light_rig(camera: &core::Camera) -> Vec<core::DirectionalLight> {
    let forward = (camera.target() - camera.eye()).normalize();
    let right = forward.cross(camera.up()).normalize();
    let up = right.cross(forward);
    LIGHT_RIG
        .iter()
        .map(|&(elevation, azimuth, intensity)| {
            let (el, az) = (elevation.to_radians(), azimuth.to_radians());
            let to_light =
                right * (az.sin() * el.cos()) + up * el.sin() - forward * (az.cos() * el.cos());
            core::DirectionalLight::new(-to_light.as_vec3(), Vec3::ONE, intensity)
                .expect("the rig's directions are unit vectors")
        })
        .collect()
}

/// `scene` as `render` lights it through `camera`: a copy with the light rig added when the
/// scene has no lights and asks for the rig (`default_lights`), else the scene itself.
pub fn lit_scene<'a>(
    scene: &'a core::Scene,
    default_lights: bool,
    camera: &core::Camera,
) -> Cow<'a, core::Scene> {
    if default_lights && scene.lights().is_empty() {
        let mut copy = scene.clone();
        for light in light_rig(camera) {
            copy.add_light(light);
        }
        Cow::Owned(copy)
    } else {
        Cow::Borrowed(scene)
    }
}

/// The scene and camera `render` draws: the camera's planes fitted, and the light rig added
/// to the copy of a scene that has no lights and asks for the rig. `render_batch` applies
/// the same two steps per view (`fit_planes`, then `lit_scene`).
pub fn prepare(
    scene: &crate::scene::PyScene,
    camera: &PyCamera,
) -> PyResult<(core::Scene, core::Camera)> {
    let cam = fit_planes(camera, &scene.inner)?;
    let copy = lit_scene(&scene.inner, scene.default_lights, &cam).into_owned();
    Ok((copy, cam))
}
