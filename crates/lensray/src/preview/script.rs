//! `lensray preview --script FILE`: timed input replayed without a person, for tests and demos.
//!
//! One event per line; `#` starts a comment, blank lines are skipped. Each line starts with the
//! delay in seconds after the previous event:
//!
//! ```text
//! 0.5 key O                  # a key press and release (names as in `bindings`)
//! 0   click 320 240.5        # left click at a window pixel
//! 0   click 40 200 shift     # Shift+click: a point of the plane of focus (three lay it)
//! 0.2 drag left 100 100 160 100   # drag with left|right|middle from x0 y0 to x1 y1
//! 0   scroll -1.5            # wheel steps; `scroll 2 ctrl` or `scroll 1 shift` with a modifier
//! 0   resize 800x600         # window size; 0 in either side means minimised
//! 0   lens double-gauss-50   # the panel's lens picker: a real lens by name, or `thin`
//! 0   frame 60               # the frame slider of a keyframed shot (`key Enter` plays)
//! 0   wait converged         # until the accumulation reaches the target spp
//! 0   screenshot out/a.png   # the rest of the line is the path
//! 1   quit
//! ```

use std::path::{Path, PathBuf};

use thiserror::Error;

use super::bindings::{action_for_key, canonical_key_name, PointerButton, WheelModifier};

#[derive(Clone, Debug, PartialEq)]
pub enum ScriptEvent {
    /// A press and release; the name is canonical (`bindings::canonical_key_name`).
    Key(String),
    /// Left click at a window pixel (fractional allowed); with Shift held, a point of the
    /// plane of focus (`click X Y shift`).
    Click {
        x: f64,
        y: f64,
        shift: bool,
    },
    Drag {
        button: PointerButton,
        from: [f64; 2],
        to: [f64; 2],
    },
    /// Wheel steps, positive away from the user.
    Scroll {
        steps: f64,
        modifier: Option<WheelModifier>,
    },
    /// Window size; a side of 0 is a minimised window.
    Resize {
        width: u32,
        height: u32,
    },
    /// The panel's lens picker: `thin`, or a real lens by the name the picker lists (a
    /// built-in lens, or the file the preview started with).
    Lens(String),
    /// The frame slider of a keyframed shot: shows this frame.
    Frame(u32),
    /// Wait until the accumulation reaches the target spp.
    WaitConverged,
    Screenshot(PathBuf),
    Quit,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TimedEvent {
    /// Seconds after the previous event (or the start).
    pub delay_seconds: f64,
    pub event: ScriptEvent,
}

/// A bad line: its 1-based number and what is wrong.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("line {line}: {problem}")]
pub struct ScriptError {
    pub line: usize,
    pub problem: String,
}

#[derive(Debug, Error)]
pub enum ScriptLoadError {
    #[error("cannot read script {}: {err}", path.display())]
    Read { path: PathBuf, err: std::io::Error },
    #[error("script {}: {err}", path.display())]
    Parse { path: PathBuf, err: ScriptError },
}

/// Reads and parses a script file; errors name the file.
pub fn load(path: &Path) -> Result<Vec<TimedEvent>, ScriptLoadError> {
    let text = std::fs::read_to_string(path).map_err(|err| ScriptLoadError::Read {
        path: path.to_path_buf(),
        err,
    })?;
    parse(&text).map_err(|err| ScriptLoadError::Parse {
        path: path.to_path_buf(),
        err,
    })
}

pub fn parse(text: &str) -> Result<Vec<TimedEvent>, ScriptError> {
    let mut events = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let event = parse_line(content).map_err(|problem| ScriptError {
            line: index + 1,
            problem,
        })?;
        events.push(event);
    }
    Ok(events)
}

fn parse_line(line: &str) -> Result<TimedEvent, String> {
    let (delay, rest) = split_word(line);
    let delay_seconds = number("delay", delay)?;
    if delay_seconds < 0.0 {
        return Err(format!("delay must not be negative, got {delay}"));
    }
    let (name, args) = split_word(rest);
    let words: Vec<&str> = args.split_whitespace().collect();
    let event = match name {
        "" => return Err(format!("'{delay}' is a delay without an event")),
        "key" => {
            let [key] = exactly(name, &words, "a key name")?;
            if action_for_key(key).is_none() {
                return Err(format!("unknown key '{key}' (see the controls help)"));
            }
            ScriptEvent::Key(canonical_key_name(key))
        }
        "click" => {
            let (x, y, shift) = match words.as_slice() {
                [x, y] => (x, y, false),
                [x, y, "shift"] => (x, y, true),
                _ => {
                    return Err(format!(
                        "click takes X Y and optionally shift, got '{args}'"
                    ))
                }
            };
            ScriptEvent::Click {
                x: number("x", x)?,
                y: number("y", y)?,
                shift,
            }
        }
        "drag" => {
            let [button, x0, y0, x1, y1] = exactly(name, &words, "BUTTON X0 Y0 X1 Y1")?;
            ScriptEvent::Drag {
                button: match button {
                    "left" => PointerButton::Left,
                    "right" => PointerButton::Right,
                    "middle" => PointerButton::Middle,
                    other => {
                        return Err(format!("unknown button '{other}' (left, right or middle)"))
                    }
                },
                from: [number("x0", x0)?, number("y0", y0)?],
                to: [number("x1", x1)?, number("y1", y1)?],
            }
        }
        "scroll" => {
            let (steps, modifier) = match words.as_slice() {
                [steps] => (steps, None),
                [steps, "ctrl"] => (steps, Some(WheelModifier::Ctrl)),
                [steps, "shift"] => (steps, Some(WheelModifier::Shift)),
                [_, other] => return Err(format!("unknown modifier '{other}' (ctrl or shift)")),
                _ => return Err("scroll takes STEPS and optionally ctrl or shift".into()),
            };
            ScriptEvent::Scroll {
                steps: number("steps", steps)?,
                modifier,
            }
        }
        "resize" => {
            let [size] = exactly(name, &words, "WxH")?;
            let (width, height) = size
                .split_once('x')
                .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
                .ok_or_else(|| format!("'{size}' is not a size like 800x600"))?;
            ScriptEvent::Resize { width, height }
        }
        "lens" => {
            let [lens] = exactly(name, &words, "a lens name or 'thin'")?;
            ScriptEvent::Lens(lens.to_owned())
        }
        "frame" => {
            let [frame] = exactly(name, &words, "a frame number")?;
            let frame = frame
                .parse()
                .map_err(|_| format!("'{frame}' is not a frame number from 0"))?;
            ScriptEvent::Frame(frame)
        }
        "wait" => match words.as_slice() {
            ["converged"] => ScriptEvent::WaitConverged,
            _ => return Err("wait takes one word: 'wait converged'".into()),
        },
        "screenshot" => {
            if args.is_empty() {
                return Err("screenshot needs a PATH".into());
            }
            ScriptEvent::Screenshot(PathBuf::from(args))
        }
        "quit" => {
            let [] = exactly(name, &words, "nothing")?;
            ScriptEvent::Quit
        }
        other => return Err(format!("unknown event '{other}'")),
    };
    Ok(TimedEvent {
        delay_seconds,
        event,
    })
}

/// The first word and the trimmed rest.
fn split_word(text: &str) -> (&str, &str) {
    let text = text.trim();
    match text.split_once(char::is_whitespace) {
        Some((word, rest)) => (word, rest.trim()),
        None => (text, ""),
    }
}

/// Exactly `N` arguments, or an error saying what the event takes.
fn exactly<'a, const N: usize>(
    event: &str,
    words: &[&'a str],
    takes: &str,
) -> Result<[&'a str; N], String> {
    <[&str; N]>::try_from(words)
        .map_err(|_| format!("{event} takes {takes}, got '{}'", words.join(" ")))
}

fn number(what: &str, word: &str) -> Result<f64, String> {
    match word.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{what} '{word}' is not a finite number")),
    }
}

#[cfg(test)]
mod tests;
