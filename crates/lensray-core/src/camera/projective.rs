//! The projective camera: the transform chain camera -> screen -> NDC -> raster built once, and
//! ray generation through a point of a pixel (slides "To generate a ray through pixel (i,j)").
//!
//! A camera ray has one entry, [`Camera::generate_ray`]: a camera sample (film point, lens
//! sample) and, for a dispersive lens, a wavelength, dispatched to the lens kind's own ray in
//! camera space ([`Camera::pinhole_ray`],
//! [`ThinLens::generate_ray`](super::ThinLens::generate_ray),
//! [`RealLens::generate_ray`](super::RealLens::generate_ray)), then taken to world space.
//! [`Camera::first_order_ray`] is another concept: the ray of the lens's first-order thin lens,
//! what rasterizing passes draw and AOVs and focus picking see (for a thin lens, the same ray).

use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};

use std::sync::Arc;

use super::coc::CocLens;
use super::look_at::CameraFrame;
use super::motion::CameraMotion;
use super::raster::{self, ScreenWindow};
use super::real_lens::RealLensError;
use super::{Aperture, Lens, Projection, Ray};
use crate::optics::glass::dispersion_offset_f32;
use crate::sampler::CameraSample;

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub projection: Projection,
    pub frame: CameraFrame,
    /// The lens: a thin lens (a pinhole when closed), or a real lens whose surfaces the traced
    /// paths' camera rays cross, with its first-order model (what rasterizing passes draw).
    pub lens: Lens,
    pub near: f32,
    pub far: f32,
    pub width: u32,
    pub height: u32,
    pub screen_window: ScreenWindow,
    pub camera_from_world: Mat4,
    pub world_from_camera: Mat4,
    pub screen_from_camera: Mat4,
    pub camera_from_screen: Mat4,
    pub ndc_from_screen: Mat4,
    pub screen_from_ndc: Mat4,
    pub raster_from_ndc: Mat4,
    pub ndc_from_raster: Mat4,
    /// raster_from_ndc * ndc_from_screen: affine.
    pub raster_from_screen: Mat4,
    /// screen_from_ndc * ndc_from_raster: affine; the course's (i, j) -> (s, t) -> (x, y).
    pub screen_from_raster: Mat4,
    /// The camera's poses while the shutter is open, when it moves then (`None`: every ray
    /// leaves from `world_from_camera`, the frame's pose).
    pub motion: Option<Arc<CameraMotion>>,
}

impl Camera {
    /// Inputs are assumed valid (see `CameraParams::build`, which checks them). `screen_shift`
    /// moves the screen window's centre off the view axis (screen units; zero: centred).
    #[expect(
        clippy::too_many_arguments,
        reason = "each is one of the camera's parameters"
    )]
    pub fn new(
        projection: Projection,
        frame: CameraFrame,
        lens: Lens,
        near: f32,
        far: f32,
        width: u32,
        height: u32,
        screen_shift: Vec2,
    ) -> Self {
        let screen_window =
            ScreenWindow::new(projection.screen_half_height(), width, height, screen_shift);
        let ndc_from_screen = screen_window.ndc_from_screen();
        let screen_from_ndc = screen_window.screen_from_ndc();
        let raster_from_ndc = raster::raster_from_ndc(width, height);
        let ndc_from_raster = raster::ndc_from_raster(width, height);
        Self {
            projection,
            frame,
            lens,
            near,
            far,
            width,
            height,
            screen_window,
            camera_from_world: frame.camera_from_world(),
            world_from_camera: frame.world_from_camera(),
            screen_from_camera: projection.screen_from_camera(near, far),
            camera_from_screen: projection.camera_from_screen(near, far),
            ndc_from_screen,
            screen_from_ndc,
            raster_from_ndc,
            ndc_from_raster,
            raster_from_screen: raster_from_ndc * ndc_from_screen,
            screen_from_raster: screen_from_ndc * ndc_from_raster,
            motion: None,
        }
    }

    /// The same camera moving through `motion` while the shutter is open (`None`: still).
    pub fn with_motion(mut self, motion: Option<CameraMotion>) -> Self {
        self.motion = motion.map(Arc::new);
        self
    }

    /// The same camera with the aperture `aperture` (the lens's opening; no matrix depends on
    /// it).
    /// A real lens's stop takes the shape (its pupil is bounded again): an error if no light
    /// then reaches the film's centre.
    pub fn with_aperture(mut self, aperture: Aperture) -> Result<Self, RealLensError> {
        if let Lens::Real { real, .. } = &mut self.lens {
            let aspect = self.width as f32 / self.height as f32;
            *real = Arc::new(real.with_aperture(aperture.clone(), aspect)?);
        }
        self.lens.first_order_mut().aperture = aperture;
        Ok(self)
    }

    /// The same camera with another film resolution (same field of view and lens).
    pub fn with_resolution(&self, width: u32, height: u32) -> Self {
        let mut camera = Self::new(
            self.projection,
            self.frame,
            self.lens.clone(),
            self.near,
            self.far,
            width,
            height,
            self.screen_window.centre,
        );
        camera.motion = self.motion.clone();
        if let Lens::Real { real, first_order } = &mut camera.lens {
            let aspect = width as f32 / height as f32;
            if aspect != real.aspect() {
                // The film's width follows the aspect: its corners need their own bounds.
                let rebuilt = real
                    .with_aperture(first_order.aperture.clone(), aspect)
                    .unwrap_or_else(|e| unreachable!("the lens passed light already: {e}"));
                *real = Arc::new(rebuilt);
            }
        }
        camera
    }

    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// Homogeneous world -> raster (x, y in pixels, z the course's depth in [0, 1]).
    pub fn raster_from_world(&self) -> Mat4 {
        self.raster_from_screen * self.screen_from_camera * self.camera_from_world
    }

    /// The raster pass's matrix: the same chain ending in Vulkan clip space.
    pub fn clip_from_world(&self) -> Mat4 {
        raster::clip_from_ndc()
            * self.ndc_from_screen
            * self.screen_from_camera
            * self.camera_from_world
    }

    /// The raster path's matrix for one camera sample shared by every pixel (film offset
    /// `film_u` in [0, 1)^2 within the pixel, lens sample `lens_u`): rasterizing with it, the
    /// pixel centre (column + 0.5, row + 0.5) sees what [`Self::first_order_ray`] of the sample
    /// (film `(column, row) + film_u`, lens `lens_u`) hits. The first-order lens's shear
    /// ([`ThinLens::pinhole_from_camera`](super::ThinLens::pinhole_from_camera)) moves the
    /// centre of projection to the lens point with the focal plane fixed, and a raster
    /// translation by `0.5 - film_u` brings the film sample to the pixel centre, where the
    /// rasterizer samples.
    /// Depth is reversed (1 at the near plane, 0 at the far plane: compare with GREATER) so
    /// that float depth keeps its relative precision when the near plane is moved close to the
    /// lens (see [`Self::for_rasterizing_rays`]).
    pub fn clip_from_world_through_lens(&self, film_u: Vec2, lens_u: Vec2) -> Mat4 {
        let to_pixel_centre = Mat4::from_translation((Vec2::splat(0.5) - film_u).extend(0.0));
        let reversed_depth = Mat4::from_cols(
            Vec4::X,
            Vec4::Y,
            Vec4::new(0.0, 0.0, -1.0, 0.0),
            Vec4::new(0.0, 0.0, 1.0, 1.0),
        );
        let lens = self.lens.first_order();
        let pinhole_from_camera =
            lens.pinhole_from_camera(lens.lens_point(lens_u), self.lens_plane_z());
        reversed_depth
            * raster::clip_from_ndc()
            * self.ndc_from_raster
            * to_pixel_centre
            * self.raster_from_screen
            * self.screen_from_camera
            * pinhole_from_camera
            * self.camera_from_world
    }

    /// The camera whose raster passes see what its rays see: a perspective camera's clipping
    /// planes move out (near / 100, far x 100). Perspective rays start at the eye and are not
    /// clipped by them (only orthographic rays start on the near plane), so a surface nearer
    /// than `near` (the floor under the lens) is hit by rays and must be drawn too. Same
    /// screen window, same pixels; the lens is the first-order thin lens alone (unless
    /// orthographic, where the camera is returned as it is).
    pub fn for_rasterizing_rays(&self) -> Camera {
        if self.is_orthographic() {
            return self.clone();
        }
        Self::new(
            self.projection,
            self.frame,
            self.lens.first_order_only(),
            self.near * 0.01,
            self.far * 100.0,
            self.width,
            self.height,
            self.screen_window.centre,
        )
    }

    /// World point -> (raster x, raster y, depth in [0, 1]), with the perspective divide.
    pub fn project(&self, p_world: Vec3) -> Vec3 {
        let h = self.raster_from_world() * p_world.extend(1.0);
        h.xyz() / h.w
    }

    /// Distance along the view axis (camera-space z): what the `depth` AOV shows.
    pub fn view_depth(&self, p_world: Vec3) -> f32 {
        (p_world - self.frame.eye).dot(self.frame.forward)
    }

    /// The camera ray of `sample` (film point: a raster point; lens sample in [0, 1)^2) in world
    /// space, with its weight (the image averages weight x radiance): the one way to make a
    /// camera ray, whatever the lens. Each lens kind makes its ray in camera space: a pinhole
    /// its aperture-centre ray, a thin lens its lens ray (weight 1 for both), a real lens its
    /// traced ray (`None` when the lens blocks it) at `wavelength` (nm; `None`: the d line,
    /// what a lens without dispersion traces at: see [`Self::sample_wavelength`]).
    pub fn generate_ray(
        &self,
        sample: CameraSample,
        wavelength: Option<f32>,
    ) -> Option<(Ray, f32)> {
        let (ray, weight) = match &self.lens {
            Lens::Thin(thin) if thin.aperture_radius <= 0.0 => (self.pinhole_ray(sample.film), 1.0),
            Lens::Thin(thin) => (
                thin.generate_ray(&self.pinhole_ray(sample.film), sample.lens),
                1.0,
            ),
            Lens::Real { real, .. } => {
                let film = real.film_point(sample.film, self.width, self.height);
                let k = wavelength.map_or(0.0, dispersion_offset_f32);
                real.generate_ray(film, sample.lens, k)?
            }
        };
        Some((self.world_ray(&ray, &sample), weight))
    }

    /// A camera-space ray of `sample` in world space: through the frame's `world_from_camera`,
    /// or, while the camera moves, through its pose at the sample's moment
    /// ([`CameraMotion::moment`] of its time and film row).
    pub fn world_ray(&self, ray: &Ray, sample: &CameraSample) -> Ray {
        match &self.motion {
            None => ray.transformed(&self.world_from_camera),
            Some(motion) => {
                let moment = motion.moment(sample.time, sample.film.y, self.height);
                let pose = motion.pose_at(moment);
                Ray {
                    origin: pose.world_point(ray.origin),
                    direction: pose.world_vector(ray.direction),
                }
            }
        }
    }

    /// The moment in the shutter's span of `sample` (its time and film row): where what moves
    /// is when its rays meet it. The middle of the span when the shutter takes no time.
    pub fn sample_moment(&self, sample: &CameraSample) -> f32 {
        self.motion.as_ref().map_or(0.5, |motion| {
            motion.moment(sample.time, sample.film.y, self.height)
        })
    }

    /// The ray of the lens's first-order thin lens ([`Lens::first_order`]: a [`Lens::Thin`]
    /// itself, or a [`Lens::Real`]'s thin lens at its entrance pupil) for `sample`, in world
    /// space: what rasterizing passes draw, and AOVs and focus picking see. For a thin lens it
    /// is [`Self::generate_ray`]'s ray; a real lens's camera rays are traced instead.
    pub fn first_order_ray(&self, sample: CameraSample) -> Ray {
        let pinhole = self.pinhole_ray(sample.film);
        let ray = self.lens.first_order().generate_ray(&pinhole, sample.lens);
        self.world_ray(&ray, &sample)
    }

    /// The pinhole's ray, in camera space: the aperture-centre ray through raster point
    /// `p_raster` = (column + u, row + v), exactly as the slides build it:
    /// (i, j) -> (s, t) -> (x, y) on the front plane -> camera point -> ray. A thin lens's
    /// rays start from it.
    pub fn pinhole_ray(&self, p_raster: Vec2) -> Ray {
        let p_screen = self
            .screen_from_raster
            .transform_point3(p_raster.extend(0.0));
        match self.projection {
            // (c_x, c_y, c_z) = (x, y, near); start there, direction (0, 0, 1).
            Projection::Orthographic { .. } => Ray {
                origin: Vec3::new(p_screen.x, p_screen.y, self.near),
                direction: Vec3::Z,
            },
            // (c_x, c_y, c_z) = (x near, y near, near); start at the eye, direction c.
            Projection::Perspective { .. } => Ray {
                origin: Vec3::ZERO,
                direction: Vec3::new(p_screen.x * self.near, p_screen.y * self.near, self.near)
                    .normalize(),
            },
        }
    }

    /// The wavelength (nm) that sample `sample_index` of `sampler`'s pixel traces the lens at:
    /// drawn from `DIM_WAVELENGTH` when the lens is dispersive (`RealLens::dispersive`), else
    /// `None` (the d line).
    pub fn sample_wavelength(
        &self,
        sampler: &crate::sampler::PixelSampler,
        sample_index: u32,
    ) -> Option<f32> {
        use crate::sampler::{pixel_dimension, DIM_WAVELENGTH};
        self.lens.real().filter(|real| real.dispersive())?;
        let u = pixel_dimension(sampler, sample_index, DIM_WAVELENGTH);
        Some(crate::film::spectral::sample_wavelength(u))
    }

    /// The shutter time in [0, 1) of sample `sample_index` of `sampler`'s pixel: drawn from
    /// `DIM_TIME` while the camera moves, else the middle (no ray depends on it then).
    pub fn sample_time(&self, sampler: &crate::sampler::PixelSampler, sample_index: u32) -> f32 {
        use crate::sampler::{pixel_dimension, DIM_TIME};
        match self.motion {
            Some(_) => pixel_dimension(sampler, sample_index, DIM_TIME),
            None => crate::sampler::CameraSample::MIDDLE,
        }
    }

    /// The wavelength (nm) at which sample `sample_index` of `sampler`'s pixel checks the d
    /// line through a dispersive lens (film::spectral, "Dispersion at little cost"): its
    /// [`Self::sample_wavelength`] where dimension `DIM_DISPERSION_CHECK` makes it check, else
    /// `None` (the sample traces the d line only).
    pub fn checked_wavelength(
        &self,
        sampler: &crate::sampler::PixelSampler,
        sample_index: u32,
    ) -> Option<f32> {
        use crate::sampler::{pixel_dimension, DIM_DISPERSION_CHECK};
        self.lens.real().filter(|real| real.dispersive())?;
        // The check first: three samples in four draw no wavelength.
        let u = pixel_dimension(sampler, sample_index, DIM_DISPERSION_CHECK);
        if !crate::film::spectral::checks_dispersion(u) {
            return None;
        }
        self.sample_wavelength(sampler, sample_index)
    }

    /// The plane z = lens_z holds the lens: z = 0 (the eye) for perspective, the near plane for
    /// orthographic (each film point's ray starts there).
    pub fn lens_plane_z(&self) -> f32 {
        if self.is_orthographic() {
            self.near
        } else {
            0.0
        }
    }

    /// Raster pixels per screen-space unit (the screen window's height spans the image's).
    pub fn pixels_per_screen_unit(&self) -> f32 {
        self.height as f32 / (2.0 * self.screen_window.half_height)
    }

    /// Radius, in pixels, of the circle of confusion of the surface at view depth `z` seen
    /// through raster point `p_raster` (see `coc`): the image of that point spreads over the
    /// film points whose lens-ray bundles reach it. Perspective, facing plane:
    /// A |1/F - 1/z| on the screen plane z = 1; orthographic: the object-space spread itself.
    /// A is the lens's reach: for a shaped aperture, the circle that holds the shape.
    pub fn coc_radius_pixels(&self, p_raster: Vec2, z: f32) -> f32 {
        CocLens::of(self).radius_pixels(p_raster, z)
    }

    /// The camera-space point at view depth `z` on the aperture-centre ray through raster
    /// point `p_raster`.
    pub fn camera_point(&self, p_raster: Vec2, z: f32) -> Vec3 {
        let ray = self.pinhole_ray(p_raster);
        ray.at((z - ray.origin.z) / ray.direction.z)
    }
}
