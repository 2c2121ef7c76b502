"""shadelab_rs: a multithreaded Rust tile rasterizer with flat, Gouraud and Phong shading.

Everything heavy runs in the compiled ``_core`` module (the GIL is released while rendering);
this package adds file helpers, the bundled demo scene and the command line.

>>> import shadelab_rs as sl
>>> scene, camera = sl.demo_scene()
>>> sl.render(scene, camera, width=64, height=48).shape
(48, 64, 3)
"""

from typing import TYPE_CHECKING, Any

from ._core import (
    DEFAULT_TOLERANCE,
    MAX_AREA_SAMPLES,
    MAX_ENVIRONMENT_SIZE,
    MAX_IMAGE_SIZE,
    MAX_SHADOW_RESOLUTION,
    MAX_TEXTURE_SIZE,
    MAX_THREADS,
    MAX_TRACE_DEPTH,
    AreaLight,
    Camera,
    DirectionalLight,
    Environment,
    Fog,
    Material,
    Mesh,
    ObjParseError,
    PointLight,
    RenderOptions,
    Scene,
    SceneObject,
    ShadowSettings,
    SpotLight,
    Texture,
    __version__,
    load_obj,
    load_obj_parts,
)
from .demo import (
    VIEWS,
    camera_from_intrinsics,
    camera_from_matrix,
    data_path,
    demo_scene,
    frame_mesh,
    intrinsics,
    orbit,
    view_direction,
)
from .io import (
    file_up_axis,
    load_environment,
    load_mesh,
    save_depth,
    save_image,
    smooth_normals,
    to_uint8,
)
from .preview import RenderedImage, preview  # eager: the module shares the function's name
from .rendering import EmptyRenderWarning, explain, render, render_frame, srgb_encode
from .textures import bake_texture, texel_centres

# Imported on first use (PEP 562), so that `import shadelab_rs` costs little beyond NumPy's
# import: these modules pull in tomllib/tomli-w, concurrent.futures, logging and dataclasses
# (about half of the package's own import time; docs/COLD_START.md).
_LAZY = {
    "iter_render": "batch",
    "render_batch": "batch",
    "distributed": None,
    "lecture_figures": "figures",
    "SceneFile": "scene_file",
    "SceneFileError": "scene_file",
    "frame_scene": "scene_file",
    "load_scene": "scene_file",
    "load_scene_dict": "scene_file",
    "save_scene": "scene_file",
    "scene_to_dict": "scene_file",
    "to_toml": "scene_file",
    "material_sheet": "swatch",
}

if TYPE_CHECKING:
    from . import distributed
    from .batch import iter_render, render_batch
    from .figures import lecture_figures
    from .scene_file import (
        SceneFile,
        SceneFileError,
        frame_scene,
        load_scene,
        load_scene_dict,
        save_scene,
        scene_to_dict,
        to_toml,
    )
    from .swatch import material_sheet


#: The lazily imported submodules themselves (``sl.scene_file.…`` works as before).
_LAZY_MODULES = {m for m in _LAZY.values() if m is not None}


def __getattr__(name: str) -> Any:
    if name in _LAZY_MODULES:
        _LAZY[name] = None
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    module = importlib.import_module(f".{_LAZY[name] or name}", __name__)
    value = module if _LAZY[name] is None else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | _LAZY_MODULES)


__all__ = [
    "DEFAULT_TOLERANCE",
    "MAX_AREA_SAMPLES",
    "MAX_ENVIRONMENT_SIZE",
    "MAX_IMAGE_SIZE",
    "MAX_SHADOW_RESOLUTION",
    "MAX_TEXTURE_SIZE",
    "MAX_THREADS",
    "MAX_TRACE_DEPTH",
    "VIEWS",
    "AreaLight",
    "Camera",
    "DirectionalLight",
    "EmptyRenderWarning",
    "Environment",
    "Fog",
    "Material",
    "Mesh",
    "ObjParseError",
    "PointLight",
    "RenderOptions",
    "RenderedImage",
    "Scene",
    "SceneFile",
    "SceneFileError",
    "SceneObject",
    "ShadowSettings",
    "SpotLight",
    "Texture",
    "__version__",
    "bake_texture",
    "camera_from_intrinsics",
    "camera_from_matrix",
    "data_path",
    "demo_scene",
    "distributed",
    "explain",
    "file_up_axis",
    "frame_mesh",
    "frame_scene",
    "intrinsics",
    "iter_render",
    "lecture_figures",
    "load_environment",
    "load_mesh",
    "load_obj",
    "load_obj_parts",
    "load_scene",
    "load_scene_dict",
    "material_sheet",
    "orbit",
    "preview",
    "render",
    "render_batch",
    "render_frame",
    "save_depth",
    "save_image",
    "save_scene",
    "scene_to_dict",
    "smooth_normals",
    "srgb_encode",
    "texel_centres",
    "to_toml",
    "to_uint8",
    "view_direction",
]
