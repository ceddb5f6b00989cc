//! The preview's controls: one table per input device, the single source of what each input does
//! and of the help text, so the two cannot drift apart.
//!
//! Keys are named as winit 0.30 names them: a `NamedKey` by its variant name ("Space", "Escape",
//! "F1", "ArrowUp"), a character key by the character itself, upper-case ("W", "1", ",").

use glam::Vec3;

use super::view::ViewMode;

/// A held fly key: the direction in camera axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FlyDirection {
    Forward,
    Back,
    Left,
    Right,
    Up,
    Down,
}

impl FlyDirection {
    /// x right, y up, z forward, as `CameraRig::fly` takes it.
    pub fn vector(self) -> Vec3 {
        match self {
            FlyDirection::Forward => Vec3::Z,
            FlyDirection::Back => Vec3::NEG_Z,
            FlyDirection::Left => Vec3::NEG_X,
            FlyDirection::Right => Vec3::X,
            FlyDirection::Up => Vec3::Y,
            FlyDirection::Down => Vec3::NEG_Y,
        }
    }
}

/// What a key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Action {
    FocusUnderCursor,
    FocusNearer,
    FocusFarther,
    ApertureWider,
    ApertureNarrower,
    ToggleProjection,
    /// Motion blur on or off (`--motion-blur`): a keyframed shot's camera moves over the
    /// frame's shutter.
    ToggleMotionBlur,
    SetView(ViewMode),
    NextView,
    Screenshot,
    PrintCamera,
    ResetCamera,
    /// Plays or pauses a keyframed shot (`playback`).
    PlayPause,
    /// The shot's frame before or after the one shown.
    PreviousFrame,
    NextFrame,
    ToggleHelp,
    Quit,
    /// Acts for as long as the key is held (the others act once per press).
    Fly(FlyDirection),
}

impl Action {
    pub fn is_held(self) -> bool {
        matches!(self, Action::Fly(_))
    }

    /// One line of help.
    pub fn description(self) -> String {
        let text = match self {
            Action::FocusUnderCursor => "focus on the surface under the cursor",
            Action::FocusNearer => "focus nearer",
            Action::FocusFarther => "focus farther",
            Action::ApertureWider => "wider aperture (more blur)",
            Action::ApertureNarrower => "narrower aperture (less blur)",
            Action::ToggleProjection => "switch perspective / orthographic",
            Action::ToggleMotionBlur => "motion blur on / off (a keyframed shot's camera move)",
            Action::SetView(view) => return format!("view: {view}"),
            Action::NextView => "next view",
            Action::Screenshot => "save a screenshot",
            Action::PrintCamera => {
                "print the camera as scene-file TOML, a render command and a [[keyframe]]"
            }
            Action::ResetCamera => "reset the camera (with keyframes: to the frame's)",
            Action::PlayPause => "play / pause the keyframed shot",
            Action::PreviousFrame => "the shot's previous frame",
            Action::NextFrame => "the shot's next frame",
            Action::ToggleHelp => "show / hide this help",
            Action::Quit => "quit",
            Action::Fly(direction) => {
                return format!("fly {} (hold)", format!("{direction:?}").to_lowercase())
            }
        };
        text.to_string()
    }
}

pub struct KeyBinding {
    pub key: &'static str,
    pub action: Action,
}

const fn bind(key: &'static str, action: Action) -> KeyBinding {
    KeyBinding { key, action }
}

/// Every key, in the order the help lists them.
pub const KEY_BINDINGS: &[KeyBinding] = &[
    bind("W", Action::Fly(FlyDirection::Forward)),
    bind("A", Action::Fly(FlyDirection::Left)),
    bind("S", Action::Fly(FlyDirection::Back)),
    bind("D", Action::Fly(FlyDirection::Right)),
    bind("Q", Action::Fly(FlyDirection::Down)),
    bind("E", Action::Fly(FlyDirection::Up)),
    bind("Space", Action::FocusUnderCursor),
    bind("[", Action::FocusNearer),
    bind("]", Action::FocusFarther),
    bind("-", Action::ApertureNarrower),
    bind("=", Action::ApertureWider),
    bind("O", Action::ToggleProjection),
    bind("B", Action::ToggleMotionBlur),
    bind("V", Action::NextView),
    bind("1", Action::SetView(ViewMode::Final)),
    bind("2", Action::SetView(ViewMode::Albedo)),
    bind("3", Action::SetView(ViewMode::Normal)),
    bind("4", Action::SetView(ViewMode::Depth)),
    bind("5", Action::SetView(ViewMode::CircleOfConfusion)),
    bind("P", Action::Screenshot),
    bind("C", Action::PrintCamera),
    bind("R", Action::ResetCamera),
    bind("Enter", Action::PlayPause),
    bind("ArrowLeft", Action::PreviousFrame),
    bind("ArrowRight", Action::NextFrame),
    bind("H", Action::ToggleHelp),
    bind("F1", Action::ToggleHelp),
    bind("Escape", Action::Quit),
];

/// A character key's name is upper-case ("w" and "W" are the same key); named keys are as given.
pub fn canonical_key_name(name: &str) -> String {
    let mut chars = name.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => c.to_uppercase().collect(),
        _ => name.to_string(),
    }
}

pub fn action_for_key(name: &str) -> Option<Action> {
    let name = canonical_key_name(name);
    KEY_BINDINGS
        .iter()
        .find(|b| b.key == name)
        .map(|b| b.action)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointerButton {
    Left,
    Right,
    Middle,
}

/// What a drag with a button does to the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DragAction {
    /// `CameraRig::orbit`.
    Orbit,
    /// `CameraRig::pan`.
    Pan,
}

pub fn drag_action(button: PointerButton) -> DragAction {
    match button {
        PointerButton::Left => DragAction::Orbit,
        PointerButton::Right | PointerButton::Middle => DragAction::Pan,
    }
}

/// The modifier held while the wheel turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WheelModifier {
    Ctrl,
    Shift,
}

/// What the wheel does; positive steps (away from the user) dolly in, focus farther, open up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WheelAction {
    /// `CameraRig::dolly`.
    Dolly,
    /// `CameraRig::step_focus`.
    Focus,
    /// `CameraRig::step_aperture`.
    Aperture,
}

pub fn wheel_action(modifier: Option<WheelModifier>) -> WheelAction {
    match modifier {
        None => WheelAction::Dolly,
        Some(WheelModifier::Ctrl) => WheelAction::Focus,
        Some(WheelModifier::Shift) => WheelAction::Aperture,
    }
}

/// The mouse column of the help, matching `drag_action`, `wheel_action` and a click.
pub const MOUSE_CONTROLS: &[(&str, &str)] = &[
    ("left drag", "orbit about the target"),
    ("right or middle drag", "pan"),
    ("wheel", "dolly (away from you: closer)"),
    ("Ctrl+wheel", "focus distance (away from you: farther)"),
    ("Shift+wheel", "aperture (away from you: wider)"),
    ("click", "focus on the surface under the cursor"),
    (
        "Shift+click",
        "three surfaces: lay the plane of focus through them",
    ),
];

/// The help text: mouse controls, then every key, keys sharing an action on one line.
pub fn controls_help() -> String {
    let mut lines = vec!["Mouse:".to_string()];
    for (gesture, what) in MOUSE_CONTROLS {
        lines.push(format!("  {gesture:<22} {what}"));
    }
    lines.push("Keys:".to_string());
    let mut listed: Vec<Action> = Vec::new();
    for binding in KEY_BINDINGS {
        if listed.contains(&binding.action) {
            continue;
        }
        listed.push(binding.action);
        let keys: Vec<&str> = KEY_BINDINGS
            .iter()
            .filter(|b| b.action == binding.action)
            .map(|b| b.key)
            .collect();
        lines.push(format!(
            "  {:<22} {}",
            keys.join(", "),
            binding.action.description()
        ));
    }
    lines.join("\n") + "\n"
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use super::*;

    #[test]
    fn every_key_is_bound_once_and_maps_back() {
        let mut seen = HashSet::new();
        for binding in KEY_BINDINGS {
            assert!(seen.insert(binding.key), "{} bound twice", binding.key);
            assert_eq!(canonical_key_name(binding.key), binding.key);
            assert_eq!(action_for_key(binding.key), Some(binding.action));
        }
        assert_eq!(seen.len(), 28);
    }

    #[test]
    fn the_brief_s_bindings() {
        assert_eq!(
            action_for_key("w"),
            Some(Action::Fly(FlyDirection::Forward))
        );
        assert_eq!(action_for_key("Q"), Some(Action::Fly(FlyDirection::Down)));
        assert_eq!(action_for_key("E"), Some(Action::Fly(FlyDirection::Up)));
        assert_eq!(action_for_key("Space"), Some(Action::FocusUnderCursor));
        assert_eq!(action_for_key("["), Some(Action::FocusNearer));
        assert_eq!(action_for_key("="), Some(Action::ApertureWider));
        assert_eq!(
            action_for_key("5"),
            Some(Action::SetView(ViewMode::CircleOfConfusion))
        );
        assert_eq!(action_for_key("F1"), Some(Action::ToggleHelp));
        assert_eq!(action_for_key("h"), Some(Action::ToggleHelp));
        assert_eq!(action_for_key("Escape"), Some(Action::Quit));
        // Space focuses, so Enter plays a keyframed shot and the arrows step its frames.
        assert_eq!(action_for_key("Enter"), Some(Action::PlayPause));
        assert_eq!(action_for_key("ArrowLeft"), Some(Action::PreviousFrame));
        assert_eq!(action_for_key("ArrowRight"), Some(Action::NextFrame));
        assert_eq!(action_for_key("escape"), None, "named keys match exactly");
        assert_eq!(action_for_key("Z"), None);
        assert_eq!(action_for_key(""), None);
        // Number keys 1-5 give the views in the order of ViewMode::ALL.
        for (i, view) in ViewMode::ALL.iter().enumerate() {
            assert_eq!(
                action_for_key(&(i + 1).to_string()),
                Some(Action::SetView(*view))
            );
        }
    }

    #[test]
    fn only_fly_keys_are_held() {
        let held: Vec<&str> = KEY_BINDINGS
            .iter()
            .filter(|b| b.action.is_held())
            .map(|b| b.key)
            .collect();
        assert_eq!(held, ["W", "A", "S", "D", "Q", "E"]);
        let sum: Vec3 = ["W", "A", "S", "D", "Q", "E"]
            .iter()
            .map(|k| match action_for_key(k) {
                Some(Action::Fly(d)) => d.vector(),
                other => panic!("{other:?}"),
            })
            .sum();
        assert_eq!(sum, Vec3::ZERO, "opposite keys cancel");
    }

    #[test]
    fn mouse_controls() {
        assert_eq!(drag_action(PointerButton::Left), DragAction::Orbit);
        assert_eq!(drag_action(PointerButton::Right), DragAction::Pan);
        assert_eq!(drag_action(PointerButton::Middle), DragAction::Pan);
        assert_eq!(wheel_action(None), WheelAction::Dolly);
        assert_eq!(wheel_action(Some(WheelModifier::Ctrl)), WheelAction::Focus);
        assert_eq!(
            wheel_action(Some(WheelModifier::Shift)),
            WheelAction::Aperture
        );
    }

    #[test]
    fn help_mentions_every_key_and_mouse_control() {
        let help = controls_help();
        for binding in KEY_BINDINGS {
            let line = help
                .lines()
                .find(|l| {
                    l.trim_start()
                        .split("  ")
                        .next()
                        .is_some_and(|keys| keys.split(", ").any(|k| k == binding.key))
                })
                .unwrap_or_else(|| panic!("help lacks {}:\n{help}", binding.key));
            assert!(line.contains(&binding.action.description()), "{line}");
        }
        for (gesture, what) in MOUSE_CONTROLS {
            assert!(help.contains(gesture) && help.contains(what));
        }
        assert!(help.contains("  H, F1 "), "{help}");
        assert!(help.contains("view: circle of confusion"));
        assert!(help.contains("fly forward (hold)"));
    }
}
