//! TEMPORARY: stands in for the software-traversal branch's API until it is merged.

use super::{GpuError, GpuOptions, GpuRenderer};

pub fn with_traversal(options: GpuOptions, _traversal: Option<Traversal>) -> GpuOptions {
    options
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Traversal {
    RayQuery,
    Software,
}

impl GpuRenderer {
    pub fn traversals(&self) -> Vec<Traversal> {
        vec![Traversal::RayQuery]
    }

    pub fn traversal(&self) -> Traversal {
        Traversal::RayQuery
    }

    pub fn set_traversal(&mut self, traversal: Traversal) -> Result<(), GpuError> {
        match traversal {
            Traversal::RayQuery => Ok(()),
            Traversal::Software => Err(GpuError::Invalid("no software traversal yet".into())),
        }
    }
}

pub fn with_hidden_ray_query(options: GpuOptions, _hide: bool) -> GpuOptions {
    options
}
