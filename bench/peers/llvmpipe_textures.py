"""Mesa llvmpipe drawing an unlit textured mesh with OpenGL's texture filters, in GLSL.

The fragment colour is ``texture(tex, uv).rgb`` (a ``sampler2D``, perspective-correct UVs),
with the filters our ``Texture`` options name: ``nearest`` (GL_NEAREST), ``bilinear``
(GL_LINEAR, level 0 only), ``trilinear`` (GL_LINEAR_MIPMAP_LINEAR over ``glGenerateMipmap``'s
levels, GL_LINEAR when magnified) and anisotropic filtering
(``GL_TEXTURE_MAX_ANISOTROPY``); ``GL_REPEAT`` wrapping. It shares the context of a
:class:`peers.llvmpipe.LlvmpipeRenderer` (llvmpipe reads ``LP_NUM_THREADS`` once per
process).
"""

from __future__ import annotations

import numpy as np

from .llvmpipe import _look_at, perspective

__all__ = ["Textured"]

_PROGRAM = dict(
    vertex_shader="""
#version 330 core
uniform mat4 mvp;
in vec3 in_pos; in vec2 in_uv;
out vec2 uv;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); uv = in_uv; }
""",
    fragment_shader="""
#version 330 core
uniform sampler2D tex;
in vec2 uv;
out vec4 frag;
void main() { frag = vec4(texture(tex, uv).rgb, 1.0); }
""",
)


class Textured:
    """One textured mesh on the context of a :class:`peers.llvmpipe.LlvmpipeRenderer`."""

    def __init__(self, gl):
        self.gl, self.ctx = gl, gl.ctx
        self.prog = self.ctx.program(**_PROGRAM)
        self._fbo = None

    def set_scene(self, vertices, uvs, faces, image: np.ndarray, camera, aspect: float) -> None:
        """Uploads the mesh and the (H, W, 3) float image (row 0 the top, as ours)."""
        data = np.hstack([np.asarray(vertices, "f4"), np.asarray(uvs, "f4")])
        vbo = self.ctx.buffer(np.ascontiguousarray(data).tobytes())
        ibo = self.ctx.buffer(np.ascontiguousarray(faces, dtype="u4").tobytes())
        self.vao = self.ctx.vertex_array(self.prog, [(vbo, "3f 2f", "in_pos", "in_uv")], ibo)
        # GL's row 0 is the bottom (v = 0): flip the image's rows.
        img = np.ascontiguousarray(np.asarray(image, "f4")[::-1])
        h, w, _ = img.shape
        self.tex = self.ctx.texture((w, h), 3, img.tobytes(), dtype="f4")
        self.tex.build_mipmaps()
        self.tex.repeat_x = self.tex.repeat_y = True
        flip = np.diag([1.0, -1.0, 1.0, 1.0])  # row 0 of the read-back image at the top
        view = _look_at(camera.eye, camera.target, camera.up)
        mvp = flip @ perspective(camera.fov_y, aspect, camera.near, camera.far) @ view
        self.prog["mvp"].write(mvp.T.astype("f4").tobytes())
        self.prog["tex"].value = 0

    def set_filter(self, name: str, anisotropy: int = 1) -> None:
        mgl = self.gl._mgl
        self.tex.filter = {
            "nearest": (mgl.NEAREST, mgl.NEAREST),
            "bilinear": (mgl.LINEAR, mgl.LINEAR),
            "trilinear": (mgl.LINEAR_MIPMAP_LINEAR, mgl.LINEAR),
        }[name]
        self.tex.anisotropy = float(anisotropy)

    def _draw(self, width: int, height: int, dtype: str):
        key = (width, height, dtype)
        if self._fbo is None or self._fbo[0] != key:
            color = self.ctx.renderbuffer((width, height), 4, dtype=dtype)
            depth = self.ctx.depth_renderbuffer((width, height))
            self._fbo = (key, self.ctx.framebuffer([color], depth))
        fbo = self._fbo[1]
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.tex.use(location=0)
        self.vao.render(self.gl._mgl.TRIANGLES)
        return fbo

    def render(self, width: int, height: int) -> np.ndarray:
        """One frame read back into a new ``(H, W, 3)`` uint8 array."""
        buf = self._draw(width, height, "f1").read(components=3, alignment=1)
        return np.frombuffer(buf, np.uint8).reshape(height, width, 3)

    def render_linear(self, width: int, height: int) -> np.ndarray:
        """The float32 colour ``(H, W, 3)`` of a frame (for the error figures, not timed)."""
        fbo = self._draw(width, height, "f4")
        rgba = np.frombuffer(fbo.read(components=4, dtype="f4"), "f4")
        return rgba.reshape(height, width, 4)[..., :3].copy()
