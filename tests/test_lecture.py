"""The lectures' own variants (issue 19): the perfect mirror exponent (``shininess=inf``),
Gouraud by averaged face intensities, and screen-space (scan-line) interpolation, each
against its definition computed in float64."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref import reference as ref

INF = float("inf")


def sphere_scene(shininess, specular=(0.6, 0.6, 0.6), light=(-0.3, -0.4, -1.0)):
    scene = sl.Scene(ambient=(0.1, 0.1, 0.1))
    m = sl.Material((0.2, 0.2, 0.2), (0.5, 0.4, 0.3), specular, shininess)
    scene.add(sl.Mesh.uv_sphere(16, 32), material=m)
    scene.add_light(sl.DirectionalLight(direction=light))
    return scene


SPHERE_CAM = sl.Camera.look_at(eye=(0, 0, 3), target=(0, 0, 0), fov_y=45.0, near=0.5, far=10)


# ---------------------------------------------------------------------------------------
# shininess = inf


@pytest.mark.parametrize("specular", ["blinn", "phong"])
@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_infinite_shininess_is_the_limit_of_large_exponents(shading, specular):
    """Away from the exact mirror direction x^f -> 0: the image with f = inf is the image
    without a specular term, and f = 1e2, 1e4, 1e6, 1e8 differ from it at ever fewer pixels
    (none left at 1e8 on this sphere)."""

    def img(shininess, ks=(0.6, 0.6, 0.6)):
        return sl.render(
            sphere_scene(shininess, ks),
            SPHERE_CAM,
            96,
            96,
            shading=shading,
            specular=specular,
            dtype="float32",
        )

    mirror = img(INF)
    assert np.isfinite(mirror).all()
    np.testing.assert_allclose(mirror, img(0.0, ks=(0, 0, 0)), rtol=0, atol=1e-6)
    differing = []
    for f in (1e2, 1e4, 1e6, 1e8):
        diff = np.abs(img(f) - mirror).max(axis=-1)
        differing.append(int((diff > 1e-6).sum()))
    assert differing[0] > 0, "the sphere must show a highlight at f = 100"
    assert differing == sorted(differing, reverse=True), differing
    assert differing[-1] == 0, differing


def mirror_quad_scene(shininess, light):
    """A unit quad in z = 0 facing +z, under a directional light, with the infinite viewer
    along +z: n·h is exactly 1 for a light travelling along -z."""
    scene = sl.Scene(ambient=(0, 0, 0), local_viewer=False)
    v = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]
    m = sl.Material((0, 0, 0), (0.25, 0.25, 0.25), (0.5, 0.5, 0.5), shininess)
    scene.add(sl.Mesh(v, [[0, 1, 2], [0, 2, 3]]), material=m)
    scene.add_light(sl.DirectionalLight(direction=light))
    return scene


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_infinite_shininess_in_the_exact_mirror_direction_is_the_whole_lobe(shading):
    """pow(x, inf) = 1 where x >= 1, 0 elsewhere: with n·h exactly 1 the specular term is
    ks·Is (as with f = 0), a hair off it nothing (as without a specular term)."""
    cam = sl.Camera.look_at(eye=(0, 0, 4), target=(0, 0, 0), fov_y=30.0, near=1, far=10)

    def img(shininess, light):
        return sl.render(
            mirror_quad_scene(shininess, light), cam, 24, 24, shading=shading, dtype="float32"
        )

    exact = img(INF, (0, 0, -1))
    covered = exact.any(axis=-1)
    assert covered.sum() > 100
    np.testing.assert_array_equal(exact[covered], 0.75)  # 0.25 diffuse + 0.5 specular
    np.testing.assert_array_equal(exact, img(0.0, (0, 0, -1)))
    off = img(INF, (0.001, 0, -1))
    np.testing.assert_allclose(off[covered], 0.25, rtol=0, atol=1e-6)


def test_infinite_shininess_with_the_normalised_lobe_is_refused():
    """(f + 8)/8π is infinite: a clear error naming shininess, not an overflow message."""
    with pytest.raises(ValueError, match="blinn-normalized") as e:
        sl.render(sphere_scene(INF), SPHERE_CAM, 8, 8, specular="blinn-normalized")
    assert e.value.field == "shininess"
    # Without a specular term there is no lobe to scale: it renders.
    img = sl.render(
        sphere_scene(INF, specular=(0, 0, 0)), SPHERE_CAM, 8, 8, specular="blinn-normalized"
    )
    assert img.any()


def test_shininess_values_accepted_and_refused():
    assert sl.Material(shininess=INF).shininess == INF
    assert "shininess=inf" in repr(sl.Material(shininess=INF))
    for bad in (-INF, float("nan"), -1.0):
        with pytest.raises(ValueError) as e:
            sl.Material(shininess=bad)
        assert e.value.field == "shininess"
    # A finite value beyond float32 is refused rather than silently becoming the mirror.
    with pytest.raises(ValueError, match="beyond float32") as e:
        sl.Material(shininess=1e300)
    assert e.value.field == "shininess"


def test_infinite_shininess_in_scene_files(tmp_path):
    doc = {
        "version": 1,
        "materials": {"mirror": {"preset": "chrome", "shininess": INF}},
        "lights": [{"type": "directional", "direction": [0, -1, 0]}],
        "objects": [{"mesh": {"primitive": "sphere"}, "material": "mirror"}],
    }
    sf = sl.load_scene_dict(doc)
    assert sf.scene.objects[0].material.shininess == INF
    path = tmp_path / "mirror.toml"
    path.write_text(sl.to_toml(sl.scene_to_dict(sf.scene)))
    assert "shininess = inf" in path.read_text()
    again = sl.load_scene(path)
    assert again.scene.objects[0].material == sf.scene.objects[0].material


# ---------------------------------------------------------------------------------------
# Gouraud by face intensities

MAT = ref.Material((0.2, 0.1, 0.1), (0.6, 0.5, 0.4), (0.5, 0.5, 0.5), 12.0, (0.02, 0, 0))
LIGHTS = [
    ref.DirectionalLight(direction=(-0.4, -0.6, -1.0), color=(1.0, 0.9, 0.8)),
    ref.PointLight(position=(2.0, 1.5, 2.5), color=(0.5, 0.6, 0.7)),
]
AMBIENT = (0.15, 0.15, 0.15)


def sl_scene(vertices, faces, material=MAT, two_sided=False):
    scene = sl.Scene(ambient=AMBIENT, two_sided=two_sided)
    m = sl.Material(
        material.ambient,
        material.diffuse,
        material.specular,
        material.shininess,
        emission=material.emission,
    )
    scene.add(sl.Mesh(vertices, faces), material=m)
    for light in LIGHTS:
        if isinstance(light, ref.DirectionalLight):
            scene.add_light(sl.DirectionalLight(light.direction, color=light.color))
        else:
            scene.add_light(sl.PointLight(light.position, color=light.color))
    return scene


def face_intensity_vertex_colors(vertices, faces, eye):
    """The lectures' simple method in float64: each face lit as flat shading lights it (unit
    face normal at the centroid), a vertex's colour the mean over the faces using it."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    centroid = v[f].mean(axis=1)
    face_color = ref.lighting(centroid, ref.face_normals(v, f), eye, MAT, LIGHTS, ambient=AMBIENT)
    total = np.zeros((len(v), 3))
    count = np.zeros(len(v))
    for face, c in zip(f, face_color):
        for k in set(face.tolist()):
            total[k] += c
            count[k] += 1
    return total / np.maximum(count, 1)[:, None]


def test_gouraud_face_intensities_against_its_definition():
    """Every covered pixel away from edges is the perspective-correct blend (the
    reference's barycentrics) of the float64 face-intensity vertex colours, within one
    8-bit level."""
    vertices, faces = ref.uv_sphere(8, 12)
    eye = (0.4, 0.9, 3.2)
    cam = ref.Camera(eye=eye, target=(0, 0, 0), up=(0, 1, 0), fov_y=40.0, near=0.5, far=20.0)
    w = h = 80
    r = ref.render_reference(
        vertices, faces, camera=cam, width=w, height=h, material=MAT, lights=LIGHTS,
        ambient=AMBIENT, shading="gouraud",
    )  # fmt: skip
    vc = face_intensity_vertex_colors(vertices, faces, eye)
    inside = r.mask & (r.edge_dist > 0.05)
    tri = r.tri[inside]
    want = np.einsum("pk,pkc->pc", r.bary[inside], vc[np.asarray(faces)[tri]])
    slc = sl.Camera.look_at(eye=eye, target=(0, 0, 0), fov_y=40.0, near=0.5, far=20.0)
    scene = sl_scene(vertices, faces)
    got = sl.render(scene, slc, w, h, shading="gouraud", gouraud="face-intensities")
    diff = np.abs(got[inside].astype(int) - ref.to_uint8(want).astype(int))
    assert inside.sum() > 1000
    assert diff.max() <= 1, diff.max()
    # It is a different picture from the default (vertex normals) one.
    default = sl.render(scene, slc, w, h, shading="gouraud")
    assert np.abs(default[inside].astype(int) - got[inside].astype(int)).max() >= 5
    # Flat and Phong ignore the option.
    for mode in ("flat", "phong"):
        np.testing.assert_array_equal(
            sl.render(scene, slc, w, h, shading=mode, gouraud="face-intensities"),
            sl.render(scene, slc, w, h, shading=mode),
        )


@pytest.mark.parametrize("eye_z", [2.5, -2.5])
def test_gouraud_face_intensities_of_a_flat_mesh_is_flat_shading(eye_z):
    """A planar mesh lit by a directional light and seen by the infinite viewer: every face
    has the same colour, so the averaged vertex colours are that colour too; seen from
    behind under two-sided lighting, the back material's flipped-normal colour."""
    scene = sl.Scene(ambient=AMBIENT, local_viewer=False, two_sided=True)
    grid = np.array([[x, y, 0.0] for y in range(4) for x in range(4)]) / 3 - 0.5
    faces = []
    for y in range(3):
        for x in range(3):
            a = y * 4 + x
            faces += [[a, a + 1, a + 5], [a, a + 5, a + 4]]
    scene.add(
        sl.Mesh(grid, faces),
        material=sl.Material.preset("gold"),
        back_material=sl.Material.preset("emerald"),
    )
    scene.add_light(sl.DirectionalLight(direction=(0.2, -0.3, -np.sign(eye_z))))
    cam = sl.Camera.look_at(eye=(0.3, 0.2, eye_z), target=(0, 0, 0), fov_y=40.0)
    flat = sl.render(scene, cam, 48, 48, shading="flat")
    assert flat.any(axis=-1).mean() > 0.2
    got = sl.render(scene, cam, 48, 48, shading="gouraud", gouraud="face-intensities")
    assert np.abs(flat.astype(int) - got.astype(int)).max() <= 1


def test_gouraud_option_names():
    assert sl.RenderOptions.gouraud_names == ("normals", "face-intensities")
    assert sl.RenderOptions().gouraud == "normals"
    assert sl.RenderOptions(gouraud="Face_Intensities").gouraud == "face-intensities"
    with pytest.raises(ValueError, match="face-intensities") as e:
        sl.RenderOptions(gouraud="faces")
    assert e.value.field == "gouraud"


# ---------------------------------------------------------------------------------------
# Screen-space interpolation

# A triangle tilted steeply away from the eye, 90° field of view: its far corner is ~7x as
# far as its near ones, where perspective and affine interpolation differ most.
TILTED = np.array([[-1.2, -0.9, -0.6], [1.3, -0.7, -0.8], [0.1, 0.8, -6.0]])
TILTED_NORMALS = np.array([[-0.6, 0.2, 1.0], [0.7, -0.3, 1.0], [0.0, 0.9, 0.5]])
W = H = 96


def scanline_weights(screen, w, h):
    """The lecture's scan-line interpolation, in float64: for each pixel row, the two edges
    crossing the row's centre give the span's end points, at which a vertex attribute is
    the linear blend along the edge in y; across the span it is the linear blend in x.
    Returned as the three vertex weights per pixel (NaN outside) and each pixel's distance
    to the nearest edge."""
    weights = np.full((h, w, 3), np.nan)
    dist = np.full((h, w), np.inf)
    eye3 = np.eye(3)
    edges = [(0, 1), (1, 2), (2, 0)]
    for j in range(h):
        y = j + 0.5
        ends = []
        for a, b in edges:
            (xa, ya), (xb, yb) = screen[a], screen[b]
            if ya == yb or not (min(ya, yb) <= y <= max(ya, yb)):
                continue
            t = (y - ya) / (yb - ya)  # I(y) = I_a + (I_b - I_a)(y - y_a)/(y_b - y_a)
            ends.append((xa + t * (xb - xa), (1 - t) * eye3[a] + t * eye3[b]))
        if len(ends) < 2:
            continue
        ends.sort(key=lambda e: e[0])
        (xl, wl), (xr, wr) = ends[0], ends[-1]
        for i in range(w):
            x = i + 0.5
            if xl < x < xr:
                s = (x - xl) / (xr - xl)  # I(x) = I_l + (I_r - I_l)(x - x_l)/(x_r - x_l)
                weights[j, i] = (1 - s) * wl + s * wr
    for a, b in edges:
        (xa, ya), (xb, yb) = screen[a], screen[b]
        px, py = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        num = np.abs((xb - xa) * (ya - py) - (xa - px) * (yb - ya))
        dist = np.minimum(dist, num / math.hypot(xb - xa, yb - ya))
    return weights, dist


def tilted_setup():
    cam = ref.Camera(eye=(0, 0, 0), target=(0, 0, -1), up=(0, 1, 0), fov_y=90.0, near=0.1)
    screen = ref.project_to_screen(TILTED, cam, W, H)  # the eye is at the origin
    weights, dist = scanline_weights(screen, W, H)
    inside = ~np.isnan(weights[..., 0]) & (dist > 0.05)
    scene = sl.Scene(ambient=AMBIENT)
    scene.add(sl.Mesh(TILTED, [[0, 1, 2]], normals=TILTED_NORMALS), material=sl_material())
    for light in LIGHTS:
        if isinstance(light, ref.DirectionalLight):
            scene.add_light(sl.DirectionalLight(light.direction, color=light.color))
        else:
            scene.add_light(sl.PointLight(light.position, color=light.color))
    slc = sl.Camera.look_at(eye=(0, 0, 0), target=(0, 0, -1), fov_y=90.0, near=0.1)
    return scene, slc, weights, inside


def sl_material():
    return sl.Material(MAT.ambient, MAT.diffuse, MAT.specular, MAT.shininess, emission=MAT.emission)


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


@pytest.mark.parametrize("shading", ["gouraud", "phong"])
def test_screen_interpolation_is_the_scan_line_formula(shading):
    """Gouraud's colours and Phong's normals and positions interpolated by the lecture's
    scan-line formula in float64: the renderer is within one 8-bit level at every pixel
    away from the edges, and the perspective-correct default differs by several levels."""
    scene, cam, weights, inside = tilted_setup()
    lam = weights[inside]
    eye = (0.0, 0.0, 0.0)
    normals = unit(TILTED_NORMALS)
    if shading == "gouraud":
        vertex_colors = ref.lighting(TILTED, normals, eye, MAT, LIGHTS, ambient=AMBIENT)
        want = lam @ vertex_colors
    else:
        want = ref.lighting(lam @ TILTED, unit(lam @ normals), eye, MAT, LIGHTS, ambient=AMBIENT)
    got = sl.render(scene, cam, W, H, shading=shading, interpolation="screen")
    diff = np.abs(got[inside].astype(int) - ref.to_uint8(want).astype(int))
    assert inside.sum() > 1500
    assert diff.max() <= 1, diff.max()
    perspective = sl.render(scene, cam, W, H, shading=shading)
    gap = np.abs(perspective[inside].astype(int) - got[inside].astype(int)).max()
    assert gap >= 3, gap


def test_screen_interpolation_keeps_depth_and_flat():
    """Depth output (and so fog) is the eye depth in both modes: with screen weights it
    comes from the depth buffer, interpolated over the snapped triangle (1/512 px), so on
    this steep triangle it is 1.8e-4 relative from the exact depth at worst where the
    perspective 1/w is 2e-7; flat has nothing to interpolate and is unchanged."""
    scene, cam, _, _ = tilted_setup()
    for mode in ("flat", "gouraud", "phong"):
        img_p, d_p = sl.render(scene, cam, W, H, shading=mode, return_depth=True)
        img_s, d_s = sl.render(
            scene, cam, W, H, shading=mode, interpolation="screen", return_depth=True
        )
        covered = np.isfinite(d_p)
        np.testing.assert_array_equal(covered, np.isfinite(d_s))
        np.testing.assert_allclose(d_s[covered], d_p[covered], rtol=1e-3)
        if mode == "flat":
            np.testing.assert_array_equal(img_s, img_p)


def test_interpolation_option_names():
    assert sl.RenderOptions.interpolation_names == ("perspective", "screen")
    assert sl.RenderOptions().interpolation == "perspective"
    o = sl.RenderOptions(interpolation="SCREEN", gouraud="face-intensities")
    assert sl.RenderOptions(**o.to_dict()) == o
    with pytest.raises(ValueError, match="perspective") as e:
        sl.RenderOptions(interpolation="affine")
    assert e.value.field == "interpolation"
