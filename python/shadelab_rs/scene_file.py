"""Scene files: a versioned TOML schema for a scene, its camera and its render options.

The schema (version 1) is documented in docs/USER_GUIDE.md, "Scene files". Everything is
checked here, before any Rust object is built: every bad key or value raises
:class:`SceneFileError` naming its key path (``lights[2].cutoff``) and what was expected, and
unknown keys are errors. ``scene_to_dict`` writes the same schema as plain Python data (meshes
as primitives when they are one, else inline arrays), so ``scene_from_dict(scene_to_dict(s))``
renders bit-identically to ``s``; ``to_toml`` writes it as TOML without any dependency.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import re
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Union

import numpy as np

from ._core import (
    MAX_AREA_SAMPLES,
    MAX_IMAGE_SIZE,
    MAX_THREADS,
    AreaLight,
    Camera,
    DirectionalLight,
    Fog,
    Material,
    Mesh,
    PointLight,
    Scene,
    SpotLight,
    load_obj_parts,
)
from .io import load_mesh

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python < 3.11 only
    import tomli as tomllib

#: The schema version this release reads and writes.
SCHEMA_VERSION = 1

_PathLike = Union[str, "os.PathLike[str]"]
_Light = Union[DirectionalLight, PointLight, SpotLight, AreaLight]


class SceneFileError(ValueError):
    """A scene file or dict does not follow the schema. ``key`` is the key path of the
    offending value (``"lights[2].cutoff"``, ``""`` for the whole document) and ``path`` the
    scene file (None for a dict); the message starts with both."""

    def __init__(
        self,
        message: str,
        key: str = "",
        path: str | None = None,
        more: list[SceneFileError] | None = None,
    ) -> None:
        self.key = key
        self.path = path
        self.detail = message
        #: The document's other errors (each with its own key), reported on their own
        #: lines after this one: a file's mistakes are all shown at once.
        self.more = [SceneFileError(e.detail, e.key, path) for e in more or []]
        prefix = "".join(f"{p}: " for p in (path, key) if p)
        super().__init__("\n".join([prefix + message, *(str(e) for e in self.more)]))


# ---------------------------------------------------------------------------------------
# Checking helpers. `where` is always the key path of the value being checked.


def _at(where: str, key: str | int) -> str:
    if isinstance(key, int):
        return f"{where}[{key}]"
    return f"{where}.{key}" if where else key


def _show(v: Any) -> str:
    if isinstance(v, Mapping):
        return "a table"
    if isinstance(v, list) and len(v) > 6:
        return f"an array of {len(v)} values"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _fail(where: str, expected: str, got: Any) -> SceneFileError:
    return SceneFileError(f"expected {expected}, got {_show(got)}", where)


def _is_number(v: Any) -> bool:
    # TOML booleans arrive as bool, which is an int subclass: never a number here.
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _table(
    d: Any, where: str, required: tuple[str, ...] = (), optional: tuple[str, ...] = ()
) -> dict[str, Any]:
    """``d`` as a dict after checking it has every required key and no other key."""
    if not isinstance(d, Mapping):
        raise _fail(where or "document", "a table", d)
    allowed = required + optional
    for k in d:
        if not isinstance(k, str):
            raise SceneFileError(f"keys must be strings, got {k!r}", where)
        if k not in allowed:
            raise SceneFileError(
                f"unknown key '{k}'; expected one of: {', '.join(allowed)}", _at(where, k)
            )
    for k in required:
        if k not in d:
            raise SceneFileError("missing required key", _at(where, k))
    return dict(d)


def _number(
    v: Any,
    where: str,
    *,
    lo: float | None = None,
    lo_open: bool = False,
    hi: float | None = None,
    hi_open: bool = False,
) -> float:
    lo_s = "" if lo is None else ("(" if lo_open else "[") + f"{lo:g}"
    hi_s = "" if hi is None else f"{hi:g}" + (")" if hi_open else "]")
    if lo is not None and hi is not None:
        what = f"a number in {lo_s}, {hi_s}"
    elif lo is not None:
        what = f"a number {'>' if lo_open else '>='} {lo:g}"
    elif hi is not None:
        what = f"a number {'<' if hi_open else '<='} {hi:g}"
    else:
        what = "a finite number"
    if not _is_number(v) or not math.isfinite(v):
        raise _fail(where, what, v)
    x = float(v)
    if lo is not None and (x < lo or (lo_open and x == lo)):
        raise _fail(where, what, v)
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise _fail(where, what, v)
    return x


def _integer(v: Any, where: str, lo: int, hi: int | None = None) -> int:
    what = f"an integer in [{lo}, {hi}]" if hi is not None else f"an integer >= {lo}"
    if not isinstance(v, int) or isinstance(v, bool) or v < lo or (hi is not None and v > hi):
        raise _fail(where, what, v)
    return v


def _boolean(v: Any, where: str) -> bool:
    if not isinstance(v, bool):
        raise _fail(where, "true or false", v)
    return v


def _choice(v: Any, where: str, choices: tuple[str, ...]) -> str:
    if not isinstance(v, str) or v not in choices:
        raise _fail(where, "one of " + ", ".join(f"'{c}'" for c in choices), v)
    return v


def _vec3(v: Any, where: str, *, nonneg: bool = False, nonzero: bool = False) -> list[float]:
    what = "3 numbers" + (" >= 0" if nonneg else "") + (", not all zero" if nonzero else "")
    if not isinstance(v, list) or len(v) != 3:
        raise _fail(where, f"an array of {what}", v)
    for i, x in enumerate(v):
        if not _is_number(x) or not math.isfinite(x) or (nonneg and x < 0):
            raise _fail(_at(where, i), "a finite number" + (" >= 0" if nonneg else ""), x)
    if nonzero and all(x == 0 for x in v):
        raise _fail(where, f"an array of {what}", v)
    return [float(x) for x in v]


def _color(v: Any, where: str) -> list[float]:
    return _vec3(v, where, nonneg=True)


def _call(where: str, make: Callable[[], Any]) -> Any:
    """Runs a constructor, turning its ValueError (a check this module does not repeat)
    into a SceneFileError at ``where``."""
    try:
        return make()
    except SceneFileError:
        raise
    except (ValueError, TypeError) as e:
        raise SceneFileError(str(e), where) from e


# ---------------------------------------------------------------------------------------
# Materials


_MATERIAL_KEYS = ("preset", "ambient", "diffuse", "specular", "shininess", "emission")


def _material_table(v: Any, where: str) -> Material:
    t = _table(v, where, optional=_MATERIAL_KEYS)
    if "preset" in t:
        name = t["preset"]
        if not isinstance(name, str):
            raise _fail(_at(where, "preset"), "a preset name (a string)", name)
        base = _preset(name, _at(where, "preset"))
    else:
        base = Material()
    values: dict[str, Any] = {
        "ambient": base.ambient,
        "diffuse": base.diffuse,
        "specular": base.specular,
        "shininess": base.shininess,
        "emission": base.emission,
    }
    for k in ("ambient", "diffuse", "specular", "emission"):
        if k in t:
            values[k] = _color(t[k], _at(where, k))
    if "shininess" in t:
        values["shininess"] = _number(t["shininess"], _at(where, "shininess"), lo=0)
    return _call(where, lambda: Material(**values))


def _preset(name: str, where: str) -> Material:
    try:
        return Material.preset(name)
    except ValueError:
        raise SceneFileError(
            f"unknown material preset '{name}'; expected one of: "
            + ", ".join(Material.preset_names()),
            where,
        ) from None


def _material(v: Any, where: str, named: Mapping[str, Material]) -> Material:
    """A material value: a name (from [materials], else a preset) or a table."""
    if isinstance(v, str):
        if v in named:
            return named[v]
        try:
            return Material.preset(v)
        except ValueError:
            raise SceneFileError(
                f"unknown material '{v}'; expected a name from [materials]"
                + (f" ({', '.join(named)})" if named else "")
                + " or a preset: "
                + ", ".join(Material.preset_names()),
                where,
            ) from None
    if isinstance(v, Mapping):
        return _material_table(v, where)
    raise _fail(where, "a material name or a table", v)


def _named_materials(v: Any, where: str) -> dict[str, Material]:
    t = _table(v, where, optional=tuple(v) if isinstance(v, Mapping) else ())
    out = {}
    for name, m in t.items():
        w = _at(where, name)
        try:
            Material.preset(name)
        except ValueError:
            pass
        else:
            raise SceneFileError(f"the name '{name}' is taken by a preset; choose another", w)
        out[name] = _material_table(m, w)
    return out


def material_to_dict(m: Material) -> dict[str, Any]:
    """A material as explicit values (exact: its float32 values as Python floats)."""
    return {
        "ambient": list(m.ambient),
        "diffuse": list(m.diffuse),
        "specular": list(m.specular),
        "shininess": float(m.shininess),
        "emission": list(m.emission),
    }


# ---------------------------------------------------------------------------------------
# Lights, fog, camera, render options

# A light's own diffuse and specular colours (GL_DIFFUSE / GL_SPECULAR), in place of color.
_SPLIT = ("diffuse", "specular")
_LIGHT_KEYS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "directional": (("type", "direction"), ("color", "intensity", "ambient", *_SPLIT)),
    "point": (("type", "position"), ("color", "intensity", "attenuation", "ambient", *_SPLIT)),
    "spot": (
        ("type", "position", "direction"),
        ("cutoff", "exponent", "inner", "color", "intensity", "attenuation", "ambient", *_SPLIT),
    ),
    "area": (
        ("type", "position", "u", "v"),
        (
            "shape",
            "samples",
            "color",
            "intensity",
            "attenuation",
            "ambient",
            "one_sided",
            *_SPLIT,
        ),
    ),
}


# The 27 ways of moving each of 3 float32 components by at most one ulp, smallest first.
_ULP_STEPS = np.array(
    sorted(itertools.product((-1, 0, 1), repeat=3), key=lambda s: sum(map(abs, s))),
    dtype=np.int32,
)


def _normalize_f32(e: np.ndarray) -> np.ndarray:
    """Rows of ``e`` (float32) normalised exactly as the core does (glam's
    ``try_normalize``: ``e * (1 / sqrt((x*x + y*y) + z*z))``, each step rounded to
    float32)."""
    dot = (e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1]) + e[:, 2] * e[:, 2]
    return e * (np.float32(1.0) / np.sqrt(dot))[:, None]


def _unit_preimage(d: list[float]) -> np.ndarray | None:
    """A float32 vector whose float32 normalisation is exactly ``d``, or None.

    Candidates are ``d`` scaled by 1 + k/4096 and rounded to float32, each moved by up to
    an ulp per component: the rounding of the scaled vector varies with k, and over a few
    thousand candidates one nearly always lands on ``d`` (every one of 5000 random unit
    vectors in a test)."""
    d32 = np.array(d, dtype=np.float32)
    with np.errstate(all="ignore"):
        for start in range(0, 4096, 128):
            m = 1.0 + np.arange(start, start + 128) / 4096.0
            base = (d32.astype(np.float64)[None, :] * m[:, None]).astype(np.float32)
            bits = base.view(np.int32)[:, None, :] + _ULP_STEPS[None, :, :]
            cand = bits.view(np.float32).reshape(-1, 3)
            ok = np.all(_normalize_f32(cand) == d32, axis=1)
            if ok.any():
                return cand[int(np.argmax(ok))]
    return None


def _exact_direction(make: Callable[[list[float]], Any], d: list[float]) -> Any:
    """``make(d)``, or ``make(e)`` for an ``e`` whose normalisation gives exactly ``d``
    when ``d`` itself does not.

    Lights store their direction normalised in float32, and normalising an already
    normalised float32 vector moves it by an ulp about a third of the time; ``to_dict``
    writes the stored unit direction, so this keeps ``from_dict(to_dict(s))``
    bit-identical. A direction that is not unit (a hand-written one) is used as given."""
    light = make(d)
    target = tuple(float(np.float32(x)) for x in d)
    if tuple(light.direction) == target or abs(math.hypot(*d) - 1.0) > 1e-6:
        return light
    e = _unit_preimage(d)
    if e is not None:
        cand = make([float(x) for x in e])
        if tuple(cand.direction) == target:  # checked on the real constructor
            return cand
    return light  # within an ulp of d; see the user guide ("Round trips")


def _light(v: Any, where: str) -> _Light:
    if not isinstance(v, Mapping):
        raise _fail(where, "a table", v)
    if "type" not in v:
        raise SceneFileError(
            "missing required key; expected one of 'directional', 'point', 'spot', 'area'",
            _at(where, "type"),
        )
    kind = _choice(v["type"], _at(where, "type"), tuple(_LIGHT_KEYS))
    required, optional = _LIGHT_KEYS[kind]
    t = _table(v, where, required, optional)
    kw: dict[str, Any] = {}
    for k in ("color", "ambient", *_SPLIT):
        if k in t:
            kw[k] = _color(t[k], _at(where, k))
    if "intensity" in t:
        kw["intensity"] = _number(t["intensity"], _at(where, "intensity"), lo=0)
    if "attenuation" in t:
        kw["attenuation"] = _vec3(t["attenuation"], _at(where, "attenuation"), nonneg=True)
        if all(x == 0 for x in kw["attenuation"]):
            raise _fail(_at(where, "attenuation"), "3 numbers >= 0, not all zero", t["attenuation"])
    if "position" in t:
        kw["position"] = _vec3(t["position"], _at(where, "position"))
    if kind == "directional":
        d = _vec3(t["direction"], _at(where, "direction"), nonzero=True)
        return _call(where, lambda: _exact_direction(lambda e: DirectionalLight(e, **kw), d))
    if kind == "point":
        return _call(where, lambda: PointLight(**kw))
    if kind == "spot":
        d = _vec3(t["direction"], _at(where, "direction"), nonzero=True)
        if "cutoff" in t:
            c = t["cutoff"]
            if not (_is_number(c) and (0 < c <= 90 or c == 180)):
                raise _fail(_at(where, "cutoff"), "a number in (0, 90] or 180", c)
            kw["cutoff"] = float(c)
        if "exponent" in t:
            kw["exponent"] = _number(t["exponent"], _at(where, "exponent"), lo=0)
        if "inner" in t:
            cutoff = kw.get("cutoff", 30.0)
            if cutoff > 90:
                raise SceneFileError("needs a cutoff <= 90 (a cone)", _at(where, "inner"))
            kw["inner"] = _number(t["inner"], _at(where, "inner"), lo=0, hi=cutoff, hi_open=True)
        return _call(where, lambda: _exact_direction(lambda e: SpotLight(direction=e, **kw), d))
    # area
    kw["u"] = _vec3(t["u"], _at(where, "u"), nonzero=True)
    kw["v"] = _vec3(t["v"], _at(where, "v"), nonzero=True)
    if "shape" in t:
        kw["shape"] = _choice(t["shape"], _at(where, "shape"), ("rectangle", "disk"))
    if "samples" in t:
        kw["samples"] = _integer(t["samples"], _at(where, "samples"), 1, MAX_AREA_SAMPLES)
    if "one_sided" in t:
        kw["one_sided"] = _boolean(t["one_sided"], _at(where, "one_sided"))
    return _call(where, lambda: AreaLight(**kw))


def light_to_dict(light: _Light) -> dict[str, Any]:
    """A light as a table of the schema, every value explicit (``diffuse`` / ``specular``
    only when the light has its own)."""
    d = _light_values(light)
    for k in _SPLIT:
        v = getattr(light, k)
        if v is not None:
            d[k] = list(v)
    return d


def _light_values(light: _Light) -> dict[str, Any]:
    if isinstance(light, DirectionalLight):
        return {
            "type": "directional",
            "direction": list(light.direction),
            "color": list(light.color),
            "intensity": float(light.intensity),
            "ambient": list(light.ambient),
        }
    if isinstance(light, PointLight):
        return {
            "type": "point",
            "position": list(light.position),
            "color": list(light.color),
            "intensity": float(light.intensity),
            "attenuation": list(light.attenuation),
            "ambient": list(light.ambient),
        }
    if isinstance(light, SpotLight):
        d: dict[str, Any] = {
            "type": "spot",
            "position": list(light.position),
            "direction": list(light.direction),
            "cutoff": float(light.cutoff),
            "exponent": float(light.exponent),
        }
        if light.inner is not None:
            d["inner"] = float(light.inner)
        d.update(
            color=list(light.color),
            intensity=float(light.intensity),
            attenuation=list(light.attenuation),
            ambient=list(light.ambient),
        )
        return d
    if isinstance(light, AreaLight):
        return {
            "type": "area",
            "position": list(light.position),
            "u": list(light.u),
            "v": list(light.v),
            "shape": light.shape,
            "samples": int(light.samples),
            "color": list(light.color),
            "intensity": float(light.intensity),
            "attenuation": list(light.attenuation),
            "ambient": list(light.ambient),
            "one_sided": bool(light.one_sided),
        }
    raise TypeError(f"not a light: {type(light).__name__}")


def _fog(v: Any, where: str) -> Fog:
    if not isinstance(v, Mapping):
        raise _fail(where, "a table", v)
    mode = _choice(v.get("mode", "linear"), _at(where, "mode"), ("linear", "exp", "exp2"))
    params = ("start", "end") if mode == "linear" else ("density",)
    t = _table(v, where, optional=("mode", *params, "color"))
    kw: dict[str, Any] = {"mode": mode}
    if "color" in t:
        kw["color"] = _color(t["color"], _at(where, "color"))
    if mode == "linear":
        kw["start"] = _number(t.get("start", 0.0), _at(where, "start"))
        kw["end"] = _number(t.get("end", 1.0), _at(where, "end"))
        if not kw["start"] < kw["end"]:
            raise _fail(_at(where, "end"), f"a number > start ({kw['start']:g})", t.get("end", 1.0))
    else:
        kw["density"] = _number(t.get("density", 1.0), _at(where, "density"), lo=0)
    return _call(where, lambda: Fog(**kw))


def fog_to_dict(fog: Fog) -> dict[str, Any]:
    """A fog as a table of the schema."""
    d: dict[str, Any] = {"mode": fog.mode}
    if fog.mode == "linear":
        d["start"] = float(fog.start)  # type: ignore[arg-type]
        d["end"] = float(fog.end)  # type: ignore[arg-type]
    else:
        d["density"] = float(fog.density)  # type: ignore[arg-type]
    d["color"] = list(fog.color)
    return d


def _camera(v: Any, where: str) -> Camera:
    if not isinstance(v, Mapping):
        raise _fail(where, "a table", v)
    kind = _choice(
        v.get("type", "perspective"), _at(where, "type"), ("perspective", "orthographic")
    )
    extra = "fov_y" if kind == "perspective" else "height"
    t = _table(v, where, ("eye", "target"), ("type", "up", extra, "near", "far"))
    eye = _vec3(t["eye"], _at(where, "eye"))
    target = _vec3(t["target"], _at(where, "target"))
    if eye == target:
        raise SceneFileError("eye and target must be distinct points", where)
    up = _vec3(t.get("up", [0.0, 1.0, 0.0]), _at(where, "up"), nonzero=True)
    # near/far left out: fitted to the scene's bounds at render time.
    far = _number(t["far"], _at(where, "far")) if "far" in t else None
    if kind == "perspective":
        fov = _number(
            t.get("fov_y", 45.0), _at(where, "fov_y"), lo=0, lo_open=True, hi=180, hi_open=True
        )
        near = _number(t["near"], _at(where, "near"), lo=0, lo_open=True) if "near" in t else None
        if near is not None and far is not None and not near < far:
            raise _fail(_at(where, "far"), f"a number > near ({near:g})", t["far"])
        return _call(where, lambda: Camera.look_at(eye, target, up, fov_y=fov, near=near, far=far))
    height = _number(t.get("height", 2.0), _at(where, "height"), lo=0, lo_open=True)
    near = _number(t["near"], _at(where, "near")) if "near" in t else None
    if near is not None and far is not None and not near < far:
        raise _fail(_at(where, "far"), f"a number > near ({near:g})", t["far"])
    return _call(
        where, lambda: Camera.orthographic(eye, target, up, height=height, near=near, far=far)
    )


def camera_to_dict(camera: Camera) -> dict[str, Any]:
    """A camera as a table of the schema (its float64 values exactly)."""
    d: dict[str, Any] = {
        "type": camera.kind,
        "eye": list(camera.eye),
        "target": list(camera.target),
    }
    d["up"] = list(camera.up)
    if camera.kind == "perspective":
        d["fov_y"] = camera.fov_y
    else:
        d["height"] = camera.height
    # Planes left to the renderer to fit (None) are left out, as in a file.
    if camera.near is not None:
        d["near"] = camera.near
    if camera.far is not None:
        d["far"] = camera.far
    return d


_RENDER_KEYS = (
    "width",
    "height",
    "shading",
    "specular",
    "background",
    "cull_backfaces",
    "threads",
)


def _render_options(v: Any, where: str) -> dict[str, Any]:
    if isinstance(v, Mapping) and "dtype" in v:
        raise SceneFileError(
            "dtype is not a file option (pass dtype= to render instead)", _at(where, "dtype")
        )
    t = _table(v, where, optional=_RENDER_KEYS)
    out: dict[str, Any] = {}
    for k in ("width", "height"):
        if k in t:
            out[k] = _integer(t[k], _at(where, k), 1, MAX_IMAGE_SIZE)
    if "shading" in t:
        out["shading"] = _choice(t["shading"], _at(where, "shading"), ("flat", "gouraud", "phong"))
    if "specular" in t:
        out["specular"] = _choice(
            t["specular"], _at(where, "specular"), ("blinn", "phong", "blinn-normalized")
        )
    if "background" in t:
        out["background"] = _vec3(t["background"], _at(where, "background"))
    if "cull_backfaces" in t:
        out["cull_backfaces"] = _boolean(t["cull_backfaces"], _at(where, "cull_backfaces"))
    if "threads" in t:
        out["threads"] = _integer(t["threads"], _at(where, "threads"), 1, MAX_THREADS)
    return out


# ---------------------------------------------------------------------------------------
# Objects: meshes and transforms


def _rows(v: Any, where: str, cols: int, integer: bool) -> list[list[Any]]:
    what = f"rows of {cols} " + ("integers" if integer else "numbers")
    if not isinstance(v, list) or not v:
        raise _fail(where, f"a non-empty array of {what}", v)
    for i, row in enumerate(v):
        if not isinstance(row, list) or len(row) != cols:
            raise _fail(
                _at(where, i), f"an array of {cols} " + ("integers" if integer else "numbers"), row
            )
        for j, x in enumerate(row):
            ok = (
                isinstance(x, int) and not isinstance(x, bool)
                if integer
                else _is_number(x) and math.isfinite(x)
            )
            if not ok:
                raise _fail(
                    _at(_at(where, i), j), "an integer" if integer else "a finite number", x
                )
    return v


_PRIMITIVES = ("sphere", "ico_sphere", "cube", "plane")


def _inline_mesh(t: dict[str, Any], where: str) -> Mesh:
    verts = np.array(_rows(t["vertices"], _at(where, "vertices"), 3, False), dtype=np.float64)
    rows = _rows(t["faces"], _at(where, "faces"), 3, True)
    # Checked as Python ints first: a huge index would overflow int64.
    n = len(verts)
    for i, row in enumerate(rows):
        for j, x in enumerate(row):
            if not 0 <= x < n:
                raise _fail(_at(_at(_at(where, "faces"), i), j), f"a vertex index in [0, {n})", x)
    faces = np.array(rows, dtype=np.int64)
    kw: dict[str, Any] = {}
    for k, cols in (("normals", 3), ("uvs", 2)):
        if k in t:
            a = np.array(_rows(t[k], _at(where, k), cols, False), dtype=np.float64)
            if len(a) != len(verts):
                raise _fail(_at(where, k), f"{len(verts)} rows (one per vertex)", t[k])
            kw[k] = a
    return _call(where, lambda: Mesh(verts, faces, **kw))


def _primitive(t: dict[str, Any], where: str) -> Mesh:
    kind = _choice(t["primitive"], _at(where, "primitive"), _PRIMITIVES)
    if kind == "sphere":
        t = _table(t, where, ("primitive",), ("rings", "segments"))
        rings = _integer(t.get("rings", 16), _at(where, "rings"), 2, 100_000)
        segments = _integer(t.get("segments", 32), _at(where, "segments"), 3, 100_000)
        return _call(where, lambda: Mesh.uv_sphere(rings, segments))
    if kind == "ico_sphere":
        t = _table(t, where, ("primitive",), ("subdivisions",))
        n = _integer(t.get("subdivisions", 3), _at(where, "subdivisions"), 0, 10)
        return _call(where, lambda: Mesh.ico_sphere(n))
    _table(t, where, ("primitive",))
    return Mesh.cube() if kind == "cube" else Mesh.plane()


def _mesh_file(v: str, where: str, base_dir: Path) -> list[tuple[Mesh, Material | None]]:
    """The meshes of a file: an OBJ's groups with their MTL materials, or one mesh."""
    p = Path(v)
    if not p.is_absolute():
        p = base_dir / p
    if not p.exists():
        raise SceneFileError(f"no such file: '{p}'", where)
    try:
        if p.suffix.lower() == ".obj":
            return [(mesh, mat) for _, mesh, mat in load_obj_parts(p)]
        return [(load_mesh(p), None)]
    except (ValueError, OSError) as e:
        raise SceneFileError(str(e), where) from e


def _mesh(v: Any, where: str, base_dir: Path) -> list[tuple[Mesh, Material | None]]:
    if isinstance(v, str):
        return _mesh_file(v, where, base_dir)
    if not isinstance(v, Mapping):
        raise _fail(where, "a file path, a {primitive = ...} table or an inline mesh table", v)
    if "primitive" in v:
        return [(_primitive(dict(v), where), None)]
    if "vertices" not in v and "faces" not in v:
        raise _fail(where, "a {primitive = ...} table or an inline {vertices, faces} table", v)
    t = _table(v, where, ("vertices", "faces"), ("normals", "uvs"))
    return [(_inline_mesh(t, where), None)]


def _rotation(deg: list[float]) -> np.ndarray:
    """R = Rz · Ry · Rx: rotate about x first, then y, then z (fixed axes), in degrees."""
    out = np.eye(3)
    for axis, a in enumerate(deg):
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
        out = r @ out
    return out


def compose_transform(
    translate: Any = (0.0, 0.0, 0.0), rotate: Any = (0.0, 0.0, 0.0), scale: Any = 1.0
) -> np.ndarray:
    """The 4x4 float64 matrix ``T · R · S`` of the schema's ``translate`` / ``rotate`` (degrees
    about x, then y, then z) / ``scale`` (a number or 3 numbers)."""
    s = np.broadcast_to(np.asarray(scale, dtype=np.float64), (3,))
    m = np.eye(4)
    m[:3, :3] = _rotation([float(x) for x in rotate]) @ np.diag(s)
    m[:3, 3] = np.asarray(translate, dtype=np.float64)
    return m


def _transform(t: dict[str, Any], where: str) -> np.ndarray:
    trs = [k for k in ("translate", "rotate", "scale") if k in t]
    if "transform" in t:
        if trs:
            raise SceneFileError(
                "give either transform or translate/rotate/scale, not both", _at(where, trs[0])
            )
        w = _at(where, "transform")
        rows = t["transform"]
        if not isinstance(rows, list) or len(rows) != 4:
            raise _fail(w, "a 4x4 matrix (4 rows of 4 numbers)", rows)
        m = np.array(_rows(rows, w, 4, False), dtype=np.float64)
        if list(m[3]) != [0.0, 0.0, 0.0, 1.0]:
            raise _fail(_at(w, 3), "[0, 0, 0, 1] (an affine transform)", rows[3])
        return m
    translate = _vec3(t.get("translate", [0, 0, 0]), _at(where, "translate"))
    rotate = _vec3(t.get("rotate", [0, 0, 0]), _at(where, "rotate"))
    scale: Any = t.get("scale", 1.0)
    if _is_number(scale):
        if not math.isfinite(scale) or scale == 0:
            raise _fail(_at(where, "scale"), "a non-zero number or 3 non-zero numbers", scale)
    else:
        scale = _vec3(scale, _at(where, "scale"))
        if 0 in scale:
            raise _fail(_at(where, "scale"), "a non-zero number or 3 non-zero numbers", t["scale"])
    return compose_transform(translate, rotate, scale)


_OBJECT_KEYS = ("material", "back_material", "transform", "translate", "rotate", "scale")


def _add_object(
    scene: Scene, v: Any, where: str, named: Mapping[str, Material], base_dir: Path
) -> None:
    t = _table(v, where, ("mesh",), _OBJECT_KEYS)
    transform = _transform(t, where)
    material = _material(t["material"], _at(where, "material"), named) if "material" in t else None
    # back_material is wired here: Scene.add(..., back_material=...).
    back = None
    if "back_material" in t:
        back = _material(t["back_material"], _at(where, "back_material"), named)
    for mesh, file_material in _mesh(t["mesh"], _at(where, "mesh"), base_dir):
        # An explicit material overrides the file's (MTL) material; else the default.
        mat = material if material is not None else file_material
        try:
            scene.add(mesh, material=mat, transform=transform, back_material=back)
        except (ValueError, TypeError) as e:
            raise SceneFileError(str(e), where) from e


# ---------------------------------------------------------------------------------------
# Documents

_TOP_KEYS = (
    "ambient",
    "two_sided",
    "local_viewer",
    "fog",
    "camera",
    "render",
    "materials",
    "lights",
    "objects",
)


@dataclass
class SceneFile:
    """What a scene file holds: the scene, its camera (None when the file has none) and the
    render options it sets (keyword arguments of :func:`shadelab_rs.render`, only those the
    file gives)."""

    scene: Scene
    camera: Camera | None = None
    render_options: dict[str, Any] = field(default_factory=dict)
    path: Path | None = None

    def render(self, **overrides: Any) -> np.ndarray:
        """Renders with the file's options updated by ``overrides``; without a camera in
        the file, one that frames every object (:func:`frame_scene`)."""
        from ._core import render

        camera = self.camera if self.camera is not None else frame_scene(self.scene)
        return render(self.scene, camera, **{**self.render_options, **overrides})


def frame_scene(
    scene: Scene, fov_y: float = 35.0, direction: Any = None, up: Any = (0.0, 1.0, 0.0)
) -> Camera:
    """A perspective camera that fits the world-space bounding sphere of every object,
    from ``direction`` (a view name or x, y, z; see :func:`frame_mesh`) with up axis ``up``."""
    from .demo import frame_mesh

    return frame_mesh(scene, fov_y=fov_y, direction=direction, up=up)


def load_scene_dict(d: Any, base_dir: _PathLike | None = None) -> SceneFile:
    """A :class:`SceneFile` from a dict in the schema; relative mesh paths are resolved
    against ``base_dir`` (default: the current directory)."""
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    if not isinstance(d, Mapping):
        raise _fail("document", "a table", d)
    if "version" not in d:
        raise SceneFileError(
            f"missing required key (the schema version, {SCHEMA_VERSION})", "version"
        )
    version = d["version"]
    if (
        not (isinstance(version, int) and not isinstance(version, bool))
        or version != SCHEMA_VERSION
    ):
        raise _fail("version", f"{SCHEMA_VERSION} (the schema version this release reads)", version)
    t = _table(d, "", ("version",), _TOP_KEYS)
    # Every section is checked even after an error, so that all are reported at once.
    errors: list[SceneFileError] = []

    def checked(fn: Any, default: Any = None) -> Any:
        try:
            return fn()
        except SceneFileError as e:
            errors.append(e)
            return default

    ambient = checked(lambda: _color(t["ambient"], "ambient")) if "ambient" in t else None
    scene = Scene(
        ambient=ambient,
        fog=checked(lambda: _fog(t["fog"], "fog")) if "fog" in t else None,
        two_sided=checked(lambda: _boolean(t.get("two_sided", False), "two_sided"), False),
        local_viewer=checked(lambda: _boolean(t.get("local_viewer", True), "local_viewer"), True),
    )
    camera = checked(lambda: _camera(t["camera"], "camera")) if "camera" in t else None
    render_options = (
        checked(lambda: _render_options(t["render"], "render"), {}) if "render" in t else {}
    )
    named = (
        checked(lambda: _named_materials(t["materials"], "materials"), {})
        if "materials" in t
        else {}
    )
    for key in ("lights", "objects"):
        items = t.get(key, [])
        if not isinstance(items, list):
            errors.append(_fail(key, "an array of tables", items))
            continue
        for i, item in enumerate(items):
            if key == "lights":
                light = checked(lambda: _light(item, _at(key, i)))  # noqa: B023
                if light is not None:
                    scene.add_light(light)
            else:
                checked(lambda: _add_object(scene, item, _at(key, i), named, base))  # noqa: B023
    if errors:
        raise SceneFileError(errors[0].detail, errors[0].key, more=errors[1:]) from errors[
            0
        ].__cause__
    return SceneFile(scene, camera, render_options)


def load_scene(path: _PathLike) -> SceneFile:
    """Reads a scene file (TOML): the scene, its camera and render options. Relative mesh
    paths are resolved against the file's directory. Raises ``FileNotFoundError`` for a
    missing file and :class:`SceneFileError` for anything wrong inside it."""
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(f"'{p}' is a directory, not a scene file")
    with open(p, "rb") as f:
        try:
            doc = tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise SceneFileError(f"not valid TOML: {e}", "", str(p)) from None
        except UnicodeDecodeError as e:
            raise SceneFileError(f"not valid TOML (UTF-8): {e}", "", str(p)) from None
    try:
        sf = load_scene_dict(doc, base_dir=p.resolve().parent)
    except SceneFileError as e:
        raise SceneFileError(e.detail, e.key, str(p), e.more) from e.__cause__
    sf.path = p
    return sf


def scene_from_file(path: _PathLike) -> Scene:
    """The scene of a scene file (``Scene.from_file``)."""
    return load_scene(path).scene


def scene_from_dict(d: Any, base_dir: _PathLike | None = None) -> Scene:
    """The scene of a dict in the schema (``Scene.from_dict``); camera and render options
    are checked too (use :func:`load_scene_dict` to get them)."""
    return load_scene_dict(d, base_dir).scene


# ---------------------------------------------------------------------------------------
# Writing


def _same_mesh(a: Mesh, b: Mesh) -> bool:
    return (
        a.n_vertices == b.n_vertices
        and a.n_faces == b.n_faces
        and a.has_normals == b.has_normals
        and np.array_equal(a.vertices, b.vertices)
        and np.array_equal(a.faces, b.faces)
        and np.array_equal(a.normals, b.normals)
        and _same_optional(a.uvs, b.uvs)
    )


def _same_optional(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return bool(np.array_equal(a, b))


def _primitive_of(mesh: Mesh) -> dict[str, Any] | None:
    """The primitive table that rebuilds ``mesh`` exactly, if it is one."""
    if mesh.n_vertices == 24 and _same_mesh(mesh, Mesh.cube()):
        return {"primitive": "cube"}
    if mesh.n_vertices == 4 and _same_mesh(mesh, Mesh.plane()):
        return {"primitive": "plane"}
    for n in range(11):
        if mesh.n_vertices == 10 * 4**n + 2:
            if _same_mesh(mesh, Mesh.ico_sphere(n)):
                return {"primitive": "ico_sphere", "subdivisions": n}
            break
    faces = mesh.faces
    # A uv sphere's first triangles are the fan around vertex 0, one per segment.
    segments = int(np.argmin(faces[:, 0] == 0)) if faces[0, 0] == 0 else 0
    if segments >= 3 and (mesh.n_vertices - 2) % segments == 0:
        rings = (mesh.n_vertices - 2) // segments + 1
        if rings >= 2 and _same_mesh(mesh, Mesh.uv_sphere(rings, segments)):
            return {"primitive": "sphere", "rings": rings, "segments": segments}
    return None


def mesh_to_dict(mesh: Mesh) -> dict[str, Any]:
    """A mesh as a primitive table when it is one, else inline arrays: vertices, faces,
    normals (only when they differ from the ones the library would generate) and uvs."""
    prim = _primitive_of(mesh)
    if prim is not None:
        return prim
    d: dict[str, Any] = {"vertices": mesh.vertices.tolist(), "faces": mesh.faces.tolist()}
    generated = Mesh(mesh.vertices, mesh.faces).normals
    if mesh.has_normals or not np.array_equal(generated, mesh.normals):
        d["normals"] = mesh.normals.tolist()
    if mesh.uvs is not None:
        d["uvs"] = mesh.uvs.tolist()
    return d


def scene_to_dict(
    scene: Scene, camera: Camera | None = None, render: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """``scene`` (and optionally a camera and render options) as plain Python data in the
    schema, which TOML can hold: ``scene_from_dict`` of it renders bit-identically."""
    d: dict[str, Any] = {
        "version": SCHEMA_VERSION,
        "ambient": list(scene.ambient),
        "two_sided": scene.two_sided,
        "local_viewer": scene.local_viewer,
    }
    if scene.fog is not None:
        d["fog"] = fog_to_dict(scene.fog)
    if camera is not None:
        d["camera"] = camera_to_dict(camera)
    if render:
        plain = {k: list(v) if isinstance(v, (tuple, np.ndarray)) else v for k, v in render.items()}
        opts = _render_options(plain, "render")
        d["render"] = {k: (v if k != "background" else list(v)) for k, v in opts.items()}
    d["lights"] = [light_to_dict(light) for light in scene.lights]
    objects = []
    for o in scene.objects:
        item: dict[str, Any] = {
            "mesh": mesh_to_dict(o.mesh),
            "material": material_to_dict(o.material),
        }
        # back_material is wired here: written when the object has one.
        if o.back_material is not None:
            item["back_material"] = material_to_dict(o.back_material)
        item["transform"] = o.transform.tolist()
        objects.append(item)
    d["objects"] = objects
    return d


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_key(k: str) -> str:
    return k if _BARE_KEY.match(k) else _toml_str(k)


def _toml_str(s: str) -> str:
    out = json.dumps(s, ensure_ascii=False)
    # JSON leaves DEL unescaped; TOML does not allow it raw in a basic string.
    return out.replace("\x7f", "\\u007f")


def _toml_value(v: Any, indent: str = "") -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
        return repr(v)
    if isinstance(v, str):
        return _toml_str(v)
    if isinstance(v, (list, tuple)):
        if v and all(isinstance(x, (list, tuple)) for x in v):
            inner = indent + "  "
            rows = ",\n".join(inner + _toml_value(x, inner) for x in v)
            return "[\n" + rows + ",\n" + indent + "]"
        return "[" + ", ".join(_toml_value(x, indent) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)


def _emit(d: Mapping[str, Any], prefix: str, out: list[str]) -> None:
    for k, v in d.items():
        if not isinstance(v, Mapping) and not _is_table_array(v):
            out.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for k, v in d.items():
        name = f"{prefix}.{_toml_key(k)}" if prefix else _toml_key(k)
        if isinstance(v, Mapping):
            out.append(f"\n[{name}]")
            _emit(v, name, out)
        elif _is_table_array(v):
            for item in v:
                out.append(f"\n[[{name}]]")
                _emit(item, name, out)


def to_toml(d: Mapping[str, Any]) -> str:
    """``d`` (plain data: tables, arrays, strings, numbers, booleans) as a TOML document."""
    out: list[str] = []
    _emit(d, "", out)
    return "\n".join(out).lstrip("\n") + "\n"


def save_scene(
    path: _PathLike,
    scene: Scene,
    camera: Camera | None = None,
    render: Mapping[str, Any] | None = None,
) -> None:
    """Writes ``scene`` (with an optional camera and render options) as a scene file."""
    Path(path).write_text(to_toml(scene_to_dict(scene, camera, render)), encoding="utf-8")
