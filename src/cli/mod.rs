//! Command-line subcommands, each a clap `Args` struct with a `run` function.

pub mod generate;
