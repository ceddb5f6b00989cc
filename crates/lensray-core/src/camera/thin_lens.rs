//! Thin-lens depth of field (slides "Non-Linear Models: Depth of Field").
//!
//! 1. For a film point, the primary ray through the centre of the aperture (the pinhole ray).
//! 2. Its intersection with the focal plane ("intersecting the ray with the plane"): the plane
//!    z = focus_distance facing the camera, or, for a tilted lens, the plane
//!    z + focus_tilt · (x, y) = focus_distance that crosses the view axis at the same distance
//!    (`movements` derives it from the tilt with the Scheimpflug and hinge rules).
//! 3. A random point on the aperture disk.
//! 4. The new ray from that lens point through the focal-plane point. Averaging over many such rays
//!    blurs everything off the focal plane. Why all of them meet there: see `physical`.
//!
//! Steps 2 and 4 are written in homogeneous form, (d a, b) for the focal point o + d a / b of a
//! pinhole ray (o, d): a tilted plane is met behind the lens (b < 0: a virtual image, whose lens
//! rays diverge) or nowhere (b = 0: parallel lens rays) by the rays that look past its hinge,
//! and the form gives every such ray its forward direction without dividing by b.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::{Aperture, Ray};

#[derive(Clone, Debug, PartialEq)]
pub struct ThinLens {
    /// World units; 0 is a pinhole. The radius of the circle the aperture's shape is
    /// inscribed in (before its aspect, see `aperture`).
    pub aperture_radius: f32,
    /// Where the plane of focus crosses the view axis: its distance from the lens along the
    /// axis, world units.
    pub focus_distance: f32,
    /// The plane of focus's slope (camera space): the plane is
    /// z + focus_tilt · (x, y) = focus_distance. Zero: it faces the camera. Tilted, it comes
    /// nearer toward `focus_tilt`'s direction and meets the lens plane at the hinge, at distance
    /// focus_distance / |focus_tilt| from the axis.
    pub focus_tilt: Vec2,
    /// The opening's shape.
    pub aperture: Aperture,
}

impl ThinLens {
    pub const PINHOLE: ThinLens = ThinLens {
        aperture_radius: 0.0,
        focus_distance: 1.0,
        focus_tilt: Vec2::ZERO,
        aperture: Aperture::ROUND,
    };

    /// A round lens.
    pub fn round(aperture_radius: f32, focus_distance: f32) -> Self {
        ThinLens {
            aperture_radius,
            focus_distance,
            focus_tilt: Vec2::ZERO,
            aperture: Aperture::ROUND,
        }
    }

    /// How far lens points reach from the lens centre: the radius of the circle that holds
    /// the shape, its aspect included (what bounds a circle of confusion).
    pub fn reach(&self) -> f32 {
        self.aperture_radius * self.aperture.reach()
    }

    /// n · v for the plane of focus's normal n = (focus_tilt, 1): the plane is
    /// n · p = focus_distance.
    #[inline]
    pub fn across(&self, v: Vec3) -> f32 {
        self.focus_tilt.x * v.x + self.focus_tilt.y * v.y + v.z
    }

    /// The plane of focus's depth z over the camera-space point (x, y).
    pub fn focus_depth_at(&self, xy: Vec2) -> f32 {
        self.focus_distance - (self.focus_tilt.x * xy.x + self.focus_tilt.y * xy.y)
    }

    /// Step 2: the point where the aperture-centre ray meets the plane of focus, if it does in
    /// front of the lens.
    pub fn focal_point(&self, pinhole: &Ray) -> Option<Vec3> {
        let t =
            (self.focus_distance - self.across(pinhole.origin)) / self.across(pinhole.direction);
        (t > 0.0 && t.is_finite()).then(|| pinhole.at(t))
    }

    /// The thin lens's camera ray (steps 3-4), in camera space, from the aperture-centre ray
    /// `pinhole` of its film point (`Camera::pinhole_ray`); a closed lens (a pinhole) returns
    /// `pinhole` itself. `lens_u` is a uniform sample of [0, 1)^2. The lens point is
    /// added to the pinhole ray's origin: the lens centre for perspective, the film point for
    /// orthographic (whose rays start on the near plane, each with its own lens centre).
    ///
    /// With a = focus_distance - n · o and b = n · d, the focal point is o + d a / b and the
    /// lens ray from o + l runs along d a - l b. An orthographic film point's lens point is
    /// scaled by a / (focus_distance - o.z), 1 when the plane faces the camera: every lens ray
    /// of one lens point then runs parallel to (focus_distance - near) z - l, whatever film
    /// point it serves, so the raster path's map stays affine ([`Self::pinhole_from_camera`]).
    /// A perspective ray starts at the lens centre, where the scale is exactly 1.
    pub fn generate_ray(&self, pinhole: &Ray, lens_u: Vec2) -> Ray {
        if self.aperture_radius <= 0.0 {
            return *pinhole;
        }
        let a = self.focus_distance - self.across(pinhole.origin);
        let b = self.across(pinhole.direction);
        let scale = a / (self.focus_distance - pinhole.origin.z);
        let lens = self.lens_point(lens_u) * scale;
        let origin = pinhole.origin + Vec3::new(lens.x, lens.y, 0.0);
        let direction = pinhole.direction * a - Vec3::new(lens.x, lens.y, 0.0) * b;
        Ray {
            origin,
            direction: direction.normalize(),
        }
    }

    /// Step 3: the point of the aperture (camera-space x, y, relative to the lens centre) that
    /// the uniform sample `lens_u` in [0, 1)^2 picks: uniform over the opening's shape.
    pub fn lens_point(&self, lens_u: Vec2) -> Vec2 {
        self.aperture_radius * self.aperture.unit_point(lens_u)
    }

    /// [`Self::lens_point`] of every sample of a packet, bit for bit.
    pub fn lens_points<const N: usize>(&self, lens_u: &[Vec2; N]) -> [Vec2; N] {
        self.aperture
            .unit_points(lens_u)
            .map(|p| self.aperture_radius * p)
    }

    /// The accumulation-buffer view of steps 1-4 (the raster path): for one lens point `lens`
    /// (from [`Self::lens_point`]) of a lens in the plane z = `lens_z`, the camera-space shear
    /// that turns every lens ray through that point into the aperture-centre ray of the same
    /// film point. Along a lens ray, x moves relative to the aperture-centre ray of its film
    /// point by `lens.x` times the distance to the plane of focus, n · p - focus_distance (0 on
    /// the plane, where both rays meet), over the same measure at the lens point,
    /// focus_distance - lens_z - focus_tilt · lens (similar triangles; likewise y). Hence
    /// `x' = x + lens.x (n · p - focus_distance) / (focus_distance - lens_z - focus_tilt · lens)`,
    /// z unchanged: the plane of focus stays fixed and depth keeps its meaning. Followed by the
    /// usual projection, this is the sheared (off-axis) projection whose centre of projection
    /// is the lens point; a tilted plane adds x and y terms, and the map stays affine.
    pub fn pinhole_from_camera(&self, lens: Vec2, lens_z: f32) -> Mat4 {
        let s = self.focus_tilt;
        let depth = self.focus_distance - lens_z - (s.x * lens.x + s.y * lens.y);
        // x' = x + (lens.x / depth) (s.x x + s.y y + z) - lens.x * focus / depth.
        let shear = lens / depth;
        let offset = -lens * self.focus_distance / depth;
        Mat4::from_cols(
            Vec4::new(1.0 + shear.x * s.x, shear.y * s.x, 0.0, 0.0),
            Vec4::new(shear.x * s.y, 1.0 + shear.y * s.y, 0.0, 0.0),
            Vec4::new(shear.x, shear.y, 1.0, 0.0),
            Vec4::new(offset.x, offset.y, 0.0, 1.0),
        )
    }

    /// Radius of the bundle of lens rays of one film point where it crosses depth z, for a lens
    /// in the plane z = `lens_z`: similar triangles between the lens's reach and the focal
    /// point give `reach * |focus - z| / (focus - lens_z)`.
    pub fn ray_spread_radius(&self, z: f32, lens_z: f32) -> f32 {
        self.reach() * (self.focus_distance - z).abs() / (self.focus_distance - lens_z)
    }
}

/// Uniform [0, 1)^2 -> uniform unit disk, preserving strata (Shirley and Chiu's concentric map).
/// The angle is pi/4 t or pi/2 - pi/4 t with |t| <= 1, so one sine and one cosine on
/// [-pi/4, pi/4] give both cases; without branches or library calls, a packet of lens samples
/// maps in vector code (reference/rays.rs), and the shaders evaluate the same polynomials.
#[inline]
pub fn concentric_sample_disk(u: Vec2) -> Vec2 {
    let offset = 2.0 * u - Vec2::ONE;
    let x_major = offset.x.abs() > offset.y.abs();
    let (radius, t) = if x_major {
        (offset.x, offset.y / offset.x)
    } else {
        (offset.y, offset.x / offset.y)
    };
    let (sin, cos) = sin_cos_quarter(std::f32::consts::FRAC_PI_4 * t);
    // theta = pi/4 t: (cos, sin); theta = pi/2 - pi/4 t: (sin, cos).
    let (x, y) = if x_major { (cos, sin) } else { (sin, cos) };
    if offset.x == 0.0 && offset.y == 0.0 {
        Vec2::ZERO
    } else {
        Vec2::new(radius * x, radius * y)
    }
}

/// Sine and cosine of `x` for |x| <= pi/4 (within 2 ulps there): the minimax polynomials of
/// Cephes' single-precision `sinf`/`cosf` kernels, in Horner form; shaders/include/camera.glsl
/// evaluates them operation for operation (`precise`, no fused multiply-adds).
#[inline]
pub fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let z = x * x;
    let sin = ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1) * z * x + x;
    let cos = ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2) * z * z - 0.5 * z + 1.0;
    (sin, cos)
}
