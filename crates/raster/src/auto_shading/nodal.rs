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

    /// Lights the points in an AVX2 + FMA copy of the lighting's lane loops when `wide` and
    /// the CPU has both (as the pipeline's `Isa::detect` decides; not called here, which
    /// would make `auto_shading` and `pipeline` import each other): eight lanes at a time
    /// where the baseline's SSE2 takes four, with the same bits
    /// ([`Surface::with_wide_lanes`]). Only the f32 lanes: the
    /// estimate's f64 work inlined into one AVX2 copy saved about a tenth more, but LLVM
    /// then emits a `vmovq` register form that valgrind 3.19 cannot decode (an illegal
    /// instruction under callgrind, our instruction counter, and under memcheck).
    pub(super) fn with_wide_lanes(mut self, wide: bool) -> Self {
        self.surface = self.surface.with_wide_lanes(wide);
        self
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
            let t = inner.map(|(x, m, l)| (x, o.true_normal(l, m)));
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

    /// Per channel, the rms error over the triangle of flat and of Gouraud where the
    /// lighting has a kink inside it (a terminator: `max(n·l, 0)`, and the clamp to 1) that
    /// the seven-point interpolant of [`Nodal::errors`] cannot follow: the error field at the
    /// [`FINE`]-grid's points against Phong's colour there, its rms that of its
    /// piecewise-linear interpolant over the grid's `FINE²` sub-triangles. A kink is then
    /// confined to the sub-triangles it crosses; the caller adds what the grid cannot
    /// resolve ([`FINE_UNRESOLVED`] times the bound's interpolation error) and the geometric
    /// error in magnitude. Not against the fitted surface with signs, as [`Nodal::errors`]
    /// is: on a mesh whose vertices are off the surface (a subdivision level against its
    /// limit) that went below the measured error.
    pub(super) fn errors_fine(&self, p: [DVec3; 3], n: [DVec3; 3], face: DVec3) -> Errors {
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        // Phong's colour at the grid's points off the vertices: the mesh point with the
        // interpolated normal.
        let inner = GRID_INNER.map(|k| {
            let l = GRID_LAMBDA[k];
            let x = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
            let m = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]).normalize_or_zero();
            (x, m)
        });
        let a = self.shade(&[
            (p[0], n[0]),
            (p[1], n[1]),
            (p[2], n[2]),
            (centroid, face),
            inner[0],
            inner[1],
            inner[2],
            inner[3],
        ]);
        let b = self.shade(&[
            inner[4], inner[5], inner[6], inner[7], inner[8], inner[9], inner[10], inner[11],
        ]);
        let clamp = |v: f64| if self.clamps { v.clamp(0.0, 1.0) } else { v };
        let mut flat = [0.0; 3];
        let mut gouraud = [0.0; 3];
        for ch in 0..3 {
            // The sixteen lanes in one row: the lane of each grid point's reference is
            // GRID_LANE's (at a vertex, the mesh is on the surface with its normal).
            let mut lanes = [0.0; 2 * LANES];
            for k in 0..LANES {
                lanes[k] = a[ch][k] as f64;
                lanes[LANES + k] = b[ch][k] as f64;
            }
            let raw = [lanes[0], lanes[1], lanes[2]];
            let f = clamp(lanes[3]);
            let mut df = [0.0; GRID_POINTS];
            let mut dg = [0.0; GRID_POINTS];
            for k in 0..GRID_POINTS {
                let l = GRID_LAMBDA[k];
                let r = clamp(lanes[GRID_LANE[k]]);
                df[k] = f - r;
                dg[k] = clamp(raw[0] * l[0] + raw[1] * l[1] + raw[2] * l[2]) - r;
            }
            flat[ch] = grid_rms(&df);
            gouraud[ch] = grid_rms(&dg);
        }
        Errors {
            flat,
            gouraud,
            against_truth: false,
        }
    }

    /// The renderer's colours at eight points (position, unit normal).
    fn shade(&self, points: &[(DVec3, DVec3); LANES]) -> [[f32; LANES]; 3] {
        #[cfg(target_arch = "x86_64")]
        if self.surface.wide() {
            // SAFETY: `wide()` only where the CPU reported AVX2 and FMA.
            return unsafe { self.shade_avx2(points) };
        }
        self.shade_body(points)
    }

    /// [`Nodal::shade_body`] compiled for AVX2 + FMA.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn shade_avx2(&self, points: &[(DVec3, DVec3); LANES]) -> [[f32; LANES]; 3] {
        self.shade_body(points)
    }

    #[inline(always)]
    fn shade_body(&self, points: &[(DVec3, DVec3); LANES]) -> [[f32; LANES]; 3] {
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

/// The fine grid's subdivisions per edge: its points are the barycentrics `(i, j, FINE −
/// i − j)/FINE`, `(FINE + 1)(FINE + 2)/2` of them.
pub(super) const FINE: usize = 4;
const GRID_POINTS: usize = (FINE + 1) * (FINE + 2) / 2;

/// What the fine grid leaves unresolved, as a share of the bound's interpolation error over
/// the whole triangle: a smooth field's interpolation error falls with the square of the
/// sub-triangles' size (`1/FINE²`); a kink's tent (height ∝ size) lies only in the
/// sub-triangles a line crosses, at most `2·FINE − 1` of the `FINE²`, so its rms falls as
/// `√2/FINE^1.5`, the larger of the two.
pub(super) const FINE_UNRESOLVED: f64 = std::f64::consts::SQRT_2 / 8.0;
const _: () = assert!(FINE == 4, "FINE_UNRESOLVED is √2/FINE^1.5 for FINE = 4");

/// The grid point `k` (row `i` = `λ₁·FINE`, then `j` = `λ₂·FINE` within it): its
/// barycentrics.
const fn grid_ij(k: usize) -> (usize, usize) {
    let mut i = 0;
    let mut start = 0;
    while start + (FINE + 1 - i) <= k {
        start += FINE + 1 - i;
        i += 1;
    }
    (i, k - start)
}

/// Each grid point's barycentrics.
const GRID_LAMBDA: [[f64; 3]; GRID_POINTS] = {
    let mut out = [[0.0; 3]; GRID_POINTS];
    let mut k = 0;
    while k < GRID_POINTS {
        let (i, j) = grid_ij(k);
        let (l1, l2) = (i as f64 / FINE as f64, j as f64 / FINE as f64);
        out[k] = [1.0 - l1 - l2, l1, l2];
        k += 1;
    }
    out
};

const fn grid_index(i: usize, j: usize) -> usize {
    // Rows 0..i hold FINE + 1, FINE, ... points.
    let mut k = 0;
    let mut r = 0;
    while r < i {
        k += FINE + 1 - r;
        r += 1;
    }
    k + j
}

/// The grid points at the triangle's vertices 0, 1, 2.
const GRID_VERTICES: [usize; 3] = [grid_index(0, 0), grid_index(FINE, 0), grid_index(0, FINE)];

/// The other grid points, in order.
const GRID_INNER: [usize; GRID_POINTS - 3] = {
    let mut out = [0; GRID_POINTS - 3];
    let (mut k, mut o) = (0, 0);
    while k < GRID_POINTS {
        if k != GRID_VERTICES[0] && k != GRID_VERTICES[1] && k != GRID_VERTICES[2] {
            out[o] = k;
            o += 1;
        }
        k += 1;
    }
    out
};

/// Where [`Nodal::errors_fine`] finds each grid point's reference among its sixteen lanes:
/// the vertices in lanes 0–2 (lane 3 is flat's colour), the other points from lane 4 on.
const GRID_LANE: [usize; GRID_POINTS] = {
    let mut out = [0; GRID_POINTS];
    let mut v = 0;
    while v < 3 {
        out[GRID_VERTICES[v]] = v;
        v += 1;
    }
    let mut i = 0;
    while i < GRID_POINTS - 3 {
        out[GRID_INNER[i]] = 4 + i;
        i += 1;
    }
    out
};

/// The grid's `FINE²` sub-triangles (equal areas) as point indices: the `FINE(FINE + 1)/2`
/// upright ones and the `FINE(FINE − 1)/2` upside-down ones between them.
const SUB_TRIANGLES: [[usize; 3]; FINE * FINE] = {
    let mut out = [[0; 3]; FINE * FINE];
    let mut o = 0;
    let mut i = 0;
    while i < FINE {
        let mut j = 0;
        while i + j < FINE {
            out[o] = [grid_index(i, j), grid_index(i + 1, j), grid_index(i, j + 1)];
            o += 1;
            if i + j + 1 < FINE {
                out[o] = [
                    grid_index(i + 1, j),
                    grid_index(i + 1, j + 1),
                    grid_index(i, j + 1),
                ];
                o += 1;
            }
            j += 1;
        }
        i += 1;
    }
    out
};

/// The rms over the triangle of the piecewise-linear interpolant of the grid values `d`:
/// over each sub-triangle with corner values `a, b, c` the mean square of the linear field
/// is `(a² + b² + c² + ab + bc + ca)/6`.
fn grid_rms(d: &[f64; GRID_POINTS]) -> f64 {
    let sum: f64 = SUB_TRIANGLES
        .iter()
        .map(|&[i, j, k]| {
            let (a, b, c) = (d[i], d[j], d[k]);
            a * a + b * b + c * c + a * b + b * c + c * a
        })
        .sum();
    (sum / (6.0 * (FINE * FINE) as f64)).max(0.0).sqrt()
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

    /// The fine grid's field at its points for `f(λ₁, λ₂)`.
    fn grid_values(f: impl Fn(f64, f64) -> f64) -> [f64; GRID_POINTS] {
        std::array::from_fn(|k| {
            let l = GRID_LAMBDA[k];
            f(l[1], l[2])
        })
    }

    #[test]
    fn the_fine_grid_tiles_the_triangle() {
        assert_eq!(GRID_POINTS, 15);
        for (v, k) in GRID_VERTICES.iter().enumerate() {
            let l = GRID_LAMBDA[*k];
            assert!((0..3).all(|i| l[i] == (i == v) as u8 as f64), "{v} {l:?}");
        }
        let mut seen = [0usize; GRID_POINTS];
        for k in GRID_INNER.iter().chain(GRID_VERTICES.iter()) {
            seen[*k] += 1;
        }
        assert!(seen.iter().all(|&c| c == 1));
        let mut lanes = GRID_LANE;
        lanes.sort_unstable();
        let want: Vec<usize> = (0..3).chain(4..2 * LANES).collect();
        assert_eq!(lanes.to_vec(), want);
        // Every sub-triangle has the area 1/FINE² of the unit right triangle's (1/2), and
        // the same orientation.
        for t in SUB_TRIANGLES {
            let [a, b, c] = t.map(|k| GRID_LAMBDA[k]);
            let area = 0.5 * ((b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2]));
            assert!(
                (area - 0.5 / (FINE * FINE) as f64).abs() < 1e-12,
                "{t:?} {area}"
            );
        }
    }

    #[test]
    fn the_fine_grid_rms_is_exact_for_a_linear_field() {
        let f = |x: f64, y: f64| 0.4 - 1.3 * x + 0.8 * y;
        assert!((grid_rms(&grid_values(f)) - brute(f)).abs() < 1e-3 * brute(f));
    }

    #[test]
    fn the_fine_grid_follows_a_kink() {
        // A Gouraud-like error across a terminator: the linear interpolant of max(g, 0)
        // against max(g, 0) itself, g linear with its zero line through the triangle. The
        // seven points miss it; the grid comes within what FINE_UNRESOLVED adds of the
        // bound's tent (span/7 for a unit slope, span = the range of g here, 1).
        let g = |x: f64, y: f64| 0.45 - x * 0.6 - y * 0.4;
        let (g0, g1, g2) = (
            g(0.0, 0.0).max(0.0),
            g(1.0, 0.0).max(0.0),
            g(0.0, 1.0).max(0.0),
        );
        let err = |x: f64, y: f64| g0 * (1.0 - x - y) + g1 * x + g2 * y - g(x, y).max(0.0);
        let exact = brute(err);
        let fine = grid_rms(&grid_values(err));
        let unresolved = FINE_UNRESOLVED * 1.0 / 7.0;
        assert!(fine + unresolved >= exact, "{fine} {exact}");
        assert!(
            fine + unresolved <= 0.5 * (1.0 / 7.0),
            "no tighter than the bound"
        );
        assert!((fine - exact).abs() < 0.25 * exact, "{fine} {exact}");
    }

    #[test]
    fn the_fine_grid_finds_a_terminator_on_a_sphere() {
        // A triangle of a 12-ring sphere that a directional light's terminator crosses;
        // Gouraud against Phong at the same mesh points (no offset), brute force over a
        // fine grid of the renderer's own colours.
        use crate::lights::DirectionalLight;
        use crate::material::Material;
        let mut scene = Scene::new(Vec3::splat(0.1)).unwrap();
        scene.add_light(DirectionalLight::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::ONE, 1.0).unwrap());
        let m = Material::default();
        let eye = DVec3::new(0.0, 0.0, 5.0);
        let nodal = Nodal::new(&scene, &m, eye, None, SpecularModel::BlinnPhong, true, true);
        let on = |lon: f64, lat: f64| {
            let (lon, lat) = (lon.to_radians(), lat.to_radians());
            DVec3::new(lon.sin() * lat.cos(), lat.sin(), lon.cos() * lat.cos())
        };
        // Longitude 90° is the terminator (n·l = sin lon · cos lat).
        let p = [on(80.0, 0.0), on(105.0, 0.0), on(90.0, 15.0)];
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let got = nodal.errors_fine(p, p, face);
        assert!(!got.against_truth);
        let shade1 = |x: DVec3, n: DVec3| nodal.shade(&[(x, n); LANES]).map(|c| c[0] as f64);
        let c = p.map(|v| shade1(v, v));
        let (mut s, mut count) = (0.0, 0usize);
        let steps = 120;
        for i in 0..=steps {
            for j in 0..=steps - i {
                let l = [
                    1.0 - (i + j) as f64 / steps as f64,
                    i as f64 / steps as f64,
                    j as f64 / steps as f64,
                ];
                let x = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
                let n = (p[0] * l[0] + p[1] * l[1] + p[2] * l[2]).normalize();
                let phong = shade1(x, n);
                for ch in 0..3 {
                    let g = (c[0][ch] * l[0] + c[1][ch] * l[1] + c[2][ch] * l[2]).clamp(0.0, 1.0);
                    s += (g - phong[ch].clamp(0.0, 1.0)).powi(2) / 3.0;
                }
                count += 1;
            }
        }
        let brute_rms = (s / count as f64).sqrt();
        let fine = (got.gouraud.iter().map(|g| g * g).sum::<f64>() / 3.0).sqrt();
        assert!(brute_rms > 1e-3, "the terminator is inside: {brute_rms}");
        assert!(
            (fine - brute_rms).abs() < 0.2 * brute_rms,
            "{fine} {brute_rms}"
        );
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
