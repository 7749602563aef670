//! `npr view --script FILE`: timed input events that drive the viewer through the same
//! input path as a person (see [`super::state::ViewerState::input`]).
//!
//! One event per line, `@FRAME COMMAND ARGS...`; `#` starts a comment. Pixels are in the
//! 3-D view (origin top-left). Commands:
//!
//! | command | what it does |
//! |---|---|
//! | `key NAME` | a key: `1`–`7` effects, `t` turntable, `r` reset view, `escape` |
//! | `click X Y` | left press and release at a pixel |
//! | `click-highlight` | left click at the projected centre of the largest highlight |
//! | `drag X0 Y0 X1 Y1 [shift\|ctrl\|right]` | a drag in 8 moves |
//! | `drag-selected DX DY` | a left drag from the selected highlight's centre |
//! | `rotate-selected DEG` | a Shift drag around the selected highlight's centre |
//! | `scroll X Y NOTCHES` | the wheel at a pixel |
//! | `scroll-selected NOTCHES` | the wheel over the selected highlight |
//! | `resize W H` | resizes the window (0 0 as a minimised window reports) |
//! | `effect NAME` | switches the effect by name (as the panel does) |
//! | `turntable on\|off` | sets the turntable |
//! | `screenshot PATH` | writes the 3-D view (no panel) as PNG |
//! | `save-svg PATH` | writes the hatching of the 3-D view as pen strokes (SVG, A4) |
//! | `save-preset PATH` | writes the preset (with the view's size) as TOML |
//! | `report PATH` | writes the selected highlight's state as JSON |
//! | `memory PATH` | writes the heap in use, resident memory and live GPU objects as JSON |
//! | `load MODEL` | opens a model as if dropped on the window |
//! | `exit` | closes the viewer |

use crate::AppError;
use crate::preset::Effect;
use std::path::{Path, PathBuf};

/// One scripted command.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// A key by name.
    Key(String),
    /// Click at a pixel.
    Click(f32, f32),
    /// Click the largest highlight.
    ClickHighlight,
    /// Drag between pixels with a modifier (`""`, `shift`, `ctrl`, `right`).
    Drag([f32; 4], String),
    /// Drag the selected highlight by a pixel offset.
    DragSelected(f32, f32),
    /// Rotate the selected highlight by degrees (a Shift drag on a circle around it).
    RotateSelected(f32),
    /// Wheel at a pixel.
    Scroll(f32, f32, f32),
    /// Wheel over the selected highlight.
    ScrollSelected(f32),
    /// Resize the window.
    Resize(u32, u32),
    /// Switch the effect.
    Effect(Effect),
    /// Turntable on or off.
    Turntable(bool),
    /// Write the 3-D view.
    Screenshot(PathBuf),
    /// Write the hatching as an SVG for pen plotters.
    SaveSvg(PathBuf),
    /// Write the preset.
    SavePreset(PathBuf),
    /// Write the selected highlight's state.
    Report(PathBuf),
    /// Write resident memory and the GPU objects alive ([`crate::memory::MemoryReading`]).
    Memory(PathBuf),
    /// Open a model.
    Load(PathBuf),
    /// Close the viewer.
    Exit,
}

/// A command and the frame it runs at.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Frame number (0 is the first frame drawn).
    pub frame: u64,
    /// The command.
    pub command: Command,
}

/// Parses a script; `origin` names it in errors.
///
/// # Errors
/// [`AppError::Usage`] naming the file, line and what is wrong.
pub fn parse(text: &str, origin: &Path) -> Result<Vec<Event>, AppError> {
    let mut events = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let err =
            |why: &str| AppError::Usage(format!("{}:{}: {why}: '{line}'", origin.display(), n + 1));
        let mut words = line.split_whitespace();
        let frame = words
            .next()
            .and_then(|w| w.strip_prefix('@'))
            .and_then(|w| w.parse::<u64>().ok())
            .ok_or_else(|| err("expected @FRAME first"))?;
        let cmd = words.next().ok_or_else(|| err("missing command"))?;
        let args: Vec<&str> = words.collect();
        let num = |i: usize| -> Result<f32, AppError> {
            args.get(i)
                .and_then(|a| a.parse::<f32>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| err("expected a number"))
        };
        let path = |i: usize| -> Result<PathBuf, AppError> {
            args.get(i)
                .map(PathBuf::from)
                .ok_or_else(|| err("expected a path"))
        };
        let command = match cmd {
            "key" => Command::Key(
                args.first()
                    .ok_or_else(|| err("expected a key"))?
                    .to_string(),
            ),
            "click" => Command::Click(num(0)?, num(1)?),
            "click-highlight" => Command::ClickHighlight,
            "drag" => Command::Drag(
                [num(0)?, num(1)?, num(2)?, num(3)?],
                args.get(4).copied().unwrap_or("").to_string(),
            ),
            "drag-selected" => Command::DragSelected(num(0)?, num(1)?),
            "rotate-selected" => Command::RotateSelected(num(0)?),
            "scroll" => Command::Scroll(num(0)?, num(1)?, num(2)?),
            "scroll-selected" => Command::ScrollSelected(num(0)?),
            "resize" => Command::Resize(num(0)?.max(0.0) as u32, num(1)?.max(0.0) as u32),
            "effect" => Command::Effect(
                args.first()
                    .and_then(|a| Effect::from_name(a))
                    .ok_or_else(|| err("unknown effect"))?,
            ),
            "turntable" => Command::Turntable(match args.first().copied() {
                Some("on") => true,
                Some("off") => false,
                _ => return Err(err("expected on or off")),
            }),
            "screenshot" => Command::Screenshot(path(0)?),
            "save-svg" => Command::SaveSvg(path(0)?),
            "save-preset" => Command::SavePreset(path(0)?),
            "report" => Command::Report(path(0)?),
            "memory" => Command::Memory(path(0)?),
            "load" => Command::Load(path(0)?),
            "exit" => Command::Exit,
            _ => return Err(err("unknown command")),
        };
        events.push(Event { frame, command });
    }
    events.sort_by_key(|e| e.frame);
    Ok(events)
}

/// Reads and parses a script file.
///
/// # Errors
/// [`AppError::Io`] or as [`parse`].
pub fn load(path: &Path) -> Result<Vec<Event>, AppError> {
    let text = std::fs::read_to_string(path).map_err(|e| AppError::io(path, e))?;
    parse(&text, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_command_and_sorts_by_frame() {
        let text = "\
            # a comment\n\
            @20 exit\n\
            @3 click 10 20   # trailing comment\n\
            @4 drag 1 2 3 4 shift\n\
            @5 effect hatching-pen\n\
            @6 resize 0 0\n\
            @7 screenshot out.png\n\
            @8 turntable on\n";
        let ev = parse(text, Path::new("s.txt")).unwrap();
        assert_eq!(ev.len(), 7);
        assert_eq!(ev[0].command, Command::Click(10.0, 20.0));
        assert_eq!(
            ev[1].command,
            Command::Drag([1.0, 2.0, 3.0, 4.0], "shift".into())
        );
        assert_eq!(ev[2].command, Command::Effect(Effect::HatchingPen));
        assert_eq!(ev[3].command, Command::Resize(0, 0));
        assert_eq!(ev.last().unwrap().command, Command::Exit);
    }

    #[test]
    fn errors_name_the_file_and_line() {
        for bad in [
            "click 1 2",
            "@x click 1 2",
            "@1 fly",
            "@1 click 1",
            "@1 effect blur",
        ] {
            let e = parse(&format!("\n{bad}\n"), Path::new("s.txt")).unwrap_err();
            assert!(e.to_string().contains("s.txt:2"), "{e}");
        }
    }
}
