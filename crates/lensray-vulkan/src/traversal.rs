//! Which closest-hit implementation the trace pass uses.

use std::fmt;
use std::str::FromStr;

/// How the trace pass finds the closest hit of a ray: both shade alike (shaders/include/shading.glsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Traversal {
    /// VK_KHR_ray_query against the driver's acceleration structures (BLAS per mesh + TLAS).
    RayQuery,
    /// VK_KHR_ray_tracing_pipeline against the same structures: the pass's shader as the ray
    /// generation stage of a ray-tracing pipeline, traceRayEXT for its closest hits and shadow
    /// rays (for devices with the pipeline but not ray queries).
    RtPipeline,
    /// A stack-based traversal in the shader of the project's own BVH (lensray-vulkan/src/scene/bvh.rs): needs
    /// no ray-tracing support.
    Software,
}

impl Traversal {
    pub const ALL: [Traversal; 3] = [
        Traversal::RayQuery,
        Traversal::RtPipeline,
        Traversal::Software,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Traversal::RayQuery => "rayquery",
            Traversal::RtPipeline => "rtpipeline",
            Traversal::Software => "software",
        }
    }
}

impl fmt::Display for Traversal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Traversal {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Traversal::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| {
                format!("unknown traversal '{s}' (expected rayquery, rtpipeline or software)")
            })
    }
}
