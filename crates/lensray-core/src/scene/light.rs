//! Punctual lights (point, spot, directional) as `KHR_lights_punctual` defines them, and the
//! uniform environment's cosine-weighted direction. The shaders mirror this file function by
//! function (shaders/include/lights.glsl): the CPU reference and every GPU path shade with the
//! same arithmetic.
//!
//! Radiometry: a point or spot light's `intensity` is radiant intensity per RGB channel (W/sr,
//! glTF's candela taken as is), a directional light's is the irradiance it gives a surface facing
//! it (W/m^2, glTF's lux taken as is). A Lambertian surface of colour Kd reflects
//! Kd / pi * E * cos(theta) of irradiance E arriving at angle theta.

use glam::{Vec2, Vec3};

use crate::camera::thin_lens::concentric_sample_disk;

/// What kind of light, with the spot's cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light in every direction from `position`.
    Point,
    /// A point light limited to a cone around `direction`: full intensity within the inner
    /// angle, none beyond the outer one; cosines of both half-angles.
    Spot { cos_inner: f32, cos_outer: f32 },
    /// Parallel light travelling along `direction` from infinitely far (the sun).
    Directional,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// World position (point and spot).
    pub position: Vec3,
    /// Unit direction the light travels (spot and directional).
    pub direction: Vec3,
    /// W/sr per channel (point, spot) or W/m^2 (directional).
    pub intensity: Vec3,
    /// Distance beyond which a point or spot light gives nothing, with the smooth window glTF
    /// recommends; 0: unlimited (inverse-square falloff only).
    pub range: f32,
}

/// The light a point receives from one [`Light`], before the cosine and the shadow ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Unit direction towards the light.
    pub direction: Vec3,
    /// Distance to the light; infinite for a directional light.
    pub distance: f32,
    /// Irradiance on a surface facing the light, W/m^2 per channel.
    pub irradiance: Vec3,
}

impl Light {
    pub const fn point(position: Vec3, intensity: Vec3) -> Self {
        Self {
            kind: LightKind::Point,
            position,
            direction: Vec3::NEG_Z,
            intensity,
            range: 0.0,
        }
    }

    /// The light arriving at `origin` (a shadow ray's origin), or `None` where the light gives
    /// nothing there (outside a spot's cone or a light's range, or at its position).
    pub fn incident(&self, origin: Vec3) -> Option<Incident> {
        if self.kind == LightKind::Directional {
            return Some(Incident {
                direction: -self.direction,
                distance: f32::INFINITY,
                irradiance: self.intensity,
            });
        }
        let to_light = self.position - origin;
        let distance = to_light.length();
        if distance <= 0.0 {
            return None;
        }
        let direction = to_light / distance;
        let mut scale = 1.0 / (distance * distance);
        if self.range > 0.0 {
            // KHR_lights_punctual's recommended window: clamp(1 - (d / range)^4, 0, 1)^2.
            let r = distance / self.range;
            let window = (1.0 - r * r * r * r).clamp(0.0, 1.0);
            scale *= window * window;
        }
        if let LightKind::Spot {
            cos_inner,
            cos_outer,
        } = self.kind
        {
            // KHR_lights_punctual's recommended falloff: a squared linear ramp in the cosine.
            let cos_angle = -direction.dot(self.direction);
            let t = ((cos_angle - cos_outer) / (cos_inner - cos_outer).max(1e-3)).clamp(0.0, 1.0);
            scale *= t * t;
        }
        if scale <= 0.0 {
            return None;
        }
        Some(Incident {
            direction,
            distance,
            irradiance: self.intensity * scale,
        })
    }

    /// Whether every number is finite, directions are unit and cones are ordered.
    pub fn check(&self) -> Result<(), String> {
        let finite = |v: Vec3| v.is_finite();
        if !finite(self.position) || !finite(self.direction) || !self.range.is_finite() {
            return Err("a light's position, direction and range must be finite".into());
        }
        if !finite(self.intensity) || self.intensity.min_element() < 0.0 {
            return Err(format!(
                "a light's intensity must be finite and not negative, got {}",
                self.intensity
            ));
        }
        if self.kind != LightKind::Point && (self.direction.length() - 1.0).abs() > 1e-3 {
            return Err(format!(
                "a light's direction must be a unit vector, got {}",
                self.direction
            ));
        }
        if let LightKind::Spot {
            cos_inner,
            cos_outer,
        } = self.kind
        {
            if !(cos_outer <= cos_inner && (-1.0..=1.0).contains(&cos_outer)) {
                return Err(
                    "a spot light's inner cone must lie within its outer cone, both 0 to 90 degrees"
                        .into(),
                );
            }
        }
        Ok(())
    }
}

/// Two unit vectors that make a right-handed orthonormal frame with unit `n` (Duff et al. 2017,
/// "Building an orthonormal basis, revisited"; pbrt-v4's CoordinateSystem).
pub fn orthonormal_frame(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// A direction about unit `n` with density cos(theta) / pi (Malley's method: the disk lifted to
/// the hemisphere), from `u` in [0, 1)^2. The environment's estimator: with this density the
/// Lambertian term Kd / pi * L * cos / pdf is Kd * L when the direction is unblocked.
pub fn cosine_direction(n: Vec3, u: Vec2) -> Vec3 {
    let d = concentric_sample_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    let (t, b) = orthonormal_frame(n);
    t * d.x + b * d.y + n * z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_light_falls_off_with_the_square_of_distance() {
        let light = Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::splat(8.0));
        let i = light.incident(Vec3::ZERO).unwrap();
        assert_eq!(i.direction, Vec3::Y);
        assert_eq!(i.distance, 2.0);
        assert_eq!(i.irradiance, Vec3::splat(2.0));
    }

    #[test]
    fn a_spot_is_full_inside_its_inner_cone_and_dark_outside_its_outer_one() {
        let spot = Light {
            kind: LightKind::Spot {
                cos_inner: 20f32.to_radians().cos(),
                cos_outer: 30f32.to_radians().cos(),
            },
            position: Vec3::new(0.0, 1.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::ONE,
            range: 0.0,
        };
        let at = |degrees: f32| {
            let x = degrees.to_radians().tan();
            spot.incident(Vec3::new(x, 0.0, 0.0))
                .map_or(0.0, |i| i.irradiance.x * i.distance * i.distance)
        };
        assert!((at(10.0) - 1.0).abs() < 1e-6);
        assert_eq!(at(31.0), 0.0);
        // Half-way in cosine: (1/2)^2.
        let mid = (0.5 * (20f32.to_radians().cos() + 30f32.to_radians().cos())).acos();
        assert!(
            (at(mid.to_degrees()) - 0.25).abs() < 1e-3,
            "{}",
            at(mid.to_degrees())
        );
    }

    #[test]
    fn range_windows_the_falloff_to_zero() {
        let light = Light {
            range: 4.0,
            ..Light::point(Vec3::ZERO, Vec3::ONE)
        };
        let e = |d: f32| {
            light
                .incident(Vec3::new(d, 0.0, 0.0))
                .map(|i| i.irradiance.x)
        };
        assert_eq!(e(4.5), None);
        // d = 2: (1 - 1/16)^2 / 4.
        assert!((e(2.0).unwrap() - (15.0f32 / 16.0).powi(2) / 4.0).abs() < 1e-7);
    }

    #[test]
    fn cosine_directions_have_the_cosine_density() {
        // E[cos] under cos/pi is 2/3; the frame is orthonormal for normals in every octant.
        let mut sum = 0.0;
        let n = Vec3::new(-0.3, 0.5, -0.81).normalize();
        let (t, b) = orthonormal_frame(n);
        assert!(t.dot(b).abs() < 1e-6 && t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6);
        assert!((t.cross(b) - n).length() < 1e-5);
        let k = 256;
        for i in 0..k {
            for j in 0..k {
                let u = Vec2::new((i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32);
                let d = cosine_direction(n, u);
                assert!((d.length() - 1.0).abs() < 1e-5);
                sum += d.dot(n);
            }
        }
        let mean = sum / (k * k) as f32;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "mean cosine {mean}");
    }
}
