//! How a surface answers the light: what leaves a point towards the camera for the light
//! arriving from each lamp.
//!
//! Three terms, per colour channel, in candela per square metre for lux arriving:
//! - **diffuse** (Lambert): `albedo / pi` times the light, times the cosine at the surface;
//! - **specular** (Cook-Torrance with the GGX distribution, Smith-Schlick shadowing and
//!   Schlick's Fresnel from 4 % at normal incidence, a dielectric's): the roughness map's
//!   value `r` sets the distribution's width `alpha = r^2`, so wet, smooth rock (low `r`)
//!   shows the lamp's highlight and dry rock (high `r`) barely does;
//! - **retroreflection** for tape that sends light back where it came from: a coefficient of
//!   retroreflection `R(b) = R0 / (1 + (b / b0)^2)` candela per lux per square metre at the
//!   observation angle `b` between the lamp and the camera seen from the point (sheeting of
//!   the ASTM D4956 kind: hundreds at a fraction of a degree, falling off within a few), so
//!   a band of tape shines bright when the lamp is beside the lens and stays dull to a lamp
//!   elsewhere.
//!
//! The surface's normal is its triangle's (or the mesh's interpolated vertex normal) bent by
//! the normal map, in the frame the texture coordinates give the triangle ([`tangent_frame`]).

use subtgraph_core::vec3::{V3, cross, dot, sub};

/// A surface's answer at one point: what the textures say there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Linear reflectance per channel.
    pub albedo: [f32; 3],
    /// 0 smooth to 1 rough.
    pub roughness: f32,
    /// Peak coefficient of retroreflection, candela per lux per square metre (0: none).
    pub retro: f32,
}

/// The width of a retroreflector's cone, radians (half its peak at 0.5 degrees).
const RETRO_WIDTH: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Light leaving a point towards the camera, per channel (candela per square metre), for the
/// light `lux` (illuminance on a surface facing the lamp) from the unit direction `l` towards
/// the lamp, seen along the unit direction `v` towards the camera, with shading normal `n`.
#[inline]
pub fn reflected(s: &Surface, n: V3, v: V3, l: V3, lux: f64) -> [f64; 3] {
    let nl = dot(n, l);
    if nl <= 0.0 || lux <= 0.0 {
        return [0.0; 3];
    }
    let nv = dot(n, v).max(1e-4);
    let e = lux * nl;
    // GGX.
    let h = {
        let s = [l[0] + v[0], l[1] + v[1], l[2] + v[2]];
        let len = dot(s, s).sqrt().max(1e-12);
        [s[0] / len, s[1] / len, s[2] / len]
    };
    let nh = dot(n, h).max(0.0);
    let r = f64::from(s.roughness).clamp(0.03, 1.0);
    let alpha2 = (r * r) * (r * r);
    let denom = nh * nh * (alpha2 - 1.0) + 1.0;
    let d = alpha2 / (std::f64::consts::PI * denom * denom);
    let k = 0.5 * r * r;
    let g = (nl / (nl * (1.0 - k) + k)) * (nv / (nv * (1.0 - k) + k));
    let vh = dot(v, h).max(0.0);
    let fresnel = 0.04 + 0.96 * (1.0 - vh).powi(5);
    let specular = d * g * fresnel / (4.0 * nl * nv);
    // A retroreflector's luminance is R(b) times the light on it, falling with the entrance
    // angle as the light on it does; tinted by its colour.
    let retro = if s.retro > 0.0 {
        let b = dot(l, v).clamp(-1.0, 1.0).acos() / RETRO_WIDTH;
        f64::from(s.retro) / (1.0 + b * b)
    } else {
        0.0
    };
    s.albedo
        .map(|a| e * (f64::from(a) * (1.0 / std::f64::consts::PI + retro) + specular))
}

/// Light leaving a diffuse point lit from everywhere by `lux`, per channel.
#[inline]
pub fn ambient(s: &Surface, lux: f64) -> [f64; 3] {
    s.albedo.map(|a| lux * f64::from(a) / std::f64::consts::PI)
}

/// The unit tangent and bitangent of a triangle with corners `p` and texture coordinates
/// `uv`: the directions in which `u` and `v` grow, the frame a normal map's red and green
/// are in, and the metres one unit of `u` and of `v` spans. `None` for a triangle whose
/// coordinates are degenerate.
#[inline]
pub fn tangent_frame(p: [V3; 3], uv: [[f64; 2]; 3]) -> Option<(V3, V3, f64, f64)> {
    let e1 = sub(p[1], p[0]);
    let e2 = sub(p[2], p[0]);
    let (du1, dv1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
    let (du2, dv2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
    let det = du1 * dv2 - du2 * dv1;
    if det.abs() < 1e-14 {
        return None;
    }
    let f = 1.0 / det;
    let t = [0, 1, 2].map(|k| f * (dv2 * e1[k] - dv1 * e2[k]));
    let b = [0, 1, 2].map(|k| f * (du1 * e2[k] - du2 * e1[k]));
    let (lt, lb) = (dot(t, t).sqrt(), dot(b, b).sqrt());
    if lt < 1e-12 || lb < 1e-12 {
        return None;
    }
    Some((t.map(|x| x / lt), b.map(|x| x / lb), lt, lb))
}

/// The normal `n` bent by a tangent-space normal `m` (`[x, y, z]`, z along `n`) in the frame
/// `(t, b)`, each made perpendicular to `n` first.
#[inline]
pub fn bend(n: V3, t: V3, b: V3, m: [f32; 3]) -> V3 {
    let t = orthogonal(t, n);
    // The bitangent made perpendicular to both, on the side `b` is (mirrored textures stay
    // right).
    let mut b2 = cross(n, t);
    if dot(b2, b) < 0.0 {
        b2 = b2.map(|x| -x);
    }
    let m = m.map(f64::from);
    let out = [0, 1, 2].map(|k| m[0] * t[k] + m[1] * b2[k] + m[2] * n[k]);
    let len = dot(out, out).sqrt();
    if len < 1e-9 { n } else { out.map(|x| x / len) }
}

/// `t` less its part along the unit `n`, made unit (any perpendicular if nothing is left).
fn orthogonal(t: V3, n: V3) -> V3 {
    let d = dot(t, n);
    let o = [t[0] - d * n[0], t[1] - d * n[1], t[2] - d * n[2]];
    let len = dot(o, o).sqrt();
    if len > 1e-9 {
        return o.map(|x| x / len);
    }
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let c = cross(n, a);
    let l = dot(c, c).sqrt();
    c.map(|x| x / l)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(roughness: f32, retro: f32) -> Surface {
        Surface {
            albedo: [0.5; 3],
            roughness,
            retro,
        }
    }

    #[test]
    fn a_rough_surface_is_lambertian_and_a_smooth_one_shines_at_the_mirror_angle() {
        let n = [0.0, 0.0, 1.0];
        let l = [0.0, 0.6, 0.8];
        // Straight on from above, rough: close to albedo / pi times the light on it.
        let diffuse = reflected(&grey(1.0, 0.0), n, [0.0, 0.0, 1.0], l, 100.0)[0];
        let lambert = 100.0 * 0.8 * 0.5 / std::f64::consts::PI;
        assert!((diffuse / lambert - 1.0).abs() < 0.1, "{diffuse} {lambert}");
        // Smooth: at the mirror direction far brighter than off it.
        let mirror = [0.0, -0.6, 0.8];
        let shine = reflected(&grey(0.1, 0.0), n, mirror, l, 100.0)[0];
        let off = reflected(&grey(0.1, 0.0), n, [0.6, 0.0, 0.8], l, 100.0)[0];
        assert!(shine > 10.0 * off, "{shine} {off}");
        // Nothing from behind.
        assert_eq!(
            reflected(&grey(0.5, 0.0), n, n, [0.0, 0.0, -1.0], 100.0),
            [0.0; 3]
        );
    }

    #[test]
    fn tape_shines_back_at_a_lamp_beside_the_lens() {
        let n = [1.0, 0.0, 0.0];
        let v = [1.0, 0.0, 0.0];
        let beside = [(1.0f64 - 0.05f64 * 0.05).sqrt(), 0.05, 0.0];
        let elsewhere = [0.7, 0.714, 0.0];
        let tape = grey(0.5, 300.0);
        let near = reflected(&tape, n, v, beside, 10.0)[0];
        let paint = reflected(&grey(0.5, 0.0), n, v, beside, 10.0)[0];
        assert!(near > 15.0 * paint, "{near} {paint}");
        let far = reflected(&tape, n, v, elsewhere, 10.0)[0];
        assert!(far < 2.0 * reflected(&grey(0.5, 0.0), n, v, elsewhere, 10.0)[0]);
    }

    #[test]
    fn a_flat_normal_map_keeps_the_normal_and_a_tilted_one_tilts_it_along_u() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let (t, b, lt, lb) = tangent_frame(p, uv).unwrap();
        assert_eq!((t, b), ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
        assert_eq!((lt, lb), (1.0, 1.0));
        let n = [0.0, 0.0, 1.0];
        assert_eq!(bend(n, t, b, [0.0, 0.0, 1.0]), n);
        let tilted = bend(n, t, b, [0.6, 0.0, 0.8]);
        assert!((tilted[0] - 0.6).abs() < 1e-6 && (tilted[2] - 0.8).abs() < 1e-6);
    }
}
