"""Issue 16: a new user's first pictures. Each test is one finding of the issue, and each
failed on the main branch it was written against (black images, cast errors, faceted STL
spheres, ...)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import shadelab_rs as sl
import trimesh

SPOT = sl.data_path("spot/spot_triangulated.obj")
CUBE = sl.data_path("cube/cube.obj")


def _object_stats(img: np.ndarray, depth: np.ndarray) -> tuple[float, np.ndarray]:
    covered = np.isfinite(depth)
    return float(img[covered].mean()) if covered.any() else 0.0, covered


# ---- 1. Cameras that always see the scene -----------------------------------------------


def test_millimetre_model_is_drawn_with_default_planes():
    """Benchy-sized box (millimetres) seen from (100, -150, 80): the old default far = 100
    drew nothing; the fitted planes draw all of it."""
    box = trimesh.creation.box(extents=(60, 30, 48))
    box.apply_translation((0, 0, 24))
    scene = sl.Scene()
    scene.add(box, material="gold")
    cam = sl.Camera.look_at(eye=(100, -150, 80), target=(0, 0, 24), up=(0, 0, 1))
    assert cam.near is None and cam.far is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        img, depth = sl.render(scene, cam, 96, 72, return_depth=True)
    mean, covered = _object_stats(img, depth)
    assert covered.mean() > 0.05 and mean > 40
    fitted = cam.fitted(scene)
    assert fitted.near < depth[covered].min() and depth[covered].max() < fitted.far


def test_eye_close_to_the_cube_does_not_cut_its_front_face():
    """--eye 1.5,1.5,3 on the unit cube: the fitted near plane keeps the whole front."""
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(1.5, 1.5, 3), target=(0, 0, 0), fov_y=90)
    _, depth = sl.render(scene, cam, 64, 64, return_depth=True)
    generous = sl.Camera.look_at(eye=(1.5, 1.5, 3), target=(0, 0, 0), fov_y=90, near=1e-3, far=1e3)
    _, ref = sl.render(scene, generous, 64, 64, return_depth=True)
    np.testing.assert_array_equal(np.isfinite(depth), np.isfinite(ref))
    np.testing.assert_allclose(depth[np.isfinite(ref)], ref[np.isfinite(ref)], rtol=1e-5)


def test_one_given_plane_is_kept_and_the_other_fitted():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(0, 0, 10), target=(0, 0, 0), near=2.0)
    f = cam.fitted(scene)
    assert f.near == 2.0 and f.far == pytest.approx(11.0, rel=0.05) and f.far > 11.0
    ortho = sl.Camera.orthographic(eye=(0, 0, 10), target=(0, 0, 0), height=3)
    f = ortho.fitted(scene)
    assert f.near < 9.0 and f.far > 11.0 and f.far - f.near < 2.5


def test_camera_looking_away_warns():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    cam = sl.Camera.look_at(eye=(0, 0, 5), target=(0, 0, 10))
    with pytest.warns(sl.EmptyRenderWarning, match="12 triangles"):
        img = sl.render(scene, cam, 16, 16)
    assert img.max() == 0


# ---- 2. The default light rig -----------------------------------------------------------


@pytest.mark.parametrize("view", ["front", "back", "left", "right", "top", "bottom", "iso"])
def test_spot_is_lit_from_every_view_by_the_default_rig(view):
    """Spot's face seen from the front was 15/255 under the fixed world light; the rig
    moves with the camera, so every view is lit about alike."""
    spot = sl.load_obj(SPOT)
    scene = sl.Scene()
    scene.add(spot, material="gold")
    img, depth = sl.render(scene, sl.frame_mesh(spot, direction=view), 96, 72, return_depth=True)
    mean, _ = _object_stats(img, depth)
    assert mean > 70


def test_default_lights_only_without_lights_and_can_be_turned_off():
    scene = sl.Scene(ambient=(0, 0, 0))
    scene.add(sl.Mesh.ico_sphere(2))
    cam = sl.frame_mesh(sl.Mesh.ico_sphere(2))
    assert scene.default_lights
    assert sl.render_frame(scene, cam, 32, 32)["stats"]["light_sources"] == 3
    scene.default_lights = False
    assert sl.render(scene, cam, 32, 32).max() == 0
    scene.default_lights = True
    scene.add_light(sl.DirectionalLight((0, 0, -1)))
    assert sl.render_frame(scene, cam, 32, 32)["stats"]["light_sources"] == 1


# ---- 3. Up axis and named views ---------------------------------------------------------


@pytest.mark.parametrize("up", [(0, 1, 0), (0, 0, 1), (1, 0, 0)])
@pytest.mark.parametrize("view", sl.VIEWS)
def test_named_views_work_for_any_up_axis(up, view):
    d, cam_up = sl.view_direction(view, up)
    assert np.linalg.norm(np.cross(d, cam_up)) > 0.5  # never parallel
    cam = sl.frame_mesh(sl.Mesh.cube(), direction=view, up=up)
    _, depth = sl.render(sl.Mesh.cube(), cam, 32, 32, return_depth=True)
    assert np.isfinite(depth).mean() > 0.1


def test_z_up_front_view_shows_the_model_standing():
    """A tall box along z (Z-up): framed with up=(0, 0, 1) it is taller than wide."""
    tall = trimesh.creation.box(extents=(1, 1, 4))
    cam = sl.frame_mesh(tall, direction="front", up=(0, 0, 1))
    _, depth = sl.render(tall, cam, 64, 64, return_depth=True)
    rows, cols = np.nonzero(np.isfinite(depth))
    assert np.ptp(rows) > 2 * np.ptp(cols)
    assert sl.file_up_axis("boat.stl") == (0, 0, 1) and sl.file_up_axis("boat.3MF") == (0, 0, 1)
    assert sl.file_up_axis("boat.glb") == (0, 1, 0) and sl.file_up_axis("boat.obj") == (0, 1, 0)


# ---- 4. Welding and crease-angle normals ------------------------------------------------


def test_stl_sphere_is_welded_and_smooth(tmp_path):
    ico = trimesh.creation.icosphere(subdivisions=2)
    path = tmp_path / "sphere.stl"
    ico.export(path)
    mesh = sl.load_mesh(path)
    assert mesh.n_vertices == 162 and mesh.n_faces == 320
    # Smooth: the normals point along the positions (a unit sphere).
    cos = np.einsum("ij,ij->i", mesh.normals, mesh.vertices)
    assert cos.min() > 0.99


def test_box_keeps_sharp_edges(tmp_path):
    """A box with 8 shared corners (PLY) is split at its 90-degree edges: 24 vertices, each
    with its face's normal, not a pillow."""
    path = tmp_path / "box.ply"
    trimesh.creation.box().export(path)
    mesh = sl.load_mesh(path)
    assert mesh.n_vertices == 24
    assert np.allclose(np.abs(mesh.normals).max(axis=1), 1.0)


def test_from_trimesh_spot_has_no_seams():
    """trimesh splits Spot at its UV seams; the normals ignore the split: the render
    matches the Rust OBJ loader's (was 795 pixels off by more than 8 levels)."""
    tm = trimesh.load(SPOT, process=False)
    spot = sl.load_obj(SPOT)
    cam = sl.frame_mesh(spot, direction=(0.3, 0.2, -1))
    a = sl.render(spot, cam, 256, 256).astype(int)
    b = sl.render(sl.Mesh.from_trimesh(tm), cam, 256, 256).astype(int)
    assert (np.abs(a - b).max(axis=2) > 8).sum() <= 5


# ---- 5. Interop and a mutable scene ------------------------------------------------------


def test_everything_a_trimesh_user_types_first():
    tm = trimesh.creation.icosphere(subdivisions=2)
    scene = sl.Scene()
    assert scene.add(tm) == 1
    assert scene.add((tm.vertices, tm.faces), material="gold") == 1
    assert scene.objects[1].material == sl.Material.preset("gold")
    mesh = sl.Mesh.from_trimesh(tm)
    cam = sl.frame_mesh(mesh)
    img = sl.render(mesh, cam, 32, 32)
    assert img.shape == (32, 32, 3) and img.max() > 0
    assert sl.render(tm, width=16, height=16).max() > 0  # no camera: framed
    ts = trimesh.Scene()
    ts.add_geometry(tm, transform=trimesh.transformations.translation_matrix((3, 0, 0)))
    s2 = sl.Scene()
    s2.add(ts)
    np.testing.assert_allclose(s2.bounds(), [(2, -1, -1), (4, 1, 1)], atol=1e-6)


def test_scene_lists_are_read_only_and_the_scene_is_mutable():
    scene = sl.Scene()
    scene.add(sl.Mesh.cube())
    scene.add(sl.Mesh.cube(), material="copper")
    scene.add_light(sl.DirectionalLight((0, -1, 0)))
    assert isinstance(scene.objects, tuple) and isinstance(scene.lights, tuple)
    with pytest.raises(AttributeError):
        scene.objects.clear()  # type: ignore[attr-defined]
    t = np.eye(4)
    t[:3, 3] = (5, 0, 0)
    scene.set_transform(-1, t)
    np.testing.assert_array_equal(scene.objects[1].transform, t)
    np.testing.assert_allclose(scene.bounds(), [(-1, -1, -1), (6, 1, 1)])
    scene.set_material(0, "gold")
    assert scene.objects[0].material == sl.Material.preset("gold")
    scene.remove_object(0)
    assert scene.n_objects == 1
    scene.set_light(0, sl.PointLight((0, 5, 0)))
    assert isinstance(scene.lights[0], sl.PointLight)
    scene.clear_lights()
    scene.clear_objects()
    assert (scene.n_objects, scene.n_lights) == (0, 0)
    with pytest.raises(IndexError, match="out of range"):
        scene.remove_object(0)
