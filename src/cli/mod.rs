//! The command line: one module per subcommand.

pub mod args;
pub mod bench;
pub mod render;
