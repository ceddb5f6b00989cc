//! The camera: the course's coordinate spaces, projections, ray generation and thin lens.
//!
//! This module is the single source of truth for the camera. `shaders/include/camera.glsl` mirrors it
//! function by function, and the raster pass uses the very matrices built here.
//!
//! # Spaces and conventions (slide "Coordinate Spaces")
//! - **Object** space: where a mesh is modelled. Scenes place meshes with `world_from_object`
//!   (identity for OBJ files: their coordinates are world coordinates).
//! - **World** space: right-handed, any orientation; the user gives `eye`, `target`, `up`.
//! - **Camera** space: eye at the origin looking along **+z** (the course's convention),
//!   **+x to the right** and **+y up** in the image. This is a left-handed frame (as in pbrt), so
//!   `camera_from_world` contains the mirror that turns the right-handed world into it:
//!   with `forward = normalize(target - eye)`, `right = normalize(cross(forward, up))`,
//!   `true_up = cross(right, forward)`, a point `p` has camera coordinates
//!   `(dot(p - eye, right), dot(p - eye, true_up), dot(p - eye, forward))`.
//! - **Screen** space: the image of camera space under the course's projection matrix `P`
//!   (`screen_from_camera`): x and y on the plane z = 1 (perspective: divided by z; orthographic:
//!   unchanged) and depth in **[0, 1]** between the near and far planes. The visible part is the
//!   *screen window* `[-aspect * s, aspect * s] x [-s, s]` with `s = tan(vfov / 2)` (perspective)
//!   or `s = ortho_height / 2` (orthographic), `aspect = width / height`.
//! - **NDC**: the screen window mapped to `[0, 1]^2` with (0, 0) at the **top-left** (y flipped),
//!   depth unchanged in [0, 1] (`ndc_from_screen`).
//! - **Raster**: NDC scaled to pixels (`raster_from_ndc`): x = column in `[0, width]`, y = row in
//!   `[0, height]`, row 0 at the top. Pixel (row i, column j) covers `[j, j+1) x [i, i+1)` and its
//!   centre is `(j + 0.5, i + 0.5)`. The course's "pixel (i, j)" with `s = i / width` names the
//!   column first: its `(i, j)` is our raster `(x, y)`.
//! - Vulkan clip space (`clip_from_ndc`, used only by the raster pass): x and y in [-1, 1] with
//!   y pointing down, like our NDC, and depth in [0, 1] like the course's matrices.
//!
//! # Files, in the order of the slides
//! - [`look_at`]: world -> camera.
//! - [`projection`]: the orthographic and perspective camera -> screen matrices ("Linear Models").
//! - [`raster`]: screen -> NDC -> raster.
//! - [`projective`]: the chain built once, and ray generation through pixel (i, j).
//! - [`thin_lens`]: depth of field ("Non-Linear Models": aperture-centre ray, focal plane, lens rays).
//! - [`movements`]: shift and tilt (a view camera's movements): the screen window moved off the
//!   axis, the plane of focus turned (Scheimpflug), and the plane through three points.
//! - [`coc`]: the circle of confusion of a point, facing or tilted plane of focus.
//! - [`aperture`]: the shape of the lens opening (round, bladed, curved, squeezed) and the
//!   uniform map of the sampler's lens dimensions onto it.
//! - [`physical`]: the thin-lens equation 1/s_o + 1/s_i = 1/f ("Paraxial Approximation").
//! - [`lens`]: what the camera's lens is ([`Lens`]): a thin lens (a pinhole when closed), or a
//!   real lens traced surface by surface with its first-order thin lens.
//! - [`real_lens`]: past the course's thin lens, rays refracted through a real lens's
//!   surfaces (`optics`), focused by moving the lens, sampled toward the exit pupil.
//! - [`flare`]: the real lens's own light: ghosts reflected between its surfaces, and the
//!   aperture's starburst.
//! - [`motion`]: the camera moving while the shutter is open (motion blur, rolling shutter).
//! - [`params`]: what a user gives, validated.

pub mod aperture;
pub mod coc;
pub mod flare;
pub mod footprint;
pub mod lens;
pub mod look_at;
pub mod motion;
pub mod movements;
pub mod params;
pub mod physical;
pub mod projection;
pub mod projective;
pub mod raster;
pub mod ray;
pub mod real_lens;
pub mod thin_lens;

pub use aperture::{Aperture, ApertureShape};
pub use coc::CocLens;
pub use footprint::Footprint;
pub use lens::Lens;
pub use look_at::CameraFrame;
pub use motion::{CameraMotion, RigidPose};
pub use movements::{FocusPlane, Movements};
pub use params::{CameraError, CameraParams, LensParams, ProjectionParams};
pub use projection::Projection;
pub use projective::Camera;
pub use ray::Ray;
pub use real_lens::{RealLens, RealLensError, RealLensParams};
pub use thin_lens::ThinLens;
