//! pbrt's scene text as tokens (`#` comments, quoted strings with escapes, `[` `]`, words and
//! numbers), and the parameter lists directives take: `"type name" value` or
//! `"type name" [ values ]`.

use std::cell::Cell;

/// One token and the line (from 1) it starts on.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Token<'a> {
    pub kind: Kind<'a>,
    pub line: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Kind<'a> {
    /// A directive's name, a number or an unquoted `true`/`false`.
    Word(&'a str),
    /// A quoted string, its escapes undone.
    Quoted(String),
    Open,
    Close,
}

/// Tokens read one at a time from a file's text, with one of look-ahead.
pub(super) struct Tokens<'a> {
    text: &'a str,
    at: usize,
    line: u32,
    peeked: Option<Token<'a>>,
}

impl<'a> Tokens<'a> {
    pub fn new(text: &'a str) -> Tokens<'a> {
        Tokens {
            text,
            at: 0,
            line: 1,
            peeked: None,
        }
    }

    pub fn peek(&mut self) -> Result<Option<&Token<'a>>, String> {
        if self.peeked.is_none() {
            self.peeked = self.read()?;
        }
        Ok(self.peeked.as_ref())
    }

    pub fn next(&mut self) -> Result<Option<Token<'a>>, String> {
        match self.peeked.take() {
            Some(token) => Ok(Some(token)),
            None => self.read(),
        }
    }

    fn read(&mut self) -> Result<Option<Token<'a>>, String> {
        let bytes = self.text.as_bytes();
        loop {
            while self.at < bytes.len() && bytes[self.at].is_ascii_whitespace() {
                if bytes[self.at] == b'\n' {
                    self.line += 1;
                }
                self.at += 1;
            }
            if self.at < bytes.len() && bytes[self.at] == b'#' {
                while self.at < bytes.len() && bytes[self.at] != b'\n' {
                    self.at += 1;
                }
                continue;
            }
            break;
        }
        let Some(&first) = bytes.get(self.at) else {
            return Ok(None);
        };
        let line = self.line;
        let token = |kind| Ok(Some(Token { kind, line }));
        match first {
            b'[' | b']' => {
                self.at += 1;
                token(if first == b'[' {
                    Kind::Open
                } else {
                    Kind::Close
                })
            }
            b'"' => {
                self.at += 1;
                let mut text = String::new();
                loop {
                    let Some(c) = self.text[self.at..].chars().next() else {
                        return Err(format!("line {line}: a string is not closed"));
                    };
                    self.at += c.len_utf8();
                    match c {
                        '"' => break,
                        '\n' => return Err(format!("line {line}: a string runs past its line")),
                        '\\' => {
                            let Some(e) = self.text[self.at..].chars().next() else {
                                return Err(format!("line {line}: a string is not closed"));
                            };
                            self.at += e.len_utf8();
                            text.push(match e {
                                'n' => '\n',
                                't' => '\t',
                                'b' => '\u{8}',
                                'f' => '\u{c}',
                                'r' => '\r',
                                other => other,
                            });
                        }
                        c => text.push(c),
                    }
                }
                token(Kind::Quoted(text))
            }
            _ => {
                let start = self.at;
                while self.at < bytes.len()
                    && !bytes[self.at].is_ascii_whitespace()
                    && !matches!(bytes[self.at], b'"' | b'[' | b']' | b'#')
                {
                    self.at += 1;
                }
                token(Kind::Word(&self.text[start..self.at]))
            }
        }
    }

    /// The next token, which must be a quoted string (`what` names it in the error).
    pub fn string(&mut self, what: &str) -> Result<String, String> {
        match self.next()? {
            Some(Token {
                kind: Kind::Quoted(s),
                ..
            }) => Ok(s),
            other => Err(format!(
                "line {}: expected {what} (a quoted string), found {}",
                self.line,
                describe(other.as_ref())
            )),
        }
    }

    /// `count` numbers, bracketed or not.
    pub fn numbers(&mut self, count: usize, what: &str) -> Result<Vec<f64>, String> {
        let bracketed = matches!(
            self.peek()?,
            Some(Token {
                kind: Kind::Open,
                ..
            })
        );
        if bracketed {
            self.next()?;
        }
        let mut values = Vec::with_capacity(count);
        for _ in 0..count {
            match self.next()? {
                Some(Token {
                    kind: Kind::Word(w),
                    line,
                }) => values.push(number(w, line)?),
                other => {
                    return Err(format!(
                        "line {}: {what} takes {count} numbers, found {}",
                        self.line,
                        describe(other.as_ref())
                    ));
                }
            }
        }
        if bracketed {
            match self.next()? {
                Some(Token {
                    kind: Kind::Close, ..
                }) => {}
                other => {
                    return Err(format!(
                        "line {}: {what} takes {count} numbers, found {} after them",
                        self.line,
                        describe(other.as_ref())
                    ));
                }
            }
        }
        Ok(values)
    }

    /// A parameter list: every `"type name" value(s)` up to the next directive.
    pub fn params(&mut self) -> Result<Params, String> {
        let mut params = Vec::new();
        while let Some(Token {
            kind: Kind::Quoted(_),
            ..
        }) = self.peek()?
        {
            let Some(Token {
                kind: Kind::Quoted(declaration),
                line,
            }) = self.next()?
            else {
                unreachable!("peeked a quoted string")
            };
            let mut words = declaration.split_whitespace();
            let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
                return Err(format!(
                    "line {line}: \"{declaration}\" is not a parameter's \"type name\""
                ));
            };
            let values = self.values(ty, name, line)?;
            params.push(Param {
                ty: ty.to_string(),
                name: name.to_string(),
                values,
                line,
                used: Cell::new(false),
            });
        }
        Ok(Params(params))
    }

    /// A parameter's value or bracketed values, read as `ty` says.
    fn values(&mut self, ty: &str, name: &str, line: u32) -> Result<Values, String> {
        let textual = matches!(ty, "string" | "texture" | "bool");
        let spectral = ty == "spectrum";
        let mut words: Vec<Token> = Vec::new();
        match self.next()? {
            Some(Token {
                kind: Kind::Open, ..
            }) => loop {
                match self.next()? {
                    Some(Token {
                        kind: Kind::Close, ..
                    }) => break,
                    Some(Token {
                        kind: Kind::Open, ..
                    }) => return Err(format!("line {line}: \"{name}\": a [ inside [ ]")),
                    Some(token) => words.push(token),
                    None => return Err(format!("line {line}: \"{name}\": a [ is not closed")),
                }
            },
            Some(Token {
                kind: Kind::Close, ..
            })
            | None => return Err(format!("line {line}: \"{name}\" has no value")),
            Some(token) => words.push(token),
        };
        let quoted = words.iter().any(|t| matches!(t.kind, Kind::Quoted(_)));
        if textual || (spectral && quoted) {
            let strings = words.into_iter().map(|t| match t.kind {
                Kind::Quoted(s) => Ok(s),
                Kind::Word(w) if ty == "bool" => Ok(w.to_string()),
                _ => Err(format!("line {line}: \"{name}\" takes quoted strings")),
            });
            let strings = strings.collect::<Result<Vec<_>, _>>()?;
            if ty != "bool" {
                return Ok(Values::Strings(strings));
            }
            let bools = strings.iter().map(|s| match s.as_str() {
                "true" => Ok(true),
                "false" => Ok(false),
                other => Err(format!(
                    "line {line}: \"{name}\": \"{other}\" is not true or false"
                )),
            });
            return Ok(Values::Bools(bools.collect::<Result<_, _>>()?));
        }
        let numbers = words.into_iter().map(|t| match t.kind {
            Kind::Word(w) => number(w, t.line),
            _ => Err(format!("line {line}: \"{name}\" takes numbers")),
        });
        Ok(Values::Numbers(numbers.collect::<Result<_, _>>()?))
    }
}

fn number(word: &str, line: u32) -> Result<f64, String> {
    match word.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("line {line}: \"{word}\" is not a number")),
    }
}

fn describe(token: Option<&Token>) -> String {
    match token.map(|t| &t.kind) {
        None => "the end of the file".into(),
        Some(Kind::Word(w)) => w.to_string(),
        Some(Kind::Quoted(s)) => format!("\"{s}\""),
        Some(Kind::Open) => "[".into(),
        Some(Kind::Close) => "]".into(),
    }
}

/// A parameter: its type and name as declared, its values, its line, and whether the reader
/// used it (pbrt warns of those it does not; so does kousen).
#[derive(Clone, Debug)]
pub(super) struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub line: u32,
    pub used: Cell<bool>,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// A directive's parameter list.
#[derive(Clone, Debug, Default)]
pub(super) struct Params(pub Vec<Param>);

impl Params {
    /// The parameter `name` (of any type), marked used. A later one of the same name wins,
    /// as pbrt's dictionaries do when a named material's parameters are overridden.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let found = self.0.iter().rev().find(|p| p.name == name)?;
        found.used.set(true);
        Some(found)
    }

    /// The parameters no reader asked for, by type and name.
    pub fn unused(&self) -> impl Iterator<Item = &Param> {
        self.0.iter().filter(|p| !p.used.get())
    }

    /// Numbers of parameter `name`, which must have one of `types`.
    pub fn numbers(&self, name: &str, types: &[&str]) -> Result<Option<&[f64]>, String> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        match &p.values {
            Values::Numbers(n) if types.contains(&p.ty.as_str()) => Ok(Some(n)),
            _ => Err(format!(
                "line {}: \"{name}\" must be a {} (found \"{} {name}\")",
                p.line, types[0], p.ty
            )),
        }
    }

    /// One float (a `float` or an `integer`), `default` where absent.
    pub fn float(&self, name: &str, default: f32) -> Result<f32, String> {
        match self.numbers(name, &["float", "integer"])? {
            None => Ok(default),
            Some([x]) => Ok(*x as f32),
            Some(values) => Err(self.count_error(name, values.len(), "one number")),
        }
    }

    /// Whole numbers of an `integer` parameter.
    pub fn integers(&self, name: &str) -> Result<Option<Vec<i64>>, String> {
        let Some(values) = self.numbers(name, &["integer"])? else {
            return Ok(None);
        };
        let whole = values
            .iter()
            .map(|&x| match x.fract() == 0.0 && x.abs() < 9e15 {
                true => Ok(x as i64),
                false => Err(format!("\"{name}\": {x} is not a whole number")),
            });
        whole.collect::<Result<_, _>>().map(Some)
    }

    /// One `integer`, `default` where absent.
    pub fn integer(&self, name: &str, default: i64) -> Result<i64, String> {
        match self.integers(name)?.as_deref() {
            None => Ok(default),
            Some([x]) => Ok(*x),
            Some(values) => Err(self.count_error(name, values.len(), "one integer")),
        }
    }

    /// Groups of `N` numbers of a parameter of one of `types`.
    fn groups<const N: usize>(
        &self,
        name: &str,
        types: &[&str],
    ) -> Result<Option<Vec<[f32; N]>>, String> {
        let Some(values) = self.numbers(name, types)? else {
            return Ok(None);
        };
        if !values.len().is_multiple_of(N) {
            let wanted = format!("a multiple of {N} numbers");
            return Err(self.count_error(name, values.len(), &wanted));
        }
        let groups = values.chunks_exact(N);
        Ok(Some(
            groups
                .map(|c| std::array::from_fn(|i| c[i] as f32))
                .collect(),
        ))
    }

    /// Triples of a point, vector or normal parameter.
    pub fn triples(&self, name: &str) -> Result<Option<Vec<glam::Vec3>>, String> {
        const TRIPLES: [&str; 6] = ["point3", "point", "vector3", "vector", "normal", "normal3"];
        let triples = self.groups::<3>(name, &TRIPLES)?;
        Ok(triples.map(|t| t.into_iter().map(glam::Vec3::from_array).collect()))
    }

    /// One point, `default` where absent.
    pub fn point(&self, name: &str, default: glam::Vec3) -> Result<glam::Vec3, String> {
        match self.triples(name)?.as_deref() {
            None => Ok(default),
            Some([p]) => Ok(*p),
            Some(values) => Err(self.count_error(name, values.len() * 3, "3 numbers")),
        }
    }

    /// Pairs of a `point2` (or pbrt-v3's `float`) parameter.
    pub fn pairs(&self, name: &str) -> Result<Option<Vec<glam::Vec2>>, String> {
        let pairs = self.groups::<2>(name, &["point2", "float", "vector2"])?;
        Ok(pairs.map(|p| p.into_iter().map(glam::Vec2::from_array).collect()))
    }

    /// One `string`, if given.
    pub fn string(&self, name: &str) -> Result<Option<String>, String> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(s) if p.ty == "string" && s.len() == 1 => Ok(Some(s[0].clone())),
            _ => Err(format!(
                "line {}: \"{name}\" must be one string (found \"{} {name}\")",
                p.line, p.ty
            )),
        }
    }

    /// Strings of a `string` parameter.
    pub fn strings(&self, name: &str) -> Result<Option<Vec<String>>, String> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(s) if p.ty == "string" => Ok(Some(s.clone())),
            _ => Err(format!("line {}: \"{name}\" must be strings", p.line)),
        }
    }

    /// One `bool`, `default` where absent.
    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, String> {
        let Some(p) = self.get(name) else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(b) if b.len() == 1 => Ok(b[0]),
            _ => Err(format!(
                "line {}: \"{name}\" must be one bool (found \"{} {name}\")",
                p.line, p.ty
            )),
        }
    }

    fn count_error(&self, name: &str, found: usize, wanted: &str) -> String {
        let line = self
            .0
            .iter()
            .rev()
            .find(|p| p.name == name)
            .map_or(0, |p| p.line);
        format!("line {line}: \"{name}\" takes {wanted}, not {found}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(text: &str) -> Vec<Kind<'_>> {
        let mut tokens = Tokens::new(text);
        let mut out = Vec::new();
        while let Some(t) = tokens.next().unwrap() {
            out.push(t.kind);
        }
        out
    }

    #[test]
    fn tokens_skip_comments_and_undo_escapes() {
        let kinds = all("Shape \"sphere\" # a comment [ \"x\"\n [1 -2.5e1]\"a\\\"b\\\\c\"");
        assert_eq!(
            kinds,
            vec![
                Kind::Word("Shape"),
                Kind::Quoted("sphere".into()),
                Kind::Open,
                Kind::Word("1"),
                Kind::Word("-2.5e1"),
                Kind::Close,
                Kind::Quoted("a\"b\\c".into()),
            ]
        );
    }

    #[test]
    fn parameter_lists_read_every_form() {
        let text = "\"float radius\" 2 \"point3 P\" [0 0 0 1 0 0] \"string filename\" \"a.ply\" \
            \"bool twosided\" true \"bool x\" [\"false\"] \"spectrum eta\" \"glass-BK7\" \
            \"rgb L\" [1 2 3] Shape";
        let mut tokens = Tokens::new(text);
        let params = tokens.params().unwrap();
        assert_eq!(params.float("radius", 1.0), Ok(2.0));
        assert_eq!(params.triples("P").unwrap().unwrap().len(), 2);
        assert_eq!(params.string("filename"), Ok(Some("a.ply".into())));
        assert_eq!(params.boolean("twosided", false), Ok(true));
        assert_eq!(params.boolean("x", true), Ok(false));
        let eta = params.get("eta").unwrap();
        assert_eq!(eta.values, Values::Strings(vec!["glass-BK7".into()]));
        assert!(params.unused().map(|p| p.name.as_str()).eq(["L"]));
        assert_eq!(tokens.next().unwrap().unwrap().kind, Kind::Word("Shape"));
    }

    #[test]
    fn bad_text_says_where() {
        for (text, why) in [
            ("\"float r\" [1 2", "not closed"),
            ("\"float r\" [1 x]", "\"x\" is not a number"),
            ("\"float\" 1", "not a parameter's"),
            ("\"bool b\" \"maybe\"", "not true or false"),
            ("\"string s\n", "runs past its line"),
            ("\n\n\"float r\" ]", "line 3: \"r\" has no value"),
        ] {
            let error = Tokens::new(text).params().unwrap_err();
            assert!(error.contains(why), "{why}: {error}");
        }
        let params = Tokens::new("\"float r\" [1 2]").params().unwrap();
        let error = params.float("r", 0.0).unwrap_err();
        assert!(error.contains("takes one number, not 2"), "{error}");
    }
}
