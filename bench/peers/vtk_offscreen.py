"""VTK off-screen on the CPU: a vtkEGLRenderWindow on Mesa's llvmpipe (surfaceless EGL).

VTK draws with its own shaders, not ours: its lights, its ambient term and its
"Gouraud" (in VTK's OpenGL2 back end, per-fragment lighting like Phong) follow VTK's model,
not exactly the renderer's equation. The scene is set up to match ours as closely as VTK
allows (same camera, same light directions, positions and colours, material colours with
the scene ambient folded into the ambient colour), so its images are close to ours but not
equal to rounding; the report shows by how much.
"""

from __future__ import annotations

import os
import time

import numpy as np

__all__ = ["VtkRenderer"]


class VtkRenderer:
    """One off-screen VTK render window; ``threads`` becomes ``LP_NUM_THREADS``."""

    def __init__(self, threads: int):
        os.environ["LP_NUM_THREADS"] = str(threads)
        os.environ.setdefault("EGL_PLATFORM", "surfaceless")
        os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = "vtkEGLRenderWindow"
        import vtk  # an optional dependency (make bench-peers)
        from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy

        self._vtk = vtk
        self._np2vtk, self._ids, self._vtk2np = numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
        t0 = time.perf_counter()
        self.window = vtk.vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetMultiSamples(0)  # no anti-aliasing: one sample per pixel centre, as ours
        self.renderer = vtk.vtkRenderer()
        self.window.AddRenderer(self.renderer)
        self.window.Render()
        self.setup_seconds = time.perf_counter() - t0
        caps = self.window.ReportCapabilities()
        gl = next((ln for ln in caps.splitlines() if "OpenGL renderer" in ln), "")
        if "llvmpipe" not in gl:
            raise RuntimeError(f"expected VTK on Mesa llvmpipe, got {gl!r}")
        self.info = {"vtk": vtk.vtkVersion.GetVTKVersion(), "window": type(self.window).__name__}
        self._pixels = vtk.vtkUnsignedCharArray()
        self.actor = None

    def set_scene(self, vertices, normals, faces, *, material, lights, ambient, camera, size):
        """Same arguments as :meth:`LlvmpipeRenderer.set_scene`, plus ``size=(w, h)``."""
        vtk = self._vtk
        w, h = size
        self.window.SetSize(w, h)
        pts = vtk.vtkPoints()
        pts.SetData(self._np2vtk(np.ascontiguousarray(vertices, np.float32), deep=True))
        f = np.asarray(faces, np.int64)
        cells = vtk.vtkCellArray()
        offsets = np.arange(0, 3 * len(f) + 1, 3, dtype=np.int64)
        cells.SetData(self._ids(offsets, deep=True), self._ids(f.ravel(), deep=True))
        poly = vtk.vtkPolyData()
        poly.SetPoints(pts)
        poly.SetPolys(cells)
        poly.GetPointData().SetNormals(
            self._np2vtk(np.ascontiguousarray(normals, np.float32), deep=True)
        )
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(poly)
        if self.actor is not None:
            self.renderer.RemoveActor(self.actor)
        self.actor = vtk.vtkActor()
        self.actor.SetMapper(mapper)
        prop = self.actor.GetProperty()
        prop.SetAmbientColor(*(np.asarray(material.ambient) * np.asarray(ambient)))
        prop.SetDiffuseColor(*material.diffuse)
        prop.SetSpecularColor(*material.specular)
        prop.SetAmbient(1.0)
        prop.SetDiffuse(1.0)
        prop.SetSpecular(1.0)
        prop.SetSpecularPower(float(material.shininess))
        self.renderer.AddActor(self.actor)
        self.renderer.RemoveAllLights()
        self.renderer.SetBackground(0.0, 0.0, 0.0)
        for kind, v, color in lights:
            light = vtk.vtkLight()
            light.SetLightTypeToSceneLight()
            light.SetColor(*color)
            if kind == "directional":  # VTK: light travels from its position to its focal point
                light.SetPositional(False)
                light.SetPosition(*(-np.asarray(v, np.float64)))
                light.SetFocalPoint(0.0, 0.0, 0.0)
            else:
                light.SetPositional(True)
                light.SetConeAngle(180.0)
                light.SetPosition(*v)
            self.renderer.AddLight(light)
        cam = self.renderer.GetActiveCamera()
        cam.SetPosition(*camera.eye)
        cam.SetFocalPoint(*camera.target)
        cam.SetViewUp(*camera.up)
        cam.SetViewAngle(camera.fov_y)
        cam.SetClippingRange(camera.near, camera.far)
        self._size = (w, h)

    def render(self, mode: str) -> np.ndarray:
        """One frame: render, read back (RGBA: VTK's RGB read-back is not wrapped for
        arrays) into a new ``(H, W, 3)`` uint8 array, row 0 on top."""
        prop = self.actor.GetProperty()
        {"flat": prop.SetInterpolationToFlat, "gouraud": prop.SetInterpolationToGouraud,
         "phong": prop.SetInterpolationToPhong}[mode]()  # fmt: skip
        self.window.Render()
        w, h = self._size
        self.window.GetRGBACharPixelData(0, 0, w - 1, h - 1, 0, self._pixels)
        return np.ascontiguousarray(self._vtk2np(self._pixels).reshape(h, w, 4)[::-1, :, :3])
