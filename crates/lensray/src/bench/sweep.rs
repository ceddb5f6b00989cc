//! The points a bench measures: one point without a sweep, else the swept values in increasing
//! order (so that peaks of memory reported at a point cover that point and the smaller ones).

use anyhow::{bail, ensure, Context, Result};

use std::sync::Arc;

use super::movements::BenchMovement;
use super::options::SweepKind;
use lensray_core::camera::aperture::ApertureImage;
use lensray_core::camera::ApertureShape;

/// One measured configuration's swept value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum SweepValue {
    Spp(u32),
    Resolution {
        width: u32,
        height: u32,
    },
    /// At least this many triangles (the generated scene may have a few more).
    Triangles(usize),
    Aperture(BenchAperture),
    Lens(BenchLens),
    Movements(BenchMovement),
}

/// The lens sweep's points: a built-in lens, traced surface by surface (`real`), or its
/// first-order model (the thin lens at its entrance pupil, of the pupil's radius, focused
/// where the real lens is: same framing, f-number and focus), which each real lens is
/// weighed against. Ordered lens by lens, the thin model first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct BenchLens {
    /// Index into `optics::builtin::LENSES`.
    pub lens: usize,
    pub real: bool,
}

impl BenchLens {
    /// The built-in lens's name.
    pub fn name(self) -> &'static str {
        lensray_core::optics::builtin::LENSES[self.lens].0
    }

    /// "double-gauss-50", or "thin:double-gauss-50" for its first-order model.
    pub fn label(self) -> String {
        if self.real {
            self.name().to_string()
        } else {
            format!("thin:{}", self.name())
        }
    }

    /// The other point of the pair (the thin model of a real lens and back).
    pub fn partner(self) -> BenchLens {
        BenchLens {
            real: !self.real,
            ..self
        }
    }
}

/// The aperture sweep's shapes (the round one first: the others are weighed against it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BenchAperture {
    Round,
    /// 6 straight blades turned by 15 degrees: the fan's cheapest case.
    Hexagon,
    /// 9 blades of roundness 0.5: the largest fan (63 triangles).
    Curved9,
    /// Round, squeezed 2x (anamorphic).
    Squeezed,
    /// A 64 x 64 soap-bubble image (brighter at the rim): the tables' searches.
    Image,
}

impl BenchAperture {
    pub const ALL: [BenchAperture; 5] = [
        BenchAperture::Round,
        BenchAperture::Hexagon,
        BenchAperture::Curved9,
        BenchAperture::Squeezed,
        BenchAperture::Image,
    ];

    pub fn name(self) -> &'static str {
        match self {
            BenchAperture::Round => "round",
            BenchAperture::Hexagon => "hexagon",
            BenchAperture::Curved9 => "curved9",
            BenchAperture::Squeezed => "squeezed",
            BenchAperture::Image => "image",
        }
    }

    /// The shape (its aperture radius is the shot's).
    pub fn shape(self) -> ApertureShape {
        let round = ApertureShape::ROUND;
        match self {
            BenchAperture::Round => round,
            BenchAperture::Hexagon => ApertureShape {
                blades: Some(6),
                rotation_degrees: 15.0,
                ..round
            },
            BenchAperture::Curved9 => ApertureShape {
                blades: Some(9),
                roundness: 0.5,
                ..round
            },
            BenchAperture::Squeezed => ApertureShape {
                aspect: 2.0,
                ..round
            },
            BenchAperture::Image => ApertureShape {
                image: Some(Arc::new(soap_bubble(64))),
                ..round
            },
        }
    }
}

/// A disk of transmission 0.3 at the centre rising to 1 at the rim, `side` cells a side.
fn soap_bubble(side: u32) -> ApertureImage {
    let values: Vec<f32> = (0..side * side)
        .map(|i| {
            let cell = |k: u32| (k as f32 + 0.5) / side as f32 * 2.0 - 1.0;
            let r = cell(i % side).hypot(cell(i / side));
            if r <= 1.0 {
                0.3 + 0.7 * r * r
            } else {
                0.0
            }
        })
        .collect();
    ApertureImage::new(side, side, &values).expect("a disk passes light")
}

/// Image sizes of the resolution sweep (4:3, each 4x the pixels of the last).
pub const RESOLUTIONS: [(u32, u32); 4] = [(160, 120), (320, 240), (640, 480), (1280, 960)];
/// Triangle counts of the triangle sweep: about half a decade apart from 10k to 1M.
pub const TRIANGLES: [usize; 5] = [10_000, 30_000, 100_000, 300_000, 1_000_000];

/// The values to measure: `list` (the `--sweep-points` text) or the sweep's defaults; without
/// a sweep the one point at `spp`.
pub fn values(kind: Option<SweepKind>, list: Option<&str>, spp: u32) -> Result<Vec<SweepValue>> {
    let mut values = match (kind, list) {
        (None, Some(_)) => {
            bail!("--sweep-points needs --sweep spp|resolution|triangles|aperture|lens|movements")
        }
        (None, None) => vec![SweepValue::Spp(spp)],
        (Some(kind), Some(list)) => parse_list(kind, list)?,
        (Some(SweepKind::Spp), None) => spp_ladder(spp).into_iter().map(SweepValue::Spp).collect(),
        (Some(SweepKind::Resolution), None) => RESOLUTIONS
            .iter()
            .map(|&(width, height)| SweepValue::Resolution { width, height })
            .collect(),
        (Some(SweepKind::Triangles), None) => TRIANGLES
            .iter()
            .copied()
            .map(SweepValue::Triangles)
            .collect(),
        (Some(SweepKind::Aperture), None) => BenchAperture::ALL
            .iter()
            .copied()
            .map(SweepValue::Aperture)
            .collect(),
        (Some(SweepKind::Lens), None) => (0..lensray_core::optics::builtin::LENSES.len())
            .map(|lens| SweepValue::Lens(BenchLens { lens, real: true }))
            .collect(),
        (Some(SweepKind::Movements), None) => BenchMovement::DEFAULT
            .iter()
            .copied()
            .map(SweepValue::Movements)
            .collect(),
    };
    if kind == Some(SweepKind::Lens) {
        // Every real lens is weighed against its own first-order thin lens.
        let thin: Vec<SweepValue> = values
            .iter()
            .filter_map(|v| match v {
                SweepValue::Lens(l) => Some(SweepValue::Lens(l.partner())),
                _ => None,
            })
            .collect();
        values.extend(thin);
    }
    if kind == Some(SweepKind::Aperture) && values[0] != SweepValue::Aperture(BenchAperture::Round)
    {
        // Every shape is weighed against the round one.
        values.push(SweepValue::Aperture(BenchAperture::Round));
    }
    if kind == Some(SweepKind::Movements) {
        // Every moved point is weighed against the plain one.
        values.push(SweepValue::Movements(BenchMovement::Plain));
    }
    values.sort();
    values.dedup();
    Ok(values)
}

/// 1, 2, 4, ... below `spp`, then `spp` itself.
pub fn spp_ladder(spp: u32) -> Vec<u32> {
    let mut ladder: Vec<u32> = (0..32)
        .map(|k| 1u32 << k)
        .take_while(|&s| s < spp)
        .collect();
    ladder.push(spp);
    ladder
}

fn parse_list(kind: SweepKind, list: &str) -> Result<Vec<SweepValue>> {
    let mut items: Vec<&str> = list
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    ensure!(!items.is_empty(), "--sweep-points: no values in '{list}'");
    if kind == SweepKind::Lens {
        // "thin" names the first-order models, which are always measured.
        items.retain(|item| *item != "thin");
        ensure!(
            !items.is_empty(),
            "--sweep-points {list}: name a lens too ({}): 'thin' is each lens's first-order model",
            lensray_core::optics::builtin::names().join(", ")
        );
    }
    items
        .iter()
        .map(|item| parse_value(kind, item).with_context(|| format!("--sweep-points {list}")))
        .collect()
}

fn parse_value(kind: SweepKind, item: &str) -> Result<SweepValue> {
    Ok(match kind {
        SweepKind::Spp => SweepValue::Spp(positive(item, "a sample count")?),
        SweepKind::Resolution => {
            let (w, h) = item
                .split_once(['x', 'X'])
                .with_context(|| format!("'{item}' is not an image size like 320x240"))?;
            SweepValue::Resolution {
                width: positive(w, "an image width")?,
                height: positive(h, "an image height")?,
            }
        }
        SweepKind::Triangles => {
            // "10k" and "1M" read as they are meant.
            let (digits, scale) = match item.chars().last() {
                Some('k' | 'K') => (&item[..item.len() - 1], 1_000),
                Some('m' | 'M') => (&item[..item.len() - 1], 1_000_000),
                _ => (item, 1),
            };
            let count: u32 = positive(digits, "a triangle count")?;
            SweepValue::Triangles(count as usize * scale)
        }
        SweepKind::Aperture => SweepValue::Aperture(
            BenchAperture::ALL
                .into_iter()
                .find(|a| a.name() == item)
                .with_context(|| {
                    format!("'{item}' is not round, hexagon, curved9, squeezed or image")
                })?,
        ),
        SweepKind::Lens => SweepValue::Lens(BenchLens {
            lens: lensray_core::optics::builtin::LENSES
                .iter()
                .position(|(name, _)| *name == item)
                .with_context(|| {
                    format!(
                        "'{item}' is not thin or a built-in lens ({})",
                        lensray_core::optics::builtin::names().join(", ")
                    )
                })?,
            real: true,
        }),
        SweepKind::Movements => SweepValue::Movements(
            BenchMovement::ALL
                .into_iter()
                .find(|m| m.name() == item)
                .with_context(|| format!("'{item}' is not plain, shift, tilt or moved"))?,
        ),
    })
}

fn positive(text: &str, what: &str) -> Result<u32> {
    match text.trim().parse::<u32>() {
        Ok(v) if v > 0 => Ok(v),
        _ => bail!("'{text}' is not {what} (a whole number >= 1)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_lists() {
        assert_eq!(spp_ladder(16), [1, 2, 4, 8, 16]);
        assert_eq!(spp_ladder(12), [1, 2, 4, 8, 12]);
        assert_eq!(spp_ladder(1), [1]);
        assert_eq!(values(None, None, 16).unwrap(), [SweepValue::Spp(16)]);
        assert_eq!(
            values(Some(SweepKind::Triangles), Some("1M, 10k"), 4).unwrap(),
            [
                SweepValue::Triangles(10_000),
                SweepValue::Triangles(1_000_000)
            ]
        );
        assert_eq!(
            values(Some(SweepKind::Resolution), Some("64x48,32x24"), 4).unwrap(),
            [
                SweepValue::Resolution {
                    width: 32,
                    height: 24
                },
                SweepValue::Resolution {
                    width: 64,
                    height: 48
                }
            ]
        );
        assert!(values(Some(SweepKind::Spp), Some("0"), 4).is_err());
        assert!(values(Some(SweepKind::Resolution), Some("64"), 4).is_err());
        assert!(values(None, Some("1,2"), 4).is_err());
        // The aperture sweep always measures the round shape, first.
        assert_eq!(
            values(Some(SweepKind::Aperture), Some("image,hexagon"), 4).unwrap(),
            [
                SweepValue::Aperture(BenchAperture::Round),
                SweepValue::Aperture(BenchAperture::Hexagon),
                SweepValue::Aperture(BenchAperture::Image)
            ]
        );
        assert!(values(Some(SweepKind::Aperture), Some("star"), 4).is_err());
        // Each real lens comes with its thin model, just before it.
        let lens = |name: &str, real| {
            let lens = lensray_core::optics::builtin::names()
                .iter()
                .position(|n| *n == name)
                .unwrap();
            SweepValue::Lens(BenchLens { lens, real })
        };
        assert_eq!(
            values(Some(SweepKind::Lens), Some("thin,double-gauss-50"), 4).unwrap(),
            [
                lens("double-gauss-50", false),
                lens("double-gauss-50", true)
            ]
        );
        let all = values(Some(SweepKind::Lens), None, 4).unwrap();
        assert_eq!(all.len(), 2 * lensray_core::optics::builtin::LENSES.len());
        assert_eq!(all[0], lens("biconvex-50", false));
        assert_eq!(all[1], lens("biconvex-50", true));
        assert!(values(Some(SweepKind::Lens), Some("thin"), 4).is_err());
        assert!(values(Some(SweepKind::Lens), Some("fisheye"), 4).is_err());
        // The movements sweep: plain and moved by default; plain always, first.
        let movements = |ms: &[BenchMovement]| -> Vec<SweepValue> {
            ms.iter().copied().map(SweepValue::Movements).collect()
        };
        assert_eq!(
            values(Some(SweepKind::Movements), None, 4).unwrap(),
            movements(&[BenchMovement::Plain, BenchMovement::Moved])
        );
        assert_eq!(
            values(Some(SweepKind::Movements), Some("moved, tilt,shift"), 4).unwrap(),
            movements(&BenchMovement::ALL)
        );
        assert_eq!(
            values(Some(SweepKind::Movements), Some("plain,moved"), 4).unwrap(),
            movements(&[BenchMovement::Plain, BenchMovement::Moved])
        );
        assert!(values(Some(SweepKind::Movements), Some("swing"), 4).is_err());
    }
}
