//! Hidden back faces (`RenderOptions::cull_hidden`): skipped exactly where they cannot show,
//! with the same image as drawing them; drawn wherever they might show.

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use shadelab_raster::*;

const W: u32 = 160;
const H: u32 = 120;

fn camera(eye: DVec3, target: DVec3, near: f64) -> Camera {
    Camera::look_at(eye, target, DVec3::Y, 50.0, near, 100.0).unwrap()
}

fn outside() -> Camera {
    camera(DVec3::new(0.4, 0.7, 3.2), DVec3::ZERO, 0.1)
}

fn scene_of(objects: Vec<(Mesh, Material, Mat4)>, shadows: bool) -> Scene {
    let mut scene = Scene::new(Vec3::splat(0.2)).unwrap();
    for (mesh, material, transform) in objects {
        scene.add(Arc::new(mesh), material, transform).unwrap();
    }
    let sun = DirectionalLight::new(Vec3::new(-1.0, -2.0, -1.5), Vec3::ONE, 1.0).unwrap();
    let sun = if shadows {
        sun.with_shadows(Shadows::Map(ShadowSettings::default()))
    } else {
        sun
    };
    scene.add_light(sun);
    scene.add_light(PointLight::new(Vec3::new(2.0, 3.0, 4.0), Vec3::splat(0.5), 1.0).unwrap());
    scene
}

fn sphere(material: &str, transform: Mat4) -> (Mesh, Material, Mat4) {
    (
        primitives::uv_sphere(24, 48),
        Material::preset(material).unwrap(),
        transform,
    )
}

/// The render's colour and depth bits and its culled-triangle count, with `cull_hidden` on
/// or off.
fn frame(scene: &Scene, camera: &Camera, mode: ShadingMode, hidden: bool) -> (Vec<u32>, usize) {
    let mut options = RenderOptions::new(W, H);
    options.shading = mode;
    options.cull_hidden = hidden;
    let f = render(scene, camera, &options, ColorFormat::F32, true).unwrap();
    let ColorBuffer::F32(c) = &f.color else {
        panic!("f32 colour asked for")
    };
    let bits = c
        .iter()
        .chain(f.depth.as_ref().unwrap())
        .map(|v| v.to_bits())
        .collect();
    (bits, f.stats.triangles_culled)
}

/// Skipped or not, the picture is the same; returns the culled counts (on, off).
fn same_picture(scene: &Scene, camera: &Camera) -> (usize, usize) {
    let mut counts = (0, 0);
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let (on, culled_on) = frame(scene, camera, mode, true);
        let (off, culled_off) = frame(scene, camera, mode, false);
        let differ = on.iter().zip(&off).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{mode:?}: {differ} values differ");
        counts = (culled_on, culled_off);
    }
    counts
}

#[test]
fn solids_seen_from_outside_skip_their_back_faces() {
    let triangles = primitives::uv_sphere(24, 48).triangle_count();
    let scene = scene_of(
        vec![
            sphere("gold", Mat4::IDENTITY),
            sphere(
                "jade",
                Mat4::from_translation(Vec3::new(-1.2, -0.3, -1.5))
                    * Mat4::from_scale(Vec3::splat(0.7)),
            ),
            (
                primitives::cube(),
                Material::preset("ruby").unwrap(),
                Mat4::from_translation(Vec3::new(1.3, 0.0, -0.5)),
            ),
        ],
        false,
    );
    let (on, off) = same_picture(&scene, &outside());
    assert_eq!(off, 0);
    // About half of each solid faces away.
    assert!(
        on > triangles * 2 * 4 / 10,
        "{on} of {}",
        triangles * 2 + 12
    );
}

#[test]
fn shadow_maps_are_unchanged() {
    let scene = scene_of(
        vec![
            sphere("gold", Mat4::IDENTITY),
            (
                primitives::plane(),
                Material::preset("white plastic").unwrap(),
                Mat4::from_translation(Vec3::new(0.0, -1.2, 0.0))
                    * Mat4::from_scale(Vec3::splat(4.0)),
            ),
        ],
        true,
    );
    let (on, off) = same_picture(&scene, &outside());
    assert!(on > 0 && off == 0);
}

#[test]
fn back_faces_that_may_show_are_drawn() {
    let culled_on = |objects: Vec<(Mesh, Material, Mat4)>, camera: &Camera| {
        let scene = scene_of(objects, false);
        let (on, off) = same_picture(&scene, camera);
        assert_eq!(off, 0);
        on
    };
    // The eye inside the sphere (it sees the inside, all back faces).
    let inside = camera(DVec3::new(0.1, 0.0, 0.2), DVec3::new(0.0, 0.0, -1.0), 0.05);
    assert_eq!(culled_on(vec![sphere("gold", Mat4::IDENTITY)], &inside), 0);
    // The near plane cuts into it.
    let cutting = camera(DVec3::new(0.0, 0.0, 1.05), DVec3::ZERO, 0.1);
    assert_eq!(culled_on(vec![sphere("gold", Mat4::IDENTITY)], &cutting), 0);
    // Mirrored by its transform: its outward faces turn clockwise on screen.
    let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    assert_eq!(culled_on(vec![sphere("gold", mirror)], &outside()), 0);
    // Transparent: the far side shows through.
    let mut glass = Material::preset("gold").unwrap();
    glass.transparency = 0.5;
    let glassy = (primitives::uv_sphere(24, 48), glass, Mat4::IDENTITY);
    assert_eq!(culled_on(vec![glassy], &outside()), 0);
    // Open: a sphere with a face missing shows its inside through the hole.
    let s = primitives::uv_sphere(24, 48);
    let mut faces = s.indices().to_vec();
    faces.remove(faces.len() / 2);
    let open = Mesh::new(s.positions().to_vec(), faces, None, None).unwrap();
    let m = Material::preset("gold").unwrap();
    assert_eq!(culled_on(vec![(open, m, Mat4::IDENTITY)], &outside()), 0);
    // Wound inward: seen from outside, its back faces are what shows.
    let inward: Vec<[u32; 3]> = s.indices().iter().map(|t| [t[0], t[2], t[1]]).collect();
    let inward = Mesh::new(s.positions().to_vec(), inward, None, None).unwrap();
    assert_eq!(culled_on(vec![(inward, m, Mat4::IDENTITY)], &outside()), 0);
}

#[test]
fn an_explicit_cull_still_culls_everything_clockwise() {
    let scene = scene_of(vec![sphere("gold", Mat4::IDENTITY)], false);
    let inside = camera(DVec3::new(0.1, 0.0, 0.2), DVec3::new(0.0, 0.0, -1.0), 0.05);
    let mut options = RenderOptions::new(W, H);
    options.cull_backfaces = true;
    let f = render(&scene, &inside, &options, ColorFormat::U8, false).unwrap();
    assert!(f.stats.triangles_culled > 0);
    assert_eq!(f.stats.triangles_setup, 0);
}

/// The documented exception: a closed, outward-wound mesh that passes through itself so that
/// part of it is turned inside out shows back faces from outside, which `cull_hidden` then
/// skips; `false` draws them. Here a sphere's north cap is pushed down through the sphere
/// and out below it (`y → c − k·y` reverses the cap's orientation), and seen from below the
/// emerging cap shows its back faces.
#[test]
fn a_mesh_turned_inside_out_through_itself_needs_cull_hidden_off() {
    let s = primitives::uv_sphere(24, 48);
    let pushed: Vec<Vec3> = s
        .positions()
        .iter()
        .map(|p| {
            if p.y > 0.5 {
                Vec3::new(p.x, 0.5 - 4.0 * (p.y - 0.5), p.z)
            } else {
                *p
            }
        })
        .collect();
    let mesh = Mesh::new(pushed, s.indices().to_vec(), None, None).unwrap();
    let scene = scene_of(
        vec![(mesh, Material::preset("gold").unwrap(), Mat4::IDENTITY)],
        false,
    );
    let below = camera(DVec3::new(0.2, -5.0, 0.3), DVec3::ZERO, 0.1);
    let (on, culled_on) = frame(&scene, &below, ShadingMode::Phong, true);
    let (off, culled_off) = frame(&scene, &below, ShadingMode::Phong, false);
    assert!(culled_on > 0 && culled_off == 0);
    let differ = on.iter().zip(&off).filter(|(a, b)| a != b).count();
    assert!(differ > 100, "{differ} values differ");
}

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    /// Any UV sphere, stretched, turned and moved, seen from outside: skipping its hidden back
    /// faces changes no pixel but at the silhouette (where snapping can let a back face tie
    /// the front one), and there only a few: at most an eighth of the silhouette's pixels
    /// (at least 8).
    #[test]
    fn skipping_changes_nothing_but_silhouette_ties(
        rings in 3u32..24,
        segments in 3u32..40,
        scale in prop::array::uniform3(0.3f32..2.0),
        axis in prop::array::uniform3(-1.0f32..1.0),
        angle in 0.0f32..6.3,
        shift in prop::array::uniform3(-0.5f32..0.5),
        eye_dir in prop::array::uniform3(-1.0f64..1.0),
        distance in 3.5f64..9.0,
        mode in 0usize..3,
    ) {
        let axis = Vec3::from_array(axis);
        let eye_dir = DVec3::from_array(eye_dir);
        prop_assume!(axis.length() > 0.1 && eye_dir.length() > 0.1);
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::from_array(scale),
            glam::Quat::from_axis_angle(axis.normalize(), angle),
            Vec3::from_array(shift),
        );
        let mesh = primitives::uv_sphere(rings, segments);
        let scene = scene_of(vec![(mesh, Material::preset("gold").unwrap(), transform)], false);
        let eye = eye_dir.normalize() * distance;
        let up = if eye_dir.normalize().y.abs() > 0.9 { DVec3::X } else { DVec3::Y };
        let cam = Camera::look_at(eye, DVec3::ZERO, up, 50.0, 0.1, 100.0).unwrap();
        let mode = [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong][mode];
        let (on, culled_on) = frame(&scene, &cam, mode, true);
        let (off, culled_off) = frame(&scene, &cam, mode, false);
        prop_assert!(culled_on > 0 && culled_off == 0);
        // Colour (3 per pixel) then depth (1 per pixel), W × H each.
        let n = (W * H) as usize;
        let depth_off = &off[3 * n..];
        let empty = |x: i64, y: i64| {
            x < 0 || y < 0 || x >= W as i64 || y >= H as i64
                || f32::from_bits(depth_off[(y * W as i64 + x) as usize]).is_infinite()
        };
        // Silhouette pixels: covered, with an empty pixel among their 8 neighbours.
        let silhouette = (0..n)
            .filter(|&p| {
                let (x, y) = ((p % W as usize) as i64, (p / W as usize) as i64);
                !empty(x, y) && (-1..=1).any(|dy| (-1..=1).any(|dx| empty(x + dx, y + dy)))
            })
            .count();
        let mut differ = 0;
        for p in 0..n {
            let same = (0..3).all(|c| on[3 * p + c] == off[3 * p + c])
                && on[3 * n + p] == off[3 * n + p];
            if same {
                continue;
            }
            differ += 1;
            let (x, y) = ((p % W as usize) as i64, (p / W as usize) as i64);
            let silhouette = (-1..=1).any(|dy| (-1..=1).any(|dx| empty(x + dx, y + dy)));
            prop_assert!(silhouette, "pixel ({x}, {y}) differs away from the silhouette");
        }
        // Ties follow the silhouette, so their number scales with its length: over 3,000
        // random cases 4 had any, the most 11 of 150 silhouette pixels (the saved
        // regression case; the bound was a flat 8 before it).
        prop_assert!(
            differ <= (silhouette / 8).max(8),
            "{differ} pixels differ ({silhouette} silhouette pixels)"
        );
    }
}
