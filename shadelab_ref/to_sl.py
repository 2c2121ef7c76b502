"""Translation of the float64 reference's scene descriptions (shadelab_ref.reference) into
shadelab_rs objects, shared by the tests that compare the two."""

from __future__ import annotations

import dataclasses

import shadelab_rs as sl

from . import reference as ref

_CLASSES = {
    ref.DirectionalLight: sl.DirectionalLight,
    ref.PointLight: sl.PointLight,
    ref.SpotLight: sl.SpotLight,
    ref.AreaLight: sl.AreaLight,
}


def sl_light(light, **extra):
    """The shadelab_rs light with every parameter of the reference ``light``: the two
    sides' dataclass fields and keyword arguments have the same names. ``extra``: keyword
    arguments the reference does not hold (``shadows=``)."""
    kwargs = {f.name: getattr(light, f.name) for f in dataclasses.fields(light)}
    return _CLASSES[type(light)](**kwargs, **extra)
