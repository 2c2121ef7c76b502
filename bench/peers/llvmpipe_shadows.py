"""Mesa llvmpipe drawing a directional light's shadow map, the classic GPU way, in GLSL.

Each frame is two passes, as an OpenGL application draws a shadow-mapped scene:

1. the depth pass from the light: an orthographic camera fitted to the scene's bounding box
   seen along the light, into a ``resolution``² depth texture (24-bit), with slope-scaled
   polygon offset as the bias (``glPolygonOffset(2, 4)``, the usual starting values);
2. the Phong pass from the camera: world position and normal interpolated and the normal
   renormalised per pixel, the light's diffuse and specular terms scaled by its visibility
   from a ``sampler2DShadow`` (hardware depth comparison with bilinear filtering of the
   results) over a 3 x 3 texel kernel (percentage-closer filtering), then ``glReadPixels``.

The lighting equation is the one of :mod:`peers.llvmpipe` (one directional light, Blinn-Phong,
local viewer). It shares that module's context (llvmpipe reads ``LP_NUM_THREADS`` once per
process).
"""

from __future__ import annotations

import itertools

import numpy as np

from .llvmpipe import _look_at, perspective

__all__ = ["ShadowMapped"]

_DEPTH = dict(
    vertex_shader="""
#version 330 core
uniform mat4 light_mvp;
in vec3 in_pos;
void main() { gl_Position = light_mvp * vec4(in_pos, 1.0); }
""",
    fragment_shader="""
#version 330 core
void main() {}
""",
)

_PHONG = dict(
    vertex_shader="""
#version 330 core
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_nrm;
out vec3 w_pos; out vec3 w_nrm;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); w_pos = in_pos; w_nrm = in_nrm; }
""",
    fragment_shader="""
#version 330 core
uniform vec3 eye;
uniform vec3 scene_ambient;
uniform vec3 ka; uniform vec3 kd; uniform vec3 ks;
uniform float shininess;
uniform vec3 to_light;  // unit direction toward the light
uniform vec3 light_color;
uniform mat4 light_tex;  // world -> shadow texture coordinates and depth in [0, 1]
uniform sampler2DShadow shadow_map;
uniform float texel;  // 1 / resolution
in vec3 w_pos; in vec3 w_nrm;
out vec4 frag;
void main() {
    vec3 n = normalize(w_nrm);
    vec3 c = ka * scene_ambient;
    float ndl = dot(n, to_light);
    if (ndl > 0.0) {
        vec4 s = light_tex * vec4(w_pos, 1.0);
        float vis = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                vis += texture(shadow_map, vec3(s.xy + vec2(dx, dy) * texel, s.z));
        vis /= 9.0;
        vec3 v = normalize(eye - w_pos);
        vec3 h = normalize(to_light + v);
        c += vis * light_color * (kd * ndl + ks * pow(max(dot(n, h), 0.0), shininess));
    }
    frag = vec4(c, 1.0);
}
""",
)


def _ortho(left, right, bottom, top, near, far) -> np.ndarray:
    return np.array(
        [
            [2 / (right - left), 0, 0, -(right + left) / (right - left)],
            [0, 2 / (top - bottom), 0, -(top + bottom) / (top - bottom)],
            [0, 0, -2 / (far - near), -(far + near) / (far - near)],
            [0, 0, 0, 1],
        ]
    )


class ShadowMapped:
    """One shadow-mapped scene on the context of a :class:`peers.llvmpipe.LlvmpipeRenderer`."""

    def __init__(self, gl, resolution: int = 2048):
        self.gl, self.ctx, self.res = gl, gl.ctx, resolution
        self.depth_prog = self.ctx.program(**_DEPTH)
        self.phong = self.ctx.program(**_PHONG)
        mgl = gl._mgl
        self.tex = self.ctx.depth_texture((resolution, resolution))
        self.tex.compare_func = "<="
        self.tex.filter = (mgl.LINEAR, mgl.LINEAR)  # bilinear PCF of the comparisons
        self.tex.repeat_x = self.tex.repeat_y = False
        self.shadow_fbo = self.ctx.framebuffer(depth_attachment=self.tex)
        self._buffers: list = []
        self._fbo = None

    def set_scene(
        self, vertices, normals, faces, *, material, direction, color, ambient, camera, aspect
    ) -> None:
        """Uploads the mesh; ``direction`` is the light's travel direction."""
        for b in self._buffers:
            b.release()
        v = np.asarray(vertices, np.float64)
        data = np.hstack([v.astype("f4"), np.asarray(normals, "f4")])
        vbo = self.ctx.buffer(np.ascontiguousarray(data).tobytes())
        ibo = self.ctx.buffer(np.ascontiguousarray(faces, dtype="u4").tobytes())
        self._buffers = [vbo, ibo]
        # The light's orthographic camera over the scene's bounding box.
        d = -np.asarray(direction, np.float64)
        d /= np.linalg.norm(d)
        lo, hi = v.min(axis=0), v.max(axis=0)
        centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
        up = (0.0, 1.0, 0.0) if abs(d[1]) < 0.9 else (1.0, 0.0, 0.0)
        view = _look_at(centre + d * 2 * radius, centre, up)
        corners = np.array([[*c, 1.0] for c in itertools.product(*zip(lo, hi))])
        q = (view @ corners.T).T
        pad = 1e-3 * radius
        proj = _ortho(
            q[:, 0].min() - pad,
            q[:, 0].max() + pad,
            q[:, 1].min() - pad,
            q[:, 1].max() + pad,
            -q[:, 2].max() - pad,
            -q[:, 2].min() + pad,
        )
        light_mvp = proj @ view
        bias = np.array([[0.5, 0, 0, 0.5], [0, 0.5, 0, 0.5], [0, 0, 0.5, 0.5], [0, 0, 0, 1]])
        flip = np.diag([1.0, -1.0, 1.0, 1.0])  # row 0 of the read-back image at the top
        cam_view = _look_at(camera.eye, camera.target, camera.up)
        mvp = flip @ perspective(camera.fov_y, aspect, camera.near, camera.far) @ cam_view
        self.depth_prog["light_mvp"].write(light_mvp.T.astype("f4").tobytes())
        p = self.phong
        p["mvp"].write(mvp.T.astype("f4").tobytes())
        p["light_tex"].write((bias @ light_mvp).T.astype("f4").tobytes())
        p["eye"].value = tuple(camera.eye)
        p["scene_ambient"].value = tuple(ambient)
        p["ka"].value = tuple(material.ambient)
        p["kd"].value = tuple(material.diffuse)
        p["ks"].value = tuple(material.specular)
        p["shininess"].value = float(material.shininess)
        p["to_light"].value = tuple(d)
        p["light_color"].value = tuple(color)
        p["shadow_map"].value = 0
        p["texel"].value = 1.0 / self.res
        self.depth_vao = self.ctx.vertex_array(self.depth_prog, [(vbo, "3f 12x", "in_pos")], ibo)
        self.vao = self.ctx.vertex_array(self.phong, [(vbo, "3f 3f", "in_pos", "in_nrm")], ibo)

    def _framebuffer(self, width: int, height: int, dtype: str):
        key = (width, height, dtype)
        if self._fbo is None or self._fbo[0] != key:
            color = self.ctx.renderbuffer((width, height), 4, dtype=dtype)
            depth = self.ctx.depth_renderbuffer((width, height))
            self._fbo = (key, self.ctx.framebuffer([color], depth))
        return self._fbo[1]

    def _draw(self, width: int, height: int, dtype: str, shadows: bool = True):
        mgl = self.gl._mgl
        self.shadow_fbo.use()
        self.shadow_fbo.clear(depth=1.0)
        if shadows:  # else an empty map: the light reaches every point (for the figures)
            # The slope-scaled bias of the depth pass (moderngl enables
            # GL_POLYGON_OFFSET_FILL for a non-zero offset).
            self.ctx.polygon_offset = (2.0, 4.0)
            self.depth_vao.render(mgl.TRIANGLES)
            self.ctx.polygon_offset = (0.0, 0.0)
        fbo = self._framebuffer(width, height, dtype)
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.tex.use(location=0)
        self.vao.render(mgl.TRIANGLES)
        return fbo

    def render(self, width: int, height: int) -> np.ndarray:
        """One frame (both passes) read back into a new ``(H, W, 3)`` uint8 array."""
        buf = self._draw(width, height, "f1").read(components=3, alignment=1)
        return np.frombuffer(buf, np.uint8).reshape(height, width, 3)

    def render_linear(self, width: int, height: int, shadows: bool = True) -> np.ndarray:
        """The float32 colour ``(H, W, 3)`` of a frame (for the error figures, not timed);
        ``shadows=False`` draws nothing into the map, so every point is lit."""
        fbo = self._draw(width, height, "f4", shadows)
        rgba = np.frombuffer(fbo.read(components=4, dtype="f4"), "f4")
        return rgba.reshape(height, width, 4)[..., :3].copy()
