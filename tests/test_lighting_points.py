"""The full lighting equation at points, on random parameters (hypothesis), against the
float64 reference (shadelab_ref.reference).

An orthographic camera looks straight down -z at the quad z = 0 spanning [-1, 1]^2 with one
constant normal, so Phong-shaded pixel (i, j) of the 8 x 8 image is the equation evaluated at
the known world point ((i + 1/2) / 4 - 1, 1 - (j + 1/2) / 4, 0) with that normal: every term
and light kind is compared value by value in float32 output.
"""

from __future__ import annotations

import math

import numpy as np
import shadelab_rs as sl
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from shadelab_ref import reference as ref
from shadelab_ref.to_sl import sl_light

SIZE = 8
EYE = (0.0, 0.0, 5.0)

unit = st.floats(0.0, 1.0)
rgb = st.tuples(unit, unit, unit)
coord = st.floats(-3.0, 3.0)
position = st.tuples(coord, coord, st.floats(0.05, 3.0))  # lights in front of the quad
direction = st.tuples(coord, coord, coord).filter(lambda d: math.hypot(*d) > 0.1)
intensity = st.floats(0.0, 4.0)
attenuation = st.one_of(
    st.just((1.0, 0.0, 0.0)),
    st.tuples(st.floats(0.1, 2.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
)


@st.composite
def lights(draw):
    kind = draw(st.sampled_from(["directional", "point", "spot", "area"]))
    common = dict(
        color=draw(rgb),
        intensity=draw(intensity),
        ambient=draw(rgb),
        diffuse=draw(st.one_of(st.none(), rgb)),
        specular=draw(st.one_of(st.none(), rgb)),
    )
    if kind == "directional":
        return ref.DirectionalLight(draw(direction), **common)
    common["attenuation"] = draw(attenuation)
    if kind == "point":
        return ref.PointLight(draw(position), **common)
    if kind == "spot":
        cutoff = draw(st.one_of(st.floats(5.0, 90.0), st.just(180.0)))
        inner = draw(st.one_of(st.none(), st.floats(0.0, 0.95)))
        return ref.SpotLight(
            draw(position),
            draw(direction),
            cutoff=cutoff,
            exponent=draw(st.floats(0.0, 64.0)),
            inner=None if inner is None or cutoff > 90 else inner * cutoff,
            **common,
        )
    u = draw(direction)
    v = draw(direction)
    assume(np.linalg.norm(np.cross(u, v)) > 0.05 * np.linalg.norm(u) * np.linalg.norm(v))
    return ref.AreaLight(
        draw(position),
        u,
        v,
        shape=draw(st.sampled_from(["rectangle", "disk"])),
        samples=draw(st.integers(1, 4)),
        one_sided=draw(st.booleans()),
        **common,
    )


def near_a_cone_edge(lights, p):
    """Whether some hard spot edge passes within 1e-4 (in cos) of a sample point: there the
    float32 and float64 sides of the step may differ, which is rounding, not a defect."""
    for light in ref.expand_area_lights(lights):
        if isinstance(light, ref.SpotLight) and light.cutoff != 180:
            d = np.asarray(light.direction) / np.linalg.norm(light.direction)
            lv = np.asarray(light.position) - p
            lv /= np.linalg.norm(lv, axis=1, keepdims=True)
            if np.any(np.abs(-(lv @ d) - math.cos(math.radians(light.cutoff))) < 1e-4):
                return True
    return False


def near_the_terminator(lights, p, n):
    """Whether some light grazes the surface (|n·l| < 1e-6) at a sample point: there the
    specular gate n·l > 0 may differ between float32 and float64, which is rounding, not a
    defect (e.g. n·l = 4e-171 in float64 is 0 in float32)."""
    for light in ref.expand_area_lights(lights):
        if isinstance(light, ref.DirectionalLight):
            lv = -np.asarray(light.direction, dtype=np.float64)[None, :]
        else:
            lv = np.asarray(light.position) - p
        lv = lv / np.linalg.norm(lv, axis=1, keepdims=True)
        if np.any(np.abs(lv @ n) < 1e-6):
            return True
    return False


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(
    ka=rgb,
    kd=rgb,
    ks=rgb,
    ke=rgb,
    shininess=st.one_of(st.floats(0.0, 128.0, width=32), st.sampled_from([0.0, 1.0, 1e3, 1e4])),
    ambient=rgb,
    lights=st.lists(lights(), min_size=1, max_size=3),
    normal=st.tuples(st.floats(-0.7, 0.7), st.floats(-0.7, 0.7)),
    specular=st.sampled_from(["blinn", "phong", "blinn-normalized"]),
    local_viewer=st.booleans(),
    fog=st.one_of(
        st.none(),
        st.builds(ref.Fog, mode=st.just("linear"), start=st.floats(0, 4), end=st.floats(5, 8)),
        st.builds(ref.Fog, mode=st.sampled_from(["exp", "exp2"]), density=st.floats(0, 0.5)),
    ),
)
def test_equation_at_points_matches_reference(
    ka, kd, ks, ke, shininess, ambient, lights, normal, specular, local_viewer, fog
):
    n = np.array([normal[0], normal[1], 1.0])
    n /= np.linalg.norm(n)
    c = (np.arange(SIZE) + 0.5) / SIZE * 2 - 1
    p = np.stack(np.meshgrid(c, -c), axis=-1).reshape(-1, 2)
    p = np.column_stack([p, np.zeros(len(p))])
    assume(not near_a_cone_edge(lights, p))
    assume(not near_the_terminator(lights, p, n))

    verts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
    mesh = sl.Mesh(verts, [[0, 1, 2], [0, 2, 3]], normals=np.tile(n, (4, 1)))
    if fog is not None:
        fog_sl = sl.Fog(fog.mode, fog.start, fog.end, fog.density, color=fog.color)
    scene = sl.Scene(ambient=ambient, fog=fog_sl if fog else None, local_viewer=local_viewer)
    scene.add(mesh, material=sl.Material(ka, kd, ks, shininess, emission=ke))
    for light in lights:
        scene.add_light(sl_light(light))
    camera = sl.Camera.orthographic(EYE, (0, 0, 0), height=2.0, near=1.0, far=10.0)
    got = sl.render(scene, camera, width=SIZE, height=SIZE, specular=specular, dtype="float32")
    got = got.reshape(-1, 3).astype(np.float64)

    # The material holds shininess as float32 (1e-292 is 0 there, and 0**0 = 1).
    material = ref.Material(ka, kd, ks, float(np.float32(shininess)), ke)
    # The infinite viewer's constant direction is toward the eye: +z here.
    want = ref.lighting(
        p,
        n,
        EYE,
        material,
        lights,
        ambient=ambient,
        specular=specular,
        view_dir=None if local_viewer else (0.0, 0.0, 1.0),
    )
    if fog is not None:
        d = np.linalg.norm(p - np.asarray(EYE), axis=1)
        f = fog.factor(d)[:, None]
        want = f * want + (1 - f) * np.asarray(fog.color)
    # x^f near x = 1 multiplies the float32 rounding of x (a few ulp, 6e-8 each) by f: with
    # f = 1e4 a 4-ulp dot product is 2.4e-3 relative (Hypothesis found 1.3e-3 in a Phong
    # lobe), so the tolerance grows with the exponent beyond the 3e-4 of real materials.
    tol = 3e-4 + 4 * 6e-8 * float(shininess)
    np.testing.assert_allclose(got, want, rtol=tol, atol=tol)
