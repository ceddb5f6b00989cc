//! The command line's values of the lower crates' option enums (`--projection`, `--dispersion`,
//! `--shutter-position`, `--sampler`, `--shading`, `--tonemap`, `--present-mode`). Each enum lists its values and names them
//! itself (`ALL`, `name`: the names its scene files take too); what `--help` says of each value
//! is the command line's text, here.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};

use lensray_core::film::tonemap::ToneMap;
use lensray_core::sampler::SamplerKind;
use lensray_core::settings::{ProjectionKind, Shading, ShutterPosition, Switch};
use lensray_vulkan::PresentMode;

/// An option enum the command line takes by name.
pub trait NamedOption: Copy + Send + Sync + 'static {
    /// Every value, in the order `--help` lists them: the enum's own `ALL`.
    const ALL: &'static [Self];

    /// The value's name on the command line: the enum's own `name`.
    fn name(self) -> &'static str;

    /// The value's line in `--help` (none: the values are listed by name only).
    fn help(self) -> Option<&'static str> {
        None
    }
}

/// The `value_parser` of a [`NamedOption`]: exact names, listed (with their help) in `--help`
/// and in the error that a wrong name gets.
pub fn by_name<T: NamedOption>() -> impl TypedValueParser<Value = T> {
    let values = T::ALL.iter().map(|&value| {
        let possible = PossibleValue::new(value.name());
        match value.help() {
            Some(help) => possible.help(help),
            None => possible,
        }
    });
    PossibleValuesParser::new(values).map(|name: String| {
        T::ALL
            .iter()
            .copied()
            .find(|value| value.name() == name)
            .expect("the parser accepts only the listed names")
    })
}

impl NamedOption for ProjectionKind {
    const ALL: &'static [Self] = &ProjectionKind::ALL;

    fn name(self) -> &'static str {
        ProjectionKind::name(self)
    }
}

impl NamedOption for ToneMap {
    const ALL: &'static [Self] = &ToneMap::ALL;

    fn name(self) -> &'static str {
        ToneMap::name(self)
    }

    fn help(self) -> Option<&'static str> {
        Some(match self {
            ToneMap::None => {
                "the values as they are, clamped at 1 (lensray's PNGs before tone maps)"
            }
            ToneMap::Neutral => {
                "Khronos PBR Neutral: colours kept, highlights compressed (default)"
            }
            ToneMap::Agx => "AgX (as three.js, after Blender): highlights roll off to white",
        })
    }
}

impl NamedOption for Switch {
    const ALL: &'static [Self] = &Switch::ALL;

    fn name(self) -> &'static str {
        Switch::name(self)
    }
}

impl NamedOption for ShutterPosition {
    const ALL: &'static [Self] = &ShutterPosition::ALL;

    fn name(self) -> &'static str {
        ShutterPosition::name(self)
    }
}

impl NamedOption for SamplerKind {
    const ALL: &'static [Self] = &SamplerKind::ALL;

    fn name(self) -> &'static str {
        SamplerKind::name(self)
    }

    fn help(self) -> Option<&'static str> {
        Some(match self {
            SamplerKind::Sobol => {
                "Owen-scrambled Sobol' points: film and lens each stratified, error falling \
                 about as N^-0.75 (at powers of two) instead of N^-0.5"
            }
            SamplerKind::Independent => {
                "Independent random numbers per dimension (white noise), for comparisons"
            }
        })
    }
}

impl NamedOption for Shading {
    const ALL: &'static [Self] = &Shading::ALL;

    fn name(self) -> &'static str {
        Shading::name(self)
    }

    fn help(self) -> Option<&'static str> {
        Some(match self {
            Shading::Unlit => {
                "Base colour of the first surface hit, or the background on a miss: pure \
                 visibility, the mode that validates depth of field"
            }
            Shading::Lit => {
                "Emission + f * E cos(theta) summed over the scene's lights (point, spot, \
                 directional; `scene::light`), each with a hard shadow, plus the environment (a \
                 uniform sky or a map) by multiple importance sampling of the environment and \
                 the BRDF; f is glTF's metallic-roughness BRDF (Lambert for materials without a \
                 specular lobe); --bounces N > 1 adds interreflection"
            }
            Shading::Depth => {
                "Distance of the first hit along the view axis (camera z); 0 on a miss"
            }
            Shading::Normal => {
                "World-space shading normal of the first hit, facing the viewer; 0 on a miss"
            }
            Shading::Albedo => {
                "Base colour of the first hit (the G-buffer's material colour); the background \
                 on a miss"
            }
        })
    }
}

impl NamedOption for PresentMode {
    const ALL: &'static [Self] = &PresentMode::ALL;

    fn name(self) -> &'static str {
        PresentMode::name(self)
    }

    fn help(self) -> Option<&'static str> {
        Some(match self {
            PresentMode::Fifo => "Wait for vertical blank, never tear (always available)",
            PresentMode::Mailbox => {
                "Replace the queued image with the newest: no tearing, no waiting"
            }
            PresentMode::Immediate => "Present at once; may tear",
        })
    }
}

#[cfg(test)]
mod tests {
    use clap::builder::TypedValueParser;

    use super::*;

    fn names<T: NamedOption>() -> Vec<&'static str> {
        T::ALL.iter().map(|v| v.name()).collect()
    }

    #[test]
    fn every_value_parses_by_its_own_name() {
        fn check<T: NamedOption + PartialEq + std::fmt::Debug>() {
            let command = clap::Command::new("lensray");
            for &value in T::ALL {
                let parsed = by_name::<T>()
                    .parse_ref(&command, None, value.name().as_ref())
                    .expect("a listed name");
                assert_eq!(parsed, value);
            }
            assert!(by_name::<T>()
                .parse_ref(&command, None, "no-such-value".as_ref())
                .is_err());
        }
        check::<ProjectionKind>();
        check::<Switch>();
        check::<ShutterPosition>();
        check::<SamplerKind>();
        check::<Shading>();
        check::<PresentMode>();
        assert_eq!(
            names::<Shading>(),
            ["unlit", "lit", "depth", "normal", "albedo"]
        );
        assert_eq!(names::<PresentMode>(), ["fifo", "mailbox", "immediate"]);
    }
}
