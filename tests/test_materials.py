"""Materials: the classic presets (exact values, name spellings), constructor and getters."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shadelab_rs as sl

# The nine presets of the spec: ambient RGB, diffuse RGB, specular RGB, shininess.
PRESETS = {
    "black plastic": ((0, 0, 0), (0.01, 0.01, 0.01), (0.5, 0.5, 0.5), 32),
    "brass": (
        (0.329412, 0.223529, 0.027451),
        (0.780392, 0.568627, 0.113725),
        (0.992157, 0.941176, 0.807843),
        27.8974,
    ),
    "bronze": (
        (0.2125, 0.1275, 0.054),
        (0.714, 0.4284, 0.18144),
        (0.393548, 0.271906, 0.166721),
        25.6,
    ),
    "chrome": ((0.25, 0.25, 0.25), (0.4, 0.4, 0.4), (0.774597, 0.774597, 0.774597), 76.8),
    "copper": (
        (0.19125, 0.0735, 0.0225),
        (0.7038, 0.27048, 0.0828),
        (0.256777, 0.137622, 0.086014),
        12.8,
    ),
    "gold": (
        (0.24725, 0.1995, 0.0745),
        (0.75164, 0.60648, 0.22648),
        (0.628281, 0.555802, 0.366065),
        51.2,
    ),
    "pewter": (
        (0.10588, 0.058824, 0.113725),
        (0.427451, 0.470588, 0.541176),
        (0.3333, 0.3333, 0.521569),
        9.84615,
    ),
    "silver": (
        (0.19225, 0.19225, 0.19225),
        (0.50754, 0.50754, 0.50754),
        (0.508273, 0.508273, 0.508273),
        51.2,
    ),
    "polished silver": (
        (0.23125, 0.23125, 0.23125),
        (0.2775, 0.2775, 0.2775),
        (0.773911, 0.773911, 0.773911),
        89.6,
    ),
}

# The rest of the classic table, as published (Kilgard's teapots.c via devernay.free.fr, and
# McReynolds & Blythe 1998 for the polished metals): shininess as a fraction of 128.
CLASSIC_FRACTIONS = {
    "emerald": (
        (0.0215, 0.1745, 0.0215),
        (0.07568, 0.61424, 0.07568),
        (0.633, 0.727811, 0.633),
        0.6,
    ),
    "jade": ((0.135, 0.2225, 0.1575), (0.54, 0.89, 0.63), (0.316228,) * 3, 0.1),
    "obsidian": (
        (0.05375, 0.05, 0.06625),
        (0.18275, 0.17, 0.22525),
        (0.332741, 0.328634, 0.346435),
        0.3,
    ),
    "pearl": ((0.25, 0.20725, 0.20725), (1, 0.829, 0.829), (0.296648,) * 3, 0.088),
    "ruby": (
        (0.1745, 0.01175, 0.01175),
        (0.61424, 0.04136, 0.04136),
        (0.727811, 0.626959, 0.626959),
        0.6,
    ),
    "turquoise": (
        (0.1, 0.18725, 0.1745),
        (0.396, 0.74151, 0.69102),
        (0.297254, 0.30829, 0.306678),
        0.1,
    ),
    "polished bronze": (
        (0.25, 0.148, 0.06475),
        (0.4, 0.2368, 0.1036),
        (0.774597, 0.458561, 0.200621),
        0.6,
    ),
    "polished copper": (
        (0.2295, 0.08825, 0.0275),
        (0.5508, 0.2118, 0.066),
        (0.580594, 0.223257, 0.0695701),
        0.4,
    ),
    "polished gold": (
        (0.24725, 0.2245, 0.0645),
        (0.34615, 0.3143, 0.0903),
        (0.797357, 0.723991, 0.208006),
        0.65,
    ),
    "cyan plastic": ((0, 0.1, 0.06), (0, 0.50980392, 0.50980392), (0.50196078,) * 3, 0.25),
    "green plastic": ((0, 0, 0), (0.1, 0.35, 0.1), (0.45, 0.55, 0.45), 0.25),
    "red plastic": ((0, 0, 0), (0.5, 0, 0), (0.7, 0.6, 0.6), 0.25),
    "white plastic": ((0, 0, 0), (0.55, 0.55, 0.55), (0.7, 0.7, 0.7), 0.25),
    "yellow plastic": ((0, 0, 0), (0.5, 0.5, 0), (0.6, 0.6, 0.5), 0.25),
    "black rubber": ((0.02, 0.02, 0.02), (0.01, 0.01, 0.01), (0.4, 0.4, 0.4), 0.078125),
    "cyan rubber": ((0, 0.05, 0.05), (0.4, 0.5, 0.5), (0.04, 0.7, 0.7), 0.078125),
    "green rubber": ((0, 0.05, 0), (0.4, 0.5, 0.4), (0.04, 0.7, 0.04), 0.078125),
    "red rubber": ((0.05, 0, 0), (0.5, 0.4, 0.4), (0.7, 0.04, 0.04), 0.078125),
    "white rubber": ((0.05, 0.05, 0.05), (0.5, 0.5, 0.5), (0.7, 0.7, 0.7), 0.078125),
    "yellow rubber": ((0.05, 0.05, 0), (0.5, 0.5, 0.4), (0.7, 0.7, 0.04), 0.078125),
}
ALL_PRESETS = {
    **PRESETS,
    **{k: (a, d, s, f * 128) for k, (a, d, s, f) in CLASSIC_FRACTIONS.items()},
}

# --------------------------------------------------------------------------------------------
# Materials
# --------------------------------------------------------------------------------------------


def test_preset_names():
    names = sl.Material.preset_names()
    assert isinstance(names, list)
    assert names == list(ALL_PRESETS)  # the seed nine first, then the rest of the table


@pytest.mark.parametrize("name", list(ALL_PRESETS))
def test_preset_exact_values(name):
    ambient, diffuse, specular, shininess = ALL_PRESETS[name]
    m = sl.Material.preset(name)
    assert m.ambient == tuple(np.float32(ambient).tolist())
    assert m.diffuse == tuple(np.float32(diffuse).tolist())
    assert m.specular == tuple(np.float32(specular).tolist())
    assert m.shininess == float(np.float32(shininess))
    assert m == sl.Material(ambient, diffuse, specular, shininess)


@pytest.mark.parametrize(
    ("spelling", "name"),
    [
        ("Polished_Silver", "polished silver"),
        ("POLISHED SILVER", "polished silver"),
        ("polished_silver", "polished silver"),
        ("Black_Plastic", "black plastic"),
        ("GOLD", "gold"),
        ("Chrome", "chrome"),
    ],
)
def test_preset_name_variants(spelling, name):
    assert sl.Material.preset(spelling) == sl.Material.preset(name)


def test_material_constructor_and_getters():
    m = sl.Material(
        ambient=(0.1, 0.2, 0.3), diffuse=(0.4, 0.5, 0.6), specular=(0.7, 0.8, 0.9), shininess=12.5
    )
    assert m.ambient == pytest.approx((0.1, 0.2, 0.3), rel=1e-7)
    assert m.diffuse == pytest.approx((0.4, 0.5, 0.6), rel=1e-7)
    assert m.specular == pytest.approx((0.7, 0.8, 0.9), rel=1e-7)
    assert m.shininess == 12.5
    assert m == sl.Material((0.1, 0.2, 0.3), (0.4, 0.5, 0.6), (0.7, 0.8, 0.9), 12.5)
    assert m != sl.Material((0.1, 0.2, 0.3), (0.4, 0.5, 0.6), (0.7, 0.8, 0.9), 12.0)
    assert m == sl.Material(np.array([0.1, 0.2, 0.3]), [0.4, 0.5, 0.6], (0.7, 0.8, 0.9), 12.5)
    assert "shininess=12.5" in repr(m)


def test_material_defaults_are_valid():
    m = sl.Material()
    for v in (*m.ambient, *m.diffuse, *m.specular, m.shininess):
        assert math.isfinite(v) and v >= 0
