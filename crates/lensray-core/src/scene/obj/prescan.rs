//! The check of an OBJ file's text before tobj parses it: what tobj would either not locate
//! (errors name the line here) or not survive (it panics on some malformed indices).

use std::path::Path;
use std::str::SplitWhitespace;

use crate::scene::SceneError;

/// What a face index refers to, by its place in a corner (`v/vt/vn`).
const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];

/// What the pre-scan learned.
pub(super) struct Scan {
    /// Whether the file has `l` statements.
    pub(super) polylines: bool,
    /// `usemtl` statements: line and material name.
    pub(super) usemtl: Vec<(usize, String)>,
    pub(super) first_mtllib: Option<usize>,
}

/// Whether `line` is a polyline (`l`) statement.
pub(super) fn is_polyline(line: &str) -> bool {
    line.split_whitespace().next() == Some("l")
}

/// Checks vertex and normal values and face indices line by line, so that errors name the line.
pub(super) fn prescan(path: &Path, text: &str) -> Result<Scan, SceneError> {
    let mut scanner = Scanner {
        path,
        counts: [0; 3],
        max_positive: [(0, 0); 3],
        scan: Scan {
            polylines: false,
            usemtl: Vec::new(),
            first_mtllib: None,
        },
    };
    for (index, raw) in text.lines().enumerate() {
        scanner.statement(index + 1, raw)?;
    }
    scanner.finish()
}

/// The pre-scan's state between lines.
struct Scanner<'a> {
    path: &'a Path,
    /// Statements so far of each kind: v, vt, vn.
    counts: [usize; 3],
    /// Largest positive index of each kind and its line: checked against the final counts, since
    /// tobj resolves positive indices when an object ends.
    max_positive: [(i64, usize); 3],
    scan: Scan,
}

impl Scanner<'_> {
    /// A malformed statement at `line`.
    fn bad(&self, line: usize, reason: String) -> SceneError {
        SceneError::ObjLine {
            path: self.path.to_path_buf(),
            line,
            reason,
        }
    }

    /// Checks one line, `raw`, numbered `line`.
    fn statement(&mut self, line: usize, raw: &str) -> Result<(), SceneError> {
        let mut words = raw.split_whitespace();
        let Some(key) = words.next() else {
            return Ok(());
        };
        match key {
            "v" | "vn" => self.vector(key, words, line, raw)?,
            "vt" => self.counts[1] += 1,
            "f" | "l" => self.face(key, words, line)?,
            "usemtl" => {
                // The name as tobj reads it: everything after the line's first space.
                let name = raw.split_once(' ').unwrap_or_default().1.trim();
                if name.is_empty() {
                    return Err(self.bad(line, "usemtl needs a material name after a space".into()));
                }
                self.scan.usemtl.push((line, name.to_string()));
            }
            "mtllib" => {
                self.scan.first_mtllib.get_or_insert(line);
            }
            _ => {}
        }
        Ok(())
    }

    /// A vertex position (`v`) or normal (`vn`): three finite numbers.
    fn vector(
        &mut self,
        key: &str,
        mut words: SplitWhitespace,
        line: usize,
        raw: &str,
    ) -> Result<(), SceneError> {
        let what = if key == "v" {
            "vertex position"
        } else {
            "vertex normal"
        };
        let mut xyz = [0.0f32; 3];
        for c in &mut xyz {
            *c = words.next().and_then(|w| w.parse().ok()).ok_or_else(|| {
                self.bad(
                    line,
                    format!("{what} needs three numbers: `{}`", raw.trim()),
                )
            })?;
        }
        if !xyz.iter().all(|c| c.is_finite()) {
            return Err(SceneError::NonFinite {
                path: self.path.to_path_buf(),
                line,
                what,
                text: raw.trim().into(),
            });
        }
        self.counts[if key == "v" { 0 } else { 2 }] += 1;
        Ok(())
    }

    /// A face (`f`, at least three corners) or a polyline (`l`): every corner's indices.
    fn face(&mut self, key: &str, words: SplitWhitespace, line: usize) -> Result<(), SceneError> {
        let mut corners = 0;
        for word in words {
            corners += 1;
            self.corner(word, line)?;
        }
        self.scan.polylines |= key == "l";
        if key == "f" && corners < 3 {
            return Err(self.bad(
                line,
                format!("face with {corners} corners (needs at least 3)"),
            ));
        }
        Ok(())
    }

    /// One corner `v`, `v/vt`, `v//vn` or `v/vt/vn`: a vertex index and at most three, each an
    /// integer; a negative one in range now, a positive one noted for `finish`.
    fn corner(&mut self, word: &str, line: usize) -> Result<(), SceneError> {
        for (kind, part) in word.split('/').enumerate() {
            if part.is_empty() {
                if kind == 0 {
                    return Err(self.bad(line, format!("face corner `{word}` has no vertex index")));
                }
                continue;
            }
            if kind > 2 {
                return Err(self.bad(line, format!("face corner `{word}` has too many indices")));
            }
            let i: i64 = part
                .parse()
                .map_err(|_| self.bad(line, format!("face index `{part}` is not an integer")))?;
            let count = self.counts[kind];
            let out_of_range = if i > 0 {
                if i > self.max_positive[kind].0 {
                    self.max_positive[kind] = (i, line);
                }
                false
            } else {
                i == 0 || i.unsigned_abs() as usize > count
            };
            if out_of_range {
                return Err(SceneError::IndexOutOfRange {
                    path: self.path.to_path_buf(),
                    line,
                    kind: KINDS[kind],
                    index: i,
                    count,
                });
            }
        }
        Ok(())
    }

    /// The scan, once the largest positive index of each kind is within the file's count.
    fn finish(self) -> Result<Scan, SceneError> {
        for (kind, &(i, line)) in self.max_positive.iter().enumerate() {
            if i as u64 > self.counts[kind] as u64 {
                return Err(SceneError::IndexOutOfRange {
                    path: self.path.to_path_buf(),
                    line,
                    kind: KINDS[kind],
                    index: i,
                    count: self.counts[kind],
                });
            }
        }
        Ok(self.scan)
    }
}
