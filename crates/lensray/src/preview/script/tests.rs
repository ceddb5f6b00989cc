//! Every event kind, comments and blank lines, and malformed lines with their messages.

use super::*;

fn one(line: &str) -> TimedEvent {
    let events = parse(line).unwrap_or_else(|e| panic!("{line}: {e}"));
    assert_eq!(events.len(), 1, "{line}");
    events.into_iter().next().unwrap()
}

fn event(line: &str) -> ScriptEvent {
    one(line).event
}

fn error(text: &str) -> String {
    parse(text).expect_err(text).to_string()
}

#[test]
fn every_event_kind() {
    assert_eq!(event("0 key O"), ScriptEvent::Key("O".into()));
    assert_eq!(
        event("0 lens double-gauss-50"),
        ScriptEvent::Lens("double-gauss-50".into())
    );
    assert_eq!(event("0 lens thin"), ScriptEvent::Lens("thin".into()));
    assert_eq!(event("0 key o"), ScriptEvent::Key("O".into()));
    assert_eq!(event("0 key Escape"), ScriptEvent::Key("Escape".into()));
    assert_eq!(event("0 key ["), ScriptEvent::Key("[".into()));
    assert_eq!(
        event("0 click 320 240.5"),
        ScriptEvent::Click {
            x: 320.0,
            y: 240.5,
            shift: false
        }
    );
    assert_eq!(
        event("0 drag middle 10 20.25 -5 400"),
        ScriptEvent::Drag {
            button: PointerButton::Middle,
            from: [10.0, 20.25],
            to: [-5.0, 400.0],
        }
    );
    assert_eq!(
        event("0 drag left 0 0 1 1"),
        ScriptEvent::Drag {
            button: PointerButton::Left,
            from: [0.0, 0.0],
            to: [1.0, 1.0],
        }
    );
    assert!(matches!(
        event("0 drag right 0 0 1 1"),
        ScriptEvent::Drag {
            button: PointerButton::Right,
            ..
        }
    ));
    assert_eq!(
        event("0 scroll -1.5"),
        ScriptEvent::Scroll {
            steps: -1.5,
            modifier: None
        }
    );
    assert_eq!(
        event("0 scroll 2 ctrl"),
        ScriptEvent::Scroll {
            steps: 2.0,
            modifier: Some(WheelModifier::Ctrl)
        }
    );
    assert_eq!(
        event("0 scroll 1 shift"),
        ScriptEvent::Scroll {
            steps: 1.0,
            modifier: Some(WheelModifier::Shift)
        }
    );
    assert_eq!(
        event("0 resize 800x600"),
        ScriptEvent::Resize {
            width: 800,
            height: 600
        }
    );
    assert_eq!(
        event("0 resize 0x0"),
        ScriptEvent::Resize {
            width: 0,
            height: 0
        }
    );
    assert_eq!(event("0 frame 60"), ScriptEvent::Frame(60));
    assert_eq!(event("0 key Enter"), ScriptEvent::Key("Enter".into()));
    assert_eq!(event("0 wait converged"), ScriptEvent::WaitConverged);
    assert_eq!(
        event("0 screenshot out/my shot.png"),
        ScriptEvent::Screenshot(PathBuf::from("out/my shot.png"))
    );
    assert_eq!(event("0 quit"), ScriptEvent::Quit);
}

#[test]
fn delays_comments_and_blank_lines() {
    let script = "# a demo\n\n0.5 key O   # orthographic\n  \n2 scroll 1\n\t0.25\tquit\n";
    let events = parse(script).unwrap();
    assert_eq!(
        events,
        [
            TimedEvent {
                delay_seconds: 0.5,
                event: ScriptEvent::Key("O".into())
            },
            TimedEvent {
                delay_seconds: 2.0,
                event: ScriptEvent::Scroll {
                    steps: 1.0,
                    modifier: None
                }
            },
            TimedEvent {
                delay_seconds: 0.25,
                event: ScriptEvent::Quit
            },
        ]
    );
    assert_eq!(parse("").unwrap(), []);
    assert_eq!(parse("# only a comment\n").unwrap(), []);
}

#[test]
fn malformed_lines_name_the_line_and_the_problem() {
    assert_eq!(error("0 key O\n\n0 jump"), "line 3: unknown event 'jump'");
    assert_eq!(error("key O"), "line 1: delay 'key' is not a finite number");
    assert_eq!(
        error("-1 quit"),
        "line 1: delay must not be negative, got -1"
    );
    assert_eq!(
        error("nan quit"),
        "line 1: delay 'nan' is not a finite number"
    );
    assert_eq!(error("0.5"), "line 1: '0.5' is a delay without an event");
    assert_eq!(
        error("0 key Z"),
        "line 1: unknown key 'Z' (see the controls help)"
    );
    assert_eq!(error("0 key"), "line 1: key takes a key name, got ''");
    assert_eq!(
        error("0 key W A"),
        "line 1: key takes a key name, got 'W A'"
    );
    assert_eq!(
        error("0 click 1"),
        "line 1: click takes X Y and optionally shift, got '1'"
    );
    assert_eq!(
        error("0 click 1 two"),
        "line 1: y 'two' is not a finite number"
    );
    assert_eq!(
        error("0 drag up 0 0 1 1"),
        "line 1: unknown button 'up' (left, right or middle)"
    );
    assert_eq!(
        error("0 drag left 0 0 1"),
        "line 1: drag takes BUTTON X0 Y0 X1 Y1, got 'left 0 0 1'"
    );
    assert_eq!(
        error("0 scroll 1 alt"),
        "line 1: unknown modifier 'alt' (ctrl or shift)"
    );
    assert_eq!(
        error("0 scroll"),
        "line 1: scroll takes STEPS and optionally ctrl or shift"
    );
    assert_eq!(
        error("0 scroll inf"),
        "line 1: steps 'inf' is not a finite number"
    );
    assert_eq!(
        error("0 resize 800"),
        "line 1: '800' is not a size like 800x600"
    );
    assert_eq!(
        error("0 resize -1x5"),
        "line 1: '-1x5' is not a size like 800x600"
    );
    assert_eq!(
        error("0 wait"),
        "line 1: wait takes one word: 'wait converged'"
    );
    assert_eq!(
        error("0 wait 5"),
        "line 1: wait takes one word: 'wait converged'"
    );
    assert_eq!(error("0 screenshot"), "line 1: screenshot needs a PATH");
    assert_eq!(
        error("0 frame"),
        "line 1: frame takes a frame number, got ''"
    );
    assert_eq!(
        error("0 frame -2"),
        "line 1: '-2' is not a frame number from 0"
    );
    assert_eq!(
        error("0 frame 1.5"),
        "line 1: '1.5' is not a frame number from 0"
    );
    assert_eq!(error("0 quit now"), "line 1: quit takes nothing, got 'now'");
    // Every message is one line.
    for text in ["0 jump", "0 click", "0 resize x"] {
        assert_eq!(error(text).lines().count(), 1);
    }
}

#[test]
fn load_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("demo.script");
    std::fs::write(&path, "0 key V\n1 quit\n").unwrap();
    assert_eq!(load(&path).unwrap().len(), 2);

    std::fs::write(&path, "0 key V\n1 fly\n").unwrap();
    let message = load(&path).unwrap_err().to_string();
    assert_eq!(
        message,
        format!("script {}: line 2: unknown event 'fly'", path.display())
    );

    let missing = dir.path().join("missing.script");
    let message = load(&missing).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("cannot read script {}: ", missing.display())),
        "{message}"
    );
}
