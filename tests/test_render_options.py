"""RenderOptions: the one spelling of the render options (render, render_frame, scene files,
the command line), and the stub that describes it."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest
import shadelab_rs as sl

STUB = Path(sl.__file__).with_name("_core.pyi")


@pytest.fixture(scope="module")
def scene_and_camera():
    s = sl.Scene()
    s.add(sl.Mesh.uv_sphere(8, 12), sl.Material.preset("gold"))
    s.add_light(sl.DirectionalLight((-1, -1, -1)))
    return s, sl.Camera.look_at((0, 0, 3), (0, 0, 0))


def test_defaults_and_round_trip():
    o = sl.RenderOptions()
    assert o.to_dict() == {
        "width": 800,
        "height": 600,
        "shading": "phong",
        "specular": "blinn",
        "background": (0.0, 0.0, 0.0),
        "cull_backfaces": False,
        "threads": None,
        "gouraud": "normals",
        "interpolation": "perspective",
        "samples": 1,
        "supersample": 1,
        "edges": None,
        "edge_color": (0.0, 0.0, 0.0),
        "edge_width": 1.0,
        "edge_angle": 30.0,
        "edges_only": False,
        "reflections": "environment",
        "refractions": None,
        "max_depth": 5,
        "tolerance": None,
        "cull_hidden": True,
    }
    p = sl.RenderOptions(64, 48, shading="FLAT", specular="blinn-normalized", threads=2)
    assert (p.width, p.height, p.shading, p.specular, p.threads) == (
        64,
        48,
        "flat",
        "blinn-normalized",
        2,
    )
    assert sl.RenderOptions(**p.to_dict()) == p
    assert p.replace(width=10) == sl.RenderOptions(10, 48, "flat", "blinn-normalized", threads=2)
    assert p.replace() == p and p != o
    assert repr(p).startswith("RenderOptions(width=64, height=48, shading='flat'")


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"width": 0}, "width"),
        ({"height": 2**70}, "height"),
        ({"shading": "toon"}, "shading"),
        ({"specular": "cook"}, "specular"),
        ({"background": (0, 0)}, "background"),
        ({"threads": 0}, "threads"),
        ({"gouraud": "faces"}, "gouraud"),
        ({"interpolation": "affine"}, "interpolation"),
        ({"samples": 3}, "samples"),
        ({"samples": 0}, "samples"),
        ({"samples": 2**70}, "samples"),
        ({"supersample": 0}, "supersample"),
        ({"supersample": 9}, "supersample"),
        ({"width": 4000, "supersample": 5}, "supersample"),
    ],
)
def test_bad_values_name_the_option(kwargs, field):
    with pytest.raises(ValueError) as e:
        sl.RenderOptions(**kwargs)
    assert e.value.field == field
    with pytest.raises(ValueError):
        sl.render(sl.Scene(), sl.Camera.look_at((0, 0, 3), (0, 0, 0)), **kwargs)


def test_render_takes_the_options_as_arguments_or_as_an_object(scene_and_camera):
    s, cam = scene_and_camera
    o = sl.RenderOptions(40, 30, shading="gouraud", background=(0.1, 0.2, 0.3))
    a = sl.render(s, cam, options=o)
    assert a.shape == (30, 40, 3)
    np.testing.assert_array_equal(a, sl.render(s, cam, **o.to_dict()))
    np.testing.assert_array_equal(
        a, sl.render(s, cam, 40, 30, shading="gouraud", background=(0.1, 0.2, 0.3))
    )
    # Keywords given with options= update it.
    b = sl.render(s, cam, options=o, shading="phong", dtype="float32")
    assert b.dtype == np.float32
    np.testing.assert_array_equal(
        b, sl.render(s, cam, options=o.replace(shading="phong"), dtype="float32")
    )
    frame = sl.render_frame(s, cam, options=o, return_depth=True)
    np.testing.assert_array_equal(frame["image"], a)
    assert frame["depth"].shape == (30, 40)


def test_render_rejects_unknown_or_doubled_options(scene_and_camera):
    s, cam = scene_and_camera
    with pytest.raises(TypeError, match="shadin"):
        sl.render(s, cam, shadin="flat")
    with pytest.raises(TypeError, match="not both"):
        sl.render(s, cam, 16, options=sl.RenderOptions())
    with pytest.raises(TypeError):
        sl.render(s, cam, 16, 16, "flat", "blinn", None, False, None, 3)


def _stub_class(name: str) -> ast.ClassDef:
    tree = ast.parse(STUB.read_text())
    return next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == name)


def test_the_stub_spells_the_options_as_the_extension_does():
    runtime = list(inspect.signature(sl.RenderOptions).parameters)
    new = next(f for f in _stub_class("RenderOptions").body if getattr(f, "name", "") == "__new__")
    assert [a.arg for a in new.args.args[1:]] == runtime  # also checked by stubtest
    typed = [
        n.target.id
        for n in _stub_class("_RenderOptionsArgs").body
        if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
    ]
    assert typed == runtime == list(sl.RenderOptions().to_dict())


def test_every_specular_and_shading_name_is_accepted_and_documented():
    tree = ast.parse(STUB.read_text())
    stub_doc = ast.get_docstring(_stub_class("RenderOptions")) or ""
    for alias in ("_Shading", "_Specular"):
        node = next(
            n
            for n in tree.body
            if isinstance(n, ast.AnnAssign) and getattr(n.target, "id", "") == alias
        )
        names = [c.value for c in ast.walk(node.value) if isinstance(c, ast.Constant)]
        key = "shading" if alias == "_Shading" else "specular"
        assert tuple(names) == getattr(sl.RenderOptions, key + "_names")
        for name in names:
            assert getattr(sl.RenderOptions(**{key: name}), key) == name
            assert f'"{name}"' in stub_doc, name


def test_scene_files_read_and_write_the_same_options(tmp_path, scene_and_camera):
    s, cam = scene_and_camera
    o = sl.RenderOptions(40, 30, specular="blinn-normalized", cull_backfaces=True)
    path = tmp_path / "s.toml"
    sl.save_scene(path, s, cam, render=o)
    sf = sl.load_scene(path)
    # threads=None (every core) is the default and TOML has no None: it is left out.
    assert "threads" not in sf.render_options
    assert sl.RenderOptions(**sf.render_options) == o
    np.testing.assert_array_equal(sf.render(), sl.render(s, cam, options=o))
    with pytest.raises(sl.SceneFileError, match=r"^render\.specular: unknown specular model"):
        sl.load_scene_dict({"version": 1, "render": {"specular": "cook"}})
