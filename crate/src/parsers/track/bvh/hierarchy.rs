//! The `HIERARCHY` of a BVH file: its joints, offsets and channels, read
//! from a lazy stream of tokens (see [`super`] for the format and what is
//! refused).

use glam::DVec3;

use super::{MAX_BVH_JOINTS, MAX_BVH_VALUE};
use crate::error::FieldError;

/// Longest joint name (characters).
const MAX_NAME: usize = 200;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Channel {
    Position(usize),
    Rotation(usize),
}

impl Channel {
    fn from_name(name: &str) -> Option<Self> {
        let axis = match name.as_bytes().first() {
            Some(b'X' | b'x') => 0,
            Some(b'Y' | b'y') => 1,
            Some(b'Z' | b'z') => 2,
            _ => return None,
        };
        match name.get(1..).map(str::to_ascii_lowercase).as_deref() {
            Some("position") => Some(Self::Position(axis)),
            Some("rotation") => Some(Self::Rotation(axis)),
            _ => None,
        }
    }

    pub(super) fn name(self) -> String {
        let (axis, kind) = match self {
            Self::Position(a) => (a, "position"),
            Self::Rotation(a) => (a, "rotation"),
        };
        format!("{}{kind}", ["X", "Y", "Z"][axis])
    }
}

/// One joint of the hierarchy.
#[derive(Clone, Debug)]
pub(crate) struct Joint {
    pub name: String,
    pub(super) parent: Option<usize>,
    pub(super) offset: DVec3,
    pub(super) channels: Vec<Channel>,
    /// Index of its first channel in a frame's values.
    pub(super) first: usize,
    /// Its first `End Site`'s offset.
    pub(super) end: Option<DVec3>,
}

/// The hierarchy: joints in the file's order (a parent before its
/// children) and the number of values per frame.
#[derive(Clone, Debug)]
pub(crate) struct Hierarchy {
    pub joints: Vec<Joint>,
    pub(super) channels: usize,
}

/// A lazy stream of whitespace-separated tokens with their line numbers.
pub(super) struct Tokens<'a> {
    pub(super) lines: std::iter::Enumerate<std::str::Lines<'a>>,
    pub(super) line: usize,
    rest: std::str::SplitWhitespace<'a>,
}

impl<'a> Tokens<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().enumerate(),
            line: 0,
            rest: "".split_whitespace(),
        }
    }

    pub(super) fn next(&mut self) -> Option<(usize, &'a str)> {
        loop {
            if let Some(t) = self.rest.next() {
                return Some((self.line, t));
            }
            let (k, l) = self.lines.next()?;
            self.line = k + 1;
            self.rest = l.split_whitespace();
        }
    }

    /// The next token on the current line.
    pub(super) fn same_line(&mut self) -> Option<&'a str> {
        self.rest.next()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Open {
    Joint(usize),
    End(usize),
}

pub(super) fn number(field: &str, token: Option<&str>) -> Result<f64, FieldError> {
    let Some(token) = token else {
        return Err(FieldError::new(field, "expected a number, the line ends"));
    };
    match token.parse::<f64>() {
        Ok(x) if x.is_finite() && x.abs() <= MAX_BVH_VALUE => Ok(x),
        Ok(x) if x.is_finite() => Err(FieldError::new(
            field,
            format!("{x} is beyond ±{MAX_BVH_VALUE:e}"),
        )),
        Ok(_) => Err(FieldError::new(
            field,
            format!("\"{token}\" is not a finite number"),
        )),
        Err(_) => Err(FieldError::new(
            field,
            format!("\"{}\" is not a number", clip(token)),
        )),
    }
}

/// At most 40 characters of `s`, for messages.
pub(super) fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(40).collect();
    if out.len() < s.len() {
        out.push('…');
    }
    out
}

/// The name after `ROOT` or `JOINT` (the rest of the line, a trailing `{`
/// opening its block) and whether the `{` was there.
fn joint_name(tok: &mut Tokens<'_>, line: usize) -> Result<(String, bool), FieldError> {
    let mut words: Vec<&str> = Vec::new();
    let mut brace = false;
    while let Some(w) = tok.same_line() {
        if w == "{" {
            brace = true;
            break;
        }
        words.push(w);
        if words.len() > MAX_NAME {
            break;
        }
    }
    let name = words.join(" ");
    if name.is_empty() {
        return Err(FieldError::new(
            format!("line {line}"),
            "a joint needs a name",
        ));
    }
    if name.chars().count() > MAX_NAME {
        return Err(FieldError::new(
            format!("line {line}"),
            format!("a joint name of at most {MAX_NAME} characters"),
        ));
    }
    if let Some(extra) = tok.same_line() {
        return Err(FieldError::new(
            format!("line {line}"),
            format!("unexpected \"{}\" after the joint's {{", clip(extra)),
        ));
    }
    Ok((name, brace))
}

/// Reads the channels of joint `j` (after `CHANNELS`).
fn channels(tok: &mut Tokens<'_>, joint: &mut Joint, first: usize) -> Result<(), FieldError> {
    let field = format!("{}.CHANNELS", joint.name);
    if !joint.channels.is_empty() {
        return Err(FieldError::new(field, "given twice"));
    }
    let n = tok
        .next()
        .and_then(|(_, t)| t.parse::<usize>().ok())
        .filter(|n| *n <= 6)
        .ok_or_else(|| FieldError::new(&field, "expected a count of 0 to 6 channels"))?;
    for _ in 0..n {
        let (_, t) = tok.next().unwrap_or((0, ""));
        let c = Channel::from_name(t).ok_or_else(|| {
            FieldError::new(
                &field,
                format!(
                    "unknown channel \"{}\" (expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)",
                    clip(t)
                ),
            )
        })?;
        joint.channels.push(c);
    }
    joint.first = first;
    Ok(())
}

/// The hierarchy as it is read: the joints so far, the blocks open, a
/// block named but not yet opened by its `{`, and the channels counted.
struct Reader {
    joints: Vec<Joint>,
    stack: Vec<Open>,
    pending: Option<Open>,
    count: usize,
}

/// Reads the `HIERARCHY` up to and including `MOTION`.
pub(super) fn hierarchy(tok: &mut Tokens<'_>) -> Result<Hierarchy, FieldError> {
    if !matches!(tok.next(), Some((_, "HIERARCHY"))) {
        return Err(FieldError::new(
            "HIERARCHY",
            "a BVH file starts with HIERARCHY",
        ));
    }
    let mut r = Reader {
        joints: Vec::new(),
        stack: Vec::new(),
        pending: None,
        count: 0,
    };
    loop {
        let Some((line, t)) = tok.next() else {
            return Err(FieldError::new(
                "MOTION",
                "missing: the file ends inside its HIERARCHY (truncated?)",
            ));
        };
        let at = format!("line {line}");
        if r.pending.is_some() && t != "{" {
            return Err(FieldError::new(
                at,
                format!("expected {{, got \"{}\"", clip(t)),
            ));
        }
        if r.token(tok, t, line, at)? {
            break;
        }
    }
    if r.count == 0 {
        return Err(FieldError::new("HIERARCHY", "no joint has CHANNELS"));
    }
    Ok(Hierarchy {
        joints: r.joints,
        channels: r.count,
    })
}

impl Reader {
    /// Reads what token `t` (on `line`, `at` for messages) begins; `true`
    /// at `MOTION`, the end of the hierarchy.
    fn token(
        &mut self,
        tok: &mut Tokens<'_>,
        t: &str,
        line: usize,
        at: String,
    ) -> Result<bool, FieldError> {
        match t {
            "ROOT" | "JOINT" => self.joint(tok, t, line, at)?,
            "End" => self.end_site(tok, at)?,
            "{" => match self.pending.take() {
                Some(p) => self.stack.push(p),
                None => return Err(FieldError::new(at, "unexpected {")),
            },
            "}" => {
                if self.stack.pop().is_none() {
                    return Err(FieldError::new(at, "unmatched }"));
                }
            }
            "OFFSET" => self.offset(tok, at)?,
            "CHANNELS" => {
                let Some(Open::Joint(j)) = self.stack.last().copied() else {
                    return Err(FieldError::new(at, "CHANNELS outside a joint's braces"));
                };
                channels(tok, &mut self.joints[j], self.count)?;
                self.count += self.joints[j].channels.len();
            }
            "MOTION" => {
                self.motion()?;
                return Ok(true);
            }
            other => {
                return Err(FieldError::new(
                    at,
                    format!("unexpected \"{}\" in the HIERARCHY", clip(other)),
                ));
            }
        }
        Ok(false)
    }

    /// A `ROOT` or `JOINT` (`t`) and its name.
    fn joint(
        &mut self,
        tok: &mut Tokens<'_>,
        t: &str,
        line: usize,
        at: String,
    ) -> Result<(), FieldError> {
        let parent = match (t, self.stack.last()) {
            ("ROOT", None) if self.joints.is_empty() => None,
            ("ROOT", _) => {
                return Err(FieldError::new(
                    "ROOT",
                    format!("only one ROOT, at the top of the HIERARCHY (another on line {line})"),
                ));
            }
            (_, Some(Open::Joint(p))) => Some(*p),
            _ => return Err(FieldError::new(at, "JOINT outside a joint's braces")),
        };
        let (name, brace) = joint_name(tok, line)?;
        if self.joints.len() >= MAX_BVH_JOINTS {
            return Err(FieldError::new(
                "HIERARCHY",
                format!("at most {MAX_BVH_JOINTS} joints"),
            ));
        }
        self.joints.push(Joint {
            name,
            parent,
            offset: DVec3::ZERO,
            channels: Vec::new(),
            first: 0,
            end: None,
        });
        let open = Open::Joint(self.joints.len() - 1);
        if brace {
            self.stack.push(open);
        } else {
            self.pending = Some(open);
        }
        Ok(())
    }

    /// An `End Site` of the joint whose block is open.
    fn end_site(&mut self, tok: &mut Tokens<'_>, at: String) -> Result<(), FieldError> {
        let Some(Open::Joint(j)) = self.stack.last().copied() else {
            return Err(FieldError::new(at, "End Site outside a joint's braces"));
        };
        if tok.same_line() != Some("Site") {
            return Err(FieldError::new(at, "expected End Site"));
        }
        match tok.same_line() {
            Some("{") => self.stack.push(Open::End(j)),
            None => self.pending = Some(Open::End(j)),
            Some(x) => {
                return Err(FieldError::new(at, format!("unexpected \"{}\"", clip(x))));
            }
        }
        Ok(())
    }

    /// The `OFFSET` of the joint or end site whose block is open.
    fn offset(&mut self, tok: &mut Tokens<'_>, at: String) -> Result<(), FieldError> {
        let (j, end) = match self.stack.last() {
            Some(Open::Joint(j)) => (*j, false),
            Some(Open::End(j)) => (*j, true),
            None => return Err(FieldError::new(at, "OFFSET outside a joint's braces")),
        };
        let field = format!(
            "{}.{}OFFSET",
            self.joints[j].name,
            if end { "End Site." } else { "" }
        );
        let mut v = DVec3::ZERO;
        for k in 0..3 {
            v[k] = number(&field, tok.same_line())?;
        }
        if end {
            self.joints[j].end.get_or_insert(v);
        } else {
            self.joints[j].offset = v;
        }
        Ok(())
    }

    /// `MOTION`: the hierarchy must have a root and every block closed.
    fn motion(&self) -> Result<(), FieldError> {
        if self.joints.is_empty() {
            return Err(FieldError::new(
                "ROOT",
                "missing: the HIERARCHY has no ROOT",
            ));
        }
        if !self.stack.is_empty() {
            return Err(FieldError::new(
                "HIERARCHY",
                format!(
                    "{} braces left open before MOTION (a missing }})",
                    self.stack.len()
                ),
            ));
        }
        Ok(())
    }
}

impl Joint {
    /// Whether the joint has an `End Site`.
    pub(crate) fn has_end(&self) -> bool {
        self.end.is_some()
    }
}
