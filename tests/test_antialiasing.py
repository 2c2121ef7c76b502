"""Anti-aliasing (``samples``, ``supersample``) against the float64 coverage truth
(shadelab_ref.coverage): sample shares exactly, edge error falling with samples, interiors
unchanged, options through render, scene files and the command line."""

from __future__ import annotations

import pickle
import subprocess
import sys

import numpy as np
import pytest
import shadelab_rs as sl

from shadelab_ref.coverage import area_coverage, sample_coverage

W, H = 72, 56


def _white(triangles: np.ndarray) -> tuple[sl.Scene, sl.Camera]:
    """Screen-space triangles (pixels, y down) drawn in emission-only white over black,
    through an orthographic camera where one world unit is one pixel."""
    t = np.asarray(triangles, dtype=np.float64)
    v = np.column_stack([t[..., 0].ravel(), H - t[..., 1].ravel(), np.zeros(t.size // 2)])
    f = np.arange(len(v)).reshape(-1, 3)
    s = sl.Scene(ambient=(0, 0, 0), default_lights=False)
    black = (0.0, 0.0, 0.0)
    white = sl.Material(ambient=black, diffuse=black, specular=black, emission=(1, 1, 1))
    s.add(sl.Mesh(v, f), white)
    c = sl.Camera.orthographic((W / 2, H / 2, 10), (W / 2, H / 2, 0), height=H, near=1, far=100)
    return s, c


def _fan() -> np.ndarray:
    """Disjoint triangles around a centre with edges at many angles."""
    c = np.array([36.0, 28.0])
    a = 0.1 + 0.4537 * np.arange(13)
    r = np.where(np.arange(13) % 2 == 0, 25.0, 19.5)
    rim = c + np.column_stack([r * np.cos(a), r * np.sin(a)])
    return np.array([[c, rim[k], rim[k + 1]] for k in range(12)])


@pytest.mark.parametrize("n", [1, 2, 4, 8, 16])
def test_each_pixel_is_the_share_of_its_samples_inside(n):
    tris = _fan()
    s, c = _white(tris)
    img = sl.render(s, c, W, H, samples=n, dtype="float32")[..., 0]
    want = sample_coverage(tris, W, H, n)
    sure = ~np.isnan(want)
    assert sure.sum() > 0.8 * W * H
    np.testing.assert_array_equal(img[sure], want[sure].astype(np.float32))


def test_edge_error_falls_as_samples_grow_and_supersampling_converges():
    tris = _fan()
    s, c = _white(tris)
    exact = area_coverage(tris, W, H)
    edge = (exact > 1e-9) & (exact < 1 - 1e-9)
    assert edge.sum() > 200

    def rmse(**kw):
        img = sl.render(s, c, W, H, dtype="float32", **kw)[..., 0]
        return float(np.sqrt(np.mean((img[edge] - exact[edge]) ** 2)))

    errors = [rmse(samples=n) for n in (1, 2, 4, 8, 16)]
    assert all(b < a for a, b in zip(errors, errors[1:])), errors
    # The standard 16 positions: about 0.045 of the contrast across an edge.
    assert errors[-1] < 0.06, errors
    ss = [rmse(supersample=k) for k in (1, 2, 4, 8)]
    assert all(b < a for a, b in zip(ss, ss[1:])), ss
    assert ss[-1] < 0.03, ss


def interior(covered: np.ndarray) -> np.ndarray:
    """Pixels that are covered (with one sample) together with their 8 neighbours, away
    from the image border: every sample position of theirs lies on the same surface."""
    inner = covered.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(covered, dy, 0), dx, 1)
    inner[[0, -1], :] = inner[:, [0, -1]] = False
    return inner


def test_interior_pixels_keep_the_single_sample_colour():
    # One big lit triangle: a pixel whose samples all fall inside it is shaded once at its
    # centre, exactly as with one sample.
    v = np.array([[-3.0, -2.0, -4.0], [3.0, -1.5, -5.0], [0.2, 2.5, -4.5]])
    s = sl.Scene(default_lights=False)
    s.add(sl.Mesh(v, [[0, 1, 2]]), sl.Material.preset("gold"))
    s.add_light(sl.PointLight((0.5, 0.3, -2.0)))
    c = sl.Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=60, near=0.1, far=50)
    for shading in ("flat", "gouraud", "phong"):
        one, d1 = sl.render(s, c, 96, 80, shading=shading, dtype="float32", return_depth=True)
        inner = interior(np.isfinite(d1))
        assert inner.sum() > 1000
        for n in (2, 4, 8, 16):
            img, d = sl.render(
                s, c, 96, 80, shading=shading, samples=n, dtype="float32", return_depth=True
            )
            np.testing.assert_array_equal(img[inner], one[inner], err_msg=f"{shading} {n}")
            np.testing.assert_allclose(d[inner], d1[inner], rtol=1e-6)


def test_identical_for_any_thread_count():
    s, c = sl.demo_scene()
    for n in (4, 16):
        a = sl.render(s, c, 160, 120, samples=n, threads=1)
        b = sl.render(s, c, 160, 120, samples=n, threads=2)
        assert np.array_equal(a, b)


def test_options_round_trip_through_pickle_and_replace():
    o = sl.RenderOptions(64, 48, samples=8, supersample=2)
    assert (o.samples, o.supersample) == (8, 2)
    assert pickle.loads(pickle.dumps(o)) == o
    assert o.replace(samples=1).samples == 1
    assert sl.RenderOptions(**o.to_dict()) == o


@pytest.mark.parametrize(
    ("kwargs", "exc"),
    [
        ({"samples": 2.0}, TypeError),
        ({"samples": "4"}, TypeError),
        ({"supersample": -1}, ValueError),
    ],
)
def test_bad_types_and_values(kwargs, exc):
    with pytest.raises(exc, match=next(iter(kwargs))):
        sl.RenderOptions(**kwargs)


def test_scene_file_and_cli(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        "version = 1\n[render]\nwidth = 40\nheight = 30\nsamples = 4\n"
        '[[objects]]\nmesh = { primitive = "sphere" }\nmaterial = "gold"\n'
    )
    sf = sl.load_scene(path)
    assert sf.render_options["samples"] == 4
    assert sf.render().shape == (30, 40, 3)
    out = tmp_path / "o.png"
    cmd = [sys.executable, "-m", "shadelab_rs", "render", str(path), "-o", str(out)]
    subprocess.run([*cmd, "--samples", "16", "--supersample", "2"], check=True)
    assert out.exists()
    bad = subprocess.run([*cmd, "--samples", "3"], capture_output=True, text=True)
    assert bad.returncode == 1
    assert "samples must be 1, 2, 4, 8 or 16, got 3" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1


def test_alpha_is_the_coverage_and_the_colour_is_premultiplied():
    tris = _fan()
    s, c = _white(tris)
    for n in (1, 4, 16):
        f = sl.render(s, c, W, H, samples=n, dtype="float32", alpha=True)
        assert f.shape == (H, W, 4)
        share = sample_coverage(tris, W, H, n)
        sure = ~np.isnan(share)
        np.testing.assert_array_equal(f[..., 3][sure], share[sure].astype(np.float32))
        # White over a transparent background: premultiplied colour = coverage.
        np.testing.assert_array_equal(f[..., 0], f[..., 3])
        u = sl.render(s, c, W, H, samples=n, alpha=True)
        np.testing.assert_array_equal(u[..., 3], np.floor(f[..., 3] * 255 + 0.5))


def test_premultiplied_image_composites_to_the_render_over_a_background():
    s, c = sl.demo_scene()
    bg = np.array([0.2, 0.5, 0.9], dtype=np.float32)
    for kw in ({"samples": 8}, {"supersample": 2}, {}):
        rgba = sl.render(s, c, 160, 120, dtype="float32", alpha=True, background=bg, **kw)
        over = sl.render(s, c, 160, 120, dtype="float32", background=bg, **kw)
        a = rgba[..., 3:]
        if kw:
            assert ((a > 0) & (a < 1)).any()
        np.testing.assert_allclose(rgba[..., :3] + (1 - a) * bg, over, atol=2e-6)


def test_srgb_alpha_encodes_the_straight_colour():
    s, c = sl.demo_scene()
    lin = sl.render(s, c, 96, 72, dtype="float32", alpha=True, samples=4)
    enc = sl.render(s, c, 96, 72, dtype="float32", alpha=True, samples=4, encoding="srgb")
    a = lin[..., 3:]
    straight = np.divide(lin[..., :3], a, out=np.zeros_like(lin[..., :3]), where=a > 0)
    np.testing.assert_allclose(enc[..., :3], sl.srgb_encode(straight) * a, atol=1e-6)
    np.testing.assert_array_equal(enc[..., 3], lin[..., 3])


def test_cli_views_with_alpha_and_samples(tmp_path):
    out = tmp_path / "v_{:02d}.png"
    cmd = [sys.executable, "-m", "shadelab_rs", "demo", "-o", str(out), "--size", "64x48"]
    subprocess.run([*cmd, "--views", "2", "--alpha", "--samples", "4"], check=True)
    from PIL import Image

    with Image.open(tmp_path / "v_00.png") as im:
        a = np.asarray(im)
    assert a.shape == (48, 64, 4)
    assert ((a[..., 3] > 0) & (a[..., 3] < 255)).any()


def test_textured_surfaces_are_antialiased_and_keep_their_interior():
    # One big textured triangle: multi-sample pixels inside it are its single-sample pixels
    # (the texture sampled once at the centre, with the same footprint), edges blend.
    rng = np.random.default_rng(3)
    tex = sl.Texture(rng.random((37, 23, 3)).astype(np.float32), filter="trilinear")
    v = np.array([[-3.0, -2.0, -4.0], [3.0, -1.5, -5.0], [0.2, 2.5, -4.5]])
    uv = np.array([[0.0, 0.0], [3.0, 0.2], [1.2, 2.5]])
    s = sl.Scene(default_lights=False)
    mat = sl.Material((0.3, 0.3, 0.3), (0.8, 0.7, 0.6), (0.4, 0.4, 0.4), 20.0, diffuse_map=tex)
    s.add(sl.Mesh(v, [[0, 1, 2]], uvs=uv), material=mat)
    s.add_light(sl.PointLight((0.5, 0.3, -2.0)))
    c = sl.Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=60, near=0.1, far=50)
    for shading in ("flat", "gouraud", "phong"):
        one, d1 = sl.render(s, c, 96, 80, shading=shading, dtype="float32", return_depth=True)
        inner = interior(np.isfinite(d1))
        four = sl.render(s, c, 96, 80, shading=shading, samples=4, dtype="float32", alpha=True)
        np.testing.assert_array_equal(four[..., :3][inner], one[inner], err_msg=shading)
        a = four[..., 3]
        assert ((a > 0) & (a < 1)).sum() > 50, shading
