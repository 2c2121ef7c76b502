"""Scene files: schema v1, every error path, dict/TOML/file round trips, the CLI."""

from __future__ import annotations

import copy
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import shadelab_rs as sl
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image
from test_cli import run  # one way to call the command line

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

REPO = Path(__file__).resolve().parent.parent
EXAMPLE = REPO / "examples" / "scene.toml"
SPOT = sl.data_path("spot/spot_triangulated.obj")
CUBE_OBJ = sl.data_path("cube/cube.obj")
DELETE = object()

#: A small valid document using every section; error cases mutate one value of it.
BASE: dict = {
    "version": 1,
    "ambient": [0.2, 0.2, 0.2],
    "two_sided": False,
    "local_viewer": True,
    "camera": {"eye": [0.5, 0.4, 3.0], "target": [0, 0, 0]},
    "render": {"width": 48, "height": 32},
    "fog": {"mode": "linear", "start": 1.0, "end": 10.0},
    "materials": {"mine": {"preset": "gold", "shininess": 10}},
    "lights": [
        {"type": "directional", "direction": [0, -1, 0]},
        {"type": "point", "position": [1, 2, 3]},
        {"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0]},
        {"type": "area", "position": [0, 3, 0], "u": [1, 0, 0], "v": [0, 0, 1]},
    ],
    "objects": [
        {"mesh": {"primitive": "sphere", "rings": 4, "segments": 6}, "material": "mine"},
        {"mesh": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "faces": [[0, 1, 2]]}},
    ],
}


def mutate(path: tuple, value) -> dict:
    """A deep copy of BASE with the value at ``path`` replaced (or deleted with DELETE)."""
    doc = copy.deepcopy(BASE)
    node = doc
    for k in path[:-1]:
        node = node[k]
    if value is DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return doc


def render_all(scene: sl.Scene, camera: sl.Camera, **kw) -> list[np.ndarray]:
    """float32 images of ``scene`` in every shading mode."""
    return [
        sl.render(scene, camera, width=72, height=48, shading=s, dtype="float32", **kw)
        for s in ("flat", "gouraud", "phong")
    ]


def assert_same_render(a: sl.Scene, b: sl.Scene, camera: sl.Camera) -> None:
    for x, y in zip(render_all(a, camera), render_all(b, camera)):
        assert x.tobytes() == y.tobytes()


def is_plain(v) -> bool:
    """True when ``v`` is built only of what TOML can hold."""
    if isinstance(v, dict):
        return all(isinstance(k, str) and is_plain(x) for k, x in v.items())
    if isinstance(v, list):
        return all(is_plain(x) for x in v)
    return isinstance(v, (str, int, float, bool)) and (not isinstance(v, float) or math.isfinite(v))


@pytest.fixture(scope="module")
def camera() -> sl.Camera:
    return sl.Camera.look_at(eye=(1.0, 1.5, 4.0), target=(0, 0, 0), fov_y=50.0)


@pytest.fixture(scope="module")
def rich_scene() -> sl.Scene:
    """Every light kind, fog, two-sided, infinite viewer, every mesh source."""
    s = sl.Scene(
        ambient=(0.1, 0.12, 0.15),
        fog=sl.Fog("exp2", density=0.07, color=(0.3, 0.3, 0.35)),
        two_sided=True,
        local_viewer=False,
    )
    s.add_light(sl.DirectionalLight((-0.3, -1.0, -0.45), color=(1, 0.9, 0.8), intensity=0.7))
    s.add_light(
        sl.PointLight(
            (2, 2, 3), color=(0.3, 0.4, 0.5), attenuation=(1, 0.1, 0.01), specular=(0, 0, 1)
        )
    )
    s.add_light(
        sl.SpotLight(
            (0, 3, 1), (0.1, -1, -0.3), cutoff=35, exponent=3, inner=20, ambient=(0.01, 0, 0)
        )
    )
    s.add_light(
        sl.AreaLight(
            (1, 2, 1), (0.5, 0, 0), (0, 0.3, 0.4), shape="disk", samples=2, diffuse=(1, 0, 0)
        )
    )
    s.add_light(sl.AreaLight((-1, 2, 1), (0.5, 0, 0), (0, 0, 0.5), one_sided=True, samples=1))
    s.add(sl.Mesh.uv_sphere(6, 9), sl.Material.preset("ruby"), np.diag([0.5, 0.8, 0.5, 1]))
    cube_at = sl.scene_file.compose_transform(translate=(1, 0.2, 0), rotate=(10, 20, 30), scale=0.3)
    s.add(sl.Mesh.cube(), sl.Material(emission=(0.1, 0, 0)), cube_at)
    s.add(sl.Mesh.plane(), transform=np.diag([3.0, 1.0, 3.0, 1.0]))
    t = np.eye(4)
    t[:3, 3] = (-1.2, 0.1, 0.3)
    t[:3, :3] *= 0.5
    s.add(sl.load_obj(SPOT), sl.Material.preset("gold"), t)
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    s.add(sl.Mesh(v, f, normals=v + 0.1, uvs=v[:, :2]), transform=np.eye(4))
    s.add(sl.Mesh(v + 0.25, f), sl.Material.preset("jade"))
    s.add(sl.Mesh.ico_sphere(1), back_material=sl.Material.preset("emerald"))
    return s


# ---------------------------------------------------------------------------------------
# Round trips


def test_to_dict_is_plain_and_from_dict_renders_bit_identically(rich_scene, camera):
    d = rich_scene.to_dict()
    assert is_plain(d)
    assert d["version"] == 2
    back = sl.Scene.from_dict(d)
    assert_same_render(rich_scene, back, camera)
    # A fixed point: writing the rebuilt scene gives the same data.
    assert back.to_dict() == d


def test_to_dict_describes_primitives_and_inline_meshes(rich_scene):
    meshes = [o["mesh"] for o in rich_scene.to_dict()["objects"]]
    assert meshes[0] == {"primitive": "sphere", "rings": 6, "segments": 9}
    assert meshes[1] == {"primitive": "cube"}
    assert meshes[2] == {"primitive": "plane"}
    # The OBJ mesh has loader-made (welded) normals, so they are written out.
    assert set(meshes[3]) == {"vertices", "faces", "normals", "uvs"}
    assert set(meshes[4]) == {"vertices", "faces", "normals", "uvs"}
    # Generated normals are not written: they are regenerated identically.
    assert set(meshes[5]) == {"vertices", "faces"}
    assert meshes[6] == {"primitive": "ico_sphere", "subdivisions": 1}
    assert meshes[5]["faces"] == [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def test_toml_round_trip(rich_scene, camera, tmp_path):
    opts = {"width": 72, "height": 48, "shading": "gouraud", "background": (0.1, 0.2, 0.3)}
    d = sl.scene_to_dict(rich_scene, camera, opts)
    text = sl.to_toml(d)
    assert tomllib.loads(text) == d
    path = tmp_path / "rt.toml"
    sl.save_scene(path, rich_scene, camera, opts)
    sf = sl.load_scene(path)
    assert sf.path == path
    assert sf.render_options == {
        "width": 72,
        "height": 48,
        "shading": "gouraud",
        "background": [0.1, 0.2, 0.3],
    }
    assert sf.camera is not None
    assert (sf.camera.eye, sf.camera.target, sf.camera.up) == (
        camera.eye,
        camera.target,
        camera.up,
    )
    assert (sf.camera.fov_y, sf.camera.near, sf.camera.far) == (
        camera.fov_y,
        camera.near,
        camera.far,
    )
    assert_same_render(rich_scene, sf.scene, camera)
    assert_same_render(rich_scene, sl.Scene.from_file(path), camera)
    assert sf.render().tobytes() == sl.render(rich_scene, camera, **opts).tobytes()


def test_orthographic_camera_round_trip(tmp_path):
    cam = sl.Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), height=3.5, near=-1, far=9)
    s = sl.Scene()
    s.add(sl.Mesh.cube())
    d = sl.scene_to_dict(s, cam)
    assert d["camera"] == {
        "type": "orthographic",
        "eye": [0.0, 0.0, 5.0],
        "target": [0.0, 0.0, 0.0],
        "up": [0.0, 1.0, 0.0],
        "height": 3.5,
        "near": -1.0,
        "far": 9.0,
    }
    cam2 = sl.load_scene_dict(d).camera
    assert cam2 is not None and cam2.kind == "orthographic" and cam2.height == 3.5


def test_to_toml_quotes_keys_and_escapes_strings():
    d = {"version": 1, "materials": {"my mat": {"preset": 'say "hi"\n\x7f'}}, "empty": []}
    assert tomllib.loads(sl.to_toml(d)) == d


@settings(max_examples=100, deadline=None)
@given(
    st.lists(st.floats(-10, 10, allow_nan=False), min_size=3, max_size=3).filter(
        lambda v: math.hypot(*v) > 1e-3
    )
)
def test_light_directions_round_trip_exactly(d):
    # Lights keep their direction as given (float64), so it is written and read back as is.
    s = sl.Scene()
    s.add_light(sl.DirectionalLight(d))
    s.add_light(sl.SpotLight((0, 1, 0), d, cutoff=40))
    assert [x.direction for x in s.lights] == [tuple(d)] * 2
    back = sl.Scene.from_dict(tomllib.loads(sl.to_toml(s.to_dict())))
    assert [x.direction for x in back.lights] == [tuple(d)] * 2


def test_hand_written_directions_need_not_be_unit():
    doc = {"version": 1, "lights": [{"type": "directional", "direction": [0, -3, 0]}]}
    doc["objects"] = [{"mesh": {"primitive": "sphere", "rings": 6, "segments": 8}}]
    scene = sl.Scene.from_dict(doc)
    assert scene.lights[0].direction == (0.0, -3.0, 0.0)
    doc["lights"][0]["direction"] = [0, -1, 0]
    cam = sl.Camera.look_at(eye=(0, 1, 4), target=(0, 0, 0))
    assert_same_render(scene, sl.Scene.from_dict(doc), cam)


_f32 = st.floats(0, 2, width=32)
_colors = st.lists(_f32, min_size=3, max_size=3)
_points = st.lists(st.floats(-3, 3, width=32), min_size=3, max_size=3)
_dirs = _points.filter(lambda v: math.hypot(*v) > 1e-2)
_atten = st.lists(st.floats(0, 1, width=32), min_size=3, max_size=3).filter(any)


@st.composite
def _lights(draw):
    kind = draw(st.sampled_from(["directional", "point", "spot", "area"]))
    common = {"color": draw(_colors), "intensity": draw(_f32), "ambient": draw(_colors)}
    for k in ("diffuse", "specular"):
        common[k] = draw(st.one_of(st.none(), _colors))
    if kind == "directional":
        return sl.DirectionalLight(draw(_dirs), **common)
    common["attenuation"] = draw(_atten)
    if kind == "point":
        return sl.PointLight(draw(_points), **common)
    if kind == "spot":
        cutoff = draw(st.one_of(st.just(180.0), st.floats(1, 90, width=32)))
        inner = draw(st.one_of(st.none(), st.floats(0, 0.875, width=32))) if cutoff <= 90 else None
        return sl.SpotLight(
            draw(_points),
            draw(_dirs),
            cutoff=cutoff,
            exponent=draw(st.floats(0, 50, width=32)),
            inner=None if inner is None else inner * cutoff,
            **common,
        )
    u = draw(st.sampled_from([(1, 0, 0), (0.5, 0.2, 0)]))
    return sl.AreaLight(
        draw(_points),
        u,
        (0, 0.3, 0.7),
        shape=draw(st.sampled_from(["rectangle", "disk"])),
        samples=draw(st.integers(1, 3)),
        one_sided=draw(st.booleans()),
        **common,
    )


@st.composite
def _scenes(draw):
    fog = draw(
        st.one_of(
            st.none(),
            st.builds(lambda a, b: sl.Fog("linear", start=a, end=a + b), _f32, st.floats(0.1, 9)),
            st.builds(lambda m, x: sl.Fog(m, density=x), st.sampled_from(["exp", "exp2"]), _f32),
        )
    )
    s = sl.Scene(
        ambient=draw(_colors),
        fog=fog,
        two_sided=draw(st.booleans()),
        local_viewer=draw(st.booleans()),
    )
    for light in draw(st.lists(_lights(), max_size=3)):
        s.add_light(light)
    meshes = [sl.Mesh.cube(), sl.Mesh.plane(), sl.Mesh.uv_sphere(5, 7)]
    scales = st.floats(0.25, 2, width=32).map(lambda x: x * (-1) ** int(x * 10))
    for i in draw(st.lists(st.integers(0, 2), min_size=1, max_size=3)):
        t = sl.scene_file.compose_transform(
            draw(_points), draw(_points.map(lambda v: [x * 60 for x in v])), draw(scales)
        )
        m = sl.Material(draw(_colors), draw(_colors), draw(_colors), draw(_f32) * 50, draw(_colors))
        s.add(meshes[i], m, t)
    return s


# A random scene may be edge-on to the camera and draw nothing: that warns, and is fine.
@pytest.mark.filterwarnings("ignore::shadelab_rs.EmptyRenderWarning")
@settings(max_examples=40, deadline=None)
@given(_scenes())
def test_random_scenes_round_trip_bit_identically(scene):
    d = scene.to_dict()
    assert is_plain(d)
    back = sl.Scene.from_dict(tomllib.loads(sl.to_toml(d)))
    assert back.to_dict() == d
    cam = sl.Camera.look_at(eye=(2, 3, 6), target=(0, 0, 0), fov_y=60)
    assert_same_render(scene, back, cam)


def test_objects_and_lights_introspection(rich_scene):
    objs = rich_scene.objects
    assert len(objs) == rich_scene.n_objects == 7
    assert objs[6].back_material == sl.Material.preset("emerald")
    assert objs[0].back_material is None
    assert isinstance(objs[0], sl.SceneObject)
    assert objs[0].material == sl.Material.preset("ruby")
    t = objs[0].transform
    assert t.dtype == np.float64 and t.shape == (4, 4)
    # The float32 values the scene holds, exactly.
    assert np.array_equal(t, np.diag([0.5, 0.8, 0.5, 1.0]).astype(np.float32))
    assert objs[0].mesh.n_faces == sl.Mesh.uv_sphere(6, 9).n_faces
    assert objs[1].material.emission == pytest.approx((0.1, 0, 0))
    lights = rich_scene.lights
    assert [type(x).__name__ for x in lights] == [
        "DirectionalLight",
        "PointLight",
        "SpotLight",
        "AreaLight",
        "AreaLight",
    ]
    assert lights[2].inner == 20 and lights[2].cutoff == 35
    assert lights[4].one_sided and lights[3].shape == "disk"
    assert lights[1].specular == (0, 0, 1) and lights[1].diffuse is None
    assert lights[3].diffuse == (1, 0, 0) and lights[3].specular is None
    d = rich_scene.to_dict()["lights"]
    assert d[1]["specular"] == [0, 0, 1] and "diffuse" not in d[1]
    assert d[3]["diffuse"] == [1, 0, 0] and "specular" not in d[3]
    assert "diffuse" not in d[0] and "specular" not in d[0]
    assert len(sl.Scene().objects) == 0 and sl.Scene().lights == ()


def test_example_file_renders(tmp_path):
    sf = sl.load_scene(EXAMPLE)
    assert sf.render_options["width"] == 640 and sf.camera is not None
    assert sf.scene.n_lights == 4 and sf.scene.fog is not None
    assert sf.scene.n_objects == 4
    img = sf.render(width=64, height=40)
    assert img.shape == (40, 64, 3) and img.max() > 0
    # Named material "floor": pewter with shininess 20.
    floor = sf.scene.objects[3].material
    pewter = sl.Material.preset("pewter")
    assert floor.shininess == 20 and floor.diffuse == pewter.diffuse


def test_relative_mesh_paths_resolve_against_the_file(tmp_path, monkeypatch):
    (tmp_path / "meshes").mkdir()
    shutil.copy(CUBE_OBJ, tmp_path / "meshes" / "box.obj")
    (tmp_path / "scenes").mkdir()
    scene = tmp_path / "scenes" / "s.toml"
    scene.write_text('version = 1\n[[objects]]\nmesh = "../meshes/box.obj"\n')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    s = sl.Scene.from_file(scene)
    assert s.n_objects == 1 and s.n_triangles == sl.load_obj(CUBE_OBJ).n_faces
    # from_dict resolves against base_dir, else the current directory.
    d = {"version": 1, "objects": [{"mesh": "meshes/box.obj"}]}
    assert sl.Scene.from_dict(d, base_dir=tmp_path).n_objects == 1
    with pytest.raises(sl.SceneFileError, match="no such file"):
        sl.Scene.from_dict(d)
    monkeypatch.chdir(tmp_path)
    assert sl.Scene.from_dict(d).n_objects == 1


MTL_OBJ = """mtllib two.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
o first
usemtl red
f 1 2 3
o second
usemtl blue
f 2 4 3
"""
MTL = """newmtl red
Kd 1 0 0
Ka 0.1 0 0
Ks 0 0 0
Ns 5
newmtl blue
Kd 0 0 1
"""


def test_obj_parts_keep_their_mtl_materials_unless_overridden(tmp_path):
    (tmp_path / "two.obj").write_text(MTL_OBJ)
    (tmp_path / "two.mtl").write_text(MTL)
    d = {"version": 1, "objects": [{"mesh": "two.obj"}]}
    s = sl.Scene.from_dict(d, base_dir=tmp_path)
    parts = sl.load_obj_parts(tmp_path / "two.obj")
    assert s.n_objects == len(parts) == 2
    assert [o.material for o in s.objects] == [m for _, _, m in parts]
    assert s.objects[0].material.diffuse == (1.0, 0.0, 0.0)
    assert s.objects[1].material.diffuse == (0.0, 0.0, 1.0)
    d["objects"][0]["material"] = "chrome"
    s = sl.Scene.from_dict(d, base_dir=tmp_path)
    assert [o.material for o in s.objects] == [sl.Material.preset("chrome")] * 2


def test_other_mesh_formats_load_through_trimesh(tmp_path):
    import trimesh

    trimesh.creation.box().export(tmp_path / "box.stl")
    s = sl.Scene.from_dict({"version": 1, "objects": [{"mesh": "box.stl"}]}, base_dir=tmp_path)
    assert s.n_triangles == 12


def test_transform_from_translate_rotate_scale():
    doc = {
        "version": 1,
        "objects": [
            {
                "mesh": {"primitive": "cube"},
                "translate": [1, 2, 3],
                "rotate": [0, 90, 0],
                "scale": [2, 1, 1],
            },
            {"mesh": {"primitive": "cube"}, "scale": 3},
        ],
    }
    s = sl.Scene.from_dict(doc)
    t = s.objects[0].transform
    # Scale x by 2, then rotate 90 degrees about y (x -> -z), then translate.
    p = t @ np.array([1.0, 0.0, 0.0, 1.0])
    assert p == pytest.approx([1.0, 2.0, 1.0, 1.0], abs=1e-6)
    assert np.array_equal(s.objects[1].transform, np.diag([3.0, 3.0, 3.0, 1.0]))
    r = sl.scene_file.compose_transform(rotate=[90, 0, 0])
    assert r @ np.array([0.0, 1.0, 0.0, 0.0]) == pytest.approx([0, 0, 1, 0], abs=1e-12)
    r = sl.scene_file.compose_transform(rotate=[0, 0, 90])
    assert r @ np.array([1.0, 0.0, 0.0, 0.0]) == pytest.approx([0, 1, 0, 0], abs=1e-12)
    # x first, then z: y -> z (about x), and z stays under the z rotation.
    r = sl.scene_file.compose_transform(rotate=[90, 0, 90])
    assert r @ np.array([0.0, 1.0, 0.0, 0.0]) == pytest.approx([0, 0, 1, 0], abs=1e-12)


def test_material_forms():
    doc = {
        "version": 1,
        "materials": {"shiny": {"diffuse": [0.1, 0.2, 0.3], "shininess": 99}},
        "objects": [
            {"mesh": {"primitive": "cube"}, "material": "Polished_Silver"},
            {"mesh": {"primitive": "cube"}, "material": "shiny"},
            {"mesh": {"primitive": "cube"}, "material": {"preset": "gold", "emission": [1, 0, 0]}},
            {"mesh": {"primitive": "cube"}},
        ],
    }
    m = [o.material for o in sl.Scene.from_dict(doc).objects]
    assert m[0] == sl.Material.preset("polished silver")
    default = sl.Material()
    assert m[1] == sl.Material(
        default.ambient, (0.1, 0.2, 0.3), default.specular, 99, default.emission
    )
    gold = sl.Material.preset("gold")
    assert m[2] == sl.Material(gold.ambient, gold.diffuse, gold.specular, gold.shininess, (1, 0, 0))
    assert m[3] == default


def test_defaults_of_an_almost_empty_document():
    sf = sl.load_scene_dict({"version": 1})
    s = sf.scene
    assert s.ambient == sl.Scene().ambient
    assert (s.two_sided, s.local_viewer, s.fog) == (False, True, None)
    assert s.n_objects == s.n_lights == 0 and sf.camera is None and sf.render_options == {}
    with pytest.raises(ValueError, match="without objects"):
        sl.frame_scene(s)


def test_back_material(camera):
    doc = mutate(("objects", 0, "back_material"), {"preset": "ruby"})
    doc["two_sided"] = True
    s = sl.Scene.from_dict(doc)
    assert s.objects[0].back_material == sl.Material.preset("ruby")
    assert s.objects[0].material == sl.load_scene_dict(BASE).scene.objects[0].material
    assert s.objects[1].back_material is None
    d = s.to_dict()
    assert d["objects"][0]["back_material"] == sl.scene_file.material_to_dict(
        sl.Material.preset("ruby")
    )
    assert "back_material" not in d["objects"][1]
    assert_same_render(s, sl.Scene.from_dict(d), camera)
    # Named materials work too, and an OBJ's parts all get the back material.
    doc["objects"][0]["back_material"] = "mine"
    doc["objects"].append({"mesh": str(CUBE_OBJ), "back_material": "jade"})
    s = sl.Scene.from_dict(doc)
    assert s.objects[0].back_material == sl.load_scene_dict(BASE).scene.objects[0].material
    assert s.objects[2].back_material == sl.Material.preset("jade")


def test_back_material_shows_on_back_faces():
    # A plane seen from below: its back faces, lit with the back material when two-sided.
    cam = sl.Camera.look_at(eye=(0, -3, 0.01), target=(0, 0, 0), fov_y=40)
    doc = {
        "version": 1,
        "two_sided": True,
        "lights": [{"type": "directional", "direction": [0, 1, 0]}],
        "objects": [{"mesh": {"primitive": "plane"}, "material": "gold"}],
    }
    plain = sl.render(sl.Scene.from_dict(doc), cam, width=16, height=16)
    doc["objects"][0]["back_material"] = {
        "diffuse": [0, 0, 1],
        "ambient": [0, 0, 0],
        "specular": [0, 0, 0],
    }
    back = sl.render(sl.Scene.from_dict(doc), cam, width=16, height=16)
    assert back[8, 8, 2] > 0 and back[8, 8, 0] == 0 and plain[8, 8, 0] > 0


def test_ico_sphere_primitive():
    d = {"version": 1, "objects": [{"mesh": {"primitive": "ico_sphere", "subdivisions": 2}}]}
    s = sl.Scene.from_dict(d)
    assert s.n_triangles == 20 * 4**2
    assert s.to_dict()["objects"][0]["mesh"] == {"primitive": "ico_sphere", "subdivisions": 2}
    d["objects"][0]["mesh"] = {"primitive": "ico_sphere"}
    assert sl.Scene.from_dict(d).n_triangles == 20 * 4**3


# ---------------------------------------------------------------------------------------
# Every error path: (where to put the bad value, the value, the key path, message part)

ERRORS = [
    (("version",), 3, "version", "expected 1 or 2 (the schema versions"),
    (("version",), True, "version", "got True"),
    (("version",), "1", "version", "got '1'"),
    (("version",), DELETE, "version", "missing required key"),
    (("colour",), 1, "colour", "unknown key 'colour'; expected one of: version, ambient, "),
    (("ambient",), [1, 2], "ambient", "ambient must be 3 numbers, got shape (2)"),
    (("ambient",), [1, -2, 0], "ambient", "scene ambient must be finite and >= 0, got"),
    (("ambient",), [1, "a", 0], "ambient[1]", "got 'a'"),
    (
        ("ambient",),
        [1, float("nan"), 0],
        "ambient",
        "ambient[1] = NaN is not a finite float32 value",
    ),
    (("ambient",), [1, True, 0], "ambient[1]", "got True"),
    (("ambient",), "grey", "ambient", "expected an array of numbers, got 'grey'"),
    (("two_sided",), 1, "two_sided", "expected true or false, got 1"),
    (("local_viewer",), "yes", "local_viewer", "expected true or false"),
    (("camera",), 5, "camera", "expected a table, got 5"),
    (("camera", "fov"), 40, "camera.fov", "unknown key 'fov'; expected one of: eye, target"),
    (("camera", "type"), "fisheye", "camera.type", "expected one of 'perspective', "),
    (("camera", "eye"), DELETE, "camera.eye", "missing required key"),
    (("camera", "eye"), [0, 0], "camera.eye", "eye must be 3 numbers, got shape (2)"),
    (("camera", "fov_y"), 180, "camera.fov_y", "fov_y must be in (0, 180) degrees, got 180"),
    (("camera", "fov_y"), 0, "camera.fov_y", "fov_y must be in (0, 180) degrees, got 0"),
    (("camera", "near"), 0, "camera.near", "a perspective camera needs 0 < near < far"),
    (("camera", "height"), 2, "camera.height", "unknown key 'height'"),
    (
        ("camera", "target"),
        [0.5, 0.4, 3.0],
        "camera.target",
        "camera eye and target must be distinct points",
    ),
    (("camera", "up"), [0, 0, 0], "camera.up", "camera up [0.0, 0.0, 0.0] must not be zero or"),
    (
        ("camera", "up"),
        [0.5, 0.4, 3.0],
        "camera.up",
        "camera up [0.5, 0.4, 3.0] must not be zero or",
    ),
    (
        ("camera",),
        {"type": "orthographic", "eye": [0, 0, 1], "target": [0, 0, 0], "fov_y": 30},
        "camera.fov_y",
        "unknown key 'fov_y'",
    ),
    (
        ("camera",),
        {"type": "orthographic", "eye": [0, 0, 1], "target": [0, 0, 0], "height": 0},
        "camera.height",
        "orthographic height must be > 0, got 0",
    ),
    (("render",), [], "render", "expected a table"),
    (("render", "dtype"), "float32", "render.dtype", "dtype is not a file option"),
    (("render", "width"), 0, "render.width", "width must be between 1 and 16384, got 0"),
    (("render", "width"), 10.0, "render.width", "got 10.0"),
    (("render", "height"), 20000, "render.height", "height must be between 1 and 16384, got 20000"),
    (
        ("render", "shading"),
        "toon",
        "render.shading",
        "unknown shading mode 'toon'; expected 'flat',",
    ),
    (("render", "specular"), "cook", "render.specular", "unknown specular model 'cook'; expected"),
    (
        ("render", "background"),
        [0, 0],
        "render.background",
        "background must be 3 numbers, got shape (2)",
    ),
    (
        ("render", "background"),
        [0, 0, float("inf")],
        "render.background",
        "background[2] = inf is not a finite float32",
    ),
    (("render", "cull_backfaces"), "no", "render.cull_backfaces", "expected true or false"),
    (("render", "cull_hidden"), 1, "render.cull_hidden", "expected true or false"),
    (("render", "threads"), 0, "render.threads", "threads must be between 1 and 256 (or None for"),
    (
        ("render", "threads"),
        257,
        "render.threads",
        "threads must be between 1 and 256 (or None for",
    ),
    (("render", "samples"), 3, "render.samples", "samples must be 1, 2, 4, 8 or 16, got 3"),
    (("render", "supersample"), 9, "render.supersample", "supersample must be between 1 and 8"),
    (("render", "antialias"), 4, "render.antialias", "unknown key 'antialias'"),
    (("fog",), "thick", "fog", "expected a table"),
    (("fog", "mode"), "fast", "fog.mode", "unknown fog mode 'fast'; expected 'linear',"),
    (("fog", "density"), 0.5, "fog.density", "unknown key 'density'"),
    (("fog", "end"), 1.0, "fog.end", "linear fog needs finite start < end, got"),
    (("fog", "start"), "near", "fog.start", "expected a number, got 'near'"),
    (
        ("fog",),
        {"mode": "exp", "density": -1},
        "fog.density",
        "fog density must be finite and >= 0, got -1",
    ),
    (("fog",), {"mode": "exp2", "start": 1}, "fog.start", "unknown key 'start'"),
    (("fog", "color"), [0, 0, -1], "fog.color", "fog color must be finite and >= 0, got [0.0,"),
    (("materials",), [], "materials", "expected a table"),
    (("materials", "gold"), {"shininess": 1}, "materials.gold", "taken by a preset"),
    (("materials", "mine"), "gold", "materials.mine", "expected a table, got 'gold'"),
    (("materials", "mine", "shine"), 3, "materials.mine.shine", "unknown key 'shine'"),
    (
        ("materials", "mine", "shininess"),
        -1,
        "materials.mine.shininess",
        "material shininess must be >= 0",
    ),
    (("materials", "mine", "preset"), "unobtainium", "materials.mine.preset", "unknown material"),
    (("materials", "mine", "preset"), 3, "materials.mine.preset", "expected a string, got 3"),
    (
        ("materials", "mine", "diffuse"),
        [1, 1],
        "materials.mine.diffuse",
        "diffuse must be 3 numbers, got shape (2)",
    ),
    (
        ("materials", "mine", "emission"),
        [1, 1, -1],
        "materials.mine.emission",
        "material emission must be finite and >= 0, got",
    ),
    (("lights",), {}, "lights", "expected an array of tables, got a table"),
    (("lights", 0), 3, "lights[0]", "expected a table, got 3"),
    (("lights", 0, "type"), "laser", "lights[0].type", "expected one of 'directional', "),
    (("lights", 0, "type"), DELETE, "lights[0].type", "missing required key; expected one"),
    (
        ("lights", 0, "direction"),
        [0, 0, 0],
        "lights[0].direction",
        "light direction must be finite and non-zero,",
    ),
    (("lights", 0, "direction"), DELETE, "lights[0].direction", "missing required key"),
    (("lights", 0, "position"), [0, 0, 0], "lights[0].position", "unknown key 'position'"),
    (
        ("lights", 0, "intensity"),
        -1,
        "lights[0].intensity",
        "light intensity must be finite and >= 0, got -1",
    ),
    (
        ("lights", 0, "color"),
        "white",
        "lights[0].color",
        "expected an array of numbers, got 'white'",
    ),
    (
        ("lights", 0, "ambient"),
        [0, -0.1, 0],
        "lights[0].ambient",
        "light ambient must be finite and >= 0, got",
    ),
    (
        ("lights", 0, "diffuse"),
        [0, -0.1, 0],
        "lights[0].diffuse",
        "light diffuse colour must be finite and >= 0,",
    ),
    (
        ("lights", 1, "specular"),
        "red",
        "lights[1].specular",
        "expected an array of numbers, got 'red'",
    ),
    (
        ("lights", 2, "diffuse"),
        [1, 1],
        "lights[2].diffuse",
        "diffuse must be 3 numbers, got shape (2)",
    ),
    (("lights", 3, "specular"), [1, 1, True], "lights[3].specular[2]", "got True"),
    (("lights", 1, "attenuation"), [0, 0, 0], "lights[1].attenuation", "not all zero"),
    (
        ("lights", 1, "attenuation"),
        [1, -1, 0],
        "lights[1].attenuation",
        "attenuation (kc, kl, kq) must be finite, >= 0",
    ),
    (("lights", 1, "cutoff"), 30, "lights[1].cutoff", "unknown key 'cutoff'"),
    (("lights", 1, "position"), DELETE, "lights[1].position", "missing required key"),
    (
        ("lights", 2, "cutoff"),
        200,
        "lights[2].cutoff",
        "spot cutoff must be in (0, 90] degrees or",
    ),
    (("lights", 2, "cutoff"), 0, "lights[2].cutoff", "spot cutoff must be in (0, 90] degrees or"),
    (("lights", 2, "cutoff"), "wide", "lights[2].cutoff", "got 'wide'"),
    (
        ("lights", 2, "exponent"),
        -1,
        "lights[2].exponent",
        "spot exponent must be finite and >= 0, got -1",
    ),
    (("lights", 2, "inner"), 30, "lights[2].inner", "spot inner angle must be in [0, cutoff) with"),
    (("lights", 2, "one_sided"), True, "lights[2].one_sided", "unknown key 'one_sided'"),
    (
        ("lights", 3, "samples"),
        0,
        "lights[3].samples",
        "area light samples must be between 1 and 64 per",
    ),
    (("lights", 3, "samples"), 65, "lights[3].samples", "got 65"),
    (("lights", 3, "samples"), 2.0, "lights[3].samples", "got 2.0"),
    (
        ("lights", 3, "shape"),
        "triangle",
        "lights[3].shape",
        "unknown area light shape 'triangle'; expected",
    ),
    (("lights", 3, "one_sided"), 1, "lights[3].one_sided", "expected true or false"),
    (
        ("lights", 3, "v"),
        [2, 0, 0],
        "lights[3].v",
        "area light edges u=[1.0, 0.0, 0.0] and v=[2.0,",
    ),
    (("lights", 3, "u"), DELETE, "lights[3].u", "missing required key"),
    (("objects",), {"mesh": "x"}, "objects", "expected an array of tables"),
    (("objects", 0), 3, "objects[0]", "expected a table, got 3"),
    (("objects", 0, "mesh"), DELETE, "objects[0].mesh", "missing required key"),
    (("objects", 0, "mesh"), 5, "objects[0].mesh", "a file path, a {primitive = ...} table"),
    (("objects", 0, "mesh", "primitive"), "torus", "objects[0].mesh.primitive", "'sphere'"),
    (
        ("objects", 0, "mesh"),
        {"primitive": "ico_sphere", "subdivisions": 11},
        "objects[0].mesh.subdivisions",
        "ico_sphere needs 0 <= subdivisions <= 10, got 11",
    ),
    (
        ("objects", 0, "mesh"),
        {"primitive": "ico_sphere", "rings": 3},
        "objects[0].mesh.rings",
        "unknown key 'rings'; expected one of: primitive, subdivisions",
    ),
    (
        ("objects", 0, "mesh", "rings"),
        1,
        "objects[0].mesh.rings",
        "uv_sphere needs rings >= 2 and segments >= 3,",
    ),
    (("objects", 0, "mesh", "segments"), 2.5, "objects[0].mesh.segments", "got 2.5"),
    (("objects", 0, "mesh", "radius"), 1, "objects[0].mesh.radius", "unknown key 'radius'"),
    (("objects", 0, "mesh"), {"primitive": "cube", "rings": 3}, "objects[0].mesh.rings", "unknown"),
    (("objects", 0, "material"), "unobtainium", "objects[0].material", "unknown material"),
    (("objects", 0, "material"), {"gloss": 1}, "objects[0].material.gloss", "unknown key"),
    (("objects", 0, "material"), 3, "objects[0].material", "a material name or a table"),
    (("objects", 0, "back_material"), "nope", "objects[0].back_material", "unknown material"),
    (("objects", 0, "back_material"), {"shininess": -2}, "objects[0].back_material.shininess", ""),
    (("objects", 0, "colour"), 1, "objects[0].colour", "unknown key 'colour'"),
    (
        ("objects", 0, "transform"),
        [[1, 0, 0, 0]],
        "objects[0].transform",
        "transform must have shape (4, 4), got (1, 4)",
    ),
    (
        ("objects", 0, "transform"),
        [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]],
        "objects[0].transform",
        "transform must be affine (last row 0 0 0 1),",
    ),
    (
        ("objects", 0, "transform"),
        [[1, 0, 0, 0], [0, 1, "x", 0], [0, 0, 1, 0], [0, 0, 0, 1]],
        "objects[0].transform[1][2]",
        "expected a number, got 'x'",
    ),
    (
        ("objects", 0, "transform"),
        [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
        "objects[0].transform",
        "transform is singular (its 3x3 part has no",
    ),
    (("objects", 0, "scale"), 0, "objects[0]", "transform is singular (its 3x3 part has no"),
    (
        ("objects", 0, "scale"),
        [1, 0, 1],
        "objects[0]",
        "transform is singular (its 3x3 part has no",
    ),
    (("objects", 0, "scale"), "big", "objects[0].scale", "expected an array of numbers, got 'big'"),
    (("objects", 0, "rotate"), [1, 2], "objects[0].rotate", "an array of 3 numbers"),
    (("objects", 0, "translate"), [1, True, 0], "objects[0].translate[1]", "got True"),
    (
        ("objects", 1, "mesh", "faces"),
        [[0, 1, 3]],
        "objects[1].mesh.faces",
        "faces[0, 2] = 3 is out of range for 3 vertices",
    ),
    (
        ("objects", 1, "mesh", "faces"),
        [[0, 1, 2**70]],
        "objects[1].mesh.faces",
        "faces must be an integer array, got dtype object",
    ),
    (
        ("objects", 1, "mesh", "faces"),
        [[0, -1, 2]],
        "objects[1].mesh.faces",
        "faces[0, 1] = -1 is out of range for 3 vertices",
    ),
    (("objects", 1, "mesh", "faces"), [[0, 1, 2.0]], "objects[1].mesh.faces[0][2]", "an integer"),
    (
        ("objects", 1, "mesh", "faces"),
        [[0, 1]],
        "objects[1].mesh.faces",
        "faces must have shape (M, 3), got (1, 2)",
    ),
    (("objects", 1, "mesh", "faces"), DELETE, "objects[1].mesh.faces", "missing required key"),
    (("objects", 1, "mesh"), {}, "objects[1].mesh", "a {primitive = ...} table or an inline"),
    (
        ("objects", 1, "mesh", "vertices"),
        [],
        "objects[1].mesh.vertices",
        "vertices must have shape (N, 3), got (0)",
    ),
    (
        ("objects", 1, "mesh", "vertices"),
        [[0, 0, 0], [1, 0], [0, 1, 0]],
        "objects[1].mesh.vertices",
        "vertices must be array-like of numbers:",
    ),
    (
        ("objects", 1, "mesh", "normals"),
        [[0, 0, 1]],
        "objects[1].mesh",
        "normals has 1 rows but the mesh has 3 vertices",
    ),
    (
        ("objects", 1, "mesh", "uvs"),
        [[0, 0, 1]] * 3,
        "objects[1].mesh.uvs",
        "uvs must have shape (N, 2), got (3, 3)",
    ),
    (("objects", 1, "mesh", "colours"), [], "objects[1].mesh.colours", "unknown key 'colours'"),
]


@pytest.mark.parametrize(("path", "value", "key", "message"), ERRORS)
def test_schema_errors_name_the_key_path(path, value, key, message):
    doc = mutate(path, value)
    with pytest.raises(sl.SceneFileError) as e:
        sl.load_scene_dict(doc)
    assert e.value.key == key
    assert str(e.value).startswith(key + ": ")
    assert message in str(e.value)
    assert isinstance(e.value, ValueError)


def test_spot_inner_needs_a_cone():
    doc = mutate(("lights", 2, "cutoff"), 180)
    doc["lights"][2]["inner"] = 10
    with pytest.raises(
        sl.SceneFileError, match=r"^lights\[2\]\.inner: spot inner angle .* with cutoff <= 90"
    ):
        sl.load_scene_dict(doc)


def test_base_document_is_valid():
    sf = sl.load_scene_dict(BASE)
    assert sf.scene.n_lights == 4 and sf.scene.n_objects == 2
    assert sf.render().shape == (32, 48, 3)


def test_not_a_table():
    with pytest.raises(sl.SceneFileError, match=r"^document: expected a table, got 3"):
        sl.load_scene_dict(3)
    with pytest.raises(sl.SceneFileError, match=r"^document: expected a table"):
        sl.Scene.from_dict([1])


def test_file_errors_name_the_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("version = 1\n[[lights]]\ntype = 'spot'\nposition = [0, 1, 0]\n")
    with pytest.raises(sl.SceneFileError) as e:
        sl.load_scene(p)
    assert str(e.value) == f"{p}: lights[0].direction: missing required key"
    assert (e.value.path, e.value.key) == (str(p), "lights[0].direction")

    p.write_text("version = 1\nambient = [0.1, 0.1\n")
    with pytest.raises(sl.SceneFileError, match="not valid TOML") as e:
        sl.load_scene(p)
    assert e.value.path == str(p)

    p.write_bytes(b"version = 1\nname = '\xff'\n")
    with pytest.raises(sl.SceneFileError, match="not valid TOML"):
        sl.load_scene(p)

    with pytest.raises(FileNotFoundError):
        sl.load_scene(tmp_path / "missing.toml")
    with pytest.raises(FileNotFoundError):
        sl.Scene.from_file(tmp_path / "missing.toml")
    with pytest.raises(IsADirectoryError):
        sl.load_scene(tmp_path)


def test_missing_and_malformed_mesh_files(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text('version = 1\n[[objects]]\nmesh = "nope.obj"\n')
    with pytest.raises(sl.SceneFileError) as e:
        sl.load_scene(p)
    assert e.value.key == "objects[0].mesh"
    assert f"no such file: '{tmp_path / 'nope.obj'}'" in str(e.value)
    (tmp_path / "bad.obj").write_text("v 0 0\nf 1 2 3\n")
    p.write_text('version = 1\n[[objects]]\nmesh = "bad.obj"\n')
    with pytest.raises(sl.SceneFileError, match=r"objects\[0\]\.mesh: .*bad\.obj") as e:
        sl.load_scene(p)
    assert isinstance(e.value.__cause__, sl.ObjParseError)
    (tmp_path / "dir.obj").mkdir()
    p.write_text('version = 1\n[[objects]]\nmesh = "dir.obj"\n')
    with pytest.raises(sl.SceneFileError, match=r"objects\[0\]\.mesh"):
        sl.load_scene(p)


# ---------------------------------------------------------------------------------------
# The command line


def read_png(path) -> np.ndarray:
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


def test_cli_renders_a_scene_file(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(sl.to_toml(BASE))
    out = tmp_path / "out.png"
    r = run("render", p, "-o", out)
    assert r.returncode == 0, r.stderr
    assert "wrote" in r.stdout and "48x32" in r.stdout
    img = read_png(out)
    expected = sl.load_scene(p).render()
    assert np.array_equal(img, expected)
    # Flags override the file's render options.
    r = run("render", p, "-o", out, "--size", "20x10", "--shading", "flat")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(
        read_png(out), sl.load_scene(p).render(width=20, height=10, shading="flat")
    )


def test_cli_scene_file_without_camera_is_framed(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(
        "version = 1\n[[lights]]\ntype = 'directional'\ndirection = [0, -1, -1]\n"
        "[[objects]]\nmesh = { primitive = 'sphere' }\n"
    )
    out = tmp_path / "o.png"
    r = run("render", p, "-o", out, "--size", "40x30")
    assert r.returncode == 0, r.stderr
    img = read_png(out)
    assert img.shape == (30, 40, 3) and img[15, 20].max() > 0 and img[0, 0].max() == 0


def test_cli_example_file(tmp_path):
    out = tmp_path / "ex.png"
    r = run("render", EXAMPLE, "-o", out, "--size", "64x40")
    assert r.returncode == 0, r.stderr
    assert read_png(out).shape == (40, 64, 3)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--material", "gold"], "--material cannot be used with a scene file"),
        (["--ambient", "0,0,0"], "--ambient cannot be used with a scene file"),
    ],
)
def test_cli_rejects_model_options_with_a_scene_file(tmp_path, extra, message):
    p = tmp_path / "s.toml"
    p.write_text(sl.to_toml(BASE))
    r = run("render", p, "-o", tmp_path / "o.png", *extra)
    assert r.returncode == 1
    assert r.stderr.strip() == f"shadelab: error: {message}; set it in the file"


def test_cli_reports_schema_errors_on_one_line(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(sl.to_toml(mutate(("lights", 2, "cutoff"), 200)))
    r = run("render", p, "-o", tmp_path / "o.png")
    assert r.returncode == 1
    assert r.stderr == (
        f"shadelab: error: {p}: lights[2].cutoff: spot cutoff must be in (0, 90] degrees"
        " or exactly 180 (no cone), got 200\n"
    )
