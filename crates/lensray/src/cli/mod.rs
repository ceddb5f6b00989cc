//! The command line: one module per subcommand.

pub mod args;
pub mod bench;
pub mod calibrate;
pub mod camera_animation;
pub mod frames;
pub mod generate;
pub mod info;
pub mod lens;
pub mod named;
pub mod posed;
pub mod preview;
pub mod progress;
pub mod render;
pub mod sequence;
pub mod video;
