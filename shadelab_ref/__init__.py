"""Independent float64 ground truth for shadelab_rs, shared by tests/ and bench/.

* :mod:`shadelab_ref.reference`: a float64 reference rasterizer (NumPy only) of the same
  conventions and lighting equation;
* :mod:`shadelab_ref.truth`: analytic images (ray-cast spheres and planes) through the same
  lighting;
* :mod:`shadelab_ref.errors`: the one definition of an image's error figures;
* :mod:`shadelab_ref.to_sl`: the reference's scene descriptions as shadelab_rs objects.

Not part of the wheel: the repository root is on the import path for pytest
(``pythonpath`` in pyproject.toml) and for the benchmarks (``PYTHONPATH`` in the Makefile).
"""
