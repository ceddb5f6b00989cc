//! The camera rays of a packet of samples at once, named after the camera's own:
//! [`generate_rays`] is `Camera::generate_ray` for every lane, [`first_order_rays`]
//! `Camera::first_order_ray` (`pixel_camera_samples` then the ray) for every lane, laid out by
//! lane so the divisions and square roots vectorize. Operation for operation the same
//! arithmetic as the camera module (glam's `transform_point3`, `transform_vector3`,
//! `normalize`; `Camera::pinhole_ray`, `ThinLens::generate_ray` and `lens_point`), so the rays
//! are bit-identical to `Camera::first_order_ray` (tests/reference/traversal.rs checks it); a
//! real lens's packet is `RealLens::generate_rays`. The camera module stays the definition the
//! GLSL mirrors.

use glam::{Mat4, Vec3};

use super::accel::PACKET_SIZE;
use crate::camera::{Camera, Projection, Ray};
use crate::optics::glass::dispersion_offset_f32;
use crate::sampler::{pixel_camera_samples, pixel_camera_samples_of, CameraSample, PixelSampler};

type PacketLanes = [f32; PACKET_SIZE];

/// PacketLanes of three coordinates.
struct Lanes3 {
    x: PacketLanes,
    y: PacketLanes,
    z: PacketLanes,
}

impl Lanes3 {
    fn splat(v: Vec3) -> Self {
        Self {
            x: [v.x; PACKET_SIZE],
            y: [v.y; PACKET_SIZE],
            z: [v.z; PACKET_SIZE],
        }
    }
}

/// glam's `Mat4::transform_point3` (`w` = 1) or `transform_vector3` (`w` = 0) per lane:
/// res = x_axis * x; res = y_axis * y + res; res = z_axis * z + res; (res = w_axis + res).
#[inline(always)]
fn transform(m: &Mat4, p: &Lanes3, point: bool) -> Lanes3 {
    let mut out = Lanes3::splat(Vec3::ZERO);
    for l in 0..PACKET_SIZE {
        let (x, y, z) = (p.x[l], p.y[l], p.z[l]);
        let mut r = m.x_axis.truncate() * x;
        r = m.y_axis.truncate() * y + r;
        r = m.z_axis.truncate() * z + r;
        if point {
            r = m.w_axis.truncate() + r;
        }
        out.x[l] = r.x;
        out.y[l] = r.y;
        out.z[l] = r.z;
    }
    out
}

/// glam's `Vec3::normalize`: v * (1 / sqrt(x x + y y + z z)).
#[inline(always)]
fn normalize(v: &mut Lanes3) {
    for l in 0..PACKET_SIZE {
        let dot = (v.x[l] * v.x[l]) + (v.y[l] * v.y[l]) + (v.z[l] * v.z[l]);
        let recip = 1.0 / dot.sqrt();
        v.x[l] *= recip;
        v.y[l] *= recip;
        v.z[l] *= recip;
    }
}

/// World-space first-order rays of samples `first..first + PACKET_SIZE` of the sampler's pixel
/// (the caller uses the first `spp - first` of them), as `Camera::first_order_ray(sample)`
/// makes them.
pub fn first_order_rays(
    camera: &Camera,
    sampler: &PixelSampler,
    first: u32,
    origins: &mut [Vec3; PACKET_SIZE],
    directions: &mut [Vec3; PACKET_SIZE],
) {
    let [film_x, film_y, lens_x, lens_y] = pixel_camera_samples::<PACKET_SIZE>(sampler, first);
    let film = Lanes3 {
        x: film_x,
        y: film_y,
        z: [0.0; PACKET_SIZE],
    };
    // Camera::pinhole_ray.
    let screen = transform(&camera.screen_from_raster, &film, true);
    let near = camera.near;
    let (mut origin, mut direction) = match camera.projection {
        Projection::Orthographic { .. } => (
            Lanes3 {
                x: screen.x,
                y: screen.y,
                z: [near; PACKET_SIZE],
            },
            Lanes3::splat(Vec3::Z),
        ),
        Projection::Perspective { .. } => {
            let mut d = Lanes3 {
                x: screen.x.map(|x| x * near),
                y: screen.y.map(|y| y * near),
                z: [near; PACKET_SIZE],
            };
            normalize(&mut d);
            (Lanes3::splat(Vec3::ZERO), d)
        }
    };
    // ThinLens::generate_ray (a closed lens keeps the pinhole's ray).
    let lens = camera.lens.first_order();
    if lens.aperture_radius > 0.0 {
        // ThinLens::lens_point: the aperture's map of each lane's lens sample.
        let lens_points = lens.lens_points::<PACKET_SIZE>(&std::array::from_fn(|l| {
            glam::Vec2::new(lens_x[l], lens_y[l])
        }));
        let mut to_focus = Lanes3::splat(Vec3::ZERO);
        let s = lens.focus_tilt;
        for (l, lens_point) in lens_points.iter().enumerate() {
            // a = focus_distance - n . o, b = n . d, the lens point scaled by
            // a / (focus_distance - o.z) (ThinLens::across).
            let across_origin = s.x * origin.x[l] + s.y * origin.y[l] + origin.z[l];
            let across_direction = s.x * direction.x[l] + s.y * direction.y[l] + direction.z[l];
            let a = lens.focus_distance - across_origin;
            let b = across_direction;
            let scale = a / (lens.focus_distance - origin.z[l]);
            let point = *lens_point * scale;
            to_focus.x[l] = direction.x[l] * a - point.x * b;
            to_focus.y[l] = direction.y[l] * a - point.y * b;
            to_focus.z[l] = direction.z[l] * a - 0.0 * b;
            origin.x[l] += point.x;
            origin.y[l] += point.y;
            origin.z[l] += 0.0;
        }
        normalize(&mut to_focus);
        direction = to_focus;
    }
    if camera.motion.is_some() {
        // Each lane at its own moment: Camera::world_ray.
        for l in 0..PACKET_SIZE {
            let sample = moving_sample(camera, sampler, first + l as u32, film_y[l]);
            let ray = Ray {
                origin: Vec3::new(origin.x[l], origin.y[l], origin.z[l]),
                direction: Vec3::new(direction.x[l], direction.y[l], direction.z[l]),
            };
            let ray = camera.world_ray(&ray, &sample);
            origins[l] = ray.origin;
            directions[l] = ray.direction;
        }
        return;
    }
    // Ray::transformed by world_from_camera.
    let world_origin = transform(&camera.world_from_camera, &origin, true);
    let world_direction = transform(&camera.world_from_camera, &direction, false);
    for l in 0..PACKET_SIZE {
        origins[l] = Vec3::new(world_origin.x[l], world_origin.y[l], world_origin.z[l]);
        directions[l] = Vec3::new(
            world_direction.x[l],
            world_direction.y[l],
            world_direction.z[l],
        );
    }
}

/// What `Camera::world_ray` needs of sample `index` (film row `film_y`): its row and time
/// (the film's column and the lens sample are the camera-space ray's already).
fn moving_sample(camera: &Camera, sampler: &PixelSampler, index: u32, film_y: f32) -> CameraSample {
    CameraSample {
        film: glam::Vec2::new(0.0, film_y),
        lens: glam::Vec2::ZERO,
        time: camera.sample_time(sampler, index),
    }
}

/// A packet of camera rays, packed: the first slots hold the rays the lens lets through, in
/// world space, with their weights, sample indices and wavelengths.
pub(super) struct LensPacket {
    pub(super) origins: [Vec3; PACKET_SIZE],
    pub(super) directions: [Vec3; PACKET_SIZE],
    pub(super) weights: [f32; PACKET_SIZE],
    pub(super) indices: [u32; PACKET_SIZE],
    /// nm; 0 when the lens carries no wavelength (`RealLens::dispersive`).
    pub(super) wavelengths: [f32; PACKET_SIZE],
    /// Each ray's moment in the shutter's span (`Camera::sample_moment`).
    pub(super) moments: [f32; PACKET_SIZE],
}

impl LensPacket {
    pub(super) fn new() -> Self {
        Self {
            origins: [Vec3::ZERO; PACKET_SIZE],
            directions: [Vec3::ZERO; PACKET_SIZE],
            weights: [0.0; PACKET_SIZE],
            indices: [0; PACKET_SIZE],
            wavelengths: [0.0; PACKET_SIZE],
            moments: [0.5; PACKET_SIZE],
        }
    }
}

/// Which rays of a dispersive lens's samples a packet holds (film::spectral, "Dispersion at
/// little cost").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum DispersionPass {
    /// Every sample at the d line (the only pass of a lens that does not disperse); a sample
    /// that checks it carries its wavelength for `d_line_value`.
    DLine,
    /// The samples that check the d line (`checks_dispersion`), each at its wavelength
    /// (`checked_value`); the others are left out.
    Checks,
}

/// Samples of one pixel traced as a packet, the first `n` lanes: their indices and, through a
/// dispersive lens, the wavelength at which each checks the d line (nm; 0: it does not).
pub(super) struct PacketSamples {
    pub(super) indices: [u32; PACKET_SIZE],
    pub(super) checked: [f32; PACKET_SIZE],
    pub(super) n: usize,
}

impl PacketSamples {
    pub(super) fn new() -> Self {
        Self {
            indices: [0; PACKET_SIZE],
            checked: [0.0; PACKET_SIZE],
            n: 0,
        }
    }

    /// Samples `first..first + n`, with the wavelengths of those that check the d line
    /// (`Camera::checked_wavelength`).
    pub(super) fn run(camera: &Camera, sampler: &PixelSampler, first: u32, n: usize) -> Self {
        let indices = std::array::from_fn(|l| first + l as u32);
        let mut checked = [0.0; PACKET_SIZE];
        if camera.lens.real().is_some_and(|real| real.dispersive()) {
            for l in 0..n {
                checked[l] = camera
                    .checked_wavelength(sampler, indices[l])
                    .unwrap_or(0.0);
            }
        }
        Self {
            indices,
            checked,
            n,
        }
    }

    /// Appends a sample; the caller traces the packet once it is full (`n == PACKET_SIZE`).
    pub(super) fn push(&mut self, index: u32, checked: f32) {
        self.indices[self.n] = index;
        self.checked[self.n] = checked;
        self.n += 1;
    }
}

/// The camera rays of `samples`, of the sampler's pixel, as `Camera::generate_ray` makes them,
/// packed into `out`; returns how many passed. Through a dispersive lens `pass` says which: the
/// d line's of every sample, or the wavelengths' (`sample_wavelength` of `DIM_WAVELENGTH`) of
/// the samples that check it (the pixel loop gathers those into packets of their own, so that
/// their packets are full but for the pixel's last).
/// A thin lens (or pinhole) passes every ray, weight 1: its [`first_order_rays`], whose
/// samples are a run (`indices[0]..`), as the pixel loop gives a lens that does not disperse.
pub(super) fn generate_rays(
    camera: &Camera,
    sampler: &PixelSampler,
    samples: &PacketSamples,
    pass: DispersionPass,
    out: &mut LensPacket,
) -> usize {
    let PacketSamples {
        indices,
        checked,
        n,
    } = samples;
    let n = *n;
    let Some(real) = camera.lens.real() else {
        let first = indices[0];
        debug_assert!((0..n).all(|l| indices[l] == first + l as u32));
        first_order_rays(
            camera,
            sampler,
            first,
            &mut out.origins,
            &mut out.directions,
        );
        out.indices = std::array::from_fn(|l| first + l as u32);
        out.weights = [1.0; PACKET_SIZE];
        if camera.motion.is_some() {
            let [_, film_y, _, _] = pixel_camera_samples::<PACKET_SIZE>(sampler, first);
            out.moments = std::array::from_fn(|l| {
                let sample = moving_sample(camera, sampler, first + l as u32, film_y[l]);
                camera.sample_moment(&sample)
            });
        }
        return n;
    };
    let [film_x, film_y, lens_x, lens_y] = pixel_camera_samples_of(sampler, indices);
    // The lanes traced in this pass: every sample at the d line, or those that check it.
    let mut lanes = [0usize; PACKET_SIZE];
    let mut count = 0;
    // RealLens::generate_rays traces the packet's rays together (what
    // Camera::generate_ray gives one by one, bit for bit).
    let mut rays = [(Vec3::ZERO, glam::Vec2::ZERO, 0.0); PACKET_SIZE];
    for l in 0..n {
        if pass == DispersionPass::Checks && checked[l] <= 0.0 {
            continue;
        }
        let offset = match pass {
            DispersionPass::Checks => dispersion_offset_f32(checked[l]),
            DispersionPass::DLine => 0.0,
        };
        let film = glam::Vec2::new(film_x[l], film_y[l]);
        rays[count] = (
            real.film_point(film, camera.width, camera.height),
            glam::Vec2::new(lens_x[l], lens_y[l]),
            offset,
        );
        lanes[count] = l;
        count += 1;
    }
    let mut traced = [None; PACKET_SIZE];
    real.generate_rays(&rays[..count], &mut traced);
    let mut passed = 0;
    for (&l, traced) in lanes[..count].iter().zip(traced) {
        let Some((ray, weight)) = traced else {
            continue;
        };
        let sample = moving_sample(camera, sampler, indices[l], film_y[l]);
        let ray = camera.world_ray(&ray, &sample);
        out.origins[passed] = ray.origin;
        out.directions[passed] = ray.direction;
        out.weights[passed] = weight;
        out.indices[passed] = indices[l];
        out.wavelengths[passed] = checked[l];
        out.moments[passed] = camera.sample_moment(&sample);
        passed += 1;
    }
    passed
}
