"""Six-face cube environments (issue 13): ``sl.Environment.from_cube`` and
``sl.load_environment`` with six files, in the OpenGL cube-map convention.

Tolerances: lookups against the float64 reference (shadelab_ref.reflect.cube_environment)
within 1e-5 relative (float32 texels and weights); a cube resampled from an
equirectangular sky renders like that sky within the resampling error of a smooth sky
(2e-3, stated at the test with the measured figures).
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reflect as rr

NAMES = ("+x", "-x", "+y", "-y", "+z", "-z")


def random_faces(n: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return (rng.random((6, n, n, 3)) * 3.0).astype(np.float32)


def directions(count: int, seed: int = 2) -> np.ndarray:
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(count, 3))
    # Near every edge and corner of the cube, where the seamless taps matter.
    edges = np.array(
        [[1, 1, 0.3], [1, -0.2, 1], [-1, 1, -0.7], [0.4, -1, -1], [1, 1, 1], [-1, -1, 1]], float
    )
    jitter = rng.normal(scale=1e-3, size=(200, 3))
    near = edges[rng.integers(0, len(edges), 200)] + jitter
    return np.concatenate([d, near])


@pytest.mark.parametrize("n, rotation, intensity", [(1, 0.0, 1.0), (5, 0.0, 1.0), (8, 35.0, 2.5)])
def test_cube_lookup_matches_the_float64_reference(n, rotation, intensity):
    faces = random_faces(n)
    env = sl.Environment.from_cube(faces, rotation=rotation, intensity=intensity)
    assert env.layout == "cube" and env.shape == (n, n)
    d = directions(2000)
    got = env.sample(d)
    want = rr.cube_environment(faces, d, rotation, intensity)
    assert np.allclose(got, want, rtol=1e-5, atol=1e-5), np.abs(got - want).max()


def test_faces_follow_the_opengl_convention():
    n = 4
    faces = np.zeros((6, n, n, 3), np.float32)
    for k in range(6):
        faces[k, ..., 0] = k
    faces[0, :, :, 1] = np.arange(n)[None, :]  # +X: column index in green
    faces[0, :, :, 2] = np.arange(n)[:, None]  # +X: row index in blue
    env = sl.Environment.from_cube(faces)
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    centre = env.sample(axes * 1.0)
    assert np.array_equal(centre[:, 0], np.arange(6))
    # On +X, s grows toward -z and t toward -y: (1, 0.5, -0.5) reads s = 0.75, t = 0.25,
    # i.e. column 0.75*4 - 0.5 = 2.5, row 0.5.
    c = env.sample(np.array([1.0, 0.5, -0.5]))
    assert c[1] == pytest.approx(2.5) and c[2] == pytest.approx(0.5)
    # A dict and a sequence give the same environment.
    assert sl.Environment.from_cube(dict(zip(NAMES, faces))) == env
    assert sl.Environment.from_cube(list(faces)) == env


def cube_from_equirect(env: sl.Environment, n: int) -> np.ndarray:
    """Each cube texel's centre direction looked up in ``env``."""
    out = np.zeros((6, n, n, 3), np.float32)
    s = (np.arange(n) + 0.5) / n
    ss, tt = np.meshgrid(s, s)  # rows: t, columns: s
    sc, tc = 2 * ss - 1, 2 * tt - 1
    one = np.ones_like(sc)
    dirs = [
        (one, -tc, -sc),
        (-one, -tc, sc),
        (sc, one, tc),
        (sc, -one, -tc),
        (sc, -tc, one),
        (-sc, -tc, -one),
    ]
    for k, (x, y, z) in enumerate(dirs):
        out[k] = env.sample(np.stack([x, y, z], axis=-1))
    return out


def smooth_sky(h: int) -> np.ndarray:
    """An equirectangular image of a colour smooth over the sphere of directions (no
    singularity at the poles): 0.5 + 0.4 d + 0.3 (d.x d.z, d.y d.z, d.x d.y)."""
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(2 * h) + 0.5) / (2 * h)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    theta, phi = vv * np.pi, (uu - 0.5) * 2 * np.pi
    x, y, z = np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)
    d = np.stack([x, y, z], axis=-1)
    return (0.5 + 0.4 * d + 0.3 * np.stack([x * z, y * z, x * y], axis=-1)).astype(np.float32)


def test_a_cube_resampled_from_an_equirectangular_sky_renders_the_same():
    equi = sl.Environment(smooth_sky(128))
    cube = sl.Environment.from_cube(cube_from_equirect(equi, 96))
    d = directions(3000)
    # Both are bilinear samplings of one smooth function: they differ by its curvature
    # over a texel (measured: lookups 6.5e-4 at most, the render 8.5e-4 at most and 1.0e-5
    # on average).
    assert np.abs(cube.sample(d) - equi.sample(d)).max() < 2e-3
    imgs = []
    for env in (equi, cube):
        scene = sl.Scene(environment=env)
        scene.add(sl.Mesh.uv_sphere(24, 48), material=sl.Material(reflectivity=0.9))
        cam = sl.Camera.look_at((0, 0.5, 3), (0, 0, 0), (0, 1, 0), fov_y=50)
        imgs.append(
            sl.render(scene, cam, 80, 60, background="environment", dtype="float32", samples=4)
        )
    diff = np.abs(imgs[0] - imgs[1])
    assert diff.max() < 2e-3 and diff.mean() < 1e-4, (diff.max(), diff.mean())


@pytest.mark.parametrize(
    "faces, message",
    [
        (np.zeros((5, 4, 4, 3), np.float32), "6 faces"),
        ([np.zeros((4, 4, 3), np.float32)] * 5 + [np.zeros((2, 2, 3), np.float32)], "one size"),
        ([np.zeros((4, 3, 3), np.float32)] * 6, "square"),
        ([np.zeros((4, 4), np.float32)] * 6, "shape"),
        ({k: np.zeros((2, 2, 3), np.float32) for k in NAMES[:5]}, "missing"),
        (np.full((6, 2, 2, 3), np.nan, np.float32), "finite"),
        (np.zeros((6, 0, 0, 3), np.float32), "empty"),
    ],
)
def test_bad_cubes_name_the_faces(faces, message):
    with pytest.raises(ValueError, match=message) as e:
        sl.Environment.from_cube(faces)
    assert e.value.field == "faces"


def test_bad_cube_arguments():
    with pytest.raises(TypeError) as e:
        sl.Environment.from_cube(3)
    assert e.value.field == "faces"
    with pytest.raises(ValueError) as e:
        sl.Environment.from_cube(random_faces(2), intensity=-1)
    assert e.value.field == "intensity"
    with pytest.raises(ValueError) as e:
        sl.Environment.from_cube(random_faces(2), srgb=True)
    assert e.value.field == "srgb"


def test_cube_files_pickle_scene_files_and_command_line(tmp_path):
    faces = random_faces(6)
    files = []
    for name, face in zip(("px", "nx", "py", "ny", "pz", "nz"), faces):
        files.append(tmp_path / f"{name}.npy")
        np.save(files[-1], face)
    env = sl.load_environment(files, rotation=20.0, intensity=0.5)
    assert env.layout == "cube" and env.face_paths == files and env.path is None
    assert env.array.shape == (6, 6, 6, 3) and np.array_equal(env.array, faces)
    assert sl.load_environment(dict(zip(NAMES, files)), 20.0, 0.5) == env
    back = pickle.loads(pickle.dumps(env))
    assert back == env and back.face_paths == files
    plain = sl.Environment.from_cube(faces)
    assert pickle.loads(pickle.dumps(plain)) == plain and plain.face_paths is None
    assert "cube" in repr(env)
    # Uint8 PNG faces are sRGB-decoded like an equirectangular PNG.
    from PIL import Image

    pngs = []
    for k in range(6):
        pngs.append(tmp_path / f"f{k}.png")
        Image.fromarray(np.full((4, 4, 3), 40 * k, np.uint8)).save(pngs[-1])
    png_env = sl.load_environment(pngs)
    assert png_env.array[5, 0, 0, 0] == pytest.approx(
        ((200 / 255 + 0.055) / 1.055) ** 2.4, abs=1e-6
    )
    with pytest.raises(ValueError, match="6 face files"):
        sl.load_environment(files[:4])
    with pytest.raises(ValueError, match="all be 8-bit"):
        sl.load_environment(files[:5] + pngs[:1])

    scene = sl.Scene(environment=env)
    scene.add(sl.Mesh.uv_sphere(8, 16), material=sl.Material(reflectivity=0.8))
    cam = sl.Camera.look_at((0, 1, 4), (0, 0, 0), (0, 1, 0))
    opts = {"width": 40, "height": 30, "background": "environment"}
    path = tmp_path / "cube.toml"
    sl.save_scene(path, scene, cam, opts)
    assert "faces" in path.read_text()
    sf = sl.load_scene(path)
    assert sf.scene.environment == env
    assert sf.render().tobytes() == sl.render(scene, cam, **opts).tobytes()
    d = sl.scene_to_dict(scene, cam, opts)
    assert d["environment"]["faces"] == [str(f) for f in files]
    d["environment"]["faces"] = d["environment"]["faces"][:3]
    with pytest.raises(sl.SceneFileError):
        sl.load_scene_dict(d, base_dir=tmp_path)

    from shadelab_rs import cli

    out = tmp_path / "c.png"
    args = ["render", str(sl.data_path("cube/cube.obj")), "-o", str(out), "--size", "32x24"]
    code = cli.main([*args, "--environment", *map(str, files), "--background", "environment"])
    assert code == 0
    assert np.asarray(Image.open(out)).std() > 0
    assert cli.main([*args, "--environment", *map(str, files[:3])]) != 0
