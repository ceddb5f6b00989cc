//! Shared pieces of the camera tests: a deterministic RNG, the sample cameras, an independent
//! f64 reference of the projection conventions, and assertions that say what differed.

use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};
use lensray_core::camera::{Camera, CameraParams, LensParams, ProjectionParams, Ray};
use lensray_core::sampler::hash_u32;

/// Counter-based deterministic RNG built on the crate's hash.
pub struct Rng {
    key: u32,
    counter: u32,
}

impl Rng {
    pub fn new(seed: u32) -> Self {
        Self {
            key: hash_u32(seed ^ 0x5bd1_e995),
            counter: 0,
        }
    }

    pub fn next_u32(&mut self) -> u32 {
        self.counter = self.counter.wrapping_add(1);
        hash_u32(self.key ^ hash_u32(self.counter))
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn f64(&mut self) -> f64 {
        let hi = (self.next_u32() >> 5) as u64;
        let lo = (self.next_u32() >> 6) as u64;
        ((hi << 26) | lo) as f64 / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }

    /// Uniform in [0, 1) as f32 (24 bits).
    pub fn f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 / 16_777_216.0
    }

    pub fn vec2(&mut self) -> Vec2 {
        Vec2::new(self.f32(), self.f32())
    }
}

/// A named set of camera parameters.
#[derive(Clone, Debug)]
pub struct Setup {
    pub name: &'static str,
    pub params: CameraParams,
}

impl Setup {
    pub fn camera(&self) -> Camera {
        self.params
            .build()
            .unwrap_or_else(|e| panic!("{}: sample camera must build, got {e}", self.name))
    }

    pub fn reference(&self) -> RefCam {
        RefCam::new(&self.params)
    }

    pub fn with_lens(mut self, lens: LensParams) -> Self {
        self.params.lens = lens;
        self
    }

    pub fn is_orthographic(&self) -> bool {
        matches!(
            self.params.projection,
            ProjectionParams::Orthographic { .. }
        )
    }
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// Sample cameras: both models, square and non-square (landscape and portrait) images, axis
/// aligned and oblique frames, narrow and wide fields of view, various near/far ratios. Each has
/// a thin lens so the depth-of-field tests can use them as they are; the pinhole tests replace it.
pub fn setups() -> Vec<Setup> {
    vec![
        Setup {
            name: "perspective 60deg 640x360 oblique",
            params: CameraParams {
                eye: v(1.0, 2.0, 3.0),
                target: v(-2.0, 0.5, -4.0),
                up: v(0.0, 1.0, 0.0),
                projection: ProjectionParams::Perspective { vfov_degrees: 60.0 },
                lens: LensParams::ThinLens {
                    aperture_radius: 0.25,
                    focus_distance: 4.0,
                },
                near: 0.1,
                far: 100.0,
                width: 640,
                height: 360,
                movements: lensray_core::camera::Movements::NONE,
            },
        },
        Setup {
            name: "perspective 25deg 123x457 z-up tilted",
            params: CameraParams {
                eye: v(-10.0, 4.0, 7.5),
                target: v(3.0, -2.0, 1.0),
                up: v(0.3, 0.2, 1.0),
                projection: ProjectionParams::Perspective { vfov_degrees: 25.0 },
                lens: LensParams::ThinLens {
                    aperture_radius: 0.05,
                    focus_distance: 12.0,
                },
                near: 1.0,
                far: 50.0,
                width: 123,
                height: 457,
                movements: lensray_core::camera::Movements::NONE,
            },
        },
        Setup {
            name: "perspective 120deg 31x17 axis-aligned",
            params: CameraParams {
                eye: v(0.0, 0.0, 0.0),
                target: v(0.0, 0.0, -1.0),
                up: v(0.0, 1.0, 0.0),
                projection: ProjectionParams::Perspective {
                    vfov_degrees: 120.0,
                },
                lens: LensParams::ThinLens {
                    aperture_radius: 0.02,
                    focus_distance: 1.2,
                },
                near: 0.5,
                far: 2.0,
                width: 31,
                height: 17,
                movements: lensray_core::camera::Movements::NONE,
            },
        },
        Setup {
            name: "orthographic h=4 640x480 diagonal",
            params: CameraParams {
                eye: v(3.0, 3.0, 3.0),
                target: v(0.0, 0.0, 0.0),
                up: v(0.0, 1.0, 0.0),
                projection: ProjectionParams::Orthographic { height: 4.0 },
                lens: LensParams::ThinLens {
                    aperture_radius: 0.3,
                    focus_distance: 6.0,
                },
                near: 0.5,
                far: 20.0,
                width: 640,
                height: 480,
                movements: lensray_core::camera::Movements::NONE,
            },
        },
        Setup {
            name: "orthographic h=0.75 97x211 oblique x-up",
            params: CameraParams {
                eye: v(-2.0, 5.0, 1.0),
                target: v(1.0, -1.0, 2.0),
                up: v(1.0, 0.0, 0.3),
                projection: ProjectionParams::Orthographic { height: 0.75 },
                lens: LensParams::ThinLens {
                    aperture_radius: 0.1,
                    focus_distance: 3.0,
                },
                near: 2.0,
                far: 9.0,
                width: 97,
                height: 211,
                movements: lensray_core::camera::Movements::NONE,
            },
        },
    ]
}

/// Independent f64 implementation of the conventions stated in `camera/mod.rs`.
#[derive(Clone, Copy, Debug)]
pub struct RefCam {
    pub eye: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub forward: DVec3,
    pub orthographic: bool,
    /// tan(vfov / 2) or ortho_height / 2.
    pub s: f64,
    pub width: f64,
    pub height: f64,
    pub near: f64,
    pub far: f64,
    pub aperture: f64,
    pub focus: f64,
}

impl RefCam {
    pub fn new(p: &CameraParams) -> Self {
        let eye = p.eye.as_dvec3();
        let forward = (p.target.as_dvec3() - eye).normalize();
        let right = forward.cross(p.up.as_dvec3()).normalize();
        let up = right.cross(forward);
        let (orthographic, s) = match p.projection {
            ProjectionParams::Perspective { vfov_degrees } => {
                (false, (0.5 * vfov_degrees.to_radians()).tan())
            }
            ProjectionParams::Orthographic { height } => (true, 0.5 * height),
        };
        let (aperture, focus) = match p.lens {
            LensParams::Pinhole => (0.0, 1.0),
            LensParams::ThinLens {
                aperture_radius,
                focus_distance,
            } => (aperture_radius, focus_distance),
            LensParams::Physical { .. } | LensParams::Real(_) => {
                panic!("RefCam models the thin lens only")
            }
        };
        Self {
            eye,
            right,
            up,
            forward,
            orthographic,
            s,
            width: p.width as f64,
            height: p.height as f64,
            near: p.near,
            far: p.far,
            aperture,
            focus,
        }
    }

    pub fn aspect(&self) -> f64 {
        self.width / self.height
    }

    /// (dot(d, right), dot(d, true_up), dot(d, forward)) with d = p - eye.
    pub fn camera_coords(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    pub fn world_from_camera_coords(&self, c: DVec3) -> DVec3 {
        self.eye + c.x * self.right + c.y * self.up + c.z * self.forward
    }

    /// The divisor of x and y at camera depth z: z (perspective) or 1 (orthographic).
    pub fn divisor(&self, z: f64) -> f64 {
        if self.orthographic {
            1.0
        } else {
            z
        }
    }

    /// The course's depth in [0, 1] of camera depth z.
    pub fn depth(&self, z: f64) -> f64 {
        let (n, f) = (self.near, self.far);
        if self.orthographic {
            (z - n) / (f - n)
        } else {
            f * (z - n) / (z * (f - n))
        }
    }

    /// Inverse of `depth`.
    pub fn z_from_depth(&self, d: f64) -> f64 {
        let (n, f) = (self.near, self.far);
        if self.orthographic {
            n + d * (f - n)
        } else {
            f * n / (f - d * (f - n))
        }
    }

    /// World point -> (column, row, depth), by the explicit formula.
    pub fn raster(&self, p: DVec3) -> DVec3 {
        let c = self.camera_coords(p);
        let k = self.divisor(c.z);
        let col = (1.0 + c.x / (k * self.s * self.aspect())) * self.width / 2.0;
        let row = (1.0 - c.y / (k * self.s)) * self.height / 2.0;
        DVec3::new(col, row, self.depth(c.z))
    }

    /// Screen-plane (x, y) of a raster position: where the pinhole ray through it crosses
    /// camera depth 1 (perspective) or its offset from the axis (orthographic).
    pub fn screen_xy(&self, col: f64, row: f64) -> (f64, f64) {
        let x = (2.0 * col / self.width - 1.0) * self.s * self.aspect();
        let y = (1.0 - 2.0 * row / self.height) * self.s;
        (x, y)
    }

    /// Camera-space point on the pinhole ray through (col, row) at camera depth z.
    pub fn pinhole_point_camera(&self, col: f64, row: f64, z: f64) -> DVec3 {
        let (x, y) = self.screen_xy(col, row);
        let k = self.divisor(z);
        DVec3::new(x * k, y * k, z)
    }

    /// Inverse of `raster`: (column, row, depth) -> world.
    pub fn unproject(&self, r: DVec3) -> DVec3 {
        let z = self.z_from_depth(r.z);
        self.world_from_camera_coords(self.pinhole_point_camera(r.x, r.y, z))
    }

    /// How far an f32 world point near `p` may be from where it should be after a few f32
    /// operations: a few ulps of the world coordinates involved (the eye's and the offset's).
    /// Tolerances below are this rounding propagated through the projection, not slack.
    pub fn world_rounding(&self, p: DVec3) -> f64 {
        4.0 * f32::EPSILON as f64 * (self.eye.length() + (p - self.eye).length())
    }

    /// Pixels per world unit across the view at camera depth z.
    pub fn pixels_per_unit(&self, z: f64) -> f64 {
        self.height / (2.0 * self.s * self.divisor(z))
    }

    /// d(depth)/dz at camera depth z.
    pub fn depth_slope(&self, z: f64) -> f64 {
        let (n, f) = (self.near, self.far);
        if self.orthographic {
            1.0 / (f - n)
        } else {
            f * n / (z * z * (f - n))
        }
    }

    /// Raster tolerance (pixels, depth) for a world point p: its rounding propagated, plus the
    /// rounding of the raster coordinates themselves.
    pub fn raster_tolerance(&self, p: DVec3) -> (f64, f64) {
        let z = self.camera_coords(p).z;
        let e = self.world_rounding(p);
        let px =
            e * self.pixels_per_unit(z) + 4.0 * f32::EPSILON as f64 * self.width.max(self.height);
        let depth = e * self.depth_slope(z) + 4.0 * f32::EPSILON as f64;
        (px, depth)
    }

    /// A random world point inside (and a little around) the view volume.
    pub fn random_point(&self, rng: &mut Rng, margin: f64) -> DVec3 {
        let z = if self.orthographic {
            rng.range(self.near, self.far)
        } else {
            // Log-uniform so that depths near the near plane are well represented.
            self.near * (self.far / self.near).powf(rng.f64())
        };
        let k = self.divisor(z);
        let x = rng.range(-margin, margin) * self.s * self.aspect() * k;
        let y = rng.range(-margin, margin) * self.s * k;
        self.world_from_camera_coords(DVec3::new(x, y, z))
    }
}

/// Homogeneous transform of a point with the perspective divide, in f64 after the f32 matrix.
pub fn transform_h(m: &Mat4, p: Vec3) -> (Vec3, f32) {
    let h: Vec4 = *m * p.extend(1.0);
    (h.truncate() / h.w, h.w)
}

/// Distance from `p` to the ray's line and the signed parameter of its foot, in f64.
pub fn ray_distance(ray: &Ray, p: DVec3) -> (f64, f64) {
    let o = ray.origin.as_dvec3();
    let d = ray.direction.as_dvec3().normalize();
    let op = p - o;
    let t = op.dot(d);
    ((op - t * d).length(), t)
}

/// Where a world-space ray crosses camera depth z (a plane perpendicular to `forward`), in f64.
pub fn cross_depth(reference: &RefCam, ray: &Ray, z: f64) -> DVec3 {
    let o = ray.origin.as_dvec3();
    let d = ray.direction.as_dvec3();
    let oz = (o - reference.eye).dot(reference.forward);
    let t = (z - oz) / d.dot(reference.forward);
    o + t * d
}

#[track_caller]
pub fn assert_close(what: &str, actual: f64, expected: f64, tol: f64) {
    let diff = (actual - expected).abs();
    assert!(
        diff <= tol,
        "{what}: got {actual}, expected {expected}, differ by {diff:.3e} (tolerance {tol:.3e})"
    );
}

#[track_caller]
pub fn assert_rel(what: &str, actual: f64, expected: f64, rel: f64) {
    let diff = (actual - expected).abs();
    let tol = rel * expected.abs();
    assert!(
        diff <= tol,
        "{what}: got {actual}, expected {expected}, differ by {diff:.3e} = {:.3e} relative \
         (tolerance {rel:.1e} relative)",
        diff / expected.abs()
    );
}

#[track_caller]
pub fn assert_vec_close(what: &str, actual: DVec3, expected: DVec3, tol: f64) {
    let diff = (actual - expected).abs().max_element();
    assert!(
        diff <= tol,
        "{what}: got {actual:?}, expected {expected:?}, largest component difference {diff:.3e} \
         (tolerance {tol:.3e})"
    );
}

/// Row-major 4x4 in f64, as written on the slides.
pub type Rows = [[f64; 4]; 4];

#[track_caller]
pub fn assert_matrix(what: &str, m: &Mat4, expected: &Rows, rel: f64) {
    for (r, row) in expected.iter().enumerate() {
        for (c, &e) in row.iter().enumerate() {
            let a = m.col(c)[r] as f64;
            let tol = rel * e.abs().max(1.0);
            let diff = (a - e).abs();
            assert!(
                diff <= tol,
                "{what}: entry (row {r}, column {c}) is {a}, expected {e}, differ by {diff:.3e} \
                 (tolerance {tol:.3e})\nwhole matrix (glam, column-major): {m:?}"
            );
        }
    }
}

#[track_caller]
pub fn assert_identity(what: &str, m: &Mat4, tol: f64) {
    let id: Rows = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    for (r, row) in id.iter().enumerate() {
        for (c, &e) in row.iter().enumerate() {
            let a = m.col(c)[r] as f64;
            let diff = (a - e).abs();
            assert!(
                diff <= tol,
                "{what}: product entry (row {r}, column {c}) is {a}, identity has {e}, \
                 differ by {diff:.3e} (tolerance {tol:.1e})\nproduct: {m:?}"
            );
        }
    }
}
