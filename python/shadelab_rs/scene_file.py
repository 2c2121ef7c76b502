"""Scene files: a versioned TOML schema for a scene, its camera and its render options.

The schema (version 1) is documented in docs/USER_GUIDE.md, "Scene files". This module
checks the document's shape (tables, keys, TOML types; unknown keys are errors); values are
checked once, by the constructors, whose errors name the argument (``field``) that is mapped
here to a key path. Every bad key or value raises :class:`SceneFileError` naming its key path
(``lights[2].cutoff``) and what was wrong. ``scene_to_dict`` writes the same schema as plain
Python data (meshes as primitives when they are one, else inline arrays), so
``scene_from_dict(scene_to_dict(s))`` renders bit-identically to ``s``; ``to_toml`` writes
it as TOML (with tomli-w).
"""

from __future__ import annotations

import contextvars
import math
import os
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, Callable, Union

import numpy as np
import tomli_w

from ._core import (
    AreaLight,
    Camera,
    DirectionalLight,
    Environment,
    Fog,
    Material,
    Mesh,
    PointLight,
    RenderOptions,
    Scene,
    ShadowSettings,
    SpotLight,
    Texture,
    load_obj_parts,
)
from .io import load_mesh

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python < 3.11 only
    import tomli as tomllib

#: The schema version this release writes; it reads this one and every earlier one (1:
#: no textures; 2: texture maps in materials and vertex colours in inline meshes).
SCHEMA_VERSION = 2
#: The schema versions this release reads.
READ_VERSIONS = (1, 2)

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
# Checking helpers. `where` is always the key path of the value being checked. This module
# checks only the document's shape: tables, keys and TOML types (a number is not a boolean
# or a string). Values — ranges, lengths, finiteness — are checked once, by the
# constructors, whose errors name the argument (`field`); `_call` turns that into a key.


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


def _number(v: Any, where: str) -> Any:
    if not _is_number(v):
        raise _fail(where, "a number", v)
    return v


def _integer(v: Any, where: str) -> int:
    if not isinstance(v, int) or isinstance(v, bool):
        raise _fail(where, "an integer", v)
    return v


def _boolean(v: Any, where: str) -> bool:
    if not isinstance(v, bool):
        raise _fail(where, "true or false", v)
    return v


def _string(v: Any, where: str) -> str:
    if not isinstance(v, str):
        raise _fail(where, "a string", v)
    return v


def _choice(v: Any, where: str, choices: tuple[str, ...]) -> str:
    """For the keys that choose a schema (a light's or a camera's type)."""
    if not isinstance(v, str) or v not in choices:
        raise _fail(where, "one of " + ", ".join(f"'{c}'" for c in choices), v)
    return v


def _numbers(v: Any, where: str) -> list[Any]:
    """An array of numbers (its length is the constructor's to check)."""
    if not isinstance(v, list):
        raise _fail(where, "an array of numbers", v)
    for i, x in enumerate(v):
        _number(x, _at(where, i))
    return v


def _rows(v: Any, where: str, integer: bool = False) -> list[list[Any]]:
    """An array of arrays of numbers (integers with ``integer``)."""
    item = _integer if integer else _number
    if not isinstance(v, list):
        raise _fail(where, "an array of arrays of " + ("integers" if integer else "numbers"), v)
    for i, row in enumerate(v):
        if not isinstance(row, list):
            raise _fail(_at(where, i), "an array of " + ("integers" if integer else "numbers"), row)
        for j, x in enumerate(row):
            item(x, _at(_at(where, i), j))
    return v


def _call(
    where: str, make: Callable[[], Any], rename: Mapping[str, str | None] | None = None
) -> Any:
    """Runs a constructor, turning its error into a SceneFileError at the key of the
    argument it names (``where.<field>``; ``rename`` maps a field to another key, or to
    None for ``where`` itself), else at ``where``."""
    try:
        return make()
    except SceneFileError:
        raise
    except (ValueError, TypeError, OverflowError) as e:
        field_name = getattr(e, "field", None)
        if isinstance(field_name, str):
            key = (rename or {}).get(field_name, field_name)
            where = _at(where, key) if key else where
        raise SceneFileError(str(e), where) from e


# ---------------------------------------------------------------------------------------
# Materials


_MAP_KEYS = (
    "diffuse_map",
    "ambient_map",
    "specular_map",
    "emission_map",
    "shininess_map",
    "normal_map",
    "bump_map",
)
#: Scales of the normal and bump maps (numbers; written when not 1).
_MAP_SCALE_KEYS = ("normal_scale", "bump_scale")
_OPTICS_KEYS = ("reflectivity", "transparency", "ior", "fresnel", "absorption")
_MATERIAL_KEYS = (
    "preset",
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "emission",
    *_MAP_KEYS,
    *_MAP_SCALE_KEYS,
    *_OPTICS_KEYS,
)
_IMAGE_KEYS = ("filter", "wrap", "srgb", "anisotropy", "uv_scale", "uv_offset")
_PROCEDURAL_KEYS = ("scale", "color_a", "color_b", "width", "octaves", "seed")

#: Base directory of relative texture paths while a document is read.
_BASE_DIR: contextvars.ContextVar[Path] = contextvars.ContextVar("_BASE_DIR", default=Path("."))


def _pair(v: Any, where: str) -> tuple[float, float]:
    n = _numbers(v, where) if isinstance(v, list) else None
    if n is None or len(n) != 2:
        raise _fail(where, "two numbers [u, v]", v)
    return (float(n[0]), float(n[1]))


def _texture(v: Any, where: str) -> Texture:
    """A texture table: ``{file = "wood.png", filter, wrap, srgb, uv_scale, uv_offset}`` or
    ``{procedural = "checker", scale, color_a, color_b, width, octaves, seed}``."""
    if isinstance(v, Mapping) and "procedural" in v:
        t = _table(v, where, ("procedural",), _PROCEDURAL_KEYS)
        name = _choice(
            t["procedural"], _at(where, "procedural"), ("checker", "grid", "stripes", "noise")
        )
        kw: dict[str, Any] = {}
        for k in ("scale", "width"):
            if k in t:
                kw[k] = _number(t[k], _at(where, k))
        for k in ("octaves", "seed"):
            if k in t:
                kw[k] = _integer(t[k], _at(where, k))
        for k in ("color_a", "color_b"):
            if k in t:
                kw[k] = _numbers(t[k], _at(where, k))
        return _call(where, lambda: Texture.procedural(name, **kw))  # type: ignore[arg-type]
    if not (isinstance(v, Mapping) and "file" in v):
        raise _fail(where, "a texture table {file = ...} or {procedural = ...}", v)
    t = _table(v, where, ("file",), _IMAGE_KEYS)
    p = Path(_string(t["file"], _at(where, "file")))
    if not p.is_absolute():
        p = _BASE_DIR.get() / p
    opts: dict[str, Any] = {}
    if "filter" in t:
        opts["filter"] = _choice(
            t["filter"], _at(where, "filter"), ("nearest", "bilinear", "trilinear")
        )
    if "wrap" in t:
        w = t["wrap"]
        wraps = ("repeat", "clamp", "mirror")
        if isinstance(w, list) and len(w) == 2:
            opts["wrap"] = tuple(
                _choice(x, _at(_at(where, "wrap"), i), wraps) for i, x in enumerate(w)
            )
        else:
            opts["wrap"] = _choice(w, _at(where, "wrap"), wraps)
    if "srgb" in t:
        opts["srgb"] = _boolean(t["srgb"], _at(where, "srgb"))
    if "anisotropy" in t:
        opts["anisotropy"] = _integer(t["anisotropy"], _at(where, "anisotropy"))
    if not p.exists():
        raise SceneFileError(f"no such file: '{p}'", _at(where, "file"))
    try:
        tex = Texture.load(p, **opts)
    except (ValueError, OSError) as e:
        key = getattr(e, "field", None)
        raise SceneFileError(str(e), _at(where, key if key in _IMAGE_KEYS else "file")) from e
    if "uv_scale" in t or "uv_offset" in t:
        scale = _pair(t["uv_scale"], _at(where, "uv_scale")) if "uv_scale" in t else (1.0, 1.0)
        offset = _pair(t["uv_offset"], _at(where, "uv_offset")) if "uv_offset" in t else (0.0, 0.0)
        tex = _call(where, lambda: tex.with_uv_transform(scale, offset))
    return tex


def texture_to_dict(tex: Texture) -> dict[str, Any]:
    """A texture as a scene-file table: its file and options, or its pattern. A texture
    made from an array has no file to name: ``ValueError`` (save the image and use
    :meth:`Texture.load`)."""
    if tex.kind == "image":
        if tex.path is None:
            raise ValueError(
                "a Texture made from an array cannot be written to a scene file; save the "
                "image to a file and use Texture.load"
            )
        d: dict[str, Any] = {"file": str(tex.path), "filter": tex.filter, "wrap": list(tex.wrap)}
        if tex.srgb:
            d["srgb"] = True
        if tex.anisotropy != 1:
            d["anisotropy"] = tex.anisotropy
        scale, offset = tex.uv_transform
        if scale != (1.0, 1.0):
            d["uv_scale"] = list(scale)
        if offset != (0.0, 0.0):
            d["uv_offset"] = list(offset)
        return d
    # The pattern's parameters, as its pickled state holds them:
    # ("procedural", name, scale, color_a, color_b, width, octaves, seed, uv).
    p = tex.__reduce__()[1][1]
    out: dict[str, Any] = {"procedural": p[1], "scale": p[2], "color_a": list(p[3])}
    out["color_b"] = list(p[4])
    if p[1] == "grid":
        out["width"] = p[5]
    if p[1] == "noise":
        out["octaves"] = p[6]
        out["seed"] = p[7]
    return out


def _material_table(v: Any, where: str) -> Material:
    t = _table(v, where, optional=_MATERIAL_KEYS)
    base = (
        _preset(_string(t["preset"], _at(where, "preset")), _at(where, "preset"))
        if "preset" in t
        else Material()
    )
    values: dict[str, Any] = {
        "ambient": base.ambient,
        "diffuse": base.diffuse,
        "specular": base.specular,
        "shininess": base.shininess,
        "emission": base.emission,
    }
    for k in ("ambient", "diffuse", "specular", "emission"):
        if k in t:
            values[k] = _numbers(t[k], _at(where, k))
    if "shininess" in t:
        values["shininess"] = _number(t["shininess"], _at(where, "shininess"))
    for k in _MAP_KEYS:
        if k in t:
            values[k] = _texture(t[k], _at(where, k))
    for k in _MAP_SCALE_KEYS:
        if k in t:
            values[k] = _number(t[k], _at(where, k))
    # Optics: a number or an RGB list (reflectivity, absorption), a number or a preset name
    # (ior), a boolean (fresnel); their ranges are the core's to check.
    for k in ("reflectivity", "absorption"):
        if k in t:
            values[k] = (
                _number(t[k], _at(where, k)) if _is_number(t[k]) else _numbers(t[k], _at(where, k))
            )
    if "transparency" in t:
        values["transparency"] = _number(t["transparency"], _at(where, "transparency"))
    if "ior" in t:
        values["ior"] = (
            _string(t["ior"], _at(where, "ior"))
            if isinstance(t["ior"], str)
            else _number(t["ior"], _at(where, "ior"))
        )
    if "fresnel" in t:
        values["fresnel"] = _boolean(t["fresnel"], _at(where, "fresnel"))
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
    """A material as explicit values (exact: its float32 values as Python floats), with its
    texture maps (see :func:`texture_to_dict`)."""
    d: dict[str, Any] = {
        "ambient": list(m.ambient),
        "diffuse": list(m.diffuse),
        "specular": list(m.specular),
        "shininess": float(m.shininess),
        "emission": list(m.emission),
    }
    for k in _MAP_KEYS:
        tex = getattr(m, k)
        if tex is not None:
            d[k] = texture_to_dict(tex)
    for k in _MAP_SCALE_KEYS:
        if getattr(m, k) != 1.0:
            d[k] = float(getattr(m, k))
    # Optics only when they differ from an opaque material's, so older files stay as they were.
    if any(m.reflectivity) or m.transparency or m.ior != 1.0 or not m.fresnel or any(m.absorption):
        d["reflectivity"] = list(m.reflectivity)
        d["transparency"] = float(m.transparency)
        d["ior"] = float(m.ior)
        d["fresnel"] = bool(m.fresnel)
        d["absorption"] = list(m.absorption)
    return d


# ---------------------------------------------------------------------------------------
# Lights, fog, camera, render options

# A light's own diffuse and specular colours (GL_DIFFUSE / GL_SPECULAR), in place of color;
# and its shadows (false, true, "exact" or a table of ShadowSettings), written when on.
_SPLIT = ("diffuse", "specular", "shadows")
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
    # Only the TOML types here; the light's constructor checks every value.
    kw: dict[str, Any] = {}
    for k, value in t.items():
        w = _at(where, k)
        if k in ("intensity", "cutoff", "exponent", "inner"):
            kw[k] = _number(value, w)
        elif k == "samples":
            kw[k] = _integer(value, w)
        elif k == "shape":
            kw[k] = _string(value, w)
        elif k == "one_sided":
            kw[k] = _boolean(value, w)
        elif k == "shadows":
            kw[k] = _shadows(value, w)
        elif k != "type":
            kw[k] = _numbers(value, w)
    make = {
        "directional": DirectionalLight,
        "point": PointLight,
        "spot": SpotLight,
        "area": AreaLight,
    }[kind]
    return _call(where, lambda: make(**kw))


def _shadows(v: Any, where: str) -> bool | str | ShadowSettings:
    """A light's ``shadows``: true, false, "exact" or a table of ShadowSettings."""
    if isinstance(v, (bool, str)):
        return v  # the light's constructor names a bad string
    if not isinstance(v, Mapping):
        raise _fail(where, 'true, false, "exact" or a table', v)
    t = _table(v, where, optional=("resolution", "filter", "kernel", "bias", "cascades"))
    kw: dict[str, Any] = {}
    for k, value in t.items():
        w = _at(where, k)
        if k in ("resolution", "kernel", "cascades"):
            kw[k] = _integer(value, w)
        elif k == "filter":
            kw[k] = _string(value, w)
        else:
            kw[k] = _number(value, w)
    return _call(where, lambda: ShadowSettings(**kw))


def _shadows_to_dict(v: Any) -> Any:
    if isinstance(v, ShadowSettings):
        return {
            "resolution": v.resolution,
            "filter": v.filter,
            "kernel": v.kernel,
            "bias": v.bias,
            "cascades": v.cascades,
        }
    return v


_LIGHT_TYPES = {
    DirectionalLight: "directional",
    PointLight: "point",
    SpotLight: "spot",
    AreaLight: "area",
}


def light_to_dict(light: _Light) -> dict[str, Any]:
    """A light as a table of the schema: every key the light's getters hold (``diffuse``,
    ``specular`` and a spot's ``inner`` only when the light has them)."""
    kind = _LIGHT_TYPES.get(type(light))
    if kind is None:
        raise TypeError(f"not a light: {type(light).__name__}")
    required, optional = _LIGHT_KEYS[kind]
    d: dict[str, Any] = {"type": kind}
    for k in required[1:] + optional:
        v = getattr(light, k)
        if k == "shadows":
            if v is not False:
                d[k] = _shadows_to_dict(v)
        elif v is not None:
            d[k] = list(v) if isinstance(v, tuple) else v
    return d


def light_with_shadows(light: _Light, shadows: bool | str | ShadowSettings) -> _Light:
    """The same light (every value kept exactly) casting shadows as ``shadows`` says."""
    d = light_to_dict(light)
    d["shadows"] = _shadows_to_dict(shadows)
    return _light(d, "light")


def _fog(v: Any, where: str) -> Fog:
    t = _table(v, where, optional=("mode", "start", "end", "density", "color"))
    mode = _string(t.get("mode", "linear"), _at(where, "mode"))
    # A key of the other modes is an error, not silently ignored.
    other = {"linear": ("density",), "exp": ("start", "end"), "exp2": ("start", "end")}
    for k in other.get(mode, ()):
        if k in t:
            raise SceneFileError(f"unknown key '{k}' for {mode!r} fog", _at(where, k))
    kw: dict[str, Any] = {"mode": mode}
    for k in ("start", "end", "density"):
        if k in t:
            kw[k] = _number(t[k], _at(where, k))
    if "color" in t:
        kw["color"] = _numbers(t["color"], _at(where, "color"))
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


def _environment(v: Any, where: str) -> Environment:
    """``{file = "sky.png", rotation = 0.0, intensity = 1.0}``, or six cube faces
    ``{faces = ["px.png", "nx.png", "py.png", "ny.png", "pz.png", "nz.png"], ...}`` in the
    order +X, -X, +Y, -Y, +Z, -Z (see :func:`load_environment`; relative paths are read
    against the file's directory)."""
    from .io import load_environment

    t = _table(v, where, (), ("file", "faces", "rotation", "intensity"))
    if ("file" in t) == ("faces" in t):
        raise SceneFileError("needs exactly one of 'file' or 'faces'", where)
    rotation = _number(t.get("rotation", 0.0), _at(where, "rotation"))
    intensity = _number(t.get("intensity", 1.0), _at(where, "intensity"))
    source: Path | list[Path]
    if "file" in t:
        key = "file"
        source = _BASE_DIR.get() / _string(t["file"], _at(where, "file"))
    else:
        key = "faces"
        faces = t["faces"]
        if not isinstance(faces, list) or len(faces) != 6:
            raise _fail(
                _at(where, "faces"), "a list of 6 file names (+x, -x, +y, -y, +z, -z)", faces
            )
        source = [
            _BASE_DIR.get() / _string(f, _at(where, f"faces[{k}]")) for k, f in enumerate(faces)
        ]
    try:
        return _call(where, lambda: load_environment(source, rotation, intensity))
    except FileNotFoundError as e:
        raise SceneFileError(str(e), _at(where, key)) from e


def environment_to_dict(env: Environment) -> dict[str, Any]:
    """An environment as a scene-file table. One made from arrays has no file to name:
    ``ValueError`` (save them as .npy and use :func:`load_environment`)."""
    common = {"rotation": env.rotation, "intensity": env.intensity}
    if env.face_paths is not None:
        return {"faces": [str(p) for p in env.face_paths], **common}
    if env.path is None:
        raise ValueError(
            "an Environment made from an array cannot be written to a scene file; save the "
            "array (.npy) and use sl.load_environment"
        )
    return {"file": str(env.path), **common}


def _camera(v: Any, where: str) -> Camera:
    if not isinstance(v, Mapping):
        raise _fail(where, "a table", v)
    kind = _choice(
        v.get("type", "perspective"),
        _at(where, "type"),
        ("perspective", "pinhole", "orthographic"),
    )
    required: tuple[str, ...] = ("eye", "target")
    extra: tuple[str, ...] = {
        "perspective": ("fov_y",),
        "orthographic": ("height",),
        "pinhole": ("fx", "fy", "cx", "cy", "width", "height", "skew"),
    }[kind]
    if kind == "pinhole":
        required += extra[:6]
    t = _table(v, where, required, ("type", "up", *extra, "near", "far"))
    kw: dict[str, Any] = {}
    for k in ("eye", "target", "up"):
        if k in t:
            kw[k] = _numbers(t[k], _at(where, k))
    for k in (*extra, "near", "far"):
        if k in t:
            integer = kind == "pinhole" and k in ("width", "height")  # pixels
            kw[k] = (_integer if integer else _number)(t[k], _at(where, k))
    if kind == "perspective":
        return _call(where, lambda: Camera.look_at(**kw))
    if kind == "pinhole":
        return _call(where, lambda: Camera.from_intrinsics(**kw))
    return _call(where, lambda: Camera.orthographic(**kw))


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
    elif camera.intrinsics is not None:
        fx, fy, cx, cy, skew, w, h = camera.intrinsics
        d.update(fx=fx, fy=fy, cx=cx, cy=cy, skew=skew, width=w, height=h)
    else:
        d["height"] = camera.height
    # Planes left to the renderer to fit (None) are left out, as in a file.
    if camera.near is not None:
        d["near"] = camera.near
    if camera.far is not None:
        d["far"] = camera.far
    return d


def _render_options(v: Any, where: str) -> dict[str, Any]:
    """The options a ``[render]`` table gives (checked by :class:`RenderOptions`)."""
    if isinstance(v, Mapping) and "dtype" in v:
        raise SceneFileError(
            "dtype is not a file option (pass dtype= to render instead)", _at(where, "dtype")
        )
    keys = tuple(RenderOptions().to_dict())
    t = _table(v, where, optional=keys)
    types: dict[str, Callable[[Any, str], Any]] = {
        "shading": _string,
        "specular": _string,
        "gouraud": _string,
        "interpolation": _string,
        "background": lambda v, w: v if v == "environment" else _numbers(v, w),
        "cull_backfaces": _boolean,
        "cull_hidden": _boolean,
        "edges": _string,
        "edge_color": _numbers,
        "edge_width": _number,
        "edge_angle": _number,
        "edges_only": _boolean,
        "reflections": _string,
        "refractions": _string,
        "tolerance": _number,
    }
    for k, value in t.items():
        if value is not None or k not in ("threads", "edges", "refractions", "tolerance"):
            types.get(k, _integer)(value, _at(where, k))
    _call(where, lambda: RenderOptions(**t))
    return t


# ---------------------------------------------------------------------------------------
# Objects: meshes and transforms


_PRIMITIVES = ("sphere", "ico_sphere", "cube", "plane")


def _inline_mesh(t: dict[str, Any], where: str) -> Mesh:
    kw: dict[str, Any] = {k: _rows(t[k], _at(where, k), integer=k == "faces") for k in t}
    if "colors" in kw:  # linear float colours (TOML writes 0 and 1 as integers)
        kw["colors"] = np.asarray(kw["colors"], dtype=np.float64)
    return _call(where, lambda: Mesh(**kw))


def _primitive(t: dict[str, Any], where: str) -> Mesh:
    kind = _choice(t["primitive"], _at(where, "primitive"), _PRIMITIVES)
    params = {"sphere": ("rings", "segments"), "ico_sphere": ("subdivisions",)}.get(kind, ())
    t = _table(t, where, ("primitive",), params)
    kw = {k: _integer(t[k], _at(where, k)) for k in params if k in t}
    make = getattr(Mesh, {"sphere": "uv_sphere"}.get(kind, kind))
    return _call(where, lambda: make(**kw))


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
    t = _table(v, where, ("vertices", "faces"), ("normals", "uvs", "colors"))
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


def _transform(t: dict[str, Any], where: str) -> tuple[Any, dict[str, str | None]]:
    """The object's transform and how the constructor's ``transform`` maps to a key."""
    trs = [k for k in ("translate", "rotate", "scale") if k in t]
    if "transform" in t:
        if trs:
            raise SceneFileError(
                "give either transform or translate/rotate/scale, not both", _at(where, trs[0])
            )
        return _rows(t["transform"], _at(where, "transform")), {}
    translate = _numbers(t.get("translate", [0, 0, 0]), _at(where, "translate"))
    rotate = _numbers(t.get("rotate", [0, 0, 0]), _at(where, "rotate"))
    scale = t.get("scale", 1.0)
    if not _is_number(scale):
        scale = _numbers(scale, _at(where, "scale"))
    for k, value, n in (("translate", translate, 3), ("rotate", rotate, 3), ("scale", scale, 3)):
        if isinstance(value, list) and len(value) != n:
            raise _fail(_at(where, k), f"an array of {n} numbers", value)
    # The matrix is built here: its errors (a zero scale) belong to the object.
    return compose_transform(translate, rotate, scale), {"transform": None}


_OBJECT_KEYS = ("material", "back_material", "transform", "translate", "rotate", "scale")


def _add_object(
    scene: Scene, v: Any, where: str, named: Mapping[str, Material], base_dir: Path
) -> None:
    t = _table(v, where, ("mesh",), _OBJECT_KEYS)
    transform, rename = _transform(t, where)
    material = _material(t["material"], _at(where, "material"), named) if "material" in t else None
    # back_material is wired here: Scene.add(..., back_material=...).
    back = None
    if "back_material" in t:
        back = _material(t["back_material"], _at(where, "back_material"), named)
    for mesh, file_material in _mesh(t["mesh"], _at(where, "mesh"), base_dir):
        # An explicit material overrides the file's (MTL) material; else the default.
        mat = material if material is not None else file_material
        _call(where, partial(scene.add, mesh, mat, transform, back), rename)


# ---------------------------------------------------------------------------------------
# Documents

_TOP_KEYS = (
    "ambient",
    "environment",
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
        or version not in READ_VERSIONS
    ):
        raise _fail(
            "version",
            " or ".join(map(str, READ_VERSIONS)) + " (the schema versions this release reads)",
            version,
        )
    _BASE_DIR.set(base)
    t = _table(d, "", ("version",), _TOP_KEYS)
    # Every section is checked even after an error, so that all are reported at once.
    errors: list[SceneFileError] = []

    def checked(fn: Any, default: Any = None) -> Any:
        try:
            return fn()
        except SceneFileError as e:
            errors.append(e)
            return default

    ambient = checked(lambda: _numbers(t["ambient"], "ambient")) if "ambient" in t else None
    fog = checked(lambda: _fog(t["fog"], "fog")) if "fog" in t else None
    environment = (
        checked(lambda: _environment(t["environment"], "environment"))
        if "environment" in t
        else None
    )
    two_sided = checked(lambda: _boolean(t.get("two_sided", False), "two_sided"), False)
    local_viewer = checked(lambda: _boolean(t.get("local_viewer", True), "local_viewer"), True)
    scene = checked(
        lambda: _call(
            "",
            lambda: Scene(
                ambient=ambient,
                fog=fog,
                two_sided=two_sided,
                local_viewer=local_viewer,
                environment=environment,
            ),
        )
    )
    if scene is None:
        # The core refused the scene's settings (recorded above): the lights and objects
        # are still checked, into a plain scene that is never returned.
        scene = Scene()
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
    if mesh.colors is not None:
        d["colors"] = mesh.colors.tolist()
    return d


def scene_to_dict(
    scene: Scene,
    camera: Camera | None = None,
    render: Mapping[str, Any] | RenderOptions | None = None,
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
    if scene.environment is not None:
        d["environment"] = environment_to_dict(scene.environment)
    if camera is not None:
        d["camera"] = camera_to_dict(camera)
    if render:
        given = render.to_dict() if isinstance(render, RenderOptions) else dict(render)
        # TOML has no None: threads = None (all cores) is the default, so it is left out.
        d["render"] = _render_options(
            {k: list(v) if isinstance(v, (tuple, np.ndarray)) else v for k, v in given.items()},
            "render",
        )
        d["render"] = {k: v for k, v in d["render"].items() if v is not None}
        if "edges" not in d["render"]:
            # No lines: their settings are the defaults' or unused; a file without lines
            # reads as before this option existed.
            for k in ("edge_color", "edge_width", "edge_angle", "edges_only"):
                d["render"].pop(k, None)
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


def to_toml(d: Mapping[str, Any]) -> str:
    """``d`` (plain data: tables, arrays, strings, numbers, booleans) as a TOML document,
    written by tomli-w."""
    return tomli_w.dumps(d)


def save_scene(
    path: _PathLike,
    scene: Scene,
    camera: Camera | None = None,
    render: Mapping[str, Any] | RenderOptions | None = None,
) -> None:
    """Writes ``scene`` (with an optional camera and render options) as a scene file."""
    Path(path).write_text(to_toml(scene_to_dict(scene, camera, render)), encoding="utf-8")
