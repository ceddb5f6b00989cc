//! How long a mesh file's load took, step by step (`lensray bench --scene-file` reports it).

use std::time::{Duration, Instant};

/// The wall time of a mesh file's load and of its texture steps; the rest of it is reading and
/// parsing the file, its buffers and its geometry ([`LoadTimes::parse`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadTimes {
    /// The whole load of the mesh file, its textures included.
    pub total: Duration,
    /// Decoding the texture images (PNG, JPEG) to RGBA8; reading their files is parsing.
    pub texture_decode: Duration,
    /// Building the textures' mip levels.
    pub texture_mips: Duration,
    /// Textures decoded.
    pub textures: usize,
}

impl LoadTimes {
    /// Reading and parsing the file, its buffers and its geometry: the load but its textures.
    pub fn parse(&self) -> Duration {
        self.total
            .saturating_sub(self.texture_decode + self.texture_mips)
    }

    /// Counts a texture decoded from `start` to `decoded` whose mip levels were built from
    /// `decoded` to now.
    pub(crate) fn add_texture(&mut self, start: Instant, decoded: Instant) {
        self.texture_decode += decoded - start;
        self.texture_mips += decoded.elapsed();
        self.textures += 1;
    }
}

/// Timings say how a load went, not what it loaded: any two compare equal, so that two loads of
/// one file do too.
impl PartialEq for LoadTimes {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_is_the_load_but_its_textures() {
        let ms = Duration::from_millis;
        let times = LoadTimes {
            total: ms(10),
            texture_decode: ms(3),
            texture_mips: ms(2),
            textures: 1,
        };
        assert_eq!(times.parse(), ms(5));
        assert_eq!(times, LoadTimes::default());
    }
}
