//! Mouse and keyboard state of the preview window, turned into camera gestures. Real winit
//! events and scripted events go through the same functions.

use glam::{Vec2, Vec3};

use super::bindings::{drag_action, DragAction, FlyDirection, PointerButton};

/// What a mouse gesture asks of the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gesture {
    Orbit(Vec2),
    Pan(Vec2),
    /// A left press and release without motion: focus on what is under the cursor.
    Click(Vec2),
}

/// Pixels a press may move and still count as a click.
const CLICK_SLOP: f32 = 3.0;

#[derive(Clone, Debug, Default)]
pub struct InputState {
    pub cursor: Vec2,
    pressed: Option<(PointerButton, Vec2)>,
    dragged: bool,
    pub ctrl: bool,
    pub shift: bool,
    /// Fly keys held.
    held: Vec<FlyDirection>,
}

impl InputState {
    pub fn press(&mut self, button: PointerButton) {
        self.pressed = Some((button, self.cursor));
        self.dragged = false;
    }

    /// The cursor moved to `to`: a drag gesture while a button is held.
    pub fn move_to(&mut self, to: Vec2) -> Option<Gesture> {
        let delta = to - self.cursor;
        self.cursor = to;
        let (button, start) = self.pressed?;
        if !self.dragged && (to - start).length() <= CLICK_SLOP {
            return None;
        }
        self.dragged = true;
        Some(match drag_action(button) {
            DragAction::Orbit => Gesture::Orbit(delta),
            DragAction::Pan => Gesture::Pan(delta),
        })
    }

    pub fn release(&mut self, button: PointerButton) -> Option<Gesture> {
        let (pressed, _) = self.pressed.take()?;
        (pressed == button && button == PointerButton::Left && !self.dragged)
            .then_some(Gesture::Click(self.cursor))
    }

    /// A fly key went down or up.
    pub fn hold(&mut self, direction: FlyDirection, down: bool) {
        self.held.retain(|&d| d != direction);
        if down {
            self.held.push(direction);
        }
    }

    /// The fly direction of the keys held (x right, y up, z forward), zero if none.
    pub fn fly_direction(&self) -> Vec3 {
        self.held.iter().map(|d| d.vector()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_press_is_a_click_and_a_moving_one_a_drag() {
        let mut input = InputState::default();
        input.move_to(Vec2::new(10.0, 10.0));
        input.press(PointerButton::Left);
        assert_eq!(input.move_to(Vec2::new(11.0, 11.0)), None);
        assert_eq!(
            input.release(PointerButton::Left),
            Some(Gesture::Click(Vec2::new(11.0, 11.0)))
        );
        input.press(PointerButton::Left);
        assert_eq!(
            input.move_to(Vec2::new(20.0, 11.0)),
            Some(Gesture::Orbit(Vec2::new(9.0, 0.0)))
        );
        assert_eq!(input.release(PointerButton::Left), None);
        input.press(PointerButton::Right);
        assert_eq!(
            input.move_to(Vec2::new(20.0, 30.0)),
            Some(Gesture::Pan(Vec2::new(0.0, 19.0)))
        );
    }

    #[test]
    fn held_fly_keys_add_up() {
        let mut input = InputState::default();
        input.hold(FlyDirection::Forward, true);
        input.hold(FlyDirection::Left, true);
        input.hold(FlyDirection::Left, true); // key repeat
        assert_eq!(input.fly_direction(), Vec3::new(-1.0, 0.0, 1.0));
        input.hold(FlyDirection::Forward, false);
        input.hold(FlyDirection::Back, true);
        assert_eq!(input.fly_direction(), Vec3::new(-1.0, 0.0, -1.0));
    }
}
