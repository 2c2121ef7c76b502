//! The optics of one surface point: the mirror direction, Snell's law with total internal
//! reflection, Schlick's Fresnel approximation and how a material splits the light among
//! its local colour, the reflected and the transmitted colour.

use glam::Vec3;

use crate::material::Material;

/// The mirror direction of `v` (unit, pointing away from the surface) about the unit
/// normal `n`: `r = 2(n·v)n − v`.
#[inline]
pub fn reflect(n: Vec3, v: Vec3) -> Vec3 {
    2.0 * n.dot(v) * n - v
}

/// The refracted direction of light arriving against `v` (unit, pointing away from the
/// surface, on the side of the unit normal `n`: `n·v ≥ 0`) from a medium of index `n1` into
/// one of index `n2`, by Snell's law `n1 sin θ1 = n2 sin θ2`:
/// `t = −η v + (η cos θ1 − cos θ2) n` with `η = n1/n2`. `None` is total internal
/// reflection (`sin θ2 > 1`: only when `n1 > n2` and `θ1 > asin(n2/n1)`).
#[inline]
pub fn refract(n: Vec3, v: Vec3, n1: f32, n2: f32) -> Option<Vec3> {
    let eta = n1 / n2;
    let cos1 = n.dot(v).clamp(0.0, 1.0);
    let sin2_sq = eta * eta * (1.0 - cos1 * cos1);
    if sin2_sq > 1.0 {
        return None;
    }
    let cos2 = (1.0 - sin2_sq).sqrt();
    Some(-eta * v + (eta * cos1 - cos2) * n)
}

/// Schlick's approximation of the Fresnel reflectance for light crossing from index `n1`
/// into `n2` at incidence cosine `cos1` (the refracted cosine `cos2` when known):
/// `F = F0 + (1 − F0)(1 − c)^5` with `F0 = ((n1 − n2)/(n1 + n2))²` and `c = cos1` entering
/// a denser medium, `c = cos2` leaving one (so F stays symmetric in the two directions);
/// exactly 0 when `n1 = n2` (no interface) and 1 under total internal reflection
/// (`cos2 = None`).
#[inline]
pub fn schlick(cos1: f32, cos2: Option<f32>, n1: f32, n2: f32) -> f32 {
    if n1 == n2 {
        return 0.0;
    }
    let Some(cos2) = cos2 else { return 1.0 };
    let f0 = ((n1 - n2) / (n1 + n2)).powi(2);
    let c = if n1 <= n2 { cos1 } else { cos2 };
    let m = (1.0 - c.clamp(0.0, 1.0)).powi(5);
    f0 + (1.0 - f0) * m
}

/// How a surface point splits the light: `c = local·L + reflected·R + transmitted·T`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    /// Weight of the local (lit) colour, `1 − reflectivity − transparency`.
    pub local: Vec3,
    /// Weight of the colour along [`Split::reflected`].
    pub reflect: Vec3,
    /// Weight of the colour along [`Split::refracted`].
    pub transmit: f32,
    /// The mirror direction.
    pub reflected: Vec3,
    /// The refracted direction (`None` under total internal reflection or when nothing is
    /// transmitted).
    pub refracted: Option<Vec3>,
}

/// The split at a point of `m` with unit normal `n` on the side of the unit direction `v`
/// toward the viewer (`n·v ≥ 0`), the light arriving from a medium of index `n1` into one of
/// index `n2`.
///
/// With `R = reflectivity`, `T = transparency`, `L = 1 − R − T` and the Fresnel weight
/// `F = schlick(n·v, cos θ2, n1, n2)` when `m.fresnel` (else `F = 0`):
/// `reflect = R + T·F`, `transmit = T·(1 − F)`; under total internal reflection everything
/// transmitted is reflected instead (`reflect = R + T`, `transmit = 0`) with or without
/// Fresnel. `F` moves only the transmitted share: the reflectivity of an opaque mirror
/// (a metal) is its constant, colour-tinted reflectance.
#[inline]
pub fn split(m: &Material, n: Vec3, v: Vec3, n1: f32, n2: f32) -> Split {
    let r = m.reflectivity;
    let t = m.transparency;
    let local = Vec3::ONE - r - Vec3::splat(t);
    let reflected = reflect(n, v);
    if t == 0.0 {
        return Split {
            local,
            reflect: r,
            transmit: 0.0,
            reflected,
            refracted: None,
        };
    }
    let refracted = refract(n, v, n1, n2);
    let (reflect_w, transmit) = match refracted {
        None => (r + Vec3::splat(t), 0.0),
        Some(d) if m.fresnel => {
            let cos1 = n.dot(v).clamp(0.0, 1.0);
            let cos2 = (-d.dot(n)).clamp(0.0, 1.0);
            let f = schlick(cos1, Some(cos2), n1, n2);
            (r + Vec3::splat(t * f), t * (1.0 - f))
        }
        Some(_) => (r, t),
    };
    Split {
        local,
        reflect: reflect_w,
        transmit,
        reflected,
        refracted: refracted.filter(|_| transmit > 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(deg: f32) -> Vec3 {
        // Toward the viewer, θ from the normal +y, in the xy plane.
        let a = deg.to_radians();
        Vec3::new(a.sin(), a.cos(), 0.0)
    }

    #[test]
    fn refraction_obeys_snell_and_total_internal_reflection() {
        let n = Vec3::Y;
        for &(n1, n2) in &[
            (1.0, 1.33),
            (1.0, 1.5),
            (1.0, 2.4),
            (1.5, 1.0),
            (2.4, 1.0),
            (1.0, 1.0),
        ] {
            for k in 0..90 {
                let th = k as f32;
                let v = dir(th);
                let s1 = (th.to_radians()).sin();
                match refract(n, v, n1, n2) {
                    Some(t) => {
                        assert!((t.length() - 1.0).abs() < 1e-5);
                        assert!(t.y <= 0.0);
                        // sin θ2 = |t.x| (in the plane), opposite side of the normal.
                        assert!((n1 * s1 - n2 * -t.x).abs() < 2e-5, "{n1} {n2} {th}");
                    }
                    None => assert!(n1 * s1 > n2, "{n1} {n2} {th}"),
                }
            }
        }
        // The critical angles into air: water 48.75°, glass 41.81°, diamond 24.62°.
        for (ior, want) in [(1.33f32, 48.75f32), (1.5, 41.81), (2.4, 24.62)] {
            let crit = (1.0 / ior).asin().to_degrees();
            assert!((crit - want).abs() < 0.005, "{ior}: {crit}");
            assert!(refract(n, dir(crit - 0.01), ior, 1.0).is_some());
            assert!(refract(n, dir(crit + 0.01), ior, 1.0).is_none());
            // Entering the denser medium there is never total internal reflection.
            assert!(refract(n, dir(89.9), 1.0, ior).is_some());
        }
    }

    #[test]
    fn schlick_and_reflection_formulas() {
        let f0 = ((1.0f32 - 1.5) / 2.5).powi(2);
        assert_eq!(schlick(1.0, Some(1.0), 1.0, 1.5), f0);
        assert_eq!(schlick(0.3, Some(0.9), 1.0, 1.0), 0.0);
        assert_eq!(schlick(0.3, None, 1.5, 1.0), 1.0);
        assert!((schlick(0.0, Some(0.5), 1.0, 1.5) - 1.0).abs() < 1e-6);
        let n = Vec3::Y;
        let v = dir(30.0);
        let r = reflect(n, v);
        assert!((r - Vec3::new(-v.x, v.y, 0.0)).length() < 1e-6);
    }

    #[test]
    fn split_moves_only_the_transmitted_share() {
        let m = Material::default()
            .with_optics(Vec3::splat(0.2), 0.5, 1.5, true, Vec3::ZERO)
            .unwrap();
        let s = split(&m, Vec3::Y, Vec3::Y, 1.0, 1.5);
        let f = 0.04;
        assert!((s.reflect.x - (0.2 + 0.5 * f)).abs() < 1e-6);
        assert!((s.transmit - 0.5 * (1.0 - f)).abs() < 1e-6);
        assert!((s.local.x - 0.3).abs() < 1e-6);
        // Leaving the glass beyond the critical angle: all reflected.
        let s = split(&m, Vec3::Y, dir(60.0), 1.5, 1.0);
        assert_eq!((s.transmit, s.refracted), (0.0, None));
        assert!((s.reflect.x - 0.7).abs() < 1e-6);
        // Without Fresnel: the constant coefficients.
        let mut c = m;
        c.fresnel = false;
        let s = split(&c, Vec3::Y, dir(40.0), 1.0, 1.5);
        assert_eq!((s.reflect.x, s.transmit), (0.2, 0.5));
    }
}
