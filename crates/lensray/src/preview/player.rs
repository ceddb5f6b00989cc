//! Replays a `--script`: each event fires its delay after the previous one; `wait converged`
//! holds the rest until the accumulation reaches its target.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::script::{ScriptEvent, TimedEvent};

#[derive(Debug, Default)]
pub struct ScriptPlayer {
    events: VecDeque<TimedEvent>,
    /// When the previous event fired (the first event counts from the first check).
    last: Option<Instant>,
}

impl ScriptPlayer {
    pub fn new(events: Vec<TimedEvent>) -> Self {
        Self {
            events: events.into(),
            last: None,
        }
    }

    /// Events remain.
    pub fn pending(&self) -> bool {
        !self.events.is_empty()
    }

    /// The next event if its time has come (`converged`: whether a `wait converged` is met).
    pub fn next_due(&mut self, converged: bool) -> Option<ScriptEvent> {
        let now = Instant::now();
        let last = *self.last.get_or_insert(now);
        let next = self.events.front()?;
        if now < last + Duration::from_secs_f64(next.delay_seconds.max(0.0)) {
            return None;
        }
        if matches!(next.event, ScriptEvent::WaitConverged) && !converged {
            return None;
        }
        self.last = Some(now);
        self.events.pop_front().map(|e| e.event)
    }

    /// When the next event is due, if it waits on time alone.
    pub fn next_wake(&self) -> Option<Instant> {
        let next = self.events.front()?;
        Some(self.last? + Duration::from_secs_f64(next.delay_seconds.max(0.0)))
    }
}
