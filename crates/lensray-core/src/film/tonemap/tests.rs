//! Exposure against its formulas and sunny 16; each tone map against values of its published
//! reference code; what each promises (order kept, no clipping where it says so).

use glam::Vec3;

use super::*;
use crate::film::colour::{linear_to_srgb, to_display_bytes, to_display_bytes_with};
use crate::film::Image;
use crate::settings::Shading;

#[test]
fn ev100_and_exposure_follow_the_formulas() {
    // EV100 = log2(N^2 / t * 100 / S).
    assert_eq!(ev100(1.0, 1.0, 100.0), 0.0);
    assert!(
        (ev100(2.0, 1.0, 100.0) - 2.0).abs() < 1e-12,
        "f/2: two stops"
    );
    assert!(
        (ev100(1.0, 0.5, 100.0) - 1.0).abs() < 1e-12,
        "half the time: one stop"
    );
    assert!(
        (ev100(1.0, 1.0, 200.0) + 1.0).abs() < 1e-12,
        "twice the ISO: one stop less"
    );
    let (n, t, s): (f64, f64, f64) = (2.8, 1.0 / 60.0, 400.0);
    let expected = (n * n / t * 100.0 / s).log2();
    assert!((ev100(n, t, s) - expected).abs() < 1e-12);
    // exposure = 1 / (1.2 * 2^EV100).
    assert!((exposure_of_ev100(0.0) - 1.0 / 1.2).abs() < 1e-15);
    assert!((exposure_of_ev100(10.0) - 1.0 / (1.2 * 1024.0)).abs() < 1e-15);
    // The plain offset alone, and on top of the physical exposure.
    assert_eq!(
        exposure_scale(0.0, None),
        1.0,
        "no option: the values as rendered"
    );
    assert_eq!(exposure_scale(1.0, None), 2.0);
    assert_eq!(exposure_scale(-2.0, None), 0.25);
    let sunny = Some((16.0, 1.0 / 125.0, 100.0));
    let camera = exposure_scale(0.0, sunny);
    assert!((exposure_scale(1.0, sunny) / camera - 2.0).abs() < 1e-12);
}

/// Sunny 16 (ISO 100, 1/125 s, f/16): EV100 = log2(16^2 * 125) = log2(32000) = 14.966, and a
/// white diffuse surface under the sun's 100,000 lux (luminance 100,000 / pi cd/m^2) comes out
/// at 0.83: just below the sensor's saturation, as the rule intends.
#[test]
fn sunny_16_is_a_sensible_exposure() {
    let ev = ev100(16.0, 1.0 / 125.0, 100.0);
    assert!((ev - 32000f64.log2()).abs() < 1e-12, "{ev}");
    assert!((ev - 14.966).abs() < 1e-3, "{ev}");
    let scale = exposure_of_ev100(ev);
    assert!((scale - 1.0 / 38400.0).abs() < 1e-15, "{scale}");
    let white = 100_000.0 / std::f64::consts::PI * scale;
    assert!((white - 0.829).abs() < 1e-3, "{white}");
}

/// (input, output) pairs computed by scripts/tonemap/reference.py: the reference code's
/// statements in double precision. Neutral: the Khronos specification "PBR Neutral Tone
/// Mapping" and its reference code (github.com/KhronosGroup/ToneMapping,
/// PBR_Neutral/pbrNeutral.glsl). AgX: three.js's AgXToneMapping
/// (src/renderers/shaders/ShaderChunk/tonemapping_pars_fragment.glsl.js), matrices with all
/// their digits.
#[rustfmt::skip]
mod reference {
    pub(super) const NEUTRAL: [([f32; 3], [f32; 3]); 15] = [
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ([0.01, 0.01, 0.01], [0.000625, 0.000625, 0.000625]),
        ([0.05, 0.05, 0.05], [0.015625, 0.015625, 0.015625]),
        ([0.18, 0.18, 0.18], [0.14, 0.14, 0.14]),
        ([0.5, 0.5, 0.5], [0.46, 0.46, 0.46]),
        ([0.76, 0.76, 0.76], [0.72, 0.72, 0.72]),
        ([1.0, 1.0, 1.0], [0.8690909, 0.8690909, 0.8690909]),
        ([2.0, 2.0, 2.0], [0.96, 0.96, 0.96]),
        ([16.0, 16.0, 16.0], [0.9962694, 0.9962694, 0.9962694]),
        ([100.0, 100.0, 100.0], [0.99942076, 0.99942076, 0.99942076]),
        ([1.0, 0.5, 0.25], [0.8690909, 0.42252886, 0.19924787]),
        ([0.8, 0.1, 0.05], [0.7654962, 0.06562748, 0.01563686]),
        ([0.02, 0.3, 0.6], [0.0025, 0.2825, 0.5825]),
        ([5.0, 2.0, 0.5], [0.98702705, 0.61295915, 0.42592517]),
        ([50.0, 10.0, 1.0], [0.99883497, 0.9029947, 0.8814306]),
    ];
    pub(super) const AGX: [([f32; 3], [f32; 3]); 15] = [
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ([0.01, 0.01, 0.01], [0.00599624, 0.0059941425, 0.005994645]),
        ([0.05, 0.05, 0.05], [0.061382532, 0.061365966, 0.0613675]),
        ([0.18, 0.18, 0.18], [0.21454863, 0.21450235, 0.21449916]),
        ([0.5, 0.5, 0.5], [0.42519653, 0.42512015, 0.42510253]),
        ([0.76, 0.76, 0.76], [0.5247465, 0.5246592, 0.52463233]),
        ([1.0, 1.0, 1.0], [0.59022945, 0.5901361, 0.5901023]),
        ([2.0, 2.0, 2.0], [0.7433954, 0.74329203, 0.74323905]),
        ([16.0, 16.0, 16.0], [0.99521214, 0.9950985, 0.99500936]),
        ([100.0, 100.0, 100.0], [0.99697834, 0.9968787, 0.99677896]),
        ([1.0, 0.5, 0.25], [0.6075674, 0.42479932, 0.30553845]),
        ([0.8, 0.1, 0.05], [0.60761905, 0.1771564, 0.1125247]),
        ([0.02, 0.3, 0.6], [0.099658355, 0.33474398, 0.49547657]),
        ([5.0, 2.0, 0.5], [0.93019164, 0.7491439, 0.56192416]),
        ([50.0, 10.0, 1.0], [1.0, 0.9857198, 0.89778125]),
    ];
}

fn assert_matches(name: &str, f: fn(Vec3) -> Vec3, table: &[([f32; 3], [f32; 3])], tol: f32) {
    for &(input, expected) in table {
        let got = f(Vec3::from_array(input));
        let error = (got - Vec3::from_array(expected)).abs().max_element();
        assert!(
            error <= tol,
            "{name}({input:?}) = {got:?}, reference {expected:?} (error {error:e})"
        );
    }
}

#[test]
fn pbr_neutral_matches_the_khronos_reference_code() {
    assert_matches("pbr_neutral", pbr_neutral, &reference::NEUTRAL, 2e-6);
}

#[test]
fn agx_matches_three_js() {
    // f32 here, f64 there: the matrices' digits beyond f32 and log2 / pow in f32.
    assert_matches("agx", agx, &reference::AGX, 2e-5);
}

/// Greys from 1e-4 to 1e5, a quarter stop apart.
fn sweep() -> impl Iterator<Item = f32> {
    (0..=120).map(|i| 1e-4 * 2f32.powf(i as f32 / 4.0))
}

/// Luminance of linear sRGB (Rec. 709 weights).
fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Brighter in, brighter out: every channel of a grey, and of a colour through PBR Neutral
/// (its specification calls the mapping one to one); AgX's channels are not each monotonic
/// (a saturated channel is clamped, then falls back as the others reach white), its luminance
/// is.
#[test]
fn tone_maps_keep_the_order_of_values() {
    for (name, f) in [("neutral", pbr_neutral as fn(Vec3) -> Vec3), ("agx", agx)] {
        for colour in [
            Vec3::ONE,
            Vec3::new(1.0, 0.5, 0.25),
            Vec3::new(0.1, 0.3, 1.0),
        ] {
            let mut last = f(Vec3::ZERO);
            for x in sweep() {
                let now = f(colour * x);
                let ordered = if name == "agx" && colour != Vec3::ONE {
                    luminance(now) >= luminance(last) - 1e-6
                } else {
                    now.cmpge(last - Vec3::splat(1e-6)).all()
                };
                assert!(ordered, "{name}: {colour} x {x} gives {now}, below {last}");
                assert!(
                    now.cmpge(Vec3::ZERO).all() && now.cmple(Vec3::ONE).all(),
                    "{name}: {now}"
                );
                last = now;
            }
        }
    }
}

/// PBR Neutral promises that no finite input reaches 1: highlights approach white. In bytes,
/// AgX keeps more of their gradations: greys from 0.5 to 12 are ten distinct bytes below 255
/// through AgX, through Neutral only those up to 4 (then 254 thrice); without a tone map
/// everything above 1 is 255.
#[test]
fn bright_values_keep_gradations() {
    for x in sweep() {
        let y = pbr_neutral(Vec3::splat(x));
        assert!(y.max_element() < 1.0, "neutral({x}) = {y}: clipped");
    }
    let greys = [0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0];
    let bytes = |f: fn(Vec3) -> Vec3| -> Vec<u8> {
        greys
            .iter()
            .map(|&x| (linear_to_srgb(f(Vec3::splat(x)).x) * 255.0 + 0.5) as u8)
            .collect()
    };
    let agx_bytes = bytes(agx);
    assert!(
        agx_bytes.windows(2).all(|w| w[0] < w[1]),
        "agx: {agx_bytes:?}"
    );
    assert!(agx_bytes.iter().all(|&v| v < 255), "agx: {agx_bytes:?}");
    let neutral = bytes(pbr_neutral);
    assert!(
        neutral[..7].windows(2).all(|w| w[0] < w[1]),
        "neutral: {neutral:?}"
    );
    assert!(neutral.iter().all(|&v| v < 255), "neutral: {neutral:?}");
    assert_eq!(bytes(|c| c)[2..], [255; 8]);
}

#[test]
fn a_bright_colour_desaturates_towards_white_step_by_step() {
    // An emitter's colour times a growing strength (EmissiveStrengthTest's case): each
    // strength looks different, and none is the flat clipped colour.
    let red = Vec3::new(1.0, 0.1, 0.05);
    for f in [pbr_neutral as fn(Vec3) -> Vec3, agx] {
        let shown: Vec<Vec3> = [1.0, 2.0, 4.0, 8.0].iter().map(|&k| f(red * k)).collect();
        for w in shown.windows(2) {
            assert!(w[1].y > w[0].y, "{shown:?}");
            assert!(w[1].x >= w[0].x, "{shown:?}");
        }
    }
}

#[test]
fn png_bytes_without_options_are_as_before_and_exposure_brightens() {
    let mut image = Image::new(4, 1);
    image.pixels = vec![
        Vec3::new(0.0, 0.001, 0.01),
        Vec3::splat(0.18),
        Vec3::new(0.5, 0.8, 1.0),
        Vec3::new(4.0, f32::NAN, -1.0),
    ];
    // Display::LINEAR is the encoding lensray always had: sRGB, clamped.
    let before: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| p.to_array())
        .map(|c| (linear_to_srgb(c).clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
        .collect();
    assert_eq!(to_display_bytes(&image, Shading::Lit), before);
    assert_eq!(
        to_display_bytes_with(&image, Shading::Lit, Display::LINEAR),
        before
    );
    for tonemap in ToneMap::ALL {
        let plain = Display {
            exposure: 1.0,
            tonemap,
        };
        let brighter = Display {
            exposure: 2.0,
            tonemap,
        };
        let a = to_display_bytes_with(&image, Shading::Lit, plain);
        let b = to_display_bytes_with(&image, Shading::Lit, brighter);
        assert!(
            a.iter().zip(&b).all(|(x, y)| y >= x),
            "{tonemap:?}: {a:?} {b:?}"
        );
        assert!(
            b.iter().map(|&v| u32::from(v)).sum::<u32>()
                > a.iter().map(|&v| u32::from(v)).sum::<u32>()
        );
    }
    // AOVs are not light: neither exposed nor tone mapped.
    let agx = Display {
        exposure: 4.0,
        tonemap: ToneMap::Agx,
    };
    for shading in [Shading::Albedo, Shading::Normal, Shading::Depth] {
        assert_eq!(
            to_display_bytes_with(&image, shading, agx),
            to_display_bytes(&image, shading)
        );
    }
}
