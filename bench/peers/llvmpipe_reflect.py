"""Mesa llvmpipe drawing the environment technique of reflection and refraction, in GLSL.

The same technique as our ``reflections="environment"`` (and ``refractions=
"environment"``): one lookup of an equirectangular environment per pixel along the mirror
direction ``reflect(-v, n)`` (and the refracted one, ``refract(-v, n, n1 / n2)``), weighted as
``optics::split`` weighs them: ``c = L·local + R·sky(r) + T·sky(t)`` with ``L = 1 - R - T``,
Schlick's Fresnel moving a share ``F`` of ``T`` to the reflection (entering a denser medium:
``F = F0 + (1 - F0)(1 - n·v)^5``). The local colour is the lighting of
:mod:`peers.llvmpipe` (Blinn-Phong per pixel, the renderer's equation); the background is the
environment along each pixel's view ray (a full-screen triangle behind everything) when
``background`` is set, else black.

The environment is a ``sampler2D`` with ``GL_LINEAR`` (no mipmaps, as ours), repeating in u
and clamped in v; ``u = 0.5 + atan(d.x, -d.z) / 2π``, ``v = acos(d.y) / π`` (row 0 the top,
as ours). Like ours (``environment_background``), the environment is drawn behind the
scene only when asked. It shares the context of a :class:`peers.llvmpipe.LlvmpipeRenderer` (llvmpipe
reads ``LP_NUM_THREADS`` once per process).
"""

from __future__ import annotations

import numpy as np

from .llvmpipe import _LIGHTING, _look_at, perspective

__all__ = ["EnvironmentScene", "Optics"]

_ENV = """
uniform sampler2D env;
vec3 sky(vec3 d) {
    d = normalize(d);
    float u = 0.5 + atan(d.x, -d.z) / 6.283185307179586;
    float v = acos(clamp(d.y, -1.0, 1.0)) / 3.141592653589793;
    return texture(env, vec2(u, v)).rgb;
}
"""

_SURFACE = dict(
    vertex_shader="""
#version 330 core
uniform mat4 mvp;
uniform mat4 model;
uniform mat3 normal_matrix;
in vec3 in_pos; in vec3 in_nrm;
out vec3 w_pos; out vec3 w_nrm;
void main() {
    vec4 p = model * vec4(in_pos, 1.0);
    gl_Position = mvp * p;
    w_pos = p.xyz;
    w_nrm = normal_matrix * in_nrm;
}
""",
    fragment_shader=_LIGHTING
    + _ENV
    + """
uniform vec3 reflectivity;
uniform float transparency;
uniform float ior;
uniform bool fresnel;
in vec3 w_pos; in vec3 w_nrm;
out vec4 frag;
void main() {
    vec3 n = normalize(w_nrm);
    vec3 v = normalize(eye - w_pos);
    if (dot(n, v) < 0.0) n = -n;  // the side toward the viewer
    vec3 c = shade(w_pos, n);
    if (reflectivity == vec3(0.0) && transparency == 0.0) { frag = vec4(c, 1.0); return; }
    vec3 local = vec3(1.0) - reflectivity - vec3(transparency);
    vec3 refl = reflectivity;
    vec3 col = local * c;
    if (transparency > 0.0) {
        vec3 t = refract(-v, n, 1.0 / ior);
        float f = 0.0;
        if (fresnel) {
            float f0 = pow((1.0 - ior) / (1.0 + ior), 2.0);
            f = f0 + (1.0 - f0) * pow(1.0 - clamp(dot(n, v), 0.0, 1.0), 5.0);
        }
        refl += vec3(transparency * f);
        col += transparency * (1.0 - f) * sky(t);
    }
    col += refl * sky(reflect(-v, n));
    frag = vec4(col, 1.0);
}
""",
)

_BACKGROUND = dict(
    vertex_shader="""
#version 330 core
in vec2 in_xy;
out vec2 ndc;
void main() { gl_Position = vec4(in_xy, 1.0, 1.0); ndc = in_xy; }
""",
    fragment_shader="""
#version 330 core
"""
    + _ENV
    + """
uniform mat4 inv_mvp;
in vec2 ndc;
out vec4 frag;
void main() {
    vec4 a = inv_mvp * vec4(ndc, -1.0, 1.0);
    vec4 b = inv_mvp * vec4(ndc, 1.0, 1.0);
    frag = vec4(sky(b.xyz / b.w - a.xyz / a.w), 1.0);
}
""",
)


class Optics:
    """A surface's optics as ours name them: reflectivity (RGB), transparency, index of
    refraction and whether Schlick's Fresnel applies."""

    def __init__(self, reflectivity=(0.0, 0.0, 0.0), transparency=0.0, ior=1.5, fresnel=True):
        self.reflectivity = tuple(float(x) for x in reflectivity)
        self.transparency = float(transparency)
        self.ior = float(ior)
        self.fresnel = bool(fresnel)


class EnvironmentScene:
    """Meshes under directional lights in an environment, on the context of a
    :class:`peers.llvmpipe.LlvmpipeRenderer`."""

    def __init__(self, gl):
        self.gl, self.ctx = gl, gl.ctx
        self.surface = self.ctx.program(**_SURFACE)
        self.background = self.ctx.program(**_BACKGROUND)
        tri = np.array([[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]], "f4")
        self._bg_vbo = self.ctx.buffer(tri.tobytes())
        self._bg = self.ctx.vertex_array(self.background, [(self._bg_vbo, "2f", "in_xy")])
        self._objects: list = []
        self._buffers: list = []
        self._fbo = None
        self.background_on = False
        """Draw the environment where no surface is (ours: ``environment_background``)."""

    def set_scene(self, objects, *, environment, lights, ambient, camera, aspect) -> None:
        """``objects``: (vertices, normals, faces, model 4x4, material, :class:`Optics`) each,
        the material with ambient/diffuse/specular/emission/shininess; ``environment`` the
        (H, W, 3) float equirectangular image (row 0 the top); ``lights`` as
        :meth:`LlvmpipeRenderer.set_scene`'s (directional only here)."""
        for b in self._buffers:
            b.release()
        self._buffers, self._objects = [], []
        img = np.ascontiguousarray(np.asarray(environment, "f4"))
        h, w, _ = img.shape
        self.env = self.ctx.texture((w, h), 3, img.tobytes(), dtype="f4")
        mgl = self.gl._mgl
        self.env.filter = (mgl.LINEAR, mgl.LINEAR)
        self.env.repeat_x, self.env.repeat_y = True, False
        flip = np.diag([1.0, -1.0, 1.0, 1.0])  # row 0 of the read-back image at the top
        view = _look_at(camera.eye, camera.target, camera.up)
        vp = flip @ perspective(camera.fov_y, aspect, camera.near, camera.far) @ view
        self.background["inv_mvp"].write(np.linalg.inv(vp).T.astype("f4").tobytes())
        self.background["env"].value = 0
        vec = np.zeros((8, 4), "f4")
        col = np.zeros((8, 3), "f4")
        for i, (kind, v, c) in enumerate(lights):
            if kind != "directional":
                raise ValueError("directional lights only")
            vec[i] = (*(-np.asarray(v, np.float64)), 0.0)
            col[i] = c
        p = self.surface
        p["mvp"].write(vp.T.astype("f4").tobytes())
        p["eye"].value = tuple(float(x) for x in camera.eye)
        p["scene_ambient"].value = tuple(ambient)
        p["n_lights"].value = len(lights)
        p["light_vec"].write(vec.tobytes())
        p["light_color"].write(col.tobytes())
        p["env"].value = 0
        for vertices, normals, faces, model, material, optics in objects:
            data = np.hstack([np.asarray(vertices, "f4"), np.asarray(normals, "f4")])
            vbo = self.ctx.buffer(np.ascontiguousarray(data).tobytes())
            ibo = self.ctx.buffer(np.ascontiguousarray(faces, dtype="u4").tobytes())
            self._buffers += [vbo, ibo]
            vao = self.ctx.vertex_array(p, [(vbo, "3f 3f", "in_pos", "in_nrm")], ibo)
            model = np.asarray(model, np.float64)
            normal_matrix = np.linalg.inv(model[:3, :3]).T
            self._objects.append((vao, model, normal_matrix, material, optics))

    def _draw(self, width: int, height: int, dtype: str):
        key = (width, height, dtype)
        if self._fbo is None or self._fbo[0] != key:
            color = self.ctx.renderbuffer((width, height), 4, dtype=dtype)
            depth = self.ctx.depth_renderbuffer((width, height))
            self._fbo = (key, self.ctx.framebuffer([color], depth))
        fbo = self._fbo[1]
        fbo.use()
        self.ctx.disable(self.gl._mgl.CULL_FACE)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.env.use(location=0)
        p = self.surface
        for vao, model, normal_matrix, m, o in self._objects:
            p["model"].write(model.T.astype("f4").tobytes())
            p["normal_matrix"].write(normal_matrix.T.astype("f4").tobytes())
            p["ka"].value = tuple(m.ambient)
            p["kd"].value = tuple(m.diffuse)
            p["ks"].value = tuple(m.specular)
            p["ke"].value = tuple(m.emission)
            p["shininess"].value = float(m.shininess)
            p["reflectivity"].value = o.reflectivity
            p["transparency"].value = o.transparency
            p["ior"].value = o.ior
            p["fresnel"].value = o.fresnel
            vao.render(self.gl._mgl.TRIANGLES)
        if self.background_on:
            # Last, at the far plane (passing "<=" only where nothing was drawn), so each
            # pixel is shaded once.
            self.ctx.depth_func = "<="
            self._bg.render(self.gl._mgl.TRIANGLES)
            self.ctx.depth_func = "<"
        return fbo

    def render(self, width: int, height: int) -> np.ndarray:
        """One frame read back into a new ``(H, W, 3)`` uint8 array."""
        buf = self._draw(width, height, "f1").read(components=3, alignment=1)
        return np.frombuffer(buf, np.uint8).reshape(height, width, 3)
