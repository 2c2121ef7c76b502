"""Property-based tests (hypothesis): random small scenes, cameras and options.

Every drawn scene is valid (the error paths live in test_errors.py) but otherwise arbitrary:
degenerate and sliver triangles, triangles crossing the near and far planes or behind the
eye, zero or unnormalised normals, shininess 0, lights inside the geometry, 1-pixel images.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl
from hypothesis import event, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

# Random scenes and cameras often see nothing; the warning that says so is not under test.
pytestmark = pytest.mark.filterwarnings("ignore::shadelab_rs.EmptyRenderWarning")

SETTINGS = settings(max_examples=25, deadline=None)
#: Lit colours are sums of products of non-negative terms, so this background marks exactly
#: the pixels no triangle covers.
BACKGROUND = (-1.0, -1.0, -1.0)

coords = st.floats(-3.0, 3.0, allow_nan=False, width=32)
unit = st.floats(0.0, 1.0, allow_nan=False, width=32)


def unit_vector(draw):
    """A random direction (rejecting near-zero draws)."""
    v = draw(arrays(np.float64, 3, elements=st.floats(-1.0, 1.0, width=32)))
    n = float(np.linalg.norm(v))
    if n < 1e-3:
        v, n = np.array([0.0, 0.0, 1.0]), 1.0
    return v / n


@st.composite
def meshes(draw):
    n_vertices = draw(st.integers(3, 8))
    vertices = draw(arrays(np.float64, (n_vertices, 3), elements=coords, fill=st.nothing()))
    index = st.integers(0, n_vertices - 1)
    # Mostly proper triangles; sometimes a repeated index (a degenerate triangle).
    corner_lists = st.lists(index, min_size=3, max_size=3, unique=draw(st.integers(0, 9)) > 0)
    faces = np.array(draw(st.lists(corner_lists, min_size=1, max_size=8)), dtype=np.int64)
    normals = None
    if draw(st.booleans()):
        normals = draw(arrays(np.float64, (n_vertices, 3), elements=st.floats(-2, 2, width=32)))
    return sl.Mesh(vertices, faces, normals=normals)


@st.composite
def transforms(draw):
    if draw(st.booleans()):
        return None
    axis = unit_vector(draw)
    angle = draw(st.floats(0.0, 2 * math.pi))
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    scale = draw(arrays(np.float64, 3, elements=st.floats(0.25, 3.0)))
    m = np.eye(4)
    m[:3, :3] = rot @ np.diag(scale)
    m[:3, 3] = draw(arrays(np.float64, 3, elements=st.floats(-1.0, 1.0)))
    return m


@st.composite
def lights(draw):
    color = tuple(draw(unit) for _ in range(3))
    intensity = draw(st.floats(0.0, 3.0))
    if draw(st.booleans()):
        return sl.DirectionalLight(tuple(unit_vector(draw)), color=color, intensity=intensity)
    position = tuple(draw(st.floats(-4.0, 4.0)) for _ in range(3))
    return sl.PointLight(position, color=color, intensity=intensity)


@st.composite
def scenes(draw):
    scene = sl.Scene(ambient=tuple(draw(unit) for _ in range(3)))
    for _ in range(draw(st.integers(1, 2))):
        material = sl.Material(
            ambient=tuple(draw(unit) for _ in range(3)),
            diffuse=tuple(draw(unit) for _ in range(3)),
            specular=tuple(draw(unit) for _ in range(3)),
            shininess=draw(st.sampled_from([0.0, 1.0, 7.5, 32.0, 128.0, 1000.0])),
        )
        scene.add(draw(meshes()), material=material, transform=draw(transforms()))
    for _ in range(draw(st.integers(0, 3))):
        scene.add_light(draw(lights()))
    return scene


@st.composite
def cameras(draw):
    target = draw(arrays(np.float64, 3, elements=st.floats(-1.0, 1.0)))
    up = np.array([0.0, 1.0, 0.0])
    direction = unit_vector(draw)
    if abs(direction @ up) > 0.999:  # up parallel to the view: an error, not a property
        direction = np.array([0.0, 0.0, 1.0])
    eye = target + direction * draw(st.floats(0.5, 8.0))
    near = draw(st.floats(0.01, 1.5))
    far = near + draw(st.floats(2.0, 50.0))
    if draw(st.booleans()):
        cam = sl.Camera.look_at(
            tuple(eye),
            tuple(target),
            up=tuple(up),
            fov_y=draw(st.floats(10.0, 150.0)),
            near=near,
            far=far,
        )
    else:
        cam = sl.Camera.orthographic(
            tuple(eye),
            tuple(target),
            up=tuple(up),
            height=draw(st.floats(1.0, 8.0)),
            near=near,
            far=far,
        )
    return cam


options = st.fixed_dictionaries(
    {
        "width": st.one_of(st.integers(1, 48), st.integers(24, 48)),
        "height": st.one_of(st.integers(1, 40), st.integers(24, 40)),
        "shading": st.sampled_from(["flat", "gouraud", "phong"]),
        "specular": st.sampled_from(["blinn", "phong"]),
        "cull_backfaces": st.booleans(),
    }
)


@SETTINGS
@given(scene=scenes(), camera=cameras(), opts=options)
def test_outputs_are_consistent(scene, camera, opts):
    """float32 output has no NaN or inf, uint8 output is exactly ``to_uint8`` of it, depth is
    +inf exactly where the background shows and within [near, far] elsewhere."""
    f32 = sl.render_frame(
        scene, camera, background=BACKGROUND, dtype="float32", return_depth=True, **opts
    )
    img, depth = f32["image"], f32["depth"]
    assert img.shape == (opts["height"], opts["width"], 3) and img.dtype == np.float32
    assert np.all(np.isfinite(img))
    empty = np.all(img == np.float32(-1.0), axis=-1)
    assert np.all(img[~empty] >= 0)
    np.testing.assert_array_equal(np.isposinf(depth), empty)
    assert not np.isnan(depth).any()
    covered = depth[~empty]
    assert np.all(covered >= camera.near * (1 - 1e-4))
    assert np.all(covered <= camera.far * (1 + 1e-4))
    if f32["stats"]["triangles_setup"] == 0:
        assert empty.all()
    # Shown by --hypothesis-show-statistics: how often the draws cover pixels and clip.
    event("covers pixels" if not empty.all() else "covers nothing")
    event("clipped" if f32["stats"]["triangles_clipped"] else "not clipped")

    u8, depth8 = sl.render(scene, camera, background=BACKGROUND, return_depth=True, **opts)
    assert u8.dtype == np.uint8
    np.testing.assert_array_equal(u8, sl.to_uint8(img))
    np.testing.assert_array_equal(depth8, depth)


@SETTINGS
@given(scene=scenes(), camera=cameras(), opts=options, dtype=st.sampled_from(["uint8", "float32"]))
def test_thread_count_never_changes_bytes(scene, camera, opts, dtype):
    outs = [
        sl.render(scene, camera, dtype=dtype, return_depth=True, threads=threads, **opts)
        for threads in (1, 2, 5, None)
    ]
    for img, depth in outs[1:]:
        assert img.tobytes() == outs[0][0].tobytes()
        assert depth.tobytes() == outs[0][1].tobytes()


@SETTINGS
@given(scene=scenes(), camera=cameras(), opts=options)
def test_rendering_twice_is_identical_and_culling_only_removes(scene, camera, opts):
    """Deterministic; culling back faces never covers a pixel that was empty without it."""
    opts = {**opts, "cull_backfaces": False}
    a = sl.render(scene, camera, dtype="float32", return_depth=True, **opts)
    b = sl.render(scene, camera, dtype="float32", return_depth=True, **opts)
    assert a[0].tobytes() == b[0].tobytes() and a[1].tobytes() == b[1].tobytes()
    culled = sl.render_frame(
        scene, camera, dtype="float32", return_depth=True, **{**opts, "cull_backfaces": True}
    )
    assert not np.any(np.isfinite(culled["depth"]) & np.isinf(a[1]))


def test_depth_stays_within_the_planes_where_a_snap_extrapolates():
    """A case hypothesis found: in a 1 x 11 image at a 112 degree field of view (pixels of
    about 10 degrees) a triangle cut by the near plane covers a pixel centre that lies a snap
    outside it, where its interpolated depth extrapolated 0.3 % before the near plane. The
    depth output is clamped to [near, far]."""
    vertices = np.array(
        [[0.0, 0.0, 0.0], [0.0, 2.53125, -0.17578125], [0.0, 0.0, 0.0], [1.5, -1.625, 1.0488281]],
        np.float32,
    )
    normals = np.tile(np.array([0.5284646, -0.058813587, -0.84691566], np.float32), (4, 1))
    transform = np.array(
        [
            [2.8131487369537354, -0.5359146595001221, -0.05683762952685356, 0.0],
            [0.4366205334663391, 2.848540782928467, -0.2116093784570694, 0.1953125],
            [0.3410577178001404, 0.7736998200416565, 0.739715576171875, 0.462890625],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )
    scene = sl.Scene(ambient=(0.0, 0.0, 0.0))
    scene.add(sl.Mesh(vertices, [[0, 1, 3]], normals), transform=transform)
    camera = sl.Camera.look_at(
        (-0.4014816282053353, 1.7951459199487365, 0.7589310834980609),
        (-0.703125, 0.0, 0.7589310834980609),
        up=(0.0, 1.0, 0.0),
        fov_y=111.8125,
        near=1.234375,
        far=3.234375,
    )
    out = sl.render_frame(
        scene,
        camera,
        width=1,
        height=11,
        shading="flat",
        cull_backfaces=False,
        dtype="float32",
        return_depth=True,
    )
    depth = out["depth"]
    covered = depth[np.isfinite(depth)]
    assert covered.size > 0, "the case covers a pixel"
    assert out["stats"]["triangles_clipped"] == 1
    assert covered.min() >= np.float32(camera.near)
    assert covered.max() <= np.float32(camera.far)
