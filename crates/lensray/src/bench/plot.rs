//! The bench's plot (plotters, drawn in memory, encoded as PNG by `image`): error (RMSE)
//! against time, one curve per path over the spp sweep, or for the other sweeps time against
//! the swept quantity, each path's tracing (filled circles) under its whole render call (open
//! circles, a thin line): the gap is the time beyond tracing. Both axes are logarithmic. Text uses a font compiled into the program
//! (egui's), so the plot needs no font installed on the machine.

use std::sync::OnceLock;

use anyhow::{anyhow, Result};
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::options::SweepKind;
use super::report::BenchReport;
use crate::paths::PathKind;

const SIZE: (u32, u32) = (1024, 720);
const FONT: &str = "sans-serif";

/// One curve: a path's points (x, y, label), and for a sweep of time against a quantity the
/// same points' whole render call (x, wall-clock seconds).
struct Curve {
    path: PathKind,
    points: Vec<(f64, f64, String)>,
    wall: Vec<(f64, f64)>,
}

/// The plot of `report` as PNG bytes.
pub fn png(report: &BenchReport) -> Result<Vec<u8>> {
    register_embedded_font()?;
    let (width, height) = SIZE;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    draw(report, &mut rgb).map_err(|e| anyhow!("drawing the plot: {e}"))?;
    let mut bytes = Vec::new();
    PngEncoder::new(&mut bytes).write_image(&rgb, width, height, ExtendedColorType::Rgb8)?;
    Ok(bytes)
}

fn register_embedded_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT).is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| anyhow!("the plot's font does not load"))
}

fn curves(report: &BenchReport) -> Vec<Curve> {
    report
        .paths
        .iter()
        .map(|info| Curve {
            path: info.path,
            wall: match report.sweep {
                None | Some(SweepKind::Spp) => Vec::new(),
                Some(_) => report
                    .points
                    .iter()
                    .flat_map(|point| {
                        point
                            .results
                            .iter()
                            .filter(|m| m.path == info.path)
                            .map(|m| (point.swept(report.sweep), m.wall_seconds.median))
                    })
                    .collect(),
            },
            points: report
                .points
                .iter()
                .flat_map(|point| {
                    point
                        .results
                        .iter()
                        .filter(|m| m.path == info.path)
                        .map(move |m| {
                            let time = m.trace_seconds.median;
                            match report.sweep {
                                None | Some(SweepKind::Spp) => {
                                    (time, m.rmse, format!("{} spp", point.spp))
                                }
                                Some(_) => (point.swept(report.sweep), time, String::new()),
                            }
                        })
                })
                .collect(),
        })
        .collect()
}

/// `lo..hi` of `values` widened to whole decades (plotters labels a logarithmic axis at the
/// powers of ten it contains, so a range inside one decade would get no numbers).
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi == 0.0 {
        return 0.1..10.0;
    }
    let decade = |v: f64, round: fn(f64) -> f64| 10f64.powf(round(v.log10()));
    // A hair below the power of ten, which plotters would otherwise round past.
    0.999 * decade(lo / 1.2, f64::floor)..decade(hi * 1.2, f64::ceil)
}

/// Asks plotters for a mark at each of 1..9 in every decade of `range` (fewer and it marks
/// the powers of ten alone); [`tick`] then numbers only some of them.
fn label_count(range: &std::ops::Range<f64>) -> usize {
    let decades = (range.end / range.start).log10().round().max(1.0) as usize;
    10 * decades + 1
}

fn colour(path: PathKind) -> RGBColor {
    match path {
        PathKind::RayQuery => RGBColor(200, 40, 40),
        PathKind::RtPipeline => RGBColor(120, 20, 20),
        PathKind::Software => RGBColor(30, 90, 200),
        PathKind::Hybrid => RGBColor(150, 60, 180),
        PathKind::Raster => RGBColor(230, 140, 20),
        PathKind::Cpu => RGBColor(20, 140, 60),
    }
}

/// Axis numbers at 1, 2 and 5 times a power of ten (none elsewhere, or they crowd): 10k, 1M
/// for counts; a few digits or scientific for small values.
fn tick(v: f64) -> String {
    let mantissa = v / 10f64.powf(v.log10().floor());
    if ![1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|m| (mantissa - m).abs() < 1e-6)
    {
        return String::new();
    }
    match v.abs() {
        a if a >= 1e6 => format!("{}M", trim(v / 1e6)),
        a if a >= 1e4 => format!("{}k", trim(v / 1e3)),
        a if a >= 0.01 => trim(v),
        _ => format!("{v:.0e}"),
    }
}

fn trim(v: f64) -> String {
    let text = format!("{v:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn draw(report: &BenchReport, rgb: &mut [u8]) -> Result<(), Box<dyn std::error::Error>> {
    let curves = curves(report);
    let all = || curves.iter().flat_map(|c| c.points.iter());
    let x_range = log_range(all().map(|p| p.0));
    let walls = curves.iter().flat_map(|c| c.wall.iter().map(|p| p.1));
    let y_range = log_range(all().map(|p| p.1).chain(walls));
    let s = &report.settings;
    let (title, x_desc, y_desc) = match report.sweep {
        None | Some(SweepKind::Spp) => (
            format!(
                "Error against time: {}, {}x{}, {:?}",
                report.scene.name, s.width, s.height, s.shading
            ),
            "time, seconds (median; GPU timestamps for GPU paths)",
            "RMSE against the converged reference",
        ),
        Some(SweepKind::Resolution) => (
            format!(
                "Time against image size: {}, {} spp",
                report.scene.name, s.spp
            ),
            "pixels",
            "time, seconds (median; filled: tracing, open: the whole render call)",
        ),
        Some(SweepKind::Triangles) => (
            format!(
                "Time against triangles: {}x{}, {} spp",
                s.width, s.height, s.spp
            ),
            "triangles",
            "time, seconds (median; filled: tracing, open: the whole render call)",
        ),
        Some(SweepKind::Aperture) => (
            format!(
                "Time against aperture shape: {}x{}, {} spp",
                s.width, s.height, s.spp
            ),
            "shape: 1 round, 2 hexagon, 3 curved9, 4 squeezed, 5 image",
            "time, seconds (median; filled: tracing, open: the whole render call)",
        ),
        Some(SweepKind::Lens) => (
            format!("Time against lens: {}x{}, {} spp", s.width, s.height, s.spp),
            "lens: 1 biconvex-50, 2 double-gauss-50, 3 wide-22, 4 cooke-triplet-50 (+0.5: real)",
            "time, seconds (median; filled: tracing, open: the whole render call)",
        ),
        Some(SweepKind::Movements) => (
            format!(
                "Time against shift and tilt: {}x{}, {} spp",
                s.width, s.height, s.spp
            ),
            "shot: 1 plain, 2 shift, 3 tilt, 4 moved (shifted and tilted)",
            "time, seconds (median; filled: tracing, open: the whole render call)",
        ),
    };

    let root = BitMapBackend::with_buffer(rgb, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 24))
        .margin(20)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d(x_range.clone().log_scale(), y_range.clone().log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style((FONT, 15))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(WHITE)
        .axis_desc_style((FONT, 17))
        .x_labels(label_count(&x_range))
        .y_labels(label_count(&y_range))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
    for curve in &curves {
        let style = colour(curve.path).stroke_width(2);
        let xy = || curve.points.iter().map(|p| (p.0, p.1));
        chart
            .draw_series(LineSeries::new(xy(), style))?
            .label(curve.path.name())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
        chart.draw_series(xy().map(|p| Circle::new(p, 4, colour(curve.path).filled())))?;
        chart.draw_series(curve.points.iter().map(|p| {
            EmptyElement::at((p.0, p.1)) + Text::new(p.2.clone(), (6, -16), (FONT, 13))
        }))?;
        if !curve.wall.is_empty() {
            let thin = colour(curve.path).stroke_width(1);
            chart.draw_series(LineSeries::new(curve.wall.iter().copied(), thin))?;
            chart.draw_series(curve.wall.iter().map(|&p| Circle::new(p, 5, thin)))?;
        }
    }
    chart
        .configure_series_labels()
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
