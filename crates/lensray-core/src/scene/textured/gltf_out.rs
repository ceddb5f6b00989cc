//! The textured scene as glTF 2.0 (`scene::gltf_out` writes the meshes and materials): its
//! textures, and the camera as a node of its own, a perspective camera without `zfar`, and its
//! point lights. Every texture samples with REPEAT, as MTL's maps do.

use std::path::Path;

use anyhow::bail;
use gltf_json as json;
use json::validation::Checked::Valid;

use super::TexturedScene;
use crate::scene::gltf_out::{push_material, Builder};

/// Writes `NAME.gltf` and `NAME.bin` into `dir`; returns their names.
pub(super) fn write_gltf(
    textured: &TexturedScene,
    dir: &Path,
    name: &str,
) -> anyhow::Result<Vec<String>> {
    let scene = &textured.scene;
    let mut b = Builder::new(name);
    // The glTF materials before any mesh, so that the loader (which numbers them as primitives
    // first use them) and the MTL list them alike when meshes use them in order.
    for m in &scene.materials {
        if m.alpha_texture.is_some() && m.alpha_texture != m.diffuse_texture {
            bail!(
                "material {}: glTF's coverage is the base colour texture's alpha",
                m.name
            );
        }
        push_material(&mut b.root, m);
    }
    let sampler = b.root.push(json::texture::Sampler {
        mag_filter: Some(Valid(json::texture::MagFilter::Linear)),
        min_filter: Some(Valid(json::texture::MinFilter::LinearMipmapLinear)),
        wrap_s: Valid(json::texture::WrappingMode::Repeat),
        wrap_t: Valid(json::texture::WrappingMode::Repeat),
        ..Default::default()
    });
    for image in &textured.images {
        let source = b.root.push(json::Image {
            buffer_view: None,
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(image.file.trim_end_matches(".png").into()),
            uri: Some(image.file.clone()),
            extensions: None,
            extras: Default::default(),
        });
        b.root.push(json::Texture {
            name: None,
            sampler: Some(sampler),
            source,
            extensions: None,
            extras: Default::default(),
        });
    }
    let mut nodes = b.meshes(scene);
    nodes.push(camera_node(&mut b.root, textured));
    nodes.extend(light_nodes(&mut b.root, &scene.lights)?);
    b.scene(name, nodes);
    b.finish(dir, name)
}

/// The camera's node: at the eye, turned down by the pitch, with a perspective camera.
fn camera_node(root: &mut json::Root, textured: &TexturedScene) -> json::Index<json::Node> {
    let c = &textured.camera;
    let camera = root.push(json::Camera {
        name: Some("view".into()),
        orthographic: None,
        perspective: Some(json::camera::Perspective {
            aspect_ratio: Some(c.aspect_ratio),
            yfov: c.yfov_degrees.to_radians(),
            zfar: None,
            znear: c.znear,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Valid(json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    root.push(json::Node {
        camera: Some(camera),
        name: Some("camera".into()),
        translation: Some(c.eye.to_array()),
        rotation: Some(json::scene::UnitQuaternion(c.rotation().to_array())),
        ..Default::default()
    })
}

/// A node per light (point lights only: at their positions), and the lights in the root's
/// `KHR_lights_punctual`.
fn light_nodes(
    root: &mut json::Root,
    lights: &[crate::scene::Light],
) -> anyhow::Result<Vec<json::Index<json::Node>>> {
    use json::extensions::scene::khr_lights_punctual as punctual;
    let mut out = Vec::new();
    let mut list = Vec::new();
    for (i, light) in lights.iter().enumerate() {
        if light.kind != crate::scene::LightKind::Point || light.range != 0.0 {
            bail!("light {i}: the textured scene writes point lights without a range only");
        }
        // glTF's colour times intensity: the brightest channel is the intensity.
        let intensity = light.intensity.max_element();
        list.push(punctual::Light {
            color: (light.intensity / intensity.max(f32::MIN_POSITIVE)).to_array(),
            extensions: None,
            extras: Default::default(),
            intensity,
            name: Some(format!("light {i}")),
            range: None,
            spot: None,
            type_: Valid(punctual::Type::Point),
        });
        out.push(root.push(json::Node {
            name: Some(format!("light {i}")),
            translation: Some(light.position.to_array()),
            extensions: Some(json::extensions::scene::Node {
                khr_lights_punctual: Some(punctual::KhrLightsPunctual {
                    light: json::Index::new(i as u32),
                }),
                ..Default::default()
            }),
            ..Default::default()
        }));
    }
    if !list.is_empty() {
        root.extensions_used.push("KHR_lights_punctual".into());
        root.extensions = Some(json::extensions::Root {
            khr_lights_punctual: Some(json::extensions::root::KhrLightsPunctual { lights: list }),
            ..Default::default()
        });
    }
    Ok(out)
}
