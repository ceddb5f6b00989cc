//! The footprint of a pixel on a surface, as the pinhole sees it: how far the point a pinhole
//! ray meets on a surface's plane moves when the ray moves one pixel along x or along y. Texture
//! filtering takes its level of detail from this footprint for every ray of the pixel, whichever
//! lens point the ray came through: the surface at the focal plane then reads the texture exactly
//! as a pinhole render does, instead of blurring it by the lens's spread of rays (pbrt-v2's
//! bug 31). A real lens uses its first-order model, whose aperture centre is the entrance pupil.
//!
//! shaders/include/texture.glsl's `footprint_dp` mirrors [`Footprint::dp`].

use glam::Vec3;

use super::Camera;

/// What the footprint at any point needs of the camera, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    pub eye: Vec3,
    pub forward: Vec3,
    /// One pixel step along raster x and along raster y: on the plane at unit depth
    /// (perspective) or across the parallel rays (orthographic).
    pub pixel_dx: Vec3,
    pub pixel_dy: Vec3,
    pub orthographic: bool,
}

/// A footprint where the plane is seen edge-on: large enough to select the coarsest level.
const EDGE_ON: f32 = 1e30;

impl Camera {
    pub fn footprint(&self) -> Footprint {
        // Screen space is the plane z = 1 (perspective) or camera x, y (orthographic); the
        // columns of screen_from_raster are the screen steps of one raster step.
        let step = |column: glam::Vec4| {
            self.world_from_camera
                .transform_vector3(Vec3::new(column.x, column.y, 0.0))
        };
        Footprint {
            eye: self.frame.eye,
            forward: self.frame.forward,
            pixel_dx: step(self.screen_from_raster.x_axis),
            pixel_dy: step(self.screen_from_raster.y_axis),
            orthographic: self.is_orthographic(),
        }
    }
}

impl Footprint {
    /// The moves of point `p` on the plane through it with normal `n` for one pixel step along
    /// x and along y: where the pinhole rays of the neighbouring pixels meet that plane.
    pub fn dp(&self, p: Vec3, n: Vec3) -> [Vec3; 2] {
        [self.pixel_dx, self.pixel_dy].map(|step| self.dp_along(p, n, step))
    }

    fn dp_along(&self, p: Vec3, n: Vec3, step: Vec3) -> Vec3 {
        if self.orthographic {
            // The neighbouring ray starts `step` aside, parallel to the axis.
            let t = -n.dot(step) / n.dot(self.forward);
            let dp = step + t * self.forward;
            return if dp.is_finite() {
                dp
            } else {
                Vec3::splat(EDGE_ON)
            };
        }
        let to_p = p - self.eye;
        // The direction through p scaled to unit depth, then one pixel over.
        let d = to_p / to_p.dot(self.forward) + step;
        let t = n.dot(to_p) / n.dot(d);
        if t > 0.0 && t.is_finite() {
            t * d - to_p
        } else {
            Vec3::splat(EDGE_ON)
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use crate::camera::{CameraParams, LensParams, ProjectionParams};
    use crate::sampler::CameraSample;

    /// The footprint is where the pinhole rays through the neighbouring pixels meet the plane:
    /// checked by intersecting those rays, for both projections and a tilted plane.
    #[test]
    fn dp_is_the_move_to_the_neighbouring_pixels_rays() {
        for projection in [
            ProjectionParams::Perspective { vfov_degrees: 40.0 },
            ProjectionParams::Orthographic { height: 2.0 },
        ] {
            let camera = CameraParams {
                eye: Vec3::new(0.3, 1.0, 4.0),
                target: Vec3::new(0.0, 0.2, 0.0),
                up: Vec3::Y,
                projection,
                lens: LensParams::Pinhole,
                near: 0.1,
                far: 100.0,
                width: 64,
                height: 48,
                movements: crate::camera::Movements::NONE,
            }
            .build()
            .unwrap();
            let n = Vec3::new(0.2, 1.0, 0.4).normalize();
            let plane_point = Vec3::new(0.0, 0.1, 0.0);
            let meet = |raster: Vec2| {
                let ray = camera.first_order_ray(CameraSample::new(raster, Vec2::splat(0.5)));
                let t = n.dot(plane_point - ray.origin) / n.dot(ray.direction);
                ray.at(t)
            };
            let pixel = Vec2::new(20.5, 30.5);
            let p = meet(pixel);
            let [dx, dy] = camera.footprint().dp(p, n);
            let want_dx = meet(pixel + Vec2::X) - p;
            let want_dy = meet(pixel + Vec2::Y) - p;
            assert!(
                (dx - want_dx).length() < 1e-4 * want_dx.length(),
                "{dx} {want_dx}"
            );
            assert!(
                (dy - want_dy).length() < 1e-4 * want_dy.length(),
                "{dy} {want_dy}"
            );
        }
    }
}
