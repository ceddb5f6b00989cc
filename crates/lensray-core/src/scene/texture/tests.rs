use glam::{Affine2, Vec2, Vec3, Vec4};

use super::*;

/// A 4 x 2 linear texture whose texel (x, y) has red x / 3 and green y.
fn ramp() -> Texture {
    let rgba: Vec<u8> = (0..2u32)
        .flat_map(|y| (0..4u32).flat_map(move |x| [(x * 85) as u8, (y * 255) as u8, 0, 255]))
        .collect();
    Texture::from_rgba8("ramp", 4, 2, &rgba, Encoding::Linear)
}

#[test]
fn mip_levels_halve_down_to_one_texel_and_average() {
    let t = ramp();
    let sizes: Vec<(u32, u32)> = t.levels.iter().map(|l| (l.width, l.height)).collect();
    assert_eq!(sizes, [(4, 2), (2, 1), (1, 1)]);
    assert_eq!(t.texels.len(), 8 + 2 + 1);
    // Level 1 texel 0 averages x = 0, 1 (red 0, 85) over both rows (green 0, 255).
    let l1 = decode_texel(t.texels[8], Encoding::Linear);
    assert!((l1.x - 42.5 / 255.0).abs() <= 0.501 / 255.0, "{l1}");
    assert!((l1.y - 0.5).abs() <= 0.501 / 255.0, "{l1}");
}

#[test]
fn bilinear_reads_texel_centres_and_interpolates_between() {
    let t = ramp();
    let at = |u: f32, v: f32| t.bilinear(0, Vec2::new(u, v), [Wrap::ClampToEdge; 2]);
    assert_eq!(at(0.125, 0.25), Vec4::new(0.0, 0.0, 0.0, 1.0));
    assert_eq!(at(0.375, 0.75), Vec4::new(85.0 / 255.0, 1.0, 0.0, 1.0));
    let between = at(0.25, 0.5);
    assert!((between.x - 42.5 / 255.0).abs() < 1e-6 && (between.y - 0.5).abs() < 1e-6);
}

#[test]
fn wrap_modes_read_the_expected_texels() {
    let t = ramp();
    let red = |u: f32, wrap: Wrap| (t.bilinear(0, Vec2::new(u, 0.25), [wrap; 2]).x * 3.0).round();
    // u = 1.125 is texel 0 repeated, texel 3 clamped, texel 3 mirrored (the first texel of the
    // mirrored copy); u = -0.125 is texel 3, 0 and 0.
    assert_eq!(red(1.125, Wrap::Repeat), 0.0);
    assert_eq!(red(1.125, Wrap::ClampToEdge), 3.0);
    assert_eq!(red(1.125, Wrap::MirroredRepeat), 3.0);
    assert_eq!(red(1.375, Wrap::MirroredRepeat), 2.0);
    assert_eq!(red(-0.125, Wrap::Repeat), 3.0);
    assert_eq!(red(-0.125, Wrap::ClampToEdge), 0.0);
    assert_eq!(red(-0.125, Wrap::MirroredRepeat), 0.0);
    assert_eq!(red(f32::NAN, Wrap::Repeat), red(0.0, Wrap::Repeat));
}

#[test]
fn level_of_detail_is_log2_of_the_longer_axis_in_texels() {
    let t = ramp();
    let footprint = |dx: Vec2, dy: Vec2| TexcoordFootprint { dx, dy };
    // One texel across (1/4 in u) is level 0; two texels in v (1 of a 2-texel height) level 1.
    assert_eq!(
        t.level_of_detail(&footprint(Vec2::new(0.25, 0.0), Vec2::ZERO)),
        0.0
    );
    assert_eq!(
        t.level_of_detail(&footprint(Vec2::ZERO, Vec2::new(0.0, 1.0))),
        1.0
    );
    // Between levels, the trilinear lookup is the linear mix of the two bilinear ones.
    let uv = Vec2::new(0.3, 0.6);
    let wrap = [Wrap::Repeat; 2];
    let mixed = t.trilinear(uv, 0.25, wrap);
    let want = t.bilinear(0, uv, wrap).lerp(t.bilinear(1, uv, wrap), 0.25);
    assert!((mixed - want).abs().max_element() < 1e-6);
    assert_eq!(t.trilinear(uv, 99.0, wrap), t.bilinear(2, uv, wrap));
}

#[test]
fn texture_transform_and_srgb() {
    let rgba = [188u8, 188, 188, 255];
    let t = Texture::from_rgba8("grey", 1, 1, &rgba, Encoding::Srgb);
    let r = TextureRef {
        uv_from_texcoord: Affine2::from_scale_angle_translation(Vec2::splat(3.0), 0.5, Vec2::X),
        ..TextureRef::new(0)
    };
    let v = sample(
        &[t],
        &r,
        &[Vec2::new(0.2, 0.7), Vec2::ZERO],
        &Default::default(),
    );
    // sRGB 188 is linear 0.5029.
    assert!((v.x - srgb_to_linear(188.0 / 255.0)).abs() < 1e-7);
    assert!((v.x - 0.5029).abs() < 1e-3, "{v}");
    assert!((linear_to_srgb(srgb_to_linear(0.3)) - 0.3).abs() < 1e-6);
}

#[test]
fn triangle_footprint_solves_for_the_texture_coordinates() {
    // A right triangle with u along x (2 per metre) and v along y (1 per metre).
    let vertices = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let texcoords = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 1.0)];
    let f = TexcoordFootprint::on_triangle(
        vertices,
        texcoords,
        [Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.0, 0.2, 0.0)],
    );
    assert!((f.dx - Vec2::new(0.2, 0.0)).length() < 1e-6, "{f:?}");
    assert!((f.dy - Vec2::new(0.0, 0.2)).length() < 1e-6, "{f:?}");
    let flat = TexcoordFootprint::on_triangle([Vec3::ZERO; 3], texcoords, [Vec3::X; 2]);
    assert_eq!(flat, TexcoordFootprint::default());
}
