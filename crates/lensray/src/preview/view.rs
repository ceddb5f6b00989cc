//! What the preview window shows: the converging thin-lens image, one of the raster G-buffer's
//! AOVs, or each pixel's circle of confusion. The shaders receive [`ViewMode::code`].

use serde::{Deserialize, Serialize};

use lensray_core::interface::{VIEW_ALBEDO, VIEW_COC, VIEW_DEPTH, VIEW_FINAL, VIEW_NORMAL};

#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum ViewMode {
    /// The thin-lens ray-traced image, accumulating towards the target spp.
    #[default]
    Final,
    /// Diffuse colour of the surface seen through each pixel centre.
    Albedo,
    /// World-space shading normal, as 0.5 n + 0.5.
    Normal,
    /// Distance along the view axis.
    Depth,
    /// Radius of each pixel's circle of confusion: where the focal plane lies.
    #[value(alias = "coc")]
    #[serde(alias = "coc")]
    CircleOfConfusion,
}

impl ViewMode {
    /// Every mode, in the order of the number keys and of [`ViewMode::next`].
    pub const ALL: [ViewMode; 5] = [
        ViewMode::Final,
        ViewMode::Albedo,
        ViewMode::Normal,
        ViewMode::Depth,
        ViewMode::CircleOfConfusion,
    ];

    /// The constant the shaders switch on (one definition in `lensray_core::interface`).
    pub fn code(self) -> u32 {
        match self {
            ViewMode::Final => VIEW_FINAL,
            ViewMode::Albedo => VIEW_ALBEDO,
            ViewMode::Normal => VIEW_NORMAL,
            ViewMode::Depth => VIEW_DEPTH,
            ViewMode::CircleOfConfusion => VIEW_COC,
        }
    }

    /// The following mode, wrapping from the last to the first.
    pub fn next(self) -> Self {
        let index = Self::ALL.iter().position(|&m| m == self).unwrap_or(0);
        Self::ALL[(index + 1) % Self::ALL.len()]
    }

    /// What a panel or the help text calls it.
    pub fn label(self) -> &'static str {
        match self {
            ViewMode::Final => "final image",
            ViewMode::Albedo => "albedo",
            ViewMode::Normal => "normal",
            ViewMode::Depth => "depth",
            ViewMode::CircleOfConfusion => "circle of confusion",
        }
    }
}

impl std::fmt::Display for ViewMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

#[cfg(test)]
mod tests {
    use clap::ValueEnum;

    use super::*;

    #[test]
    fn codes_are_the_interface_constants_in_order() {
        let codes: Vec<u32> = ViewMode::ALL.iter().map(|m| m.code()).collect();
        assert_eq!(codes, [0, 1, 2, 3, 4]);
        assert_eq!(ViewMode::CircleOfConfusion.code(), VIEW_COC);
    }

    #[test]
    fn next_cycles_through_every_mode() {
        let mut mode = ViewMode::Final;
        let mut seen = vec![mode];
        for _ in 0..4 {
            mode = mode.next();
            seen.push(mode);
        }
        assert_eq!(seen, ViewMode::ALL);
        assert_eq!(mode.next(), ViewMode::Final);
    }

    #[test]
    fn command_line_and_toml_names() {
        assert_eq!(
            ViewMode::from_str("circle-of-confusion", false),
            Ok(ViewMode::CircleOfConfusion)
        );
        assert_eq!(
            ViewMode::from_str("coc", false),
            Ok(ViewMode::CircleOfConfusion)
        );
        assert_eq!(ViewMode::from_str("depth", false), Ok(ViewMode::Depth));
        #[derive(Deserialize)]
        struct ViewHolder {
            view: ViewMode,
        }
        let parsed: ViewHolder = toml::from_str("view = \"circle-of-confusion\"").unwrap();
        assert_eq!(parsed.view, ViewMode::CircleOfConfusion);
        assert_eq!(ViewMode::Normal.to_string(), "normal");
    }
}
