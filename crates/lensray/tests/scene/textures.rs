//! Textured OBJ files: `vt` (flipped to the images' rows), `map_Kd`, `map_d` and the forgiving
//! reading of missing and broken texture files.

use std::path::Path;

use lensray_core::scene::{load_obj, AlphaMode, SceneError};

use crate::write;

#[test]
fn the_bundled_tree_reads_its_bark_and_leaves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/tree");
    let file = load_obj(&root.join("Tree_1.obj")).expect("the tree loads");
    assert!(file.notices.is_empty(), "{:?}", file.notices);
    let scene = &file.scene;
    // Bark and leaf colour (sRGB), and the leaves' coverage (their PNG's alpha).
    assert_eq!(scene.textures.len(), 3);
    let leaves = scene
        .materials
        .iter()
        .find(|m| m.name == "Tree_Leaves")
        .expect("the leaves' material");
    assert_eq!(leaves.alpha_mode, AlphaMode::Blend);
    let coverage = &scene.textures[leaves.alpha_texture.expect("map_d").texture as usize];
    let alphas: Vec<u32> = coverage.texels.iter().map(|t| t >> 24).collect();
    assert!(
        alphas.contains(&0) && alphas.contains(&255),
        "a cut-out mask"
    );
    assert!(scene
        .meshes
        .iter()
        .all(|m| m.texcoords.len() == m.positions.len()));
}

#[test]
fn a_missing_texture_warns_and_a_broken_one_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\n";
    write(d, "m.mtl", "newmtl a\nKd 1 1 1\nmap_Kd -s 2 2 1 gone.png\n");
    let path = write(d, "t.obj", obj);
    let file = load_obj(&path).expect("a missing texture is not fatal");
    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    assert!(file.notices[0].contains("gone.png"), "{:?}", file.notices);
    assert!(file.scene.materials[0].diffuse_texture.is_none());
    // OBJ's v runs up: v = 0 is the image's last row.
    assert_eq!(file.scene.meshes[0].texcoords[0], glam::Vec2::new(0.0, 1.0));

    std::fs::write(d.join("gone.png"), b"not a PNG").unwrap();
    let err = load_obj(&path).expect_err("an undecodable texture");
    assert!(matches!(err, SceneError::Texture { .. }), "{err:?}");
    let line = err.to_string();
    assert!(!line.contains('\n') && line.contains("gone.png"), "{line}");
}

/// `map_Pr` and `map_Pm` become one metallic-roughness texture (roughness in G, metallic in B,
/// each image's red channel; the metallic image, of another size, read at the roughness image's
/// texels), their factors 1 where `Pr` and `Pm` are absent; `norm` is a linear normal map with
/// `-bm` its scale; `map_Bump` is left with one notice. Triangles with texture coordinates get
/// MikkTSpace tangents.
#[test]
fn mtl_roughness_metallic_and_normal_maps_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    image::GrayImage::from_pixel(4, 4, image::Luma([64u8]))
        .save(d.join("rough.png"))
        .unwrap();
    image::GrayImage::from_fn(2, 2, |x, _| image::Luma([if x == 0 { 200u8 } else { 10 }]))
        .save(d.join("metal.png"))
        .unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([128u8, 128, 255]))
        .save(d.join("normal.png"))
        .unwrap();
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\n";
    write(
        d,
        "m.mtl",
        "newmtl a\nKd 1 1 1\nmap_Pr rough.png\nmap_Pm metal.png\nnorm -bm 0.5 normal.png\n\
         map_Bump bump.png\n",
    );
    let file = load_obj(&write(d, "t.obj", obj)).expect("loads");
    let m = &file.scene.materials[0];
    assert_eq!((m.metallic, m.roughness, m.specular), (1.0, 1.0, 1.0));
    let mr = &file.scene.textures[m.metallic_roughness_texture.expect("map_Pr").texture as usize];
    assert_eq!((mr.levels[0].width, mr.levels[0].height), (4, 4));
    // Rows of 4: x = 0, 1 read the metallic image's x = 0 (200), x = 2, 3 its x = 1 (10).
    let texel = |x: usize| mr.texels[x].to_le_bytes();
    assert_eq!(
        [texel(0)[1], texel(0)[2]],
        [64, 200],
        "G roughness, B metallic"
    );
    assert_eq!(
        [texel(3)[1], texel(3)[2]],
        [64, 10],
        "G roughness, B metallic"
    );
    let normal = &file.scene.textures[m.normal_texture.expect("norm").texture as usize];
    assert_eq!(
        normal.encoding,
        lensray_core::scene::texture::Encoding::Linear
    );
    assert_eq!(m.normal_scale, 0.5);
    assert_eq!(file.scene.meshes[0].tangents.len(), 3);
    assert_eq!(file.notices.len(), 1, "{:?}", file.notices);
    assert!(file.notices[0].contains("map_Bump"), "{:?}", file.notices);
}
