//! The interpolation error of flat and Gouraud over one triangle, from the renderer's own
//! lighting evaluated at seven points of it: where the lighting is smooth on the triangle's
//! scale this replaces [`super::bound`]'s worst-case terms (curvatures taken in magnitude,
//! lights added in magnitude, clamping ignored) by the error itself.
//!
//! The error field of a mode against the truth (`d = mode − truth`: the surface the vertex
//! normals describe, lit where each pixel's ray meets it, see [`Offset`]; against Phong at
//! the same mesh point where that is unknown) is taken as its quadratic interpolant through
//! the three vertices and the three edge midpoints, whose mean square over the triangle is
//! exact (the P2 mass matrix), plus the cubic bubble `27λ₀λ₁λ₂ρ` through the centroid's
//! residual `ρ` (its value there minus the quadratic's), added in magnitude. For lighting
//! that is quadratic over the triangle the result is exact; the caller uses it only where
//! the lobe and the diffuse term are smooth on the triangle (no terminator inside it, a
//! highlight at least two thirds as wide as the triangle's turn), and keeps the bound
//! elsewhere. The derivation is in docs/LIGHTING.md.

use glam::{DVec3, Vec3};

use super::Offset;
use crate::lighting::{Geometry, LightSet, Surface, LANES};
use crate::options::SpecularModel;
use crate::scene::Scene;

/// The P2 element's mass matrix over the triangle's area, times 180: nodes are the vertices
/// 0, 1, 2 and the midpoints of the edges 01, 12, 20 (vertex `i` is opposite midpoint
/// `3 + (i + 1) % 3`). [`rms`] evaluates its quadratic form written out.
#[cfg(test)]
const MASS: [[f64; 6]; 6] = [
    [6.0, -1.0, -1.0, 0.0, -4.0, 0.0],
    [-1.0, 6.0, -1.0, 0.0, 0.0, -4.0],
    [-1.0, -1.0, 6.0, -4.0, 0.0, 0.0],
    [0.0, 0.0, -4.0, 32.0, 16.0, 16.0],
    [-4.0, 0.0, 0.0, 16.0, 32.0, 16.0],
    [0.0, -4.0, 0.0, 16.0, 16.0, 32.0],
];

/// The rms over a triangle of the bubble `27λ₀λ₁λ₂` (1 at the centroid):
/// `√(729 · 2·2!2!2!/8!)`.
const BUBBLE_RMS: f64 = 0.537_914;

/// The lighting the renderer does for one object's front faces, as the estimate evaluates
/// it: its surface (spot cones taken as 1, as the bound takes them; shadows ignored), the
/// eye, and whether the colours are clamped to [0, 1] as the image is.
pub(super) struct Nodal {
    surface: Surface,
    eye: Vec3,
    clamps: bool,
    /// Whether Gouraud lights the vertex normals and blends their colours over the world
    /// triangle (its default method, perspective-correct): otherwise the bound is used.
    gouraud: bool,
}

impl Nodal {
    /// One object's lighting: `material` under the scene's lights and ambient, seen from
    /// `eye` (or from the direction `toward` for an infinite viewer).
    pub(super) fn new(
        scene: &Scene,
        material: &crate::material::Material,
        eye: DVec3,
        toward: Option<DVec3>,
        model: SpecularModel,
        clamps: bool,
        gouraud: bool,
    ) -> Self {
        let mut set = LightSet::new(scene.lights());
        for s in &mut set.sources {
            if let Geometry::Spot { position, .. } = s.geometry {
                s.geometry = Geometry::Point(position);
            }
        }
        let surface = Surface::folded(material, scene.ambient(), &set, model);
        let surface = match toward {
            Some(t) => surface.with_infinite_viewer(t.as_vec3()),
            None => surface,
        };
        Nodal {
            surface,
            eye: eye.as_vec3(),
            clamps,
            gouraud,
        }
    }

    /// Whether Gouraud's error can be found here (its vertex-normal method, colours blended
    /// over the world triangle); otherwise the bound stands for both modes.
    pub(super) fn covers_gouraud(&self) -> bool {
        self.gouraud
    }

    /// Per channel, the rms error over the triangle of flat and of Gouraud, in linear
    /// colour: against the true surface where `offset` says where it is (the normal at each
    /// interior node taken where the pixel's ray meets the surface, so the geometric error is
    /// in the result with its sign), otherwise against Phong at the same mesh points. `p`:
    /// world positions; `n`: unit vertex normals; `face`: the unit face normal flat lights
    /// with.
    pub(super) fn errors(
        &self,
        p: [DVec3; 3],
        n: [DVec3; 3],
        face: DVec3,
        offset: Option<&Offset>,
    ) -> Errors {
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let third = 1.0 / 3.0;
        // The interior nodes: edge midpoints and the centroid, with their barycentrics.
        let inner = [
            ((p[0] + p[1]) * 0.5, n[0] + n[1], [0.5, 0.5, 0.0]),
            ((p[1] + p[2]) * 0.5, n[1] + n[2], [0.0, 0.5, 0.5]),
            ((p[2] + p[0]) * 0.5, n[2] + n[0], [0.5, 0.0, 0.5]),
            (centroid, n[0] + n[1] + n[2], [third; 3]),
        ]
        .map(|(x, m, l)| (x, m.normalize_or_zero(), l));
        // Lanes: the vertices, the midpoints and the centroid (Phong's colour: the mesh's
        // interpolated normal), the centroid with the face normal (flat's colour).
        let points = [
            (p[0], n[0]),
            (p[1], n[1]),
            (p[2], n[2]),
            (inner[0].0, inner[0].1),
            (inner[1].0, inner[1].1),
            (inner[2].0, inner[2].1),
            (inner[3].0, inner[3].1),
            (centroid, face),
        ];
        let c = self.shade(&points);
        // The truth at the interior nodes (at the vertices the mesh is on the surface and its
        // normals are the surface's: Phong's colours there).
        let truth = offset.map(|o| {
            let t = inner.map(|(x, m, l)| (x, o.true_normal(x, l, &p, m)));
            self.shade(&[t[0], t[1], t[2], t[3], t[3], t[3], t[3], t[3]])
        });
        let clamp = |v: f64| if self.clamps { v.clamp(0.0, 1.0) } else { v };
        let mut flat = [0.0; 3];
        let mut gouraud = [0.0; 3];
        for ch in 0..3 {
            let v = c[ch].map(|x| clamp(x as f64));
            let raw = c[ch].map(|x| x as f64);
            // The reference at the six P2 nodes and the centroid.
            let r: [f64; 7] = match &truth {
                Some(t) => {
                    let t = t[ch].map(|x| clamp(x as f64));
                    [v[0], v[1], v[2], t[0], t[1], t[2], t[3]]
                }
                None => [v[0], v[1], v[2], v[3], v[4], v[5], v[6]],
            };
            // Flat: one colour against the reference at every node.
            let f = v[7];
            flat[ch] = rms(
                [f - r[0], f - r[1], f - r[2], f - r[3], f - r[4], f - r[5]],
                f - r[6],
            );
            // Gouraud: the vertex colours (unclamped, as interpolated) blended linearly.
            let g = |a: f64, b: f64| clamp(0.5 * (a + b));
            gouraud[ch] = rms(
                [
                    0.0,
                    0.0,
                    0.0,
                    g(raw[0], raw[1]) - r[3],
                    g(raw[1], raw[2]) - r[4],
                    g(raw[2], raw[0]) - r[5],
                ],
                clamp((raw[0] + raw[1] + raw[2]) / 3.0) - r[6],
            );
        }
        Errors {
            flat,
            gouraud,
            against_truth: truth.is_some(),
        }
    }

    /// The renderer's colours at eight points (position, unit normal).
    fn shade(&self, points: &[(DVec3, DVec3); LANES]) -> [[f32; LANES]; 3] {
        let mut pos = [[0.0f32; LANES]; 3];
        let mut nrm = [[0.0f32; LANES]; 3];
        for (k, (q, m)) in points.iter().enumerate() {
            for ax in 0..3 {
                pos[ax][k] = q[ax] as f32;
                nrm[ax][k] = m[ax] as f32;
            }
        }
        self.surface.shade_lanes(&nrm, &pos, self.eye)
    }
}

/// Flat's and Gouraud's rms error per channel over one triangle ([`Nodal::errors`]).
pub(super) struct Errors {
    pub flat: [f64; 3],
    pub gouraud: [f64; 3],
    /// Against the true surface (the geometric error included, with its sign); otherwise
    /// against Phong at the same mesh points.
    pub against_truth: bool,
}

/// The rms over the triangle of the field with values `d` at the six P2 nodes and `dc` at
/// the centroid: the quadratic's exact rms plus the cubic bubble's through the centroid's
/// residual.
fn rms(d: [f64; 6], dc: f64) -> f64 {
    // dᵀ·MASS·d written out (vertex i meets the midpoint opposite it with −4).
    let [v0, v1, v2, e0, e1, e2] = d;
    let ms = 6.0 * (v0 * v0 + v1 * v1 + v2 * v2)
        - 2.0 * (v0 * v1 + v1 * v2 + v2 * v0)
        - 8.0 * (v0 * e1 + v1 * e2 + v2 * e0)
        + 32.0 * (e0 * e0 + e1 * e1 + e2 * e2 + e0 * e1 + e1 * e2 + e2 * e0);
    let ms = (ms / 180.0).max(0.0);
    // The quadratic at the centroid: each vertex's basis λ(2λ − 1) is −1/9 there, each
    // midpoint's 4λλ 4/9.
    let at_centroid = (4.0 * (d[3] + d[4] + d[5]) - (d[0] + d[1] + d[2])) / 9.0;
    ms.sqrt() + BUBBLE_RMS * (dc - at_centroid).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rms of a field over the unit right triangle by a fine midpoint-rule grid.
    fn brute(f: impl Fn(f64, f64) -> f64) -> f64 {
        let n = 600;
        let (mut s, mut count) = (0.0, 0usize);
        for i in 0..n {
            for j in 0..n - i {
                for (x, y) in [
                    (
                        (i as f64 + 1.0 / 3.0) / n as f64,
                        (j as f64 + 1.0 / 3.0) / n as f64,
                    ),
                    (
                        (i as f64 + 2.0 / 3.0) / n as f64,
                        (j as f64 + 2.0 / 3.0) / n as f64,
                    ),
                ] {
                    if x + y <= 1.0 {
                        s += f(x, y).powi(2);
                        count += 1;
                    }
                }
            }
        }
        (s / count as f64).sqrt()
    }

    fn nodes(f: &impl Fn(f64, f64) -> f64) -> ([f64; 6], f64) {
        (
            [
                f(0.0, 0.0),
                f(1.0, 0.0),
                f(0.0, 1.0),
                f(0.5, 0.0),
                f(0.5, 0.5),
                f(0.0, 0.5),
            ],
            f(1.0 / 3.0, 1.0 / 3.0),
        )
    }

    #[test]
    fn the_written_out_form_is_the_mass_matrix() {
        let d = [0.3, -1.1, 0.7, 2.0, -0.4, 0.9];
        let mut want = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                want += d[i] * MASS[i][j] * d[j];
            }
        }
        // The centroid on the quadratic: no bubble term.
        let at = (4.0 * (d[3] + d[4] + d[5]) - (d[0] + d[1] + d[2])) / 9.0;
        assert!((rms(d, at) - (want / 180.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_quadratic_field_has_its_exact_rms() {
        let f = |x: f64, y: f64| 0.3 - 1.2 * x + 0.7 * y + 2.0 * x * x - 0.9 * x * y + 0.4 * y * y;
        let (d, dc) = nodes(&f);
        let got = rms(d, dc);
        let want = brute(f);
        assert!((got - want).abs() < 1e-3 * want, "{got} {want}");
    }

    #[test]
    fn a_gouraud_bubble_has_the_known_ratio() {
        // x(1 − x − y)·4: zero at the vertices, 1 at the midpoint of edge 0-1... and its
        // rms agrees with the brute-force one.
        let f = |x: f64, y: f64| 4.0 * x * (1.0 - x - y);
        let (d, dc) = nodes(&f);
        assert!((rms(d, dc) - brute(f)).abs() < 1e-3);
    }

    #[test]
    fn a_cubic_field_is_not_under_estimated() {
        let f = |x: f64, y: f64| 27.0 * x * y * (1.0 - x - y) + 0.5 * x * x * x - y * y * x;
        let (d, dc) = nodes(&f);
        assert!(
            rms(d, dc) >= brute(f) * 0.999,
            "{} {}",
            rms(d, dc),
            brute(f)
        );
    }
}
