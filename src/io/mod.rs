//! Readers and writers.

pub mod arrays;
pub mod carry;
pub mod deck;
pub mod eclipse;
pub mod edg;
pub mod poly;
pub mod schedule;
pub mod svg;
pub mod tetgen;
pub mod tough;
pub mod vtu;
pub mod wellpath;

use crate::complex::Complex;
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// A constraint complex of either dimension.
#[derive(Debug, Clone)]
pub enum Input {
    /// A 2D complex.
    Plane(Complex),
    /// A 3D complex.
    Space(crate::complex::Complex3),
}

/// Reads a constraint complex, the file telling the dimension: .edg is
/// 2D, .smesh 3D, and a .poly says in its header (Triangle's 2D, TetGen's 3D).
pub fn read_input(path: &Path) -> Result<Input> {
    let text = read_text(path)?;
    match extension(path).as_deref() {
        Some("poly") if header_dimension(&text) == Some(3) => {
            tetgen::parse(&text, path, tetgen::Format::Poly)
                .map(Input::Space)
                .map_err(|e| match e {
                    Error::Parse {
                        path,
                        line,
                        message,
                    } => Error::Parse {
                        path,
                        line,
                        message: format!(
                            "{message} (read as TetGen's 3D .poly: its header says dimension 3)"
                        ),
                    },
                    e => e,
                })
        }
        Some("poly") => poly::parse(&text, path).map(Input::Plane),
        Some("edg") => edg::parse(&text, path).map(Input::Plane),
        Some("smesh") => tetgen::parse(&text, path, tetgen::Format::Smesh).map(Input::Space),
        _ => Err(Error::Usage(format!(
            "{}: unknown input format (expected .poly, .edg or .smesh)",
            path.display()
        ))),
    }
}

/// Reads a 2D constraint complex (Triangle .poly or CGAL .edg).
pub fn read_complex(path: &Path) -> Result<Complex> {
    match read_input(path)? {
        Input::Plane(cx) => Ok(cx),
        Input::Space(_) => Err(Error::Usage(format!(
            "{}: a TetGen piecewise linear complex (dimension 3); `io::read_complex3` reads it",
            path.display()
        ))),
    }
}

/// Reads a 3D constraint complex (TetGen `.poly` or `.smesh`), not yet
/// validated.
pub fn read_complex3(path: &Path) -> Result<crate::complex::Complex3> {
    let text = read_text(path)?;
    let format = match extension(path).as_deref() {
        Some("poly") => tetgen::Format::Poly,
        Some("smesh") => tetgen::Format::Smesh,
        _ => {
            return Err(Error::Usage(format!(
                "{}: unknown 3D input format (expected .poly or .smesh)",
                path.display()
            )))
        }
    };
    tetgen::parse(&text, path, format)
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

/// The second number of the first record (a .poly's dimension).
fn header_dimension(text: &str) -> Option<usize> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .find(|l| !l.trim().is_empty())?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

pub(crate) fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
    // A byte-order mark (editors on Windows write one) is not content.
    let bytes = bytes
        .strip_prefix(b"\xEF\xBB\xBF")
        .unwrap_or(&bytes)
        .to_vec();
    String::from_utf8(bytes).map_err(|_| Error::Io {
        path: path.into(),
        message: "not UTF-8 text".into(),
    })
}

pub(crate) fn io_err(path: &Path, e: std::io::Error) -> Error {
    Error::Io {
        path: path.into(),
        message: e.to_string(),
    }
}

/// Writes a file whole or not at all: to a temporary sibling, then renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    // A temporary name of its own per writer (process, call): two writers
    // of one path never rename each other's file away; the last rename wins.
    static CALLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut tmp: PathBuf = path.into();
    let name = format!(
        ".{}.{}-{call}.partial",
        path.file_name().and_then(|n| n.to_str()).unwrap_or("out"),
        std::process::id()
    );
    tmp.set_file_name(name);
    std::fs::write(&tmp, bytes).map_err(|e| io_err(path, e))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io_err(path, e)
    })
}

/// Input index of each file id.
pub(crate) fn index_of(ids: &[i64]) -> std::collections::HashMap<i64, u32> {
    ids.iter()
        .enumerate()
        .map(|(i, &id)| (id, i as u32))
        .collect()
}

/// Token 0 of a record as a vertex id, which must follow `prev` (ids are
/// consecutive).
pub(crate) fn next_id(r: &Records, line: usize, t: &[&str], prev: Option<&i64>) -> Result<i64> {
    let id: i64 = r.num(line, t, 0, "vertex id")?;
    match prev {
        Some(prev) if id != prev + 1 => Err(r.error(
            line,
            format!("vertex id {id} after {prev}: ids must be consecutive"),
        )),
        _ => Ok(id),
    }
}

/// The vertices of a Triangle or TetGen file (records `id x y [z]`):
/// after its header `count dimension ...` at `line`, or, when the count
/// is 0, in the .node file next to `path`. `noun` names them in messages.
pub(crate) fn read_nodes<const D: usize>(
    r: &mut Records,
    (line, head): (usize, &[&str]),
    path: &Path,
    noun: &str,
    wrong_dimension: &dyn Fn(usize) -> String,
) -> Result<(Vec<[f64; D]>, Vec<i64>)> {
    if r.num::<usize>(line, head, 0, &format!("{noun} count"))? == 0 {
        let node_path = path.with_extension("node");
        let node_text = read_text(&node_path)?;
        let mut nr = Records::new(&node_text, &node_path);
        let (line, head) = nr.next_record(&format!("the {noun} header"))?;
        return node_list(&mut nr, (line, &head), noun, wrong_dimension);
    }
    node_list(r, (line, head), noun, wrong_dimension)
}

fn node_list<const D: usize>(
    r: &mut Records,
    (line, head): (usize, &[&str]),
    noun: &str,
    wrong_dimension: &dyn Fn(usize) -> String,
) -> Result<(Vec<[f64; D]>, Vec<i64>)> {
    let n: usize = r.num(line, head, 0, &format!("{noun} count"))?;
    let dim: usize = r.num(line, head, 1, "dimension").unwrap_or(D);
    if dim != D {
        return Err(r.error(line, wrong_dimension(dim)));
    }
    // No capacity from the header: a huge count must end at the missing
    // records, not in the allocator.
    let (mut points, mut ids) = (vec![], vec![]);
    for k in 1..=n {
        let (line, t) = r.next_record(&format!("{noun} {k} of {n}"))?;
        ids.push(next_id(r, line, &t, ids.last())?);
        points.push(coordinates(r, line, &t)?);
    }
    Ok((points, ids))
}

/// Tokens 1..=D of a record `id x y [z]` as a point.
pub(crate) fn coordinates<const D: usize>(
    r: &Records,
    line: usize,
    t: &[&str],
) -> Result<[f64; D]> {
    let mut p = [0.0; D];
    for (i, x) in p.iter_mut().enumerate() {
        *x = r.num(
            line,
            t,
            i + 1,
            &format!("{} coordinate", ["x", "y", "z"][i]),
        )?;
    }
    Ok(p)
}

/// Non-blank, non-comment lines of a text file as (1-based line, tokens),
/// with `#` starting a comment.
pub(crate) struct Records<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    path: &'a Path,
    last_line: usize,
}

impl<'a> Records<'a> {
    pub fn new(text: &'a str, path: &'a Path) -> Self {
        Records {
            lines: text.lines().enumerate(),
            path,
            last_line: 0,
        }
    }

    /// The next record, or a parse error saying what was expected.
    pub fn next_record(&mut self, what: &str) -> Result<(usize, Vec<&'a str>)> {
        for (i, line) in self.lines.by_ref() {
            let content = line.split('#').next().unwrap_or("");
            let toks: Vec<&str> = content.split_whitespace().collect();
            self.last_line = i + 1;
            if !toks.is_empty() {
                return Ok((i + 1, toks));
            }
        }
        Err(self.error(
            self.last_line + 1,
            format!("file ends where {what} was expected (truncated?)"),
        ))
    }

    /// Whether any record is left.
    pub fn at_end(&mut self) -> bool {
        let rest = self.lines.clone();
        for (_, line) in rest {
            if !line.split('#').next().unwrap_or("").trim().is_empty() {
                return false;
            }
        }
        true
    }

    pub fn error(&self, line: usize, message: String) -> Error {
        Error::Parse {
            path: self.path.into(),
            line,
            message,
        }
    }

    /// Parses token `k` of a record.
    pub fn num<T: std::str::FromStr>(
        &self,
        line: usize,
        toks: &[&str],
        k: usize,
        what: &str,
    ) -> Result<T> {
        let t = toks
            .get(k)
            .ok_or_else(|| self.error(line, format!("missing {what}")))?;
        t.parse()
            .map_err(|_| self.error(line, format!("{what}: cannot read '{t}' as a number")))
    }
}
