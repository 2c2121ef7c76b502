//! Pinhole cameras from pixel intrinsics, end to end: markers are drawn where K (float64)
//! projects their centres, and fog reads the Euclidean distance along K's rays.

mod common;

use std::sync::Arc;

use common::*;
use glam::{DMat3, DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 120;
const H: u32 = 90;

/// Off-centre principal point, skew and non-square pixels.
fn general() -> Intrinsics {
    Intrinsics {
        fx: 150.0,
        fy: 115.0,
        cx: 71.5,
        cy: 38.25,
        skew: 12.0,
        width: W,
        height: H,
    }
}

fn camera(k: Intrinsics) -> Camera {
    Camera::from_intrinsics(
        DVec3::new(0.5, 1.0, 6.0),
        DVec3::new(0.1, 0.2, 0.0),
        DVec3::Y,
        k,
        0.5,
        50.0,
    )
    .unwrap()
}

/// The camera's world-space right, up and forward axes.
fn axes(c: &Camera) -> (DVec3, DVec3, DVec3) {
    let r = DMat3::from_mat4(c.view_matrix()).transpose();
    (r.x_axis, r.y_axis, -r.z_axis)
}

/// Where K sees world point `p` (x right, y down, pixel centres at +0.5).
fn k_pixel(c: &Camera, k: &Intrinsics, p: DVec3) -> (f64, f64) {
    let e = c.view_matrix().transform_point3(p);
    let (x, y, z) = (e.x, -e.y, -e.z);
    (
        (k.fx * x + k.skew * y + k.cx * z) / z,
        (k.fy * y + k.cy * z) / z,
    )
}

#[test]
fn markers_are_drawn_where_k_projects_them() {
    let k = general();
    let c = camera(k);
    let (right, up, fwd) = axes(&c);
    for (w, h) in [(W, H), (2 * W, 3 * H)] {
        let ks = k.scaled_to(w, h);
        for p in [
            c.target(),
            c.target() + 1.1 * right + 0.8 * up,
            c.target() - 1.4 * right - 0.5 * up + 1.5 * fwd,
            c.target() + 0.2 * right - 0.9 * up - 2.0 * fwd,
        ] {
            // A triangle facing the camera, about 5 reference pixels across.
            let r = 5.0 * (p - c.eye()).dot(fwd) / k.fy;
            let v: Vec<Vec3> = [90f64, 210.0, 330.0]
                .iter()
                .map(|a| {
                    let a = a.to_radians();
                    (p + r * (a.cos() * right + a.sin() * up)).as_vec3()
                })
                .collect();
            let n = counts(Mesh::new(v, vec![[0, 1, 2]], None, None).unwrap(), &c, w, h);
            let (mut sx, mut sy, mut total) = (0.0, 0.0, 0.0);
            for (i, &n) in n.iter().enumerate() {
                if n > 0 {
                    sx += (i % w as usize) as f64 + 0.5;
                    sy += (i / w as usize) as f64 + 0.5;
                    total += 1.0;
                }
            }
            assert!(total > 10.0, "marker at {p} barely drawn: {total} pixels");
            let (u, v) = k_pixel(&c, &ks, p);
            let limit = 0.5 * (w / W).max(h / H) as f64;
            assert!(
                (sx / total - u).abs() < limit && (sy / total - v).abs() < limit,
                "{w}x{h} {p}: drawn at ({}, {}), K says ({u}, {v})",
                sx / total,
                sy / total
            );
        }
    }
}

#[test]
fn fog_reads_the_distance_along_k_rays() {
    let k = general();
    let c = camera(k);
    let (right, up, fwd) = axes(&c);
    // A tilted plane filling the view, white and unlit, under linear fog to black.
    let centre = c.target() + 2.0 * fwd;
    let (a, b) = (9.0 * right + 3.0 * fwd, 9.0 * up);
    let v = [
        centre - a - b,
        centre + a - b,
        centre + a + b,
        centre - a + b,
    ]
    .map(|p| p.as_vec3())
    .to_vec();
    let mesh = Mesh::new(v, vec![[0, 1, 2], [0, 2, 3]], None, None).unwrap();
    let mut scene = Scene::new(Vec3::ONE).unwrap();
    let white = Material::new(Vec3::ONE, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    scene.add(Arc::new(mesh), white, Mat4::IDENTITY).unwrap();
    let (start, end) = (3.0f32, 12.0f32);
    scene.set_fog(Some(
        Fog::new(FogMode::Linear { start, end }, Vec3::ZERO).unwrap(),
    ));
    let mut opts = RenderOptions::new(W, 2 * H);
    opts.cull_backfaces = false;
    let (color, depth) = render_f32(&scene, &c, &opts);
    let ks = k.scaled_to(W, 2 * H);
    let mut checked = 0;
    for (i, &d) in depth.iter().enumerate() {
        if !d.is_finite() {
            continue;
        }
        let (u, v) = ((i % W as usize) as f64 + 0.5, (i / W as usize) as f64 + 0.5);
        let yc = (v - ks.cy) / ks.fy;
        let xc = (u - ks.cx - ks.skew * yc) / ks.fx;
        let dist = d as f64 * DVec3::new(xc, yc, 1.0).length();
        let want = ((end as f64 - dist) / (end - start) as f64).clamp(0.0, 1.0);
        let got = color[3 * i] as f64;
        assert!((got - want).abs() < 2e-5, "pixel {i}: {got} vs {want}");
        checked += 1;
    }
    assert!(checked > (W * H) as usize, "only {checked} pixels drawn");
}
