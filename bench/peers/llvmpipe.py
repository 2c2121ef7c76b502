"""Mesa llvmpipe through moderngl, headless: our flat, Gouraud and Phong in GLSL.

A standalone EGL context on Mesa's surfaceless platform (no display, no GPU); the GLSL
programs implement the renderer's lighting equation term for term for the scenes the
benchmark uses (directional and point lights without attenuation or per-light ambient,
Blinn-Phong, local viewer), with the same camera matrices, so the two images agree up to
rounding:

* flat: a geometry shader lights each triangle once with its world face normal
  ``normalize((p1 - p0) x (p2 - p0))`` at its world centroid;
* Gouraud: the vertex shader lights each vertex with its renormalised normal and the
  colour is interpolated (perspective-correct, GL's default);
* Phong: world position and normal are interpolated and the normal renormalised per pixel.

The projection's y axis is flipped so that ``glReadPixels`` returns row 0 at the top, as our
images are: no copy is needed to match the layout. Install with ``make bench-peers``.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np

__all__ = ["LlvmpipeRenderer", "perspective"]

_LIGHTING = """
#version 330 core
uniform vec3 eye;
uniform vec3 scene_ambient;
uniform vec3 ka; uniform vec3 kd; uniform vec3 ks; uniform vec3 ke;
uniform float shininess;
uniform int n_lights;
uniform vec4 light_vec[8];  // w = 0: direction toward the light; w = 1: position
uniform vec3 light_color[8];

vec3 shade(vec3 p, vec3 n) {
    vec3 c = ke + ka * scene_ambient;
    vec3 v = normalize(eye - p);
    for (int i = 0; i < n_lights; ++i) {
        vec3 l = normalize(light_vec[i].w == 0.0 ? light_vec[i].xyz : light_vec[i].xyz - p);
        float ndl = dot(n, l);
        c += kd * light_color[i] * max(ndl, 0.0);
        if (ndl > 0.0) {
            vec3 h = normalize(l + v);
            c += ks * light_color[i] * pow(max(dot(n, h), 0.0), shininess);
        }
    }
    return c;
}
"""

_PROGRAMS = {
    "phong": dict(
        vertex_shader="""
#version 330 core
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_nrm;
out vec3 w_pos; out vec3 w_nrm;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); w_pos = in_pos; w_nrm = in_nrm; }
""",
        fragment_shader=_LIGHTING
        + """
in vec3 w_pos; in vec3 w_nrm;
out vec4 frag;
void main() { frag = vec4(shade(w_pos, normalize(w_nrm)), 1.0); }
""",
    ),
    "gouraud": dict(
        vertex_shader=_LIGHTING
        + """
uniform mat4 mvp;
in vec3 in_pos; in vec3 in_nrm;
out vec3 v_col;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); v_col = shade(in_pos, normalize(in_nrm)); }
""",
        fragment_shader="""
#version 330 core
in vec3 v_col;
out vec4 frag;
void main() { frag = vec4(v_col, 1.0); }
""",
    ),
    "flat": dict(
        vertex_shader="""
#version 330 core
uniform mat4 mvp;
in vec3 in_pos;
out vec3 w_pos;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); w_pos = in_pos; }
""",
        geometry_shader=_LIGHTING
        + """
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 w_pos[];
flat out vec3 f_col;
void main() {
    vec3 n = normalize(cross(w_pos[1] - w_pos[0], w_pos[2] - w_pos[0]));
    vec3 col = shade((w_pos[0] + w_pos[1] + w_pos[2]) / 3.0, n);
    for (int i = 0; i < 3; ++i) { gl_Position = gl_in[i].gl_Position; f_col = col; EmitVertex(); }
    EndPrimitive();
}
""",
        fragment_shader="""
#version 330 core
flat in vec3 f_col;
out vec4 frag;
void main() { frag = vec4(f_col, 1.0); }
""",
    ),
}


def perspective(fov_y: float, aspect: float, near: float, far: float) -> np.ndarray:
    """OpenGL's ``gluPerspective`` matrix (float64, column-vector convention)."""
    g = 1.0 / math.tan(math.radians(fov_y) / 2.0)
    return np.array(
        [
            [g / aspect, 0.0, 0.0, 0.0],
            [0.0, g, 0.0, 0.0],
            [0.0, 0.0, (far + near) / (near - far), 2.0 * far * near / (near - far)],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )


def _look_at(eye, target, up) -> np.ndarray:
    eye, target, up = (np.asarray(x, np.float64) for x in (eye, target, up))
    f = (target - eye) / np.linalg.norm(target - eye)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -(m[:3, :3] @ eye)
    return m


class LlvmpipeRenderer:
    """One headless llvmpipe context rendering one mesh in the three modes.

    ``threads`` becomes ``LP_NUM_THREADS``, which llvmpipe reads when the context is
    created, so it must be the first context of the process. ``setup_seconds`` holds the
    first-use costs measured here: context creation and shader compilation (llvmpipe
    compiles the actual code lazily at the first draw, which the first frame then pays).
    """

    def __init__(self, threads: int):
        os.environ["LP_NUM_THREADS"] = str(threads)
        os.environ.setdefault("EGL_PLATFORM", "surfaceless")
        os.environ.setdefault("GALLIUM_DRIVER", "llvmpipe")
        import moderngl  # imported here: an optional dependency (make bench-peers)

        self._mgl = moderngl
        t0 = time.perf_counter()
        self.ctx = moderngl.create_context(standalone=True, backend="egl")
        t1 = time.perf_counter()
        self.programs = {k: self.ctx.program(**src) for k, src in _PROGRAMS.items()}
        t2 = time.perf_counter()
        self.setup_seconds = {"context": t1 - t0, "compile": t2 - t1}
        renderer = self.ctx.info["GL_RENDERER"]
        if "llvmpipe" not in renderer:
            raise RuntimeError(f"expected Mesa llvmpipe, the GL context is {renderer!r}")
        self.info = {
            "renderer": renderer,
            "version": self.ctx.info["GL_VERSION"],
            "moderngl": moderngl.__version__,
        }
        self.ctx.enable(moderngl.DEPTH_TEST)
        # The y flip of `set_scene` (row 0 at the top) turns counter-clockwise faces
        # clockwise in GL's window space, so the front is clockwise there.
        self.ctx.front_face = "cw"
        self.cull_back = False
        """Draw with ``GL_CULL_FACE`` (back faces culled): what a GL program does for a closed
        mesh, the same work our ``cull_hidden`` skips."""
        self._fbos: dict[tuple[int, int, str, int], tuple] = {}
        self._vaos: dict[str, object] = {}
        self._buffers: list = []

    def _fbo(self, width: int, height: int, dtype: str, samples: int = 1):
        """The framebuffer to draw into and the one to read from (the same one without
        multisampling; with ``samples`` > 1 a multisampled one and its single-sample
        resolve target, filled by ``glBlitFramebuffer``)."""
        key = (width, height, dtype, samples)
        if key not in self._fbos:
            if any(k[:2] != (width, height) for k in self._fbos):  # one image size at a time
                for pair in self._fbos.values():
                    for fbo in set(pair):
                        fbo.release()
                self._fbos = {}

            def make(n: int):
                color = self.ctx.renderbuffer((width, height), 4, samples=n, dtype=dtype)
                depth = self.ctx.depth_renderbuffer((width, height), samples=n)
                return self.ctx.framebuffer([color], depth)

            draw = make(samples if samples > 1 else 0)
            self._fbos[key] = (draw, make(0) if samples > 1 else draw)
        return self._fbos[key]

    def set_scene(
        self,
        vertices,
        normals,
        faces,
        *,
        material,
        lights,
        ambient,
        camera,
        aspect,
        projection_view=None,
    ):
        """Uploads a mesh and sets the uniforms of every program.

        ``material`` has ambient/diffuse/specular/emission/shininess; ``lights`` is a list of
        ``("directional", travel_direction, color)`` or ``("point", position, color)``;
        ``camera`` has eye/target/up/fov_y/near/far. ``projection_view`` (4x4, optional)
        replaces the perspective camera's projection x view (e.g. an orthographic one).
        """
        for b in self._buffers:
            b.release()
        data = np.hstack([np.asarray(vertices, "f4"), np.asarray(normals, "f4")])
        vbo = self.ctx.buffer(np.ascontiguousarray(data).tobytes())
        ibo = self.ctx.buffer(np.ascontiguousarray(faces, dtype="u4").tobytes())
        self._buffers = [vbo, ibo]
        flip = np.diag([1.0, -1.0, 1.0, 1.0])  # row 0 of the read-back image at the top
        view = _look_at(camera.eye, camera.target, camera.up)
        if projection_view is None:
            projection_view = perspective(camera.fov_y, aspect, camera.near, camera.far) @ view
        mvp = flip @ np.asarray(projection_view, np.float64)
        vec = np.zeros((8, 4), "f4")
        col = np.zeros((8, 3), "f4")
        for i, (kind, v, c) in enumerate(lights):
            vec[i] = (*(-np.asarray(v, np.float64)), 0.0) if kind == "directional" else (*v, 1.0)
            col[i] = c
        self._vaos = {}
        for mode, prog in self.programs.items():
            prog["mvp"].write(mvp.T.astype("f4").tobytes())  # GLSL matrices are column-major
            prog["eye"].value = tuple(camera.eye)
            prog["scene_ambient"].value = tuple(ambient)
            prog["ka"].value = tuple(material.ambient)
            prog["kd"].value = tuple(material.diffuse)
            prog["ks"].value = tuple(material.specular)
            prog["ke"].value = tuple(material.emission)
            prog["shininess"].value = float(material.shininess)
            prog["n_lights"].value = len(lights)
            prog["light_vec"].write(vec.tobytes())
            prog["light_color"].write(col.tobytes())
            layout = ("3f 3f", "in_pos", "in_nrm") if mode != "flat" else ("3f 12x", "in_pos")
            self._vaos[mode] = self.ctx.vertex_array(prog, [(vbo, *layout)], ibo)

    def _draw(self, mode: str, width: int, height: int, dtype: str, samples: int):
        draw, read = self._fbo(width, height, dtype, samples)
        draw.use()
        if self.cull_back:
            self.ctx.enable(self._mgl.CULL_FACE)
        else:
            self.ctx.disable(self._mgl.CULL_FACE)
        draw.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self._vaos[mode].render(self._mgl.TRIANGLES)
        if read is not draw:
            self.ctx.copy_framebuffer(read, draw)  # the MSAA resolve (glBlitFramebuffer)
        return read

    def render(self, mode: str, width: int, height: int, samples: int = 1) -> np.ndarray:
        """One frame: clear, draw (with ``samples`` > 1: multisampled, then resolved), read
        back into a new ``(H, W, 3)`` uint8 array."""
        buf = self._draw(mode, width, height, "f1", samples).read(components=3, alignment=1)
        return np.frombuffer(buf, np.uint8).reshape(height, width, 3)

    def render_linear(
        self, mode: str, width: int, height: int, samples: int = 1
    ) -> tuple[np.ndarray, np.ndarray]:
        """The unclamped float32 colour ``(H, W, 3)`` and coverage ``(H, W)`` of a frame,
        from a float colour buffer (for the error figures, not timed); with ``samples`` > 1
        the resolved (averaged) colour, and coverage where any sample was drawn."""
        fbo = self._draw(mode, width, height, "f4", samples)
        rgba = np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32)
        rgba = rgba.reshape(height, width, 4)
        return rgba[..., :3].copy(), rgba[..., 3] > 0
