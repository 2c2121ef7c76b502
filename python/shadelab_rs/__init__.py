"""shadelab_rs: a multithreaded Rust tile rasterizer with flat, Gouraud and Phong shading.

Everything heavy runs in the compiled ``_core`` module (the GIL is released while rendering);
this package adds file helpers, the bundled demo scene and the command line.

>>> import shadelab_rs as sl
>>> scene, camera = sl.demo_scene()
>>> sl.render(scene, camera, width=64, height=48).shape
(48, 64, 3)
"""

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
    ObjParseError,
    PointLight,
    RenderOptions,
    Scene,
    SceneObject,
    SpotLight,
    __version__,
    load_obj,
    load_obj_parts,
    render,
    render_frame,
)
from .demo import data_path, demo_scene, frame_mesh
from .figures import lecture_figures
from .io import load_mesh, save_image, to_uint8
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

__all__ = [
    "MAX_AREA_SAMPLES",
    "MAX_IMAGE_SIZE",
    "MAX_THREADS",
    "AreaLight",
    "Camera",
    "DirectionalLight",
    "Fog",
    "Material",
    "Mesh",
    "ObjParseError",
    "PointLight",
    "RenderOptions",
    "Scene",
    "SceneFile",
    "SceneFileError",
    "SceneObject",
    "SpotLight",
    "__version__",
    "data_path",
    "demo_scene",
    "frame_mesh",
    "frame_scene",
    "lecture_figures",
    "load_mesh",
    "load_obj",
    "load_obj_parts",
    "load_scene",
    "load_scene_dict",
    "material_sheet",
    "render",
    "render_frame",
    "save_image",
    "save_scene",
    "scene_to_dict",
    "to_toml",
    "to_uint8",
]
