"""Type stubs of the compiled extension ``shadelab_rs._core`` (crates/py, PyO3).

Every class is immutable after construction except :class:`Scene`, and none can be
subclassed. Array arguments accept anything ``numpy.asarray`` accepts, in any memory layout
(C, Fortran, strided, read-only); floating inputs may be of any float or integer dtype.
Errors: ``ValueError`` (bad values, with the offending element named, e.g.
``vertices[1, 2]``), ``TypeError`` (bad types), ``FileNotFoundError`` / ``OSError`` (files),
:class:`ObjParseError` (malformed mesh files; a ``ValueError``), ``MemoryError``.
"""

import os
import pathlib
from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar, Final, Literal, TypedDict, final, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray
from typing_extensions import TypeAlias, Unpack

__all__ = [
    "DEFAULT_TOLERANCE",
    "MAX_AREA_SAMPLES",
    "MAX_ENVIRONMENT_SIZE",
    "MAX_IMAGE_SIZE",
    "MAX_SHADOW_RESOLUTION",
    "MAX_TEXTURE_SIZE",
    "MAX_THREADS",
    "MAX_TRACE_DEPTH",
    "AreaLight",
    "Camera",
    "DirectionalLight",
    "Environment",
    "Fog",
    "Material",
    "Mesh",
    "ObjParseError",
    "PointLight",
    "RenderOptions",
    "Scene",
    "SceneObject",
    "ShadowSettings",
    "SpotLight",
    "Texture",
    "__version__",
    "encode_png",
    "explain",
    "load_obj",
    "load_obj_parts",
    "render",
    "render_batch",
    "render_frame",
]

#: Three numbers: a tuple, list or shape-(3,) array (any real dtype).
_Vec3Like: TypeAlias = Sequence[float] | NDArray[Any]
#: ``(r, g, b)`` / ``(x, y, z)`` as returned by the getters.
_Vec3: TypeAlias = tuple[float, float, float]
#: A filesystem path.
_Path: TypeAlias = str | os.PathLike[str]
#: The ``dtype`` argument of :func:`render` selecting uint8 output.
_U8: TypeAlias = Literal["uint8"] | type[np.uint8] | np.dtype[np.uint8]
#: The ``dtype`` argument of :func:`render` selecting float32 output.
_F32: TypeAlias = Literal["float32"] | type[np.float32] | np.dtype[np.float32]
# Literal only, so that a type checker rejects an unknown mode (the runtime also accepts
# any capitalisation).
_Shading: TypeAlias = Literal["flat", "gouraud", "phong", "auto"]
_Specular: TypeAlias = Literal["blinn", "phong", "blinn-normalized"]
_Gouraud: TypeAlias = Literal["normals", "face-intensities"]
_Interpolation: TypeAlias = Literal["perspective", "screen"]
_Edges: TypeAlias = Literal["all", "visible", "features"]
_Technique: TypeAlias = Literal["environment", "ray"]
#: An index of refraction: a number > 0 or a preset name.
_Ior: TypeAlias = float | Literal["air", "water", "glass", "diamond"]
#: What Scene.add takes as a mesh: a Mesh, trimesh.Trimesh / Scene, (V, F), PyVista PolyData.
_MeshLike: TypeAlias = Mesh | tuple[ArrayLike, ArrayLike] | Any
#: A Material or a preset name.
_MaterialLike: TypeAlias = Material | str

__version__: Final[str]
#: Largest supported image width or height in pixels (16384).
MAX_IMAGE_SIZE: Final[int]
#: Largest ``threads`` argument of :func:`render` (256).
MAX_THREADS: Final[int]
#: Largest ``samples`` per side of an :class:`AreaLight` (64, i.e. 4096 point sources).
MAX_AREA_SAMPLES: Final[int]
#: Largest texture image width or height in texels (16384).
MAX_TEXTURE_SIZE: Final[int]

#: Largest :class:`Environment` width in texels (16384).
MAX_ENVIRONMENT_SIZE: Final[int]
#: Largest ``max_depth`` of :class:`RenderOptions` (32).
MAX_TRACE_DEPTH: Final[int]
#: The tolerance of ``shading="auto"`` when none is given: RMSE of 1.0 level of 255.
DEFAULT_TOLERANCE: Final[float]

#: Largest :class:`ShadowSettings` ``resolution`` (8192 texels a side).
MAX_SHADOW_RESOLUTION: Final[int]

@final
class ShadowSettings:
    """A shadow map's settings, for a light's ``shadows=``: ``resolution`` texels a side
    (16 to ``MAX_SHADOW_RESOLUTION``; each of a point light's six cube faces), ``filter``
    ``"pcf"`` (percentage-closer filtering over ``kernel`` x ``kernel`` texels, kernel odd,
    3 to 9) or ``"none"`` (the lectures' plain comparison), and ``bias``, the scale of the
    depth tolerance (one texel's world size at the point, compared with the receiver-plane
    depth: the exact slope-scaled bias; 0 to 100, 1 by default, 0 shows acne), and
    ``cascades`` (1 to 4; directional lights only): the camera's view cut along its axis,
    one map fitted to each slice. ``shadows=True`` is ``ShadowSettings()``."""

    def __copy__(self) -> ShadowSettings: ...
    def __deepcopy__(self, _memo: Any) -> ShadowSettings: ...
    def __new__(
        cls,
        resolution: int = 2048,
        filter: Literal["pcf", "none"] = "pcf",
        kernel: int = 3,
        bias: float = 1.0,
        cascades: int = 1,
    ) -> ShadowSettings: ...
    @property
    def resolution(self) -> int:
        """Texels per side of the map (of each cube face for point lights)."""
    @property
    def filter(self) -> Literal["pcf", "none"]:
        """``"pcf"`` or ``"none"``."""
    @property
    def kernel(self) -> int:
        """The PCF kernel's side in texels (1 with ``filter="none"``)."""
    @property
    def bias(self) -> float:
        """Scale of the default bias."""
    @property
    def cascades(self) -> int:
        """Maps of a directional light, one per slice of the view (other lights: ignored)."""

#: A light's ``shadows=``: False (none), True (a shadow map, default settings), "exact"
#: (shadow rays against the scene's triangles) or a :class:`ShadowSettings`.
_Shadows: TypeAlias = bool | Literal["exact"] | ShadowSettings

class ObjParseError(ValueError):
    """A mesh file was read but its content is malformed (a ValueError).

    The message starts with the file's path and, when known, the 1-based line number:
    ``"model.obj:12: face vertex index out of range"``.
    """

@final
class Mesh:
    """A validated triangle mesh (shared, immutable).

    ``vertices``: (N, 3) positions; ``faces``: (M, 3) vertex indices of any integer dtype,
    counter-clockwise = front; ``normals``: optional (N, 3) vertex normals (normalised
    before use; when omitted, each vertex gets the normalised average of the unit normals of
    its faces); ``uvs``: optional (N, 2) texture coordinates (OpenGL's: (0, 0) is the
    bottom-left of an image); ``colors``: optional (N, 3) or (N, 4) vertex colours, uint8
    (divided by 255) or float (linear, >= 0; alpha is ignored), which replace the material's
    ambient and diffuse colour. Values must be finite in float32 and indices in ``[0, N)``;
    the mesh needs at least one triangle.
    """

    def __copy__(self) -> Mesh: ...
    def __deepcopy__(self, _memo: Any) -> Mesh:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        vertices: ArrayLike,
        faces: ArrayLike,
        normals: ArrayLike | None = None,
        uvs: ArrayLike | None = None,
        colors: ArrayLike | None = None,
    ) -> Mesh: ...
    @classmethod
    def from_trimesh(
        cls, tm: Any, use_normals: bool = False, crease_angle: float | None = 60.0
    ) -> Mesh:
        """Builds a mesh from a ``trimesh.Trimesh`` (its vertices, faces and, when present,
        UVs). Unless ``use_normals`` (trimesh's own normals), the normals are computed on the
        welded positions (no seams where trimesh split vertices for UVs) with edges sharper
        than ``crease_angle`` degrees kept sharp (None: none); see
        ``shadelab_rs.smooth_normals``. Vertices are split at sharp edges."""
    @staticmethod
    def uv_sphere(rings: int = 16, segments: int = 32) -> Mesh:
        """A unit UV sphere at the origin with exact normals: ``rings`` latitude bands (>= 2)
        and ``segments`` longitude segments (>= 3), ``2*segments*(rings - 1)`` triangles."""
    @staticmethod
    def ico_sphere(subdivisions: int = 3) -> Mesh:
        """A unit sphere at the origin from a regular icosahedron subdivided
        ``subdivisions`` times (0 to 10): ``20 * 4**subdivisions`` nearly equal triangles,
        ``10 * 4**subdivisions + 2`` vertices, exact normals."""
    @staticmethod
    def cube() -> Mesh:
        """The cube [-1, 1]^3: 24 vertices (4 per face) with exact face normals and UVs."""
    @staticmethod
    def plane() -> Mesh:
        """The square [-1, 1]^2 in the xz plane at y = 0, facing +y, with UVs."""
    @property
    def vertices(self) -> NDArray[np.float32]:
        """Vertex positions, float32 (N, 3) (a new array on every access)."""
    @property
    def faces(self) -> NDArray[np.uint32]:
        """Triangles, uint32 (M, 3)."""
    @property
    def normals(self) -> NDArray[np.float32]:
        """The vertex normals used for shading (given, or generated), float32 (N, 3)."""
    @property
    def has_normals(self) -> bool:
        """Whether normals were given (True) or are generated (False)."""
    @property
    def uvs(self) -> NDArray[np.float32] | None:
        """Texture coordinates, float32 (N, 2), or None."""
    @property
    def colors(self) -> NDArray[np.float32] | None:
        """Per-vertex linear RGB colours, float32 (N, 3), or None."""
    def with_normals(self, crease_angle: float | None = 60.0) -> Mesh:
        """The same mesh with vertex normals recomputed with a crease angle (degrees, 0 to
        180; None: every edge smooth): positions are welded for the computation, each
        corner takes the normalised sum of the unit normals of the faces around it within
        the angle of its own face, and a vertex whose corners disagree is split (its UV
        and colour copied). Faces keep their order; vertices are never merged."""
    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
    @property
    def n_faces(self) -> int:
        """Number of triangles."""

@final
class Material:
    """OpenGL-style material: ambient, diffuse, specular RGB (each >= 0), shininess (the
    specular exponent, >= 0; ``float("inf")`` is the lectures' perfect mirror: specular only
    where the lobe's base is exactly 1, so none on a rasterized surface in practice, and
    refused with ``specular="blinn-normalized"``) and emission (RGB >= 0, added unlit; black
    by default). Omitted arguments take the default grey plastic's values. Texture maps
    (``diffuse_map``, ``ambient_map`` (default: the diffuse map), ``specular_map``,
    ``emission_map``) multiply their coefficient per point; the specular term is added after
    the texture. ``shininess_map``: the mean of a texel's r, g, b multiplies the shininess per
    pixel (Phong shading only). ``normal_map``: a tangent-space normal map (texel (r, g, b)
    is the normal (2r-1, 2g-1, 2b-1) in the frame tangent, bitangent, normal; tangents come
    from the mesh's UVs), its x and y scaled by ``normal_scale``; ``bump_map``: a height map
    (mean of r, g, b), a value 1 standing ``bump_scale`` UV units above the surface, its
    gradient by central differences of one texel (Phong shading only, both; the mesh needs
    UVs). Materials compare equal when all their values are equal and
    they hold the same Texture objects (and are not hashable).

    Optics (see the user guide, "Reflection, refraction and transparency"):
    ``reflectivity`` (0 to 1, a number or an RGB colour for metals) mirrors that share of
    light; ``transparency`` (0 to 1; reflectivity + transparency <= 1 per channel)
    transmits that share; the colour is ``(1 - R - T)*local + R*reflected +
    T*transmitted``. ``ior`` (> 0, or "air" 1.0, "water" 1.33, "glass" 1.5, "diamond" 2.4)
    bends transmitted light by Snell's law when a render refracts; ``fresnel`` (default
    True) moves the Schlick share F of the transmitted light to the reflected one
    (False: the constant coefficients); ``absorption`` (RGB per unit distance, >= 0)
    darkens light travelling inside (Beer-Lambert, ray-traced refraction only)."""

    def __copy__(self) -> Material: ...
    def __deepcopy__(self, _memo: Any) -> Material:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        ambient: _Vec3Like | None = None,
        diffuse: _Vec3Like | None = None,
        specular: _Vec3Like | None = None,
        shininess: float | None = None,
        emission: _Vec3Like | None = None,
        diffuse_map: Texture | None = None,
        ambient_map: Texture | None = None,
        specular_map: Texture | None = None,
        emission_map: Texture | None = None,
        shininess_map: Texture | None = None,
        reflectivity: float | _Vec3Like | None = None,
        transparency: float = 0.0,
        ior: _Ior | None = None,
        fresnel: bool = True,
        absorption: float | _Vec3Like | None = None,
        normal_map: Texture | None = None,
        normal_scale: float = 1.0,
        bump_map: Texture | None = None,
        bump_scale: float = 1.0,
    ) -> Material: ...
    def with_optics(
        self,
        reflectivity: float | _Vec3Like | None = None,
        transparency: float = 0.0,
        ior: _Ior | None = None,
        fresnel: bool = True,
        absorption: float | _Vec3Like | None = None,
    ) -> Material:
        """The same material (maps kept) with these optical parameters."""
    @property
    def reflectivity(self) -> _Vec3:
        """Share of light mirrored (r, g, b)."""
    @property
    def transparency(self) -> float:
        """Share of light transmitted."""
    @property
    def ior(self) -> float:
        """Index of refraction."""
    @property
    def fresnel(self) -> bool:
        """Whether Schlick's Fresnel term weighs reflection against transmission."""
    @property
    def absorption(self) -> _Vec3:
        """Beer-Lambert absorption per unit distance inside the material (r, g, b)."""
    def with_maps(
        self,
        diffuse_map: Texture | None = None,
        ambient_map: Texture | None = None,
        specular_map: Texture | None = None,
        emission_map: Texture | None = None,
        shininess_map: Texture | None = None,
        normal_map: Texture | None = None,
        normal_scale: float = 1.0,
        bump_map: Texture | None = None,
        bump_scale: float = 1.0,
    ) -> Material:
        """The same material with these texture maps (the others dropped)."""
    @property
    def diffuse_map(self) -> Texture | None:
        """The diffuse map, or None."""
    @property
    def ambient_map(self) -> Texture | None:
        """The ambient map, or None (the diffuse map then weighs the ambient term)."""
    @property
    def specular_map(self) -> Texture | None:
        """The specular map, or None."""
    @property
    def emission_map(self) -> Texture | None:
        """The emission map, or None."""
    @property
    def shininess_map(self) -> Texture | None:
        """The shininess map, or None."""
    @property
    def normal_map(self) -> Texture | None:
        """The tangent-space normal map, or None."""
    @property
    def normal_scale(self) -> float:
        """Scale of the normal map's x and y (1.0 without maps)."""
    @property
    def bump_map(self) -> Texture | None:
        """The bump (height) map, or None."""
    @property
    def bump_scale(self) -> float:
        """Height of a bump-map value 1 in UV units (1.0 without maps)."""
    @staticmethod
    def preset(name: str) -> Material:
        """The named classic preset (case-insensitive; "polished_silver" = "polished silver").

        Raises ``ValueError`` listing the known names for an unknown one."""
    @staticmethod
    def preset_names() -> list[str]:
        """Names of all presets: black plastic, brass, bronze, chrome, copper, gold, pewter,
        silver, polished silver."""
    @property
    def ambient(self) -> _Vec3:
        """Ambient reflectance (r, g, b)."""
    @property
    def diffuse(self) -> _Vec3:
        """Diffuse reflectance (r, g, b)."""
    @property
    def specular(self) -> _Vec3:
        """Specular reflectance (r, g, b)."""
    @property
    def emission(self) -> _Vec3:
        """Emitted colour, added unlit."""
    @property
    def shininess(self) -> float:
        """Specular exponent."""
    def __eq__(self, value: object, /) -> bool: ...
    def __ne__(self, value: object, /) -> bool: ...
    __hash__: None  # type: ignore[assignment]

_Wrap: TypeAlias = Literal["repeat", "clamp", "mirror"]

@final
class Texture:
    """A texture for a Material's maps: an image or a procedural pattern.

    ``array``: (H, W, 3) or (H, W, 4) uint8 (divided by 255), uint16 (by 65535) or float
    (linear values as given) array, or a Pillow RGB/RGBA image; ``array[0]`` is the top row
    of the picture (v near 1); alpha is ignored. ``filter``: "nearest" and "bilinear" read
    the full-size image at every distance, "trilinear" (default) the mip levels around the
    exact level of detail. ``wrap``: "repeat" (default), "clamp" (to the edge) or "mirror",
    or a (u, v) pair. ``srgb``: decode sRGB-encoded values to linear (default False: values
    used as stored, as classic OpenGL). ``anisotropy``: 1 (off) to 16 probes along the
    footprint's major axis (see the user guide). Sizes up to MAX_TEXTURE_SIZE per side and
    2**26 texels.
    """

    def __new__(
        cls,
        array: ArrayLike | Any,
        filter: Literal["nearest", "bilinear", "trilinear"] = "trilinear",
        wrap: _Wrap | tuple[_Wrap, _Wrap] | None = None,
        srgb: bool = False,
        anisotropy: int = 1,
    ) -> Texture: ...
    @staticmethod
    def load(
        path: str | os.PathLike[str],
        filter: Literal["nearest", "bilinear", "trilinear"] = "trilinear",
        wrap: _Wrap | tuple[_Wrap, _Wrap] | None = None,
        srgb: bool = False,
        anisotropy: int = 1,
    ) -> Texture:
        """Decodes an image file (PNG 8 or 16 bit, JPEG); a missing file is
        ``FileNotFoundError``, an undecodable one ``ObjParseError`` naming it."""
    @staticmethod
    def procedural(
        name: Literal["checker", "grid", "stripes", "noise"],
        scale: float = 8.0,
        color_a: _Vec3Like | None = None,
        color_b: _Vec3Like | None = None,
        width: float = 0.1,
        octaves: int = 4,
        seed: int = 0,
    ) -> Texture:
        """A pattern evaluated at each shaded point (not filtered): ``scale`` cells per unit
        of u and v, ``color_a`` (default white) and ``color_b`` (default black); the grid's
        line ``width`` (fraction of a cell); value noise with ``octaves`` (1 to 16) and
        ``seed``."""
    @property
    def kind(self) -> str:
        """ "image", or the procedural pattern's name."""
    @property
    def width(self) -> int | None:
        """Image width in texels (None for a procedural texture)."""
    @property
    def height(self) -> int | None:
        """Image height in texels (None for a procedural texture)."""
    @property
    def levels(self) -> int:
        """Number of mip levels (1 for a procedural texture)."""
    @property
    def anisotropy(self) -> int:
        """Probes of anisotropic filtering (1: off)."""
    @property
    def filter(self) -> str:
        """The filter's name."""
    @property
    def wrap(self) -> tuple[str, str]:
        """The wrap modes (u, v)."""
    @property
    def path(self) -> pathlib.Path | None:
        """The image file this texture was loaded from (None for arrays and patterns)."""
    @property
    def srgb(self) -> bool:
        """Whether the image file was decoded as sRGB."""
    @property
    def uv_transform(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """(scale, offset) applied to (u, v) before sampling (MTL's ``-s`` and ``-o``)."""
    def with_uv_transform(self, scale: tuple[float, float], offset: tuple[float, float]) -> Texture:
        """The same texture read at (u, v) * scale + offset."""
    def to_array(self) -> NDArray[np.float32] | None:
        """The full-size image as linear float32 (H, W, 3), row 0 the top."""
    def sample(
        self,
        u: float,
        v: float,
        derivatives: tuple[float, float, float, float] | None = None,
    ) -> _Vec3:
        """The colour at (u, v) as the renderer reads it, with the screen-space
        derivatives (du/dx, dv/dx, du/dy, dv/dy) that set the level of detail."""
    def __copy__(self) -> Texture: ...
    def __deepcopy__(self, _memo: Any) -> Texture:
        """Pickling and copying keep every texel exactly (textures are immutable)."""

@final
class DirectionalLight:
    """A light at infinity; ``direction`` is where the light travels (a sun overhead:
    ``(0, -1, 0)``) and must be non-zero. ``color`` (default white) and ``intensity``
    (its multiplier) must be >= 0; ``ambient`` is the light's own ambient colour (default
    black). ``diffuse`` / ``specular`` (default None) give the light its own diffuse or
    specular colour (OpenGL's GL_DIFFUSE / GL_SPECULAR of a light) in place of ``color``;
    both are scaled by ``intensity``. No attenuation."""

    def __copy__(self) -> DirectionalLight: ...
    def __deepcopy__(self, _memo: Any) -> DirectionalLight:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        direction: _Vec3Like,
        color: _Vec3Like | None = None,
        intensity: float = 1.0,
        ambient: _Vec3Like | None = None,
        diffuse: _Vec3Like | None = None,
        specular: _Vec3Like | None = None,
        shadows: _Shadows | None = None,
    ) -> DirectionalLight: ...
    @property
    def ambient(self) -> _Vec3:
        """The light's own ambient colour."""
    @property
    def direction(self) -> _Vec3:
        """The direction of travel as given (not normalised: the light uses its unit
        vector), so a light written to a scene file reads back exactly."""
    @property
    def color(self) -> _Vec3:
        """RGB colour."""
    @property
    def intensity(self) -> float:
        """Multiplier of ``color``."""
    @property
    def diffuse(self) -> _Vec3 | None:
        """The light's own diffuse colour, or None when ``color`` sets it."""
    @property
    def specular(self) -> _Vec3 | None:
        """The light's own specular colour, or None when ``color`` sets it."""
    @property
    def shadows(self) -> _Shadows:
        """False, True (a shadow map with default settings), "exact" or the
        :class:`ShadowSettings` of its map."""

@final
class PointLight:
    """A light at a point, shining in all directions. ``color`` (default white) and
    ``intensity`` must be >= 0. ``attenuation=(kc, kl, kq)`` divides the light by
    ``kc + kl*d + kq*d**2`` (d: distance to the light; default (1, 0, 0), none; coefficients
    >= 0, not all zero; the divisor is at least 1e-6). ``ambient`` is the light's own ambient
    colour (default black), attenuated like the rest. ``diffuse`` / ``specular`` override
    ``color`` for their term, as for DirectionalLight."""

    def __copy__(self) -> PointLight: ...
    def __deepcopy__(self, _memo: Any) -> PointLight:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        position: _Vec3Like,
        color: _Vec3Like | None = None,
        intensity: float = 1.0,
        attenuation: _Vec3Like | None = None,
        ambient: _Vec3Like | None = None,
        diffuse: _Vec3Like | None = None,
        specular: _Vec3Like | None = None,
        shadows: _Shadows | None = None,
    ) -> PointLight: ...
    @property
    def ambient(self) -> _Vec3:
        """The light's own ambient colour."""
    @property
    def attenuation(self) -> _Vec3:
        """(kc, kl, kq)."""
    @property
    def position(self) -> _Vec3:
        """World position."""
    @property
    def color(self) -> _Vec3:
        """RGB colour."""
    @property
    def intensity(self) -> float:
        """Multiplier of ``color``."""
    @property
    def diffuse(self) -> _Vec3 | None:
        """The light's own diffuse colour, or None when ``color`` sets it."""
    @property
    def specular(self) -> _Vec3 | None:
        """The light's own specular colour, or None when ``color`` sets it."""
    @property
    def shadows(self) -> _Shadows:
        """False, True (a shadow map with default settings), "exact" or the
        :class:`ShadowSettings` of its map."""

@final
class SpotLight:
    """A point light restricted to a cone, with OpenGL's GL_SPOT_CUTOFF / GL_SPOT_EXPONENT
    meaning: the spot factor is ``max(-l.d, 0)**exponent`` inside the cone
    (``-l.d >= cos(cutoff)``) and 0 outside (l: surface to light, d: ``direction``).
    ``cutoff`` is in degrees, in (0, 90] or exactly 180 (no cone). ``inner`` (degrees,
    < cutoff) fades the edge with a smoothstep from the cutoff in to ``inner``. The other
    arguments are those of PointLight; ambient is scaled by the spot factor too."""

    def __copy__(self) -> SpotLight: ...
    def __deepcopy__(self, _memo: Any) -> SpotLight:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        position: _Vec3Like,
        direction: _Vec3Like,
        cutoff: float = 30.0,
        exponent: float = 0.0,
        color: _Vec3Like | None = None,
        intensity: float = 1.0,
        attenuation: _Vec3Like | None = None,
        ambient: _Vec3Like | None = None,
        inner: float | None = None,
        diffuse: _Vec3Like | None = None,
        specular: _Vec3Like | None = None,
        shadows: _Shadows | None = None,
    ) -> SpotLight: ...
    @property
    def position(self) -> _Vec3:
        """World position."""
    @property
    def direction(self) -> _Vec3:
        """The direction the cone points, as given (not normalised: the light uses its
        unit vector)."""
    @property
    def cutoff(self) -> float:
        """Cone half-angle in degrees (180: no cone)."""
    @property
    def exponent(self) -> float:
        """Fall-off exponent."""
    @property
    def inner(self) -> float | None:
        """Inner angle of the smooth edge in degrees, or None."""
    @property
    def color(self) -> _Vec3:
        """RGB colour."""
    @property
    def intensity(self) -> float:
        """Multiplier of ``color``."""
    @property
    def diffuse(self) -> _Vec3 | None:
        """The light's own diffuse colour, or None when ``color`` sets it."""
    @property
    def specular(self) -> _Vec3 | None:
        """The light's own specular colour, or None when ``color`` sets it."""
    @property
    def shadows(self) -> _Shadows:
        """False, True (a shadow map with default settings), "exact" or the
        :class:`ShadowSettings` of its map."""
    @property
    def attenuation(self) -> _Vec3:
        """(kc, kl, kq)."""
    @property
    def ambient(self) -> _Vec3:
        """The light's own ambient colour."""

@final
class AreaLight:
    """A rectangle or disk light modelled, as in the lecture model, by ``samples**2`` point
    sources spread evenly over it, each carrying ``1 / samples**2`` of the colour and
    ambient (so the total light does not depend on ``samples``, the speed/accuracy knob).

    The outline is centred at ``position`` and spanned by the edge vectors ``u`` and ``v``
    (finite, non-zero, not parallel): a rectangle is ``position + s*u + t*v`` for ``s, t`` in
    ``[-1/2, 1/2]`` with one point at the centre of each cell of a ``samples x samples``
    grid; a disk is the ellipse inscribed in it, sampled by a golden-angle spiral at
    equal-area radii. Each point is a point light with this light's ``attenuation``;
    ``one_sided=True`` makes each a Lambertian emitter (a spot light with cutoff 90 and
    exponent 1 along ``normal = u x v / |u x v|``), dark behind the light."""

    def __copy__(self) -> AreaLight: ...
    def __deepcopy__(self, _memo: Any) -> AreaLight:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        position: _Vec3Like,
        u: _Vec3Like,
        v: _Vec3Like,
        shape: Literal["rectangle", "disk"] = "rectangle",
        samples: int | None = None,
        color: _Vec3Like | None = None,
        intensity: float = 1.0,
        attenuation: _Vec3Like | None = None,
        ambient: _Vec3Like | None = None,
        one_sided: bool = False,
        diffuse: _Vec3Like | None = None,
        specular: _Vec3Like | None = None,
        shadows: _Shadows | None = None,
    ) -> AreaLight: ...
    @property
    def position(self) -> _Vec3:
        """Centre."""
    @property
    def u(self) -> _Vec3:
        """First edge vector."""
    @property
    def v(self) -> _Vec3:
        """Second edge vector."""
    @property
    def normal(self) -> _Vec3:
        """Unit normal ``u x v / |u x v|``: the emitting side of a one-sided light."""
    @property
    def shape(self) -> Literal["rectangle", "disk"]:
        """``"rectangle"`` or ``"disk"``."""
    @property
    def samples(self) -> int:
        """Points per side (default 4; 1 to ``MAX_AREA_SAMPLES``)."""
    @property
    def n_points(self) -> int:
        """Number of point sources, ``samples**2``: the per-pixel cost in point lights."""
    @property
    def one_sided(self) -> bool:
        """Whether only the side ``normal`` points to emits (with a cosine fall-off)."""
    @property
    def color(self) -> _Vec3:
        """RGB colour of the whole light."""
    @property
    def intensity(self) -> float:
        """Multiplier of ``color``, shared equally by the points."""
    @property
    def diffuse(self) -> _Vec3 | None:
        """The light's own diffuse colour, or None when ``color`` sets it."""
    @property
    def specular(self) -> _Vec3 | None:
        """The light's own specular colour, or None when ``color`` sets it."""
    @property
    def shadows(self) -> _Shadows:
        """False, True (a shadow map with default settings), "exact" or the
        :class:`ShadowSettings` of its map."""
    @property
    def attenuation(self) -> _Vec3:
        """Distance attenuation (kc, kl, kq), applied to each point with its own distance."""
    @property
    def ambient(self) -> _Vec3:
        """The light's own ambient colour, shared by the points."""
    def points(self) -> NDArray[np.float32]:
        """The sample positions, an ``(n_points, 3)`` float32 array."""

@final
class Fog:
    """Depth cueing: each pixel's colour c becomes ``f*c + (1 - f)*color`` with d the
    Euclidean distance from the eye to the surface and f, clamped to [0, 1], given by
    ``mode``: "linear" ``(end - d)/(end - start)`` (start < end), "exp" ``exp(-density*d)``,
    "exp2" ``exp(-(density*d)**2)`` (density >= 0). Applied per pixel in every shading
    mode; the background is not fogged."""

    def __copy__(self) -> Fog: ...
    def __deepcopy__(self, _memo: Any) -> Fog:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        mode: Literal["linear", "exp", "exp2"] = "linear",
        start: float = 0.0,
        end: float = 1.0,
        density: float = 1.0,
        color: _Vec3Like | None = None,
    ) -> Fog: ...
    @property
    def mode(self) -> Literal["linear", "exp", "exp2"]:
        """The fall-off."""
    @property
    def start(self) -> float | None:
        """Linear fog: where it starts (None otherwise)."""
    @property
    def end(self) -> float | None:
        """Linear fog: where only fog is left (None otherwise)."""
    @property
    def density(self) -> float | None:
        """Exp/exp2 fog: the density (None for linear)."""
    @property
    def color(self) -> _Vec3:
        """The colour far objects fade to (default (0.5, 0.5, 0.5))."""
    def factor(self, d: float) -> float:
        """The fog factor f in [0, 1] at eye distance ``d`` (1: no fog)."""

@final
class Environment:
    """An equirectangular (latitude-longitude) environment: the light arriving from every
    direction, read by reflections and refractions and shown by
    ``background="environment"``.

    ``array``: (H, 2H, 3) float32/float64 (linear, HDR values allowed, each finite and
    >= 0) or uint8 (divided by 255; ``srgb=True`` decodes sRGB instead). A unit direction d
    maps to ``u = 0.5 + atan2(d.x, -d.z)/(2 pi)``, ``v = acos(d.y)/pi``: column ``u*W`` and
    row ``v*H`` (texel centres at half-integers; in float32, u and v within 3e-7 of the
    exact values), so row 0 looks straight up (+y) and the
    centre column along -z; sampled bilinearly, wrapping in u and clamped in v.
    ``rotation`` turns it about +y (degrees; positive turns what was seen along -z toward
    -x); ``intensity`` (>= 0) scales every value. Six cube faces: :meth:`from_cube`."""

    def __new__(
        cls,
        array: ArrayLike,
        rotation: float = 0.0,
        intensity: float = 1.0,
        srgb: bool = False,
        *,
        path: _Path | None = None,
    ) -> Environment: ...
    @staticmethod
    def from_cube(
        faces: Sequence[ArrayLike] | Mapping[str, ArrayLike] | ArrayLike,
        rotation: float = 0.0,
        intensity: float = 1.0,
        srgb: bool = False,
        *,
        paths: Sequence[_Path] | None = None,
    ) -> Environment:
        """An environment from six square cube faces of one size N, in the OpenGL cube-map
        convention: a sequence (or a (6, N, N, 3) array) in the order +X, -X, +Y, -Y, +Z,
        -Z, or a dict with the keys "+x", "-x", "+y", "-y", "+z", "-z"; each face an
        (N, N, 3) array as for :class:`Environment`. A direction's major axis picks the
        face; ``(sc, tc, ma)`` is ``(-z, -y, x)`` on +X, ``(z, -y, x)`` on -X, ``(x, z, y)``
        on +Y, ``(x, -z, y)`` on -Y, ``(x, -y, z)`` on +Z, ``(-x, -y, z)`` on -Z, and
        ``s = (sc/|ma| + 1)/2``, ``t = (tc/|ma| + 1)/2`` are read at column ``s*N``, row
        ``t*N`` (row 0 the face image's first row). Bilinear and seamless: a tap beyond a
        face's border reads the neighbouring face. ``rotation``, ``intensity``, ``srgb``
        as for :class:`Environment`; ``paths``: the six files
        (:func:`shadelab_rs.load_environment`)."""
    @property
    def layout(self) -> Literal["equirectangular", "cube"]:
        """How the texels cover the directions."""
    @property
    def path(self) -> pathlib.Path | None:
        """The equirectangular file it was read from
        (:func:`shadelab_rs.load_environment`), or None."""
    @property
    def face_paths(self) -> list[pathlib.Path] | None:
        """The six cube face files it was read from (+X, -X, +Y, -Y, +Z, -Z), or None."""
    def __copy__(self) -> Environment: ...
    def __deepcopy__(self, _memo: Any) -> Environment: ...
    @property
    def array(self) -> NDArray[np.float32]:
        """The texels, float32 linear (before the intensity): (H, 2H, 3), or (6, N, N, 3)
        for a cube."""
    @property
    def rotation(self) -> float:
        """Rotation about +y in degrees."""
    @property
    def intensity(self) -> float:
        """The factor every value is multiplied by."""
    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) in texels (a cube: one face's)."""
    def sample(self, directions: ArrayLike) -> NDArray[np.float32]:
        """The colour seen along each direction of an (..., 3) array, as reflections read
        it (intensity included)."""
    def __eq__(self, value: object, /) -> bool: ...
    def __ne__(self, value: object, /) -> bool: ...
    __hash__: None  # type: ignore[assignment]

@final
class SceneObject:
    """One object of a scene as read back by :attr:`Scene.objects`: a snapshot, so changing
    it does not change the scene. There is no constructor."""

    def __copy__(self) -> SceneObject: ...
    def __deepcopy__(self, _memo: Any) -> SceneObject:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    @property
    def mesh(self) -> Mesh:
        """The mesh (shared with the scene, not copied)."""
    @property
    def material(self) -> Material:
        """The material."""
    @property
    def back_material(self) -> Material | None:
        """The material of back faces under two-sided lighting, or None (``material`` is
        used for both sides)."""
    @property
    def transform(self) -> NDArray[np.float64]:
        """The 4x4 model matrix, float64 (the float32 values the scene holds, exactly)."""

@final
class Scene:
    """Objects, lights, the global ambient light (default ``(0.2, 0.2, 0.2)``) and an
    optional fog."""

    def __copy__(self) -> Scene: ...
    def __deepcopy__(self, _memo: Any) -> Scene:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    def __new__(
        cls,
        ambient: _Vec3Like | None = None,
        fog: Fog | None = None,
        two_sided: bool = False,
        local_viewer: bool = True,
        default_lights: bool = True,
        environment: Environment | None = None,
    ) -> Scene: ...
    @property
    def environment(self) -> Environment | None:
        """The environment read by reflections and refractions (and shown by
        ``background="environment"``), or None; assignable."""
    @environment.setter
    def environment(self, environment: Environment | None) -> None: ...
    @property
    def default_lights(self) -> bool:
        """True (default): while the scene has no lights, ``render`` lights it with a rig
        that moves with the camera: a headlight (intensity 0.35) from the eye, a key light
        (0.55) from 45 degrees above and 35 to the left, and a fill (0.25) from 25 below and
        50 to the right, all white directional lights. False: no lights means unlit
        (ambient and emission only); assignable."""
    @default_lights.setter
    def default_lights(self, on: bool) -> None: ...
    @property
    def two_sided(self) -> bool:
        """Two-sided lighting: back faces (clockwise on screen) are lit with the flipped
        normal (OpenGL's GL_LIGHT_MODEL_TWO_SIDE); assignable. Off: the normal as given."""
    @two_sided.setter
    def two_sided(self, on: bool) -> None: ...
    @property
    def local_viewer(self) -> bool:
        """True (default): v points from each surface point to the eye. False: OpenGL's
        infinite viewer, v is the constant direction toward the eye; assignable."""
    @local_viewer.setter
    def local_viewer(self, local: bool) -> None: ...
    @property
    def fog(self) -> Fog | None:
        """The fog, or None; assignable."""
    @fog.setter
    def fog(self, fog: Fog | None) -> None: ...
    def add(
        self,
        mesh: _MeshLike,
        material: _MaterialLike | None = None,
        transform: ArrayLike | None = None,
        back_material: _MaterialLike | None = None,
    ) -> int:
        """Adds ``mesh`` with ``material`` (a Material or a preset name; default: the
        mesh's own colour when it has one, else grey plastic) placed by the 4x4 model
        matrix ``transform`` (column vectors: ``p_world = transform @ [x, y, z, 1]``; it must
        be affine and invertible). The mesh is shared, not copied. ``back_material`` lights
        the back faces (clockwise on screen) when the scene is two-sided, as OpenGL's
        ``GL_BACK`` material; otherwise both sides use ``material``.

        ``mesh`` may also be a ``trimesh.Trimesh``, a ``trimesh.Scene`` (each geometry
        instance with its transform, then ``transform``), a ``(vertices, faces)`` pair or a
        PyVista ``PolyData``. Returns the number of objects added."""
    def remove_object(self, index: int) -> None:
        """Removes the object at ``index`` (negative counts from the end; ``IndexError``
        when out of range)."""
    def remove_light(self, index: int) -> None:
        """Removes the light at ``index``."""
    def set_light(
        self, index: int, light: DirectionalLight | PointLight | SpotLight | AreaLight
    ) -> None:
        """Replaces the light at ``index``."""
    def clear_objects(self) -> None:
        """Removes every object."""
    def clear_lights(self) -> None:
        """Removes every light (the default rig then lights renders unless
        ``default_lights`` is False)."""
    def set_transform(self, index: int, transform: ArrayLike) -> None:
        """Moves the object at ``index``: its model matrix becomes ``transform``."""
    def set_material(self, index: int, material: _MaterialLike) -> None:
        """Gives the object at ``index`` a new material (a Material or a preset name)."""
    def bounds(self) -> tuple[_Vec3, _Vec3] | None:
        """The world-space axis-aligned box of all objects (each mesh's box, transformed)
        as ``((x0, y0, z0), (x1, y1, z1))``, or None without objects."""
    def add_obj(
        self,
        path: _Path,
        material: _MaterialLike | None = None,
        transform: ArrayLike | None = None,
        back_material: _MaterialLike | None = None,
    ) -> int:
        """Loads an OBJ file and adds each part (one per ``o``/``g`` group and per ``usemtl``
        switch) as its own object with its MTL material (grey plastic where it has none),
        or with ``material`` for every part when given (a preset overrides the file).
        Returns the number of objects added."""
    def add_light(self, light: DirectionalLight | PointLight | SpotLight | AreaLight) -> None:
        """Adds a DirectionalLight, PointLight, SpotLight or AreaLight."""
    @property
    def objects(self) -> tuple[SceneObject, ...]:
        """The objects, in the order they were added: a read-only tuple of snapshots (change
        the scene with remove_object, set_transform, set_material, clear_objects)."""
    @property
    def lights(self) -> tuple[DirectionalLight | PointLight | SpotLight | AreaLight, ...]:
        """The lights, in the order they were added: a read-only tuple (change the scene
        with add_light, remove_light, set_light, clear_lights)."""
    @staticmethod
    def from_file(path: _Path) -> Scene:
        """The scene of a scene file (TOML, schema in the user guide); relative mesh paths
        are resolved against the file's directory. ``shadelab_rs.load_scene`` also returns
        the file's camera and render options.

        Raises ``FileNotFoundError`` or ``shadelab_rs.SceneFileError`` (a ``ValueError``
        naming the key path of the bad value)."""
    @staticmethod
    def from_dict(d: Mapping[str, Any], base_dir: _Path | None = None) -> Scene:
        """The scene described by ``d`` (the scene-file schema as plain Python data);
        relative mesh paths are resolved against ``base_dir`` (default: the current
        directory)."""
    def to_dict(self) -> dict[str, Any]:
        """This scene as plain Python data in the scene-file schema (meshes as primitives
        when they are one, else inline arrays); ``Scene.from_dict(scene.to_dict())``
        renders bit-identically."""
    @property
    def ambient(self) -> _Vec3:
        """Global ambient light (r, g, b)."""
    @property
    def n_objects(self) -> int:
        """Number of objects."""
    @property
    def n_lights(self) -> int:
        """Number of lights."""
    @property
    def n_triangles(self) -> int:
        """Total triangles over all objects."""

@final
class Camera:
    """A look-at camera with perspective, pinhole (pixel intrinsics) or orthographic
    projection (OpenGL conventions: right-handed world, the camera looks down -z in eye
    space). Build one with :meth:`look_at`, :meth:`from_intrinsics` or :meth:`orthographic`;
    there is no constructor."""

    def __copy__(self) -> Camera: ...
    def __deepcopy__(self, _memo: Any) -> Camera:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""

    @staticmethod
    def look_at(
        eye: _Vec3Like,
        target: _Vec3Like,
        up: _Vec3Like | None = None,
        fov_y: float = 45.0,
        near: float | None = None,
        far: float | None = None,
    ) -> Camera:
        """Perspective camera; ``fov_y`` is the full vertical angle in degrees, in (0, 180);
        ``0 < near < far``; ``up`` defaults to ``(0, 1, 0)`` and must not be parallel to
        ``target - eye``.

        ``near`` / ``far`` None (the default): fitted at render time to the scene's bounds
        for this eye (from just in front of the nearest to just behind the farthest corner
        of the scene's box along the view axis; near at least far / 1e5), so the whole
        scene is drawn whatever its scale. See :meth:`fitted`."""
    @staticmethod
    def from_intrinsics(
        eye: _Vec3Like,
        target: _Vec3Like,
        up: _Vec3Like | None = None,
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        width: int,
        height: int,
        skew: float = 0.0,
        near: float | None = None,
        far: float | None = None,
    ) -> Camera:
        """Pinhole camera from pixel intrinsics ``K = [[fx, skew, cx], [0, fy, cy], [0, 0,
        1]]`` of a ``width`` x ``height`` image, in the computer-vision convention (x right,
        y down, pixel (x, y) centred at (x + 0.5, y + 0.5)); the optical axis passes through
        ``target``, which is seen at the principal point (cx, cy). Every value must be
        finite, ``fx, fy > 0`` and ``width, height >= 1``; planes as for :meth:`look_at`.

        Rendering at another size scales K by the size ratio (``fx``, ``skew``, ``cx`` by
        ``render_width / width``; ``fy``, ``cy`` by ``render_height / height``), so another
        aspect ratio stretches the image."""
    @staticmethod
    def orthographic(
        eye: _Vec3Like,
        target: _Vec3Like,
        up: _Vec3Like | None = None,
        height: float = 2.0,
        near: float | None = None,
        far: float | None = None,
    ) -> Camera:
        """Orthographic camera; ``height`` (> 0) is the view's vertical extent in world units
        and ``near < far``; None planes are fitted to the scene as for :meth:`look_at`."""
    def fitted(self, scene: Scene) -> Camera:
        """This camera with the planes ``render`` uses for ``scene``: the given ones kept,
        the others fitted to the scene's bounds."""
    def view_matrix(self) -> NDArray[np.float64]:
        """The 4x4 world-to-eye matrix (OpenGL's gluLookAt)."""
    def projection_matrix(self, aspect: float) -> NDArray[np.float64]:
        """The 4x4 eye-to-clip matrix for ``aspect`` = width / height: reversed-Z with a
        [0, 1] depth range (near maps to 1, far to 0). Uses the placeholder planes (0.1,
        100) for planes left to fit; call it on :meth:`fitted` for the rendered ones. A
        pinhole camera's matrix does not depend on ``aspect`` (K scales with the render
        size)."""
    @property
    def eye(self) -> _Vec3:
        """Eye position."""
    @property
    def target(self) -> _Vec3:
        """Point looked at."""
    @property
    def up(self) -> _Vec3:
        """Up hint."""
    @property
    def near(self) -> float | None:
        """Near plane distance, or None when it is fitted to the scene at render time."""
    @property
    def far(self) -> float | None:
        """Far plane distance, or None when it is fitted to the scene at render time."""
    @property
    def kind(self) -> Literal["perspective", "pinhole", "orthographic"]:
        """``"perspective"``, ``"pinhole"`` or ``"orthographic"``."""
    @property
    def fov_y(self) -> float | None:
        """Vertical field of view in degrees (None for pinhole and orthographic)."""
    @property
    def height(self) -> float | None:
        """Vertical extent (None for perspective and pinhole)."""
    @property
    def intrinsics(self) -> tuple[float, float, float, float, float, int, int] | None:
        """``(fx, fy, cx, cy, skew, width, height)`` of a pinhole camera, else None."""

def load_obj(path: _Path) -> Mesh:
    """Loads an OBJ file as one mesh (all groups merged; polygons triangulated).

    Raises ``FileNotFoundError``, ``OSError`` or :class:`ObjParseError`."""

def load_obj_parts(path: _Path) -> list[tuple[str, Mesh, Material | None]]:
    """Loads every group of an OBJ file as ``(name, Mesh, Material | None)`` tuples, the
    material read from the file's MTL library (Ka, Kd, Ks, Ns) when it has one."""

def encode_png(
    image: NDArray[np.uint8] | NDArray[np.uint16],
    compression: Literal["none", "fastest", "fast", "balanced", "high"] = "fast",
    text: Sequence[tuple[str, str]] | None = None,
) -> bytes:
    """The PNG file of an (H, W) or (H, W, C) C-contiguous uint8 or uint16 array (C = 1 to
    4), with ``text`` as tEXt chunks; ``compression`` is "none", "fastest", "fast",
    "balanced" or "high"."""

class _Frame(TypedDict):
    image: NDArray[Any]
    depth: NDArray[np.float32] | None
    alpha: NDArray[np.float32] | None
    stats: dict[str, Any]

@final
class RenderOptions:
    """How to render, spelled once: :func:`render` and :func:`render_frame` take these
    arguments (positionally after the camera, or by keyword) or an ``options=`` object,
    scene files' ``[render]`` table has these keys, and the command line's flags map to
    them. Checked when built (a ``ValueError`` names the argument in ``field``).

    ``width``, ``height``: 1 to :data:`MAX_IMAGE_SIZE`. ``shading``: "flat", "gouraud",
    "phong", or "auto": each object shaded with the fastest mode whose estimated error
    (RMSE in 8-bit levels against the exact surface) is within ``tolerance`` (finite,
    > 0; default :data:`DEFAULT_TOLERANCE`; only with "auto"), Phong where none is
    (see :func:`explain`); ``specular``: "blinn" (Blinn-Phong), "phong" or "blinn-normalized"
    (case-insensitive). ``background``: linear RGB of empty pixels (default black).
    ``cull_backfaces``: skip clockwise faces. ``cull_hidden``: skip the back faces that
    cannot show (default True): those of an opaque object whose mesh is closed, consistently
    wound and encloses each piece outward, seen from outside (every vertex beyond the near
    plane) and not mirrored by its transform; the image is the same. ``threads``: worker
    threads, None for all cores; the image is bit-identical for any count. ``gouraud``:
    "normals" (each vertex lit with its normal, the default) or "face-intensities" (the
    mean of the flat-lit colours of the faces around the vertex, the lectures' simple
    method). ``interpolation``:
    "perspective" (perspective-correct, the default) or "screen" (affine, the lectures'
    scan-line formulas) for Gouraud colours and Phong normals and positions. ``samples``:
    1 (default) or 2, 4, 8, 16: multi-sample anti-aliasing at the standard D3D/Vulkan
    sample positions, each pixel shaded once per visible triangle and resolved by coverage.
    ``supersample``: k from 1 (default) to 8: render k x k pixels per output pixel and
    average them (exact but k^2 times the work). ``edges``: None (default), "all" (every
    triangle edge, a wireframe), "visible" (hidden-line removal: every edge not hidden by a
    nearer surface) or "features" (visible silhouettes, boundaries and creases) drawn as
    lines over the image; ``edge_color`` (linear RGB, each >= 0), ``edge_width`` (pixels,
    > 0, at most 256; anti-aliased with ``samples`` > 1), ``edge_angle`` (degrees, 0 to
    180: the crease angle of "features", default 30), ``edges_only`` (draw the lines
    alone: surfaces still hide what is behind them but show the background).
    ``background="environment"`` shows the
    scene's environment along each pixel's view ray. ``reflections``: "environment" (one
    lookup along the mirror direction, the default) or "ray" (secondary rays through the
    scene); ``refractions``: None (transparent surfaces blend straight through, sorted per
    pixel), "environment" or "ray" (Snell's law, total internal reflection);
    ``max_depth``: 0 to :data:`MAX_TRACE_DEPTH` secondary ray segments (default 5; at the
    limit the environment is looked up)."""

    def __new__(
        cls,
        width: int = 800,
        height: int = 600,
        shading: _Shading = "phong",
        specular: _Specular = "blinn",
        background: _Vec3Like | Literal["environment"] | None = None,
        cull_backfaces: bool = False,
        threads: int | None = None,
        gouraud: _Gouraud = "normals",
        interpolation: _Interpolation = "perspective",
        samples: int | None = 1,
        supersample: int | None = 1,
        edges: _Edges | None = None,
        edge_color: _Vec3Like | None = (0.0, 0.0, 0.0),
        edge_width: float | None = 1.0,
        edge_angle: float | None = 30.0,
        edges_only: bool = False,
        reflections: _Technique = "environment",
        refractions: _Technique | None = None,
        max_depth: int | None = 5,
        tolerance: float | None = None,
        cull_hidden: bool = True,
    ) -> RenderOptions: ...
    def __copy__(self) -> RenderOptions: ...
    def __deepcopy__(self, _memo: Any) -> RenderOptions:
        """Pickling and copying keep every value exactly (see the user guide, "Many views")."""
    shading_names: ClassVar[tuple[str, str, str, str]]
    """The names ``shading`` takes (in any case)."""
    specular_names: ClassVar[tuple[str, str, str]]
    """The names ``specular`` takes (in any case)."""
    gouraud_names: ClassVar[tuple[str, str]]
    """The names ``gouraud`` takes (in any case)."""
    interpolation_names: ClassVar[tuple[str, str]]
    """The names ``interpolation`` takes (in any case)."""
    edges_names: ClassVar[tuple[str, str, str]]
    """The names ``edges`` takes besides None (in any case)."""
    def replace(self, **changes: Unpack[_RenderOptionsArgs]) -> RenderOptions:
        """The same options with the given ones changed."""
    def to_dict(self) -> dict[str, Any]:
        """Every option by name: ``RenderOptions(**o.to_dict()) == o``."""
    @property
    def width(self) -> int:
        """Image width in pixels."""
    @property
    def height(self) -> int:
        """Image height in pixels."""
    @property
    def shading(self) -> str:
        """ "flat", "gouraud", "phong" or "auto"."""
    @property
    def tolerance(self) -> float | None:
        """The error budget of ``shading="auto"`` (RMSE in 8-bit levels), else None."""
    @property
    def specular(self) -> str:
        """ "blinn", "phong" or "blinn-normalized"."""
    @property
    def background(self) -> _Vec3 | Literal["environment"]:
        """Linear RGB of empty pixels, or "environment"."""
    @property
    def reflections(self) -> str:
        """ "environment" or "ray"."""
    @property
    def refractions(self) -> str | None:
        """None, "environment" or "ray"."""
    @property
    def max_depth(self) -> int:
        """Secondary ray segments followed at most."""
    @property
    def cull_backfaces(self) -> bool:
        """Whether clockwise (back) faces are skipped."""
    @property
    def cull_hidden(self) -> bool:
        """Whether the back faces that cannot show (of opaque closed solids seen from
        outside) are skipped."""
    @property
    def threads(self) -> int | None:
        """Worker threads, or None for all cores."""
    @property
    def gouraud(self) -> str:
        """ "normals" or "face-intensities"."""
    @property
    def interpolation(self) -> str:
        """ "perspective" or "screen"."""
    @property
    def samples(self) -> int:
        """Visibility samples per pixel: 1, or 2, 4, 8, 16 (multi-sample anti-aliasing)."""
    @property
    def supersample(self) -> int:
        """Supersampling factor k (k x k pixels averaged per output pixel)."""
    @property
    def edges(self) -> str | None:
        """Which edges are drawn as lines: None, "all", "visible" or "features"."""
    @property
    def edge_color(self) -> _Vec3:
        """Linear RGB of the lines."""
    @property
    def edge_width(self) -> float:
        """Line width in pixels."""
    @property
    def edge_angle(self) -> float:
        """Crease angle in degrees ("features")."""
    @property
    def edges_only(self) -> bool:
        """Whether the lines are drawn alone (surfaces painted as the background)."""

class _RenderOptionsArgs(TypedDict, total=False):
    """The keywords of :class:`RenderOptions` (tests/test_render_options.py checks that
    they are the constructor's)."""

    width: int
    height: int
    shading: _Shading
    specular: _Specular
    background: _Vec3Like | Literal["environment"] | None
    cull_backfaces: bool
    threads: int | None
    gouraud: _Gouraud
    interpolation: _Interpolation
    samples: int | None
    supersample: int | None
    edges: _Edges | None
    edge_color: _Vec3Like | None
    edge_width: float | None
    edge_angle: float | None
    edges_only: bool
    reflections: _Technique
    refractions: _Technique | None
    max_depth: int | None
    tolerance: float | None
    cull_hidden: bool

# One overload per output type; the render options are RenderOptions' arguments.
@overload
def render(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: _U8 | None = None,
    return_depth: Literal[False] = False,
    options: RenderOptions | None = None,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> NDArray[np.uint8]: ...
@overload
def render(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: _F32,
    return_depth: Literal[False] = False,
    options: RenderOptions | None = None,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> NDArray[np.float32]: ...
@overload
def render(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: _U8 | None = None,
    return_depth: Literal[True],
    options: RenderOptions | None = None,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> tuple[NDArray[np.uint8], NDArray[np.float32]]: ...
@overload
def render(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: _F32,
    return_depth: Literal[True],
    options: RenderOptions | None = None,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> tuple[NDArray[np.float32], NDArray[np.float32]]: ...
@overload
def render(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> NDArray[Any] | tuple[NDArray[Any], NDArray[np.float32]]:
    """Renders ``scene`` through ``camera`` into a C-contiguous (height, width, 3) array, or
    a tuple (image, depth) with ``return_depth=True``. The GIL is released while rendering.

    The render options are :class:`RenderOptions`' arguments (``render(s, c, 640, 480,
    shading="flat")``), or ``options=`` (updated by any keyword given with it).
    ``dtype``: "uint8" (default, ``round(clamp(c, 0, 1) * 255)``) or "float32" (linear,
    unclamped). ``depth``: float32 eye-space depth (distance along the viewing axis, world
    units), +inf where nothing was drawn.
    """

def render_frame(
    scene: Scene,
    camera: Camera,
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    alpha: bool = False,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> _Frame:
    """Like :func:`render`, returning a dict with "image", "depth" (or None), "alpha" and
    "stats": triangle counters (``triangles_in``, ``triangles_setup``,
    ``triangles_clipped``, ``triangles_culled``, ``triangles_dropped``), ``light_sources``
    (point sources lit per shaded point; an area light counts its ``n_points``) and
    per-stage wall times in milliseconds (keys ending in ``_ms``). With ``alpha=True`` the
    background is transparent: "image" is premultiplied and "alpha" is the float32 coverage
    (the share of each pixel's samples a triangle covers); otherwise "alpha" is None.
    With ``shading="auto"`` the stats also hold "shading" (the mode per object, in scene
    order) and "shading_estimates" (see :func:`explain`)."""

def explain(
    scene: Scene,
    camera: Camera,
    *args: Any,
    tolerance: float | None = None,
    options: RenderOptions | None = None,
    **kwargs: Any,
) -> dict[str, Any]:
    """What ``shading="auto"`` chooses, without rendering: "shading" (the mode per object,
    in scene order), "shading_estimates" (per object: the ``mode``, the estimated RMSE in
    8-bit levels of ``flat``, ``gouraud`` and ``phong``, ``meets`` and the estimated
    ``pixels``) and "tolerance". The other keywords are :class:`RenderOptions`' (as for
    :func:`render`)."""

def render_batch(
    scene: Scene | Sequence[Scene],
    cameras: Camera | Sequence[Camera],
    *args: Any,
    dtype: Any = None,
    return_depth: bool = False,
    options: RenderOptions | None = None,
    callback: Callable[..., object] | None = None,
    progress: Callable[[int], object] | None = None,
    index_base: int = 0,
    **kwargs: Unpack[_RenderOptionsArgs],
) -> Any:
    """The loop of :func:`shadelab_rs.render_batch` (which adds the progress bar): one scene
    or camera is used for every view, two sequences are paired. Returns ``(N, H, W, 3)``
    (plus ``(N, H, W)`` depth with ``return_depth``), or None with ``callback``, which is
    called as ``callback(i, image[, depth])`` after each frame; ``progress(done)`` after
    each frame. ``index_base`` is added to the view indices in errors and callbacks. The
    render options are :func:`render`'s, and each view is prepared as :func:`render`
    prepares it (fitted near/far planes, the default light rig)."""

def _set_rendezvous(renders: int, timeout: float) -> None:
    """Test hook: every render waits on its workers (up to ``timeout`` seconds) until
    ``renders`` renders are in flight together; resets :func:`_max_in_flight`."""

def _max_in_flight() -> int:
    """Test hook: the most renders seen running at once since :func:`_set_rendezvous`."""

def _restore(kind: str, state: Any) -> Any:
    """Pickle's reconstructor: rebuilds the ``kind`` object from the state its
    ``__reduce__`` gave, through the validating constructors (``ValueError`` when corrupt)."""

def _panic_for_tests() -> None:
    """Test hook: panics inside Rust behind the guard every entry point uses, so the test
    suite can check that a panic arrives as ``RuntimeError``, never ``PanicException``."""
