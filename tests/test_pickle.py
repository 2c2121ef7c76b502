"""Pickling and copying: every public class round-trips to an equal value and identical
renders; mesh buffers go out of band under pickle protocol 5."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest
import shadelab_rs as sl

KW = dict(width=96, height=72)

#: A light's pickled shadows when off.
_OFF = ("off", (2048, 3, 1.0, 1))


def _rich_scene() -> tuple[sl.Scene, sl.Camera]:
    """Every kind of light, fog, a back material, a shared mesh, loader-welded normals."""
    scene, camera = sl.demo_scene()
    scene.fog = sl.Fog(mode="exp2", density=0.05, color=(0.3, 0.4, 0.5))
    scene.two_sided = True
    scene.local_viewer = False
    sphere = sl.Mesh.uv_sphere(8, 12)
    back = sl.Material(diffuse=(0.1, 0.9, 0.2), emission=(0.05, 0, 0))
    for x in (-1.0, 1.0):
        t = np.diag([0.3, 0.3, 0.3, 1.0])
        t[:3, 3] = (x, 0.6, 0.2)
        scene.add(sphere, sl.Material.preset("jade"), t, back)
    scene.add_light(
        sl.DirectionalLight(
            (0.3, -1, 0.2), color=(1, 0.9, 0.8), ambient=(0.05,) * 3, diffuse=(1, 1, 1)
        )
    )
    scene.add_light(
        sl.SpotLight(
            (0, 3, 2), (0, -1, -0.7), cutoff=35, exponent=4, inner=20, attenuation=(1, 0.1, 0.01)
        )
    )
    scene.add_light(
        sl.AreaLight(
            (0, 2, 1),
            (0.5, 0, 0),
            (0, 0, 0.3),
            shape="disk",
            samples=3,
            one_sided=True,
            specular=(0.2, 0.2, 0.2),
        )
    )
    return scene, camera


_TEXTURE = sl.Texture(
    np.random.default_rng(3).random((5, 7, 3)).astype(np.float32),
    filter="nearest",
    wrap=("mirror", "clamp"),
)


def _objects() -> list[object]:
    scene, camera = _rich_scene()
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    return [
        sl.Mesh(verts, [[0, 1, 2]], normals=[[0, 0, 1]] * 3, uvs=[[0, 0], [1, 0], [0, 1]]),
        sl.Mesh.ico_sphere(2),
        sl.Material.preset("brass"),
        sl.Material(ambient=(0.1, 0.2, 0.3), shininess=7.5, emission=(0.01, 0.02, 0.03)),
        _TEXTURE,
        sl.Texture.procedural("noise", scale=3.5, color_a=(1, 0, 0), octaves=3, seed=7),
        sl.Material(diffuse_map=_TEXTURE, specular_map=sl.Texture.procedural("grid", width=0.2)),
        sl.DirectionalLight((1, -2, 3), color=(0.5, 0.6, 0.7), intensity=0.9),
        sl.PointLight((1, 2, 3), attenuation=(1, 0.5, 0.25), diffuse=(0.2, 0.3, 0.4)),
        sl.SpotLight((0, 1, 0), (0.3, -1, 0.1), cutoff=180),
        sl.AreaLight((0, 2, 0), (1, 0, 0), (0, 0, 1)),
        sl.DirectionalLight((0, -1, 0), shadows="exact"),
        sl.SpotLight((0, 1, 0), (0, -1, 0), shadows=True),
        sl.AreaLight((0, 2, 0), (1, 0, 0), (0, 0, 1), shadows=sl.ShadowSettings(512, "none")),
        sl.ShadowSettings(resolution=1024, kernel=5, bias=2.5),
        sl.Fog(mode="linear", start=1.5, end=7.25, color=(0.1, 0.2, 0.3)),
        sl.Fog(mode="exp", density=0.3),
        sl.Material(reflectivity=(0.5, 0.25, 0.125), transparency=0.25, ior="glass", fresnel=False),
        sl.Environment(np.linspace(0, 2, 24, dtype=np.float32).reshape(2, 4, 3), 12.5, 0.75),
        camera,
        sl.Camera.orthographic((0, 0, 5), (0, 0, 0), up=(0, 1, 0.1), height=3.5, near=-1, far=9),
        # Planes left as None are fitted at render time: they stay None.
        sl.Camera.look_at((1, 2, 3), (0, 0, 0)),
        sl.Camera.look_at((1, 2, 3), (0, 0, 0), near=0.25),
        sl.Camera.orthographic((0, 0, 5), (0, 0, 0), far=12.5),
        # A pinhole camera keeps its intrinsics (and its fitted planes).
        sl.Camera.from_intrinsics(
            (1, 2, 3),
            (0, 0, 0),
            fx=410.5,
            fy=390.25,
            cx=70.5,
            cy=40.0,
            skew=3.5,
            width=160,
            height=90,
            near=0.5,
        ),
        scene,
        scene.objects[0],
        sl.Scene(ambient=(0.1, 0.1, 0.1), default_lights=False),
        sl.RenderOptions(),
        sl.RenderOptions(
            64, 48, "gouraud", "blinn-normalized", (0.1, 0.2, 0.3), cull_backfaces=True, threads=3
        ),
    ]


@pytest.mark.parametrize("how", ["pickle", "pickle5", "deepcopy", "copy"])
def test_every_class_round_trips(how):
    for obj in _objects():
        if how == "pickle":
            back = pickle.loads(pickle.dumps(obj))
        elif how == "pickle5":
            back = pickle.loads(pickle.dumps(obj, protocol=5))
        elif how == "deepcopy":
            back = copy.deepcopy(obj)
        else:
            back = copy.copy(obj)
        assert type(back) is type(obj)
        assert back is not obj
        assert repr(back) == repr(obj), type(obj).__name__
        # The reduced state holds every stored value: equal states, equal objects.
        assert _state(back) == _state(obj), type(obj).__name__


def _state(obj: object) -> object:
    """A comparable view of ``obj.__reduce__()``'s state (arrays as bytes)."""

    def plain(v: object) -> object:
        if isinstance(v, np.ndarray):
            return (v.dtype.str, v.shape, v.tobytes())
        if isinstance(v, (list, tuple)):
            return tuple(plain(x) for x in v)
        if isinstance(v, dict):
            return tuple(sorted((k, plain(x)) for k, x in v.items()))
        if isinstance(
            v, (sl.Mesh, sl.DirectionalLight, sl.PointLight, sl.SpotLight, sl.AreaLight, sl.Texture)
        ):
            return plain(v.__reduce__()[1])
        return v

    return plain(obj.__reduce__()[1])  # type: ignore[attr-defined]


def test_all_public_classes_are_covered():
    kinds = {type(o) for o in _objects()}
    public = {
        v for v in vars(sl._core).values() if isinstance(v, type) and not issubclass(v, Exception)
    }
    assert public <= kinds, public - kinds


@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
def test_scene_round_trip_renders_identically(how):
    scene, camera = _rich_scene()
    back = pickle.loads(pickle.dumps(scene)) if how == "pickle" else copy.deepcopy(scene)
    cam = pickle.loads(pickle.dumps(camera))
    for shading in ("flat", "gouraud", "phong"):
        a, da = sl.render(scene, camera, shading=shading, return_depth=True, **KW)
        b, db = sl.render(back, cam, shading=shading, return_depth=True, **KW)
        assert a.tobytes() == b.tobytes(), shading
        assert da.tobytes() == db.tobytes(), shading


@pytest.mark.parametrize("how", ["pickle", "deepcopy", "copy"])
def test_state_of_the_other_branches_survives(how):
    """Light directions as given (not normalised), Scene.default_lights, planes left to
    fit (None) and RenderOptions round-trip, and the copy renders like the original."""

    def again(o: object) -> object:
        if how == "pickle":
            return pickle.loads(pickle.dumps(o))
        return copy.deepcopy(o) if how == "deepcopy" else copy.copy(o)

    d = sl.DirectionalLight((0.3, -2.0, 0.1))
    spot = sl.SpotLight((0, 3, 2), (0.0, -5.0, -3.5), cutoff=40)
    for light in (d, spot):
        back = again(light)
        assert back.direction == light.direction  # type: ignore[attr-defined]
    scene = sl.Scene()
    scene.add(sl.Mesh.ico_sphere(2))
    scene.add_light(d)
    scene.add_light(sl.PointLight((1, 1, 1)))
    scene.add_light(spot)
    back = again(scene)
    assert [lt.direction for lt in back.lights if not isinstance(lt, sl.PointLight)] == [
        (0.3, -2.0, 0.1),
        (0.0, -5.0, -3.5),
    ]
    unlit = sl.Scene(default_lights=False)
    unlit.add(sl.Mesh.ico_sphere(2))
    rigged = sl.Scene()
    rigged.add(sl.Mesh.ico_sphere(2))
    cam = sl.Camera.look_at((0, 0, 4), (0, 0, 0), near=None, far=9.0)
    cam_back = again(cam)
    assert (cam_back.near, cam_back.far) == (None, 9.0)
    for s in (scene, unlit, rigged):
        s_back = again(s)
        assert s_back.default_lights == s.default_lights
        assert sl.render(s_back, cam_back, **KW).tobytes() == sl.render(s, cam, **KW).tobytes()
    opts = sl.RenderOptions(32, 24, "flat", background=(0.5, 0.25, 0.125), threads=2)
    assert again(opts) == opts


def test_loader_normals_survive_pickling():
    """An OBJ with UV seams gets welded normals from the loader: they are kept as such
    (``has_normals`` stays False) and give the same shading."""
    cow = sl.load_obj(sl.data_path("spot/spot_triangulated.obj"))
    back = pickle.loads(pickle.dumps(cow))
    assert back.has_normals is cow.has_normals is False
    assert back.normals.tobytes() == cow.normals.tobytes()


def test_shared_mesh_is_pickled_once():
    mesh = sl.Mesh.uv_sphere(40, 80)
    one, many = sl.Scene(), sl.Scene()
    one.add(mesh)
    for i in range(10):
        many.add(mesh, transform=np.diag([1.0, 1.0, 1.0 + i, 1.0]))
    n1, n10 = len(pickle.dumps(one)), len(pickle.dumps(many))
    assert n10 < n1 * 1.1
    back = pickle.loads(pickle.dumps(many))
    assert back.n_triangles == many.n_triangles


def test_protocol5_passes_mesh_buffers_out_of_band():
    mesh = sl.Mesh.uv_sphere(64, 128)
    scene = sl.Scene()
    scene.add(mesh)
    for obj in (mesh, scene):
        buffers: list[pickle.PickleBuffer] = []
        data = pickle.dumps(obj, protocol=5, buffer_callback=buffers.append)
        # vertices, faces and the given normals: three buffers, and the pickle itself holds
        # none of their bytes.
        sizes = sorted(memoryview(b).nbytes for b in buffers)
        assert sizes == sorted([mesh.n_vertices * 12, mesh.n_faces * 12, mesh.n_vertices * 12])
        assert len(data) < 4096
        back = pickle.loads(data, buffers=buffers)
        m = back if isinstance(back, sl.Mesh) else back.objects[0].mesh
        assert m.vertices.tobytes() == mesh.vertices.tobytes()
        assert m.faces.tobytes() == mesh.faces.tobytes()


def test_copies_are_independent():
    scene, _ = _rich_scene()
    c = copy.deepcopy(scene)
    c.fog = None
    c.add_light(sl.PointLight((0, 0, 1)))
    assert scene.fog is not None and scene.n_lights == c.n_lights - 1
    s = copy.copy(scene)
    s.two_sided = False
    assert scene.two_sided


@pytest.mark.parametrize(
    ("kind", "state", "match"),
    [
        (
            "Mesh",
            (np.zeros((3, 3), np.float32), np.array([[0, 1, 5]], np.uint32), None, None, None),
            "out of range",
        ),
        ("Material", ((0, 0, 0), (1, 1, 1), (0, 0, 0), -1.0, (0, 0, 0)), "shininess"),
        (
            "DirectionalLight",
            ((0, 0, 2), (1, 1, 1), 1.0, (0, 0, 0), (None, None), (0, 0, 2), _OFF),
            "unit vector",
        ),
        (
            "DirectionalLight",
            ((0, 0, 1), (1, 1, 1), 1.0, (0, 0, 0), (None, None), (0, 0, 0), _OFF),
            "given direction",
        ),
        (
            "DirectionalLight",
            ((0, 0, 1), (1, 1, 1), 1.0, (0, 0, 0), (None, None), (0, 0, 1), ("soft", _OFF[1])),
            "shadows",
        ),
        ("ShadowSettings", (8, 3, 1.0, 1), "resolution"),
        ("ShadowSettings", (1024, 4, 1.0, 1), "kernel"),
        ("ShadowSettings", (1024, 3, 1.0, 9), "cascades"),
        ("RenderOptions", {"width": 0}, "width"),
        (
            "Camera",
            ("perspective", (0, 0, 0), (0, 0, 0), (0, 1, 0), 45.0, 0.1, 10.0, None),
            "distinct",
        ),
        (
            "Camera",
            ("pinhole", (0, 0, 1), (0, 0, 0), (0, 1, 0), 0.0, 0.1, 10.0, None),
            "no intrinsics",
        ),
        (
            "Camera",
            ("pinhole", (0, 0, 1), (0, 0, 0), (0, 1, 0), 0.0, 0.1, 10.0, (-1, 1, 0, 0, 0, 4, 4)),
            "fx",
        ),
        ("Scene", "nonsense", "Scene"),
        ("Teapot", (), "unknown"),
    ],
)
def test_corrupt_state_is_a_clear_error(kind, state, match):
    with pytest.raises(ValueError, match=match):
        sl._core._restore(kind, state)
