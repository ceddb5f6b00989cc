//! The camera test suite: the course's matrices, the projection conventions of `camera/mod.rs`,
//! ray generation, thin-lens depth of field, the concentric disk map, physical units and
//! parameter validation. Every check compares real numbers against an independent formula and
//! reports what differed and by how much.
//!
//! Run with `cargo test --test camera`.

#[path = "camera/common.rs"]
mod common;

#[path = "camera/disk.rs"]
mod disk;
#[path = "camera/matrices.rs"]
mod matrices;
#[path = "camera/physical.rs"]
mod physical;
#[path = "camera/rays.rs"]
mod rays;
#[path = "camera/round_trip.rs"]
mod round_trip;
#[path = "camera/thin_lens.rs"]
mod thin_lens;
#[path = "camera/validation.rs"]
mod validation;
