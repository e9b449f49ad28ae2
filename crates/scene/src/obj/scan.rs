//! A first pass over the OBJ text before `tobj` parses it.
//!
//! `tobj` trusts face indices in places (its texture-coordinate and normal lookups multiply an
//! unchecked index, which overflows, a panic in debug builds, for a relative index that reaches
//! before the first element), reads `l` polylines as polygons, and reports errors without a line
//! number. This pass checks every face index against the elements defined so far (relative
//! indices) or in the whole file (absolute ones), names the offending line, and collects what
//! the loader needs before parsing: the `mtllib` statements and the `usemtl` names.

use std::collections::HashSet;

/// What the scan found. Line numbers are 1-based.
#[derive(Debug, Default)]
pub(super) struct Scan {
    /// The `mtllib` statements in file order (one entry per statement, as `tobj` asks for them).
    pub mtllibs: Vec<MtlLib>,
    /// Distinct `usemtl` names with the line of their first use.
    pub used_materials: Vec<(String, usize)>,
    /// Faces with one or two vertices: `tobj` is told to ignore them.
    pub short_faces: usize,
    /// `l` statements: removed from the text `tobj` sees, which would read them as faces.
    pub polylines: usize,
    /// `usemtl`, `mtllib`, `o` and `g` statements that are indented or separate their argument
    /// with something other than one space, which `tobj` misreads; such text is rewritten.
    pub irregular_statements: usize,
    /// `v` statements.
    pub vertices: usize,
    /// `f` statements with three or more vertices.
    pub faces: usize,
    /// Lines whose first word is no OBJ statement we know.
    pub unknown_lines: usize,
}

#[derive(Debug)]
pub(super) struct MtlLib {
    pub line: usize,
    /// Everything after the keyword, trimmed: one file name, or several separated by spaces.
    pub argument: String,
}

impl Scan {
    /// Whether `tobj` must see a cleaned copy of the text (see [`rewrite`]).
    pub fn needs_rewrite(&self) -> bool {
        self.polylines > 0 || self.irregular_statements > 0
    }
}

/// Element kinds a face vertex refers to: position, texture coordinate, normal.
const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];
const KINDS_PLURAL: [&str; 3] = ["vertices", "texture coordinates", "normals"];

/// Per kind: the elements defined so far (for relative indices), and the largest absolute index
/// seen with its line (checked once the file's totals are known).
#[derive(Default)]
struct IndexBounds {
    counts: [usize; 3],
    max_absolute: [(u64, usize); 3],
}

impl IndexBounds {
    /// Checks one face vertex (`v`, `v/vt`, `v//vn`, `v/vt/vn`), saying what is wrong.
    fn check_token(&mut self, token: &str, line: usize) -> Result<(), String> {
        let mut parts = token.split('/');
        for (kind, name) in KINDS.iter().enumerate() {
            let Some(part) = parts.next() else {
                break;
            };
            if part.is_empty() {
                if kind == 0 {
                    return Err(format!(
                        "line {line}: face vertex '{token}' has no vertex index"
                    ));
                }
                continue;
            }
            let index: i64 = part
                .parse()
                .map_err(|_| format!("line {line}: face vertex '{token}' is not an index"))?;
            match index {
                0 => return Err(format!("line {line}: {name} index 0 (OBJ counts from 1)")),
                i if i > 0 => {
                    let max = &mut self.max_absolute[kind];
                    if i as u64 > max.0 {
                        *max = (i as u64, line);
                    }
                }
                i => {
                    if i.unsigned_abs() > self.counts[kind] as u64 {
                        return Err(format!(
                            "line {line}: relative {name} index {i} reaches before the first \
                             {name} ({} defined so far)",
                            self.counts[kind]
                        ));
                    }
                }
            }
        }
        if parts.next().is_some() {
            return Err(format!(
                "line {line}: face vertex '{token}' has more than three indices"
            ));
        }
        Ok(())
    }

    /// Checks a face's indices without allocating or splitting strings; `None` when anything
    /// is unusual (an error, a `+` sign, non-ASCII text), for the slow path to say what.
    fn face_fast(&mut self, bytes: &[u8], line: usize) -> Option<usize> {
        let mut corners = 0;
        let mut i = 0;
        loop {
            while bytes.get(i).is_some_and(u8::is_ascii_whitespace) {
                i += 1;
            }
            if i == bytes.len() {
                return Some(corners);
            }
            let mut kind = 0;
            loop {
                let negative = bytes.get(i) == Some(&b'-');
                i += negative as usize;
                let digits = i;
                let mut value: u64 = 0;
                while let Some(&digit) = bytes.get(i).filter(|b| b.is_ascii_digit()) {
                    value = value.checked_mul(10)?.checked_add((digit - b'0') as u64)?;
                    i += 1;
                }
                if i == digits {
                    if negative || kind == 0 {
                        return None;
                    }
                } else if !self.accept(kind, negative, value, line) {
                    return None;
                }
                match bytes.get(i) {
                    Some(b'/') if kind < 2 => {
                        kind += 1;
                        i += 1;
                    }
                    Some(b) if b.is_ascii_whitespace() => break,
                    None => break,
                    Some(_) => return None,
                }
            }
            corners += 1;
        }
    }

    /// Records a valid index; `false` for one the slow path must report.
    fn accept(&mut self, kind: usize, negative: bool, value: u64, line: usize) -> bool {
        if value == 0 || value > i64::MAX as u64 {
            return false;
        }
        if negative {
            return value <= self.counts[kind] as u64;
        }
        let max = &mut self.max_absolute[kind];
        if value > max.0 {
            *max = (value, line);
        }
        true
    }

    /// Absolute indices may refer to elements defined later in the file, as `tobj` allows.
    fn check_totals(&self) -> Result<(), String> {
        for kind in 0..KINDS.len() {
            let ((max, line), count) = (self.max_absolute[kind], self.counts[kind]);
            if max > count as u64 {
                let (name, plural) = (KINDS[kind], KINDS_PLURAL[kind]);
                return Err(format!(
                    "line {line}: {name} index {max} out of range (the file has {count} {plural})"
                ));
            }
        }
        Ok(())
    }
}

/// Scans the OBJ text. An error is one line naming the offending line number.
pub(super) fn scan(text: &str) -> Result<Scan, String> {
    let mut scanner = Scanner::default();
    // `str::lines` splits at '\n' and drops a '\r' before it, as `tobj`'s `BufRead::lines`.
    for (number, raw) in text.lines().enumerate() {
        scanner.line(raw, number + 1)?;
    }
    scanner.bounds.check_totals()?;
    Ok(scanner.scan)
}

#[derive(Default)]
struct Scanner {
    scan: Scan,
    bounds: IndexBounds,
    seen_materials: HashSet<String>,
}

impl Scanner {
    /// One line. The common statements (`v`, `vt`, `vn`, `f` in ASCII) take a fast path that
    /// reads bytes; everything else is split into words as `tobj` splits it.
    fn line(&mut self, raw: &str, number: usize) -> Result<(), String> {
        let bytes = raw.as_bytes();
        let start = bytes.iter().position(|b| !matches!(b, b' ' | b'\t'));
        let Some(start) = start else {
            return Ok(());
        };
        let rest = &bytes[start..];
        let ascii_space_after = |n: usize| rest.get(n).is_some_and(|b| b.is_ascii_whitespace());
        match rest[0] {
            b'v' if ascii_space_after(1) => {
                self.scan.vertices += 1;
                self.bounds.counts[0] += 1;
            }
            b'v' if rest.get(1) == Some(&b't') && ascii_space_after(2) => {
                self.bounds.counts[1] += 1
            }
            b'v' if rest.get(1) == Some(&b'n') && ascii_space_after(2) => {
                self.bounds.counts[2] += 1
            }
            b'f' if ascii_space_after(1) => match self.bounds.face_fast(&rest[1..], number) {
                Some(corners) => self.count_face(corners),
                None => self.statement(raw, number)?,
            },
            _ => self.statement(raw, number)?,
        }
        Ok(())
    }

    fn count_face(&mut self, corners: usize) {
        if corners < 3 {
            self.scan.short_faces += 1;
        } else {
            self.scan.faces += 1;
        }
    }

    /// Any statement, read the slow way.
    fn statement(&mut self, raw: &str, number: usize) -> Result<(), String> {
        let line = raw.trim_start();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            return Ok(());
        };
        let scan = &mut self.scan;
        if matches!(keyword, "usemtl" | "mtllib" | "o" | "g") && is_irregular(raw, keyword) {
            scan.irregular_statements += 1;
        }
        match keyword {
            "v" => {
                scan.vertices += 1;
                self.bounds.counts[0] += 1;
            }
            "vt" => self.bounds.counts[1] += 1,
            "vn" => self.bounds.counts[2] += 1,
            "f" => {
                let mut corners = 0;
                for token in words {
                    self.bounds.check_token(token, number)?;
                    corners += 1;
                }
                self.count_face(corners);
            }
            "l" => scan.polylines += 1,
            "usemtl" => {
                let name = argument(line);
                if name.is_empty() {
                    return Err(format!("line {number}: usemtl without a material name"));
                }
                if self.seen_materials.insert(name.to_string()) {
                    scan.used_materials.push((name.to_string(), number));
                }
            }
            "mtllib" => scan.mtllibs.push(MtlLib {
                line: number,
                argument: argument(line).to_string(),
            }),
            k if k.starts_with('#') || KNOWN_STATEMENTS.contains(&k) => {}
            _ => scan.unknown_lines += 1,
        }
        Ok(())
    }
}

/// OBJ statements the loader ignores (free-form geometry, grouping, display attributes).
const KNOWN_STATEMENTS: &[&str] = &[
    "vp",
    "o",
    "g",
    "s",
    "p",
    "cstype",
    "deg",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "lod",
    "usemap",
    "maplib",
    "bevel",
    "c_interp",
    "d_interp",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "bmat",
    "step",
    "call",
    "csh",
];

/// Whether `tobj`'s reading of the statement (split at the first space) would go wrong.
fn is_irregular(raw: &str, keyword: &str) -> bool {
    !raw.starts_with(keyword)
        || raw
            .as_bytes()
            .get(keyword.len())
            .is_some_and(|&separator| separator != b' ')
}

/// A statement's argument as `tobj` reads it: everything after the first space, trimmed.
fn argument(line: &str) -> &str {
    line.split_once(char::is_whitespace)
        .map(|(_, rest)| rest.trim())
        .unwrap_or("")
}

/// The text `tobj` should parse: statements without indentation and without `l` polylines.
pub(super) fn rewrite(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for raw in text.lines() {
        let line = raw.trim_start();
        let is_polyline = line.split_whitespace().next() == Some("l");
        if !is_polyline {
            // `tobj` splits `usemtl`/`mtllib` at the first space: make that space a space.
            match line.split_once(char::is_whitespace) {
                Some((keyword, rest)) => {
                    out.push_str(keyword);
                    out.push(' ');
                    out.push_str(rest);
                }
                None => out.push_str(line),
            }
        }
        out.push('\n');
    }
    out
}

/// The line `tobj`'s error most likely comes from, for the kinds of error the scan leaves to
/// it (malformed `v`, `vt`, `vn` statements). `None` when no line matches.
pub(super) fn locate(text: &str, error: &tobj::LoadError) -> Option<usize> {
    use tobj::LoadError as E;
    let (keyword, bad): (&str, fn(&[&str]) -> bool) = match error {
        E::PositionParseError | E::ScalingByZeroError | E::ColorParseError => ("v", bad_position),
        E::TexcoordParseError => ("vt", |w| !numbers(w, 2)),
        E::NormalParseError => ("vn", |w| !numbers(w, 3)),
        _ => return None,
    };
    text.lines().enumerate().find_map(|(number, line)| {
        let words: Vec<&str> = line.split_whitespace().collect();
        (words.first() == Some(&keyword) && bad(&words[1..])).then_some(number + 1)
    })
}

/// Whether the first `n` words are numbers (`tobj` ignores what follows them).
fn numbers(words: &[&str], n: usize) -> bool {
    words.len() >= n && words[..n].iter().all(|w| w.parse::<f32>().is_ok())
}

/// `tobj` accepts `v x y z`, `v x y z w` (w ≠ 0) and `v x y z r g b`.
fn bad_position(words: &[&str]) -> bool {
    if !numbers(words, 3) {
        return true;
    }
    match words.len() {
        3 | 6 => false,
        4 => words[3].parse::<f32>().map_or(true, |w| w == 0.0),
        _ => true,
    }
}
