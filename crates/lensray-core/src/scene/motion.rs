//! Meshes and lights moved by a glTF file's animations: each keeps its node chain (a scene root
//! first, its own node last, each node's tracks from the animations that move it) and its data
//! in its node's space, and is posed at a time on the file's timeline by the chain's transform
//! then, as the loader places a node at rest (`gltf_file/nodes.rs`): positions through
//! `world_from_node`, normals through its inverse transpose, tangents through it with their
//! sign turned where it mirrors, and the triangles' winding turned with them.

use glam::{DMat4, Vec3, Vec4};

use super::camera_animation::{chain_time_range, world_from_chain, AnimatedNode};
use super::{Light, Mesh, Scene};

/// A mesh of the scene that animations move.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingMesh {
    /// Its index in [`Scene::meshes`].
    pub index: usize,
    pub chain: Vec<AnimatedNode>,
    /// The mesh in its node's space, wound counter-clockwise there.
    pub node_mesh: Mesh,
}

/// A punctual light of the scene that animations move.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingLight {
    /// Its index in [`Scene::lights`].
    pub index: usize,
    pub chain: Vec<AnimatedNode>,
    /// The light in its node's space (at the origin, along -Z).
    pub node_light: Light,
}

/// The meshes that move while a frame's shutter is open (motion blur): each one's vertices at
/// the moments of the frame's span where the camera's poses are known (`camera::motion`,
/// `MOTION_STEPS` evenly spaced), between which a ray at its moment sees them interpolated
/// linearly, as Embree's motion blur interpolates its time steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjectMotion {
    pub meshes: Vec<MeshSteps>,
    /// The punctual lights that move, each at every step.
    pub lights: Vec<LightSteps>,
    /// Where the frame's own time lies in the span, in [0, 1]: what the AOVs see.
    pub frame_moment: f32,
}

/// One moving mesh of [`ObjectMotion`]: its index in [`Scene::meshes`] (whose triangles, and
/// every attribute but these, are the frame's) and its vertices at each step.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshSteps {
    pub index: usize,
    pub steps: Vec<StepVertices>,
}

/// One moving light of [`ObjectMotion`]: its index in [`Scene::lights`] and its pose at each
/// step (between two, its position and direction are interpolated linearly, the direction
/// normalized).
#[derive(Clone, Debug, PartialEq)]
pub struct LightSteps {
    pub index: usize,
    pub steps: Vec<Light>,
}

impl LightSteps {
    /// The light at `moment` in [0, 1] of the span: between the two steps around it.
    pub fn at(&self, moment: f32) -> Light {
        let (i, f) = crate::camera::motion::step_at(moment, self.steps.len());
        let (a, b) = (&self.steps[i], &self.steps[i + 1]);
        Light {
            position: a.position * (1.0 - f) + b.position * f,
            direction: (a.direction * (1.0 - f) + b.direction * f).normalize_or_zero(),
            ..*a
        }
    }
}

/// A mesh's positions, normals and tangents at one step, as [`posed_mesh`] places them.
#[derive(Clone, Debug, PartialEq)]
pub struct StepVertices {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec4>,
}

/// What a file's animations move, and how to pose the scene at a time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneMotion {
    /// The animations played, as lines name them ("animation I ('NAME')").
    pub names: Vec<String>,
    pub meshes: Vec<MovingMesh>,
    pub lights: Vec<MovingLight>,
    /// The world's scale after the chains (the scene's units in metres).
    world_scale: f64,
}

impl SceneMotion {
    /// The motion of `meshes` and `lights` by the animations `names`; `None` when nothing moves.
    pub fn new(
        names: Vec<String>,
        meshes: Vec<MovingMesh>,
        lights: Vec<MovingLight>,
    ) -> Option<Self> {
        (!meshes.is_empty() || !lights.is_empty()).then_some(Self {
            names,
            meshes,
            lights,
            world_scale: 1.0,
        })
    }

    /// The earliest and latest key times of what moves, seconds.
    pub fn time_range(&self) -> (f64, f64) {
        let chains = self
            .meshes
            .iter()
            .map(|m| &m.chain)
            .chain(self.lights.iter().map(|l| &l.chain));
        chains
            .map(|c| chain_time_range(c))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (s, e)| {
                (a.min(s), b.max(e))
            })
    }

    /// Places every moving mesh and light of `scene` (the scene this motion was read with, or
    /// an earlier pose of it) where the animations have them at `time` seconds.
    pub fn pose(&self, scene: &mut Scene, time: f64) {
        for moving in &self.meshes {
            let world_from_node = world_from_chain(self.world_scale, &moving.chain, time);
            scene.meshes[moving.index] = posed_mesh(&moving.node_mesh, &world_from_node);
        }
        for moving in &self.lights {
            scene.lights[moving.index] = self.posed_light(moving, time);
        }
    }

    /// `moving`'s light where its chain has it at `time` seconds.
    fn posed_light(&self, moving: &MovingLight, time: f64) -> Light {
        let world_from_node = world_from_chain(self.world_scale, &moving.chain, time);
        let node = &moving.node_light;
        Light {
            position: world_from_node
                .transform_point3(node.position.as_dvec3())
                .as_vec3(),
            direction: world_from_node
                .transform_vector3(node.direction.as_dvec3())
                .normalize_or_zero()
                .as_vec3(),
            range: node.range * self.world_scale as f32,
            ..*node
        }
    }

    /// The vertices of the meshes and the poses of the lights that move between `times`
    /// (seconds on the file's timeline, one per step of a frame's span, the frame's own time
    /// at `frame_moment` of it), `None` when none does: one standing still over the span is
    /// the frame's own.
    pub fn steps(&self, times: &[f64], frame_moment: f32) -> Option<ObjectMotion> {
        let meshes: Vec<MeshSteps> = self
            .meshes
            .iter()
            .filter_map(|moving| {
                let steps: Vec<StepVertices> = times
                    .iter()
                    .map(|&time| {
                        let world_from_node =
                            world_from_chain(self.world_scale, &moving.chain, time);
                        let posed = posed_mesh(&moving.node_mesh, &world_from_node);
                        StepVertices {
                            positions: posed.positions,
                            normals: posed.normals,
                            tangents: posed.tangents,
                        }
                    })
                    .collect();
                let moves = steps
                    .iter()
                    .any(|step| step.positions != steps[0].positions);
                moves.then_some(MeshSteps {
                    index: moving.index,
                    steps,
                })
            })
            .collect();
        let lights: Vec<LightSteps> = self
            .lights
            .iter()
            .filter_map(|moving| {
                let steps: Vec<Light> =
                    times.iter().map(|&t| self.posed_light(moving, t)).collect();
                let moves = steps.iter().any(|step| step != &steps[0]);
                moves.then_some(LightSteps {
                    index: moving.index,
                    steps,
                })
            })
            .collect();
        (!meshes.is_empty() || !lights.is_empty()).then_some(ObjectMotion {
            meshes,
            lights,
            frame_moment,
        })
    }

    /// Gives the moving meshes without normals smoothed ones, in their nodes' spaces, as
    /// [`Scene::smooth_normals`] gives the scene's (`--smooth-normals`).
    pub fn smooth_normals(&mut self, crease_degrees: f64) {
        let mut node_scene = Scene {
            meshes: self
                .meshes
                .iter_mut()
                .map(|m| std::mem::take(&mut m.node_mesh))
                .collect(),
            ..Scene::default()
        };
        node_scene.smooth_normals(crease_degrees);
        for (moving, mesh) in self.meshes.iter_mut().zip(node_scene.meshes) {
            moving.node_mesh = mesh;
        }
    }

    /// This motion in a world scaled by `factor` (`Scene::scale`).
    pub fn scale(&mut self, factor: f64) {
        self.world_scale *= factor;
    }
}

/// `node_mesh` placed by `world_from_node`, as the loader places a mesh at rest.
pub fn posed_mesh(node_mesh: &Mesh, world_from_node: &DMat4) -> Mesh {
    let mirrored = world_from_node.determinant() < 0.0;
    let normal_from_node = world_from_node.inverse().transpose();
    let sign = if mirrored { -1.0 } else { 1.0 };
    Mesh {
        positions: node_mesh
            .positions
            .iter()
            .map(|p| world_from_node.transform_point3(p.as_dvec3()).as_vec3())
            .collect(),
        normals: node_mesh
            .normals
            .iter()
            .map(|n| {
                normal_from_node
                    .transform_vector3(n.as_dvec3())
                    .normalize_or_zero()
                    .as_vec3()
            })
            .collect(),
        tangents: node_mesh
            .tangents
            .iter()
            .map(|t| {
                let xyz = world_from_node.transform_vector3(t.truncate().as_dvec3());
                xyz.normalize_or_zero().as_vec3().extend(t.w * sign)
            })
            .collect(),
        triangles: if mirrored {
            node_mesh
                .triangles
                .iter()
                .map(|&[a, b, c]| [a, c, b])
                .collect()
        } else {
            node_mesh.triangles.clone()
        },
        ..node_mesh.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::camera_animation::{AnimationTrack, TrackInterpolation};
    use glam::{DQuat, DVec3, Vec3, Vec4};

    /// Whether `tangents` are unit vectors with a sign (what [`posed_mesh`] keeps).
    fn unit_with_sign(tangents: &[Vec4]) -> bool {
        tangents
            .iter()
            .all(|t| (t.truncate().length() - 1.0).abs() < 1e-5 && t.w.abs() == 1.0)
    }

    fn triangle() -> Mesh {
        Mesh {
            name: "tri".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3],
            triangles: vec![[0, 1, 2]],
            material_ids: vec![0],
            ..Mesh::default()
        }
    }

    /// A node at rest at the origin, moved along +X by 2 m a second from 0 to 1 s.
    fn sliding() -> AnimatedNode {
        let track = AnimationTrack::new(
            TrackInterpolation::Linear,
            vec![0.0, 1.0],
            vec![DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0)],
        )
        .unwrap();
        AnimatedNode {
            rest: DMat4::IDENTITY,
            rest_trs: (DVec3::ZERO, DQuat::IDENTITY, DVec3::ONE),
            translation: Some(track),
            rotation: None,
            scale: None,
        }
    }

    /// A mesh under a parent mirrored in X and a sliding child is posed at the interpolated
    /// place, its winding and tangent signs turned by the mirror, its normals kept unit; the
    /// world scale multiplies after.
    #[test]
    fn a_pose_is_the_chain_s_transform_at_the_time() {
        let mirror = AnimatedNode {
            rest: DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)),
            rest_trs: (DVec3::ZERO, DQuat::IDENTITY, DVec3::new(-1.0, 1.0, 1.0)),
            translation: None,
            rotation: None,
            scale: None,
        };
        let mut motion = SceneMotion::new(
            vec!["animation 0".into()],
            vec![MovingMesh {
                index: 0,
                chain: vec![mirror, sliding()],
                node_mesh: triangle(),
            }],
            Vec::new(),
        )
        .unwrap();
        assert_eq!(motion.time_range(), (0.0, 1.0));
        let mut scene = Scene {
            meshes: vec![triangle()],
            ..Scene::default()
        };
        motion.pose(&mut scene, 0.25);
        let posed = &scene.meshes[0];
        // At 0.25 s the child is 0.5 m along +X, which the parent mirrors to -X.
        assert_eq!(
            posed.positions,
            vec![
                Vec3::new(-0.5, 0.0, 0.0),
                Vec3::new(-1.5, 0.0, 0.0),
                Vec3::new(-0.5, 1.0, 0.0)
            ]
        );
        assert_eq!(posed.triangles, vec![[0, 2, 1]]);
        assert_eq!(posed.normals, vec![Vec3::Z; 3]);
        assert_eq!(posed.tangents, vec![Vec4::new(-1.0, 0.0, 0.0, -1.0); 3]);
        assert!(unit_with_sign(&posed.tangents));
        motion.scale(0.001);
        motion.pose(&mut scene, 2.0);
        let after = scene.meshes[0].positions[0];
        assert!(
            (after - Vec3::new(-0.002, 0.0, 0.0)).length() < 1e-9,
            "{after}"
        );
    }

    /// `--smooth-normals` reaches the moving meshes: one without normals gets them in its
    /// node's space, and its poses carry them.
    #[test]
    fn smoothed_normals_reach_the_poses() {
        let mut bare = triangle();
        bare.normals.clear();
        let mut motion = SceneMotion::new(
            Vec::new(),
            vec![MovingMesh {
                index: 0,
                chain: vec![sliding()],
                node_mesh: bare.clone(),
            }],
            Vec::new(),
        )
        .unwrap();
        motion.smooth_normals(60.0);
        let mut scene = Scene {
            meshes: vec![bare],
            ..Scene::default()
        };
        motion.pose(&mut scene, 0.5);
        assert_eq!(scene.meshes[0].normals, vec![Vec3::Z; 3]);
    }

    /// A light follows its chain: its position and direction through the transform, its range
    /// scaled with the world.
    #[test]
    fn a_light_follows_its_chain() {
        let mut node_light = Light::point(Vec3::ZERO, Vec3::ONE);
        node_light.direction = Vec3::NEG_Z;
        node_light.range = 3.0;
        let mut motion = SceneMotion::new(
            Vec::new(),
            Vec::new(),
            vec![MovingLight {
                index: 0,
                chain: vec![sliding()],
                node_light,
            }],
        )
        .unwrap();
        motion.scale(2.0);
        let mut scene = Scene {
            lights: vec![node_light],
            ..Scene::default()
        };
        motion.pose(&mut scene, 0.5);
        assert_eq!(scene.lights[0].position, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(scene.lights[0].direction, Vec3::NEG_Z);
        assert_eq!(scene.lights[0].range, 6.0);
    }

    /// A light's steps over a span follow its chain, and between two it is interpolated: the
    /// sliding light at 0, 0.5 and 1 s is at x = 0, 1 and 2 m, and at moment 0.25 of that span
    /// at 0.5 m.
    #[test]
    fn a_moving_light_has_its_steps() {
        let node_light = Light::point(Vec3::ZERO, Vec3::ONE);
        let motion = SceneMotion::new(
            Vec::new(),
            Vec::new(),
            vec![MovingLight {
                index: 0,
                chain: vec![sliding()],
                node_light,
            }],
        )
        .unwrap();
        let steps = motion
            .steps(&[0.0, 0.5, 1.0], 0.5)
            .expect("the light moves");
        let light = &steps.lights[0];
        let xs: Vec<f32> = light.steps.iter().map(|l| l.position.x).collect();
        assert_eq!(xs, vec![0.0, 1.0, 2.0]);
        assert_eq!(light.at(0.25).position, Vec3::new(0.5, 0.0, 0.0));
        assert!(
            motion.steps(&[2.0, 3.0], 0.5).is_none(),
            "at rest after its last key"
        );
    }
}
