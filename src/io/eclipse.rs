//! Eclipse keyword files: GRDECL corner-point grids (SPECGRID or DIMENS,
//! COORD, ZCORN, ACTNUM, MAPAXES, FAULTS, INCLUDE) and the wells of a deck
//! (WELSPECS, COMPDAT). Free format: records end with `/`, `--` starts a
//! comment, `N*v` repeats v, `N*` leaves N items defaulted.
//!
//! Frame: everything stays in the frame COORD is written in (the one the
//! simulator computes geometry in). MAPAXES is read and kept, not applied.

use crate::error::{Error, Result};
use crate::reservoir::{CornerPointGrid, Fault, FaultFace};
use std::path::{Path, PathBuf};

/// A token with where it came from.
#[derive(Debug, Clone)]
pub(super) struct Tok {
    pub(super) text: String,
    pub(super) quoted: bool,
    pub(super) file: usize,
    pub(super) line: usize,
}

/// The tokens of a file and of the files it includes, in order.
pub(super) struct Tokens {
    pub(super) toks: Vec<Tok>,
    files: Vec<PathBuf>,
    /// Include files that are missing (only allowed when reading wells).
    missing: Vec<String>,
}

fn parse_err(path: &Path, line: usize, message: String) -> Error {
    Error::Parse {
        path: path.into(),
        line,
        message,
    }
}

fn lex(text: &str, file: usize, out: &mut Vec<Tok>) {
    for (n, line) in text.lines().enumerate() {
        let line = match line.find("--") {
            Some(c) if !line[..c].contains('\'') || line[..c].matches('\'').count() % 2 == 0 => {
                &line[..c]
            }
            _ => line,
        };
        let mut rest = line;
        loop {
            rest = rest.trim_start();
            if rest.is_empty() {
                break;
            }
            let tok = if let Some(r) = rest.strip_prefix('\'') {
                let end = r.find('\'').unwrap_or(r.len());
                let t = (r[..end].to_string(), true);
                rest = r.get(end + 1..).unwrap_or("");
                t
            } else if let Some(r) = rest.strip_prefix('/') {
                rest = r;
                ("/".to_string(), false)
            } else {
                let end = rest
                    .find(|c: char| c.is_whitespace() || c == '/' || c == '\'')
                    .unwrap_or(rest.len());
                let t = (rest[..end].to_string(), false);
                rest = &rest[end..];
                t
            };
            out.push(Tok {
                text: tok.0,
                quoted: tok.1,
                file,
                line: n + 1,
            });
        }
    }
}

impl Tokens {
    /// Reads a file, following INCLUDE records (paths relative to the
    /// including file). Missing includes are errors unless `lenient`.
    pub(super) fn read(path: &Path, lenient: bool) -> Result<Tokens> {
        let mut t = Tokens {
            toks: vec![],
            files: vec![],
            missing: vec![],
        };
        t.add(path, lenient, 0)?;
        Ok(t)
    }

    fn add(&mut self, path: &Path, lenient: bool, depth: usize) -> Result<()> {
        if depth > 16 {
            return Err(parse_err(
                path,
                0,
                "INCLUDE nested more than 16 deep (a cycle?)".into(),
            ));
        }
        let text = super::read_text(path)?;
        let file = self.files.len();
        self.files.push(path.into());
        let mut toks = vec![];
        lex(&text, file, &mut toks);
        let mut k = 0;
        while k < toks.len() {
            if !toks[k].quoted && toks[k].text.eq_ignore_ascii_case("INCLUDE") {
                let name = toks.get(k + 1).filter(|t| t.text != "/").ok_or_else(|| {
                    parse_err(path, toks[k].line, "INCLUDE without a file name".into())
                })?;
                let inc = path.parent().unwrap_or(Path::new(".")).join(&name.text);
                let slash = k + 2;
                if toks.get(slash).is_none_or(|t| t.text != "/") {
                    return Err(parse_err(
                        path,
                        name.line,
                        "INCLUDE record not ended by '/'".into(),
                    ));
                }
                if inc.exists() || !lenient {
                    self.add(&inc, lenient, depth + 1)?;
                } else {
                    self.missing.push(inc.display().to_string());
                }
                k = slash + 1;
                continue;
            }
            self.toks.push(toks[k].clone());
            k += 1;
        }
        Ok(())
    }

    pub(super) fn error(&self, at: &Tok, message: String) -> Error {
        parse_err(&self.files[at.file], at.line, message)
    }
}

/// Whether a token looks like a keyword (starts a new record list).
pub(super) fn is_keyword(t: &Tok) -> bool {
    !t.quoted
        && t.text.len() <= 8
        && t.text
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
        && t.text
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// The next keyword from token `k` on (the tokens between skipped), with
/// `k` moved past it.
pub(super) fn next_keyword(ts: &Tokens, k: &mut usize) -> Option<Tok> {
    while let Some(t) = ts.toks.get(*k) {
        *k += 1;
        if is_keyword(t) {
            return Some(t.clone());
        }
    }
    None
}

/// One record's items after repeat expansion; None is a defaulted item.
pub(super) type Record = Vec<Option<Tok>>;

/// Values one record may expand to (ZCORN of 4 million cells): a repeat
/// count beyond it is an error, not an allocation of many gigabytes.
const MAX_RECORD: usize = 1 << 25;

/// Reads one record starting at `k`: items up to `/`. Returns the items and
/// the index after the `/`.
pub(super) fn record(ts: &Tokens, mut k: usize, keyword: &Tok) -> Result<(Record, usize)> {
    let mut items = vec![];
    loop {
        let Some(t) = ts.toks.get(k) else {
            return Err(ts.error(
                keyword,
                format!("{} record not ended by '/' (truncated file?)", keyword.text),
            ));
        };
        k += 1;
        if !t.quoted && t.text == "/" {
            return Ok((items, k));
        }
        if !t.quoted {
            if let Some((n, v)) = t.text.split_once('*') {
                if let Ok(n) = n.parse::<usize>() {
                    if n > MAX_RECORD - items.len().min(MAX_RECORD) {
                        return Err(ts.error(
                            t,
                            format!(
                                "repeat count {n}: the {} record would hold more than {MAX_RECORD} values, \
                                 the most this reader takes",
                                keyword.text
                            ),
                        ));
                    }
                    let item = (!v.is_empty()).then(|| Tok {
                        text: v.to_string(),
                        ..t.clone()
                    });
                    items.extend(std::iter::repeat_n(item, n));
                    continue;
                }
            }
        }
        items.push(Some(t.clone()));
    }
}

/// Reads the records of a keyword that takes a list, up to the empty
/// record that ends it, handing each to `f` as it is read; returns the
/// index after the end.
pub(super) fn each_record(
    ts: &Tokens,
    mut k: usize,
    keyword: &Tok,
    mut f: impl FnMut(Record) -> Result<()>,
) -> Result<usize> {
    loop {
        let (rec, next) = record(ts, k, keyword)?;
        k = next;
        if rec.is_empty() {
            return Ok(k);
        }
        f(rec)?;
    }
}

pub(super) fn number<T: std::str::FromStr>(
    ts: &Tokens,
    t: &Option<Tok>,
    at: &Tok,
    what: &str,
) -> Result<T> {
    let t = t
        .as_ref()
        .ok_or_else(|| ts.error(at, format!("{what} may not be defaulted")))?;
    // Fortran doubles may use D as exponent letter.
    t.text
        .replace(['D', 'd'], "E")
        .parse()
        .map_err(|_| ts.error(t, format!("{what}: cannot read '{}' as a number", t.text)))
}

fn dims(ts: &Tokens, kw: &Tok, rec: &Record) -> Result<[usize; 3]> {
    if rec.len() < 3 {
        return Err(ts.error(kw, format!("{} needs nx ny nz", kw.text)));
    }
    let mut d = [0usize; 3];
    for (k, v) in d.iter_mut().enumerate() {
        *v = number(ts, &rec[k], kw, &kw.text)?;
        if *v == 0 {
            return Err(ts.error(kw, format!("{}: a dimension is zero", kw.text)));
        }
    }
    if d.iter()
        .try_fold(1usize, |a, &b| a.checked_mul(b))
        .is_none_or(|n| n > 1 << 31)
    {
        return Err(ts.error(kw, format!("{}: {d:?} cells are too many", kw.text)));
    }
    Ok(d)
}

pub(super) fn reals(ts: &Tokens, kw: &Tok, rec: &Record, want: usize) -> Result<Vec<f64>> {
    if rec.len() != want {
        return Err(ts.error(
            kw,
            format!(
                "{} has {} values, the grid needs {want}",
                kw.text,
                rec.len()
            ),
        ));
    }
    rec.iter()
        .map(|t| {
            let v: f64 = number(ts, t, kw, &kw.text)?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(ts.error(
                    t.as_ref().unwrap_or(kw),
                    format!("{}: non-finite value", kw.text),
                ))
            }
        })
        .collect()
}

fn fault_face(ts: &Tokens, kw: &Tok, rec: &Record, d: [usize; 3]) -> Result<(String, FaultFace)> {
    if rec.len() < 8 {
        return Err(ts.error(kw, "FAULTS record needs NAME I1 I2 J1 J2 K1 K2 FACE".into()));
    }
    let name = rec[0].as_ref().map(|t| t.text.clone()).unwrap_or_default();
    let mut r = [0usize; 6];
    for (k, v) in r.iter_mut().enumerate() {
        let x: usize = number(ts, &rec[k + 1], kw, "FAULTS index")?;
        let n = d[k / 2];
        if x == 0 || x > n {
            return Err(ts.error(
                rec[k + 1].as_ref().unwrap_or(kw),
                format!("FAULTS '{name}': index {x} outside 1..{n}"),
            ));
        }
        *v = x - 1;
    }
    let face = rec[7]
        .as_ref()
        .map(|t| t.text.to_ascii_uppercase())
        .unwrap_or_default();
    let (axis, sign) = match face.as_str() {
        "X" | "X+" | "I" | "I+" => ('X', 1),
        "X-" | "I-" => ('X', -1),
        "Y" | "Y+" | "J" | "J+" => ('Y', 1),
        "Y-" | "J-" => ('Y', -1),
        "Z" | "Z+" | "K" | "K+" => ('Z', 1),
        "Z-" | "K-" => ('Z', -1),
        _ => return Err(ts.error(kw, format!("FAULTS '{name}': unknown face '{face}'"))),
    };
    Ok((
        name,
        FaultFace {
            i: [r[0].min(r[1]), r[0].max(r[1])],
            j: [r[2].min(r[3]), r[2].max(r[3])],
            k: [r[4].min(r[5]), r[4].max(r[5])],
            axis,
            sign,
        },
    ))
}

/// The sections of a deck.
const SECTIONS: [&str; 8] = [
    "RUNSPEC", "GRID", "EDIT", "PROPS", "REGIONS", "SOLUTION", "SUMMARY", "SCHEDULE",
];

/// Skips the records of a keyword this reader does not use: none when the
/// next token is a keyword, else records up to the one that ends before
/// the next keyword; TITLE's line.
pub(super) fn skip(ts: &Tokens, mut k: usize, kw: &Tok) -> Result<usize> {
    // TITLE takes the next line as it is, with no '/'; a section's name
    // takes no record, the rest of its line a decoration
    let line = match kw.text.as_str() {
        "TITLE" => ts.toks.get(k).map(|t| (t.file, t.line)),
        w if SECTIONS.contains(&w) => Some((kw.file, kw.line)),
        _ => None,
    };
    if let Some(line) = line {
        while ts.toks.get(k).is_some_and(|t| (t.file, t.line) == line) {
            k += 1;
        }
        return Ok(k);
    }
    while ts.toks.get(k).is_some_and(|t| !is_keyword(t)) {
        k = record(ts, k, kw)?.1;
    }
    Ok(k)
}

/// Reads a GRDECL file (or a deck holding one).
pub fn read_grid(path: &Path) -> Result<CornerPointGrid> {
    let ts = Tokens::read(path, false)?;
    let mut d: Option<[usize; 3]> = None;
    let (mut coord, mut zcorn, mut actnum, mut mapaxes) = (None, None, None, None);
    let mut faults: Vec<Fault> = vec![];
    let mut k = 0;
    while k < ts.toks.len() {
        let kw = ts.toks[k].clone();
        k += 1;
        if !is_keyword(&kw) {
            return Err(ts.error(&kw, format!("expected a keyword, found '{}'", kw.text)));
        }
        let need = |what: &str| -> Result<[usize; 3]> {
            d.ok_or_else(|| ts.error(&kw, format!("{what} before SPECGRID or DIMENS")))
        };
        match kw.text.as_str() {
            "SPECGRID" | "DIMENS" => {
                let (rec, next) = record(&ts, k, &kw)?;
                d = Some(dims(&ts, &kw, &rec)?);
                k = next;
            }
            "COORD" => {
                let [nx, ny, _] = need("COORD")?;
                let (rec, next) = record(&ts, k, &kw)?;
                let v = reals(&ts, &kw, &rec, 6 * (nx + 1) * (ny + 1))?;
                coord = Some(
                    v.chunks_exact(6)
                        .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]])
                        .collect(),
                );
                k = next;
            }
            "ZCORN" => {
                let [nx, ny, nz] = need("ZCORN")?;
                let (rec, next) = record(&ts, k, &kw)?;
                zcorn = Some(reals(&ts, &kw, &rec, 8 * nx * ny * nz)?);
                k = next;
            }
            "ACTNUM" => {
                let [nx, ny, nz] = need("ACTNUM")?;
                let (rec, next) = record(&ts, k, &kw)?;
                let v = reals(&ts, &kw, &rec, nx * ny * nz)?;
                actnum = Some(v.iter().map(|&a| a != 0.0).collect::<Vec<bool>>());
                k = next;
            }
            "MAPAXES" => {
                let (rec, next) = record(&ts, k, &kw)?;
                let v = reals(&ts, &kw, &rec, 6)?;
                mapaxes = Some([v[0], v[1], v[2], v[3], v[4], v[5]]);
                k = next;
            }
            "FAULTS" => {
                let dd = need("FAULTS")?;
                k = each_record(&ts, k, &kw, |rec| {
                    let (name, face) = fault_face(&ts, &kw, &rec, dd)?;
                    match faults.iter_mut().find(|f| f.name == name) {
                        Some(f) => f.faces.push(face),
                        None => faults.push(Fault {
                            name,
                            faces: vec![face],
                        }),
                    }
                    Ok(())
                })?;
            }
            _ => k = skip(&ts, k, &kw)?,
        }
    }
    let missing = |what: &str| parse_err(path, 0, format!("no {what} in the file"));
    let [nx, ny, nz] = d.ok_or_else(|| missing("SPECGRID or DIMENS"))?;
    let coord = coord.ok_or_else(|| missing("COORD"))?;
    let zcorn = zcorn.ok_or_else(|| missing("ZCORN"))?;
    Ok(CornerPointGrid {
        nx,
        ny,
        nz,
        coord,
        zcorn,
        actnum: actnum.unwrap_or_else(|| vec![true; nx * ny * nz]),
        mapaxes,
        faults,
    })
}

/// A well of a deck: head column (0-based i, j), completed layers (0-based,
/// inclusive) and the wellbore radius from COMPDAT's diameter, when given.
#[derive(Debug, Clone, PartialEq)]
pub struct Well {
    /// Its name.
    pub name: String,
    /// Head column I (0-based).
    pub i: usize,
    /// Head column J (0-based).
    pub j: usize,
    /// Completed layers (0-based, inclusive) from COMPDAT.
    pub k: Option<[usize; 2]>,
    /// Wellbore radius from COMPDAT's diameter.
    pub radius: Option<f64>,
    /// COMPDAT's lines in order: column (0-based; the head where the line
    /// leaves it out) and layers K1, K2 (0-based, K1 <= K2).
    pub completions: Vec<[usize; 4]>,
}

impl Well {
    /// The 3D hybrid's well: this head column and completed layers, its
    /// completed cells in COMPDAT's order (each line's layers downwards, a
    /// cell given again once), and this radius or else `radius`.
    pub fn well3(self, radius: f64) -> crate::reservoir::Well3 {
        let mut cells: Vec<[usize; 3]> = vec![];
        for &[i, j, k1, k2] in &self.completions {
            for k in k1..=k2 {
                if !cells.contains(&[i, j, k]) {
                    cells.push([i, j, k]);
                }
            }
        }
        crate::reservoir::Well3 {
            name: self.name,
            i: self.i,
            j: self.j,
            k: self.k,
            radius: self.radius.unwrap_or(radius),
            cells,
            ..Default::default()
        }
    }
}

/// The wells of a deck, from WELSPECS (head column) and COMPDAT (layers,
/// diameter). Included files that do not exist are skipped and named in
/// the second value (a deck's other data is not needed here).
pub fn read_wells(path: &Path) -> Result<(Vec<Well>, Vec<String>)> {
    let ts = Tokens::read(path, true)?;
    let mut wells: Vec<Well> = vec![];
    let mut k = 0;
    let text = |r: &Record, n: usize| r.get(n).cloned().flatten().map(|t| t.text);
    // (tokens between keywords: data of keywords this reader does not know)
    while let Some(kw) = next_keyword(&ts, &mut k) {
        match kw.text.as_str() {
            "WELSPECS" | "COMPDAT" => {
                k = each_record(&ts, k, &kw, |rec| {
                    // names padded with spaces name the same well
                    let name = text(&rec, 0).map(|t| t.trim().to_string()).ok_or_else(|| {
                        ts.error(&kw, format!("{} record without a well name", kw.text))
                    })?;
                    let (ci, cj) = if kw.text == "WELSPECS" {
                        (2, 3)
                    } else {
                        (1, 2)
                    };
                    let one_based = |n: usize, what: &str| -> Result<Option<usize>> {
                        match rec.get(n).cloned().flatten() {
                            None => Ok(None),
                            Some(t) => {
                                let v: usize = number(&ts, &Some(t.clone()), &kw, what)?;
                                if v == 0 {
                                    return Err(ts.error(
                                        &t,
                                        format!("{} '{name}': {what} is 1-based, found 0", kw.text),
                                    ));
                                }
                                Ok(Some(v - 1))
                            }
                        }
                    };
                    let (i, j) = (one_based(ci, "I")?, one_based(cj, "J")?);
                    let at = wells.iter().position(|w| w.name == name);
                    let w = match at {
                        Some(at) => &mut wells[at],
                        None => {
                            let (Some(i), Some(j)) = (i, j) else {
                                return Err(ts.error(
                                    &kw,
                                    format!("{} '{name}': no I, J for a new well", kw.text),
                                ));
                            };
                            wells.push(Well {
                                name: name.clone(),
                                i,
                                j,
                                k: None,
                                radius: None,
                                completions: vec![],
                            });
                            wells.last_mut().expect("just pushed")
                        }
                    };
                    if kw.text == "WELSPECS" {
                        if let (Some(i), Some(j)) = (i, j) {
                            (w.i, w.j) = (i, j);
                        }
                    } else {
                        if let (Some(k1), Some(k2)) = (one_based(3, "K1")?, one_based(4, "K2")?) {
                            let [a, b] = w.k.unwrap_or([k1.min(k2), k1.max(k2)]);
                            w.k = Some([a.min(k1.min(k2)), b.max(k1.max(k2))]);
                            let (ci, cj) = (i.unwrap_or(w.i), j.unwrap_or(w.j));
                            w.completions.push([ci, cj, k1.min(k2), k1.max(k2)]);
                        }
                        if let Some(t) = rec.get(8).cloned().flatten() {
                            let dia: f64 = number(&ts, &Some(t), &kw, "COMPDAT diameter")?;
                            if dia > 0.0 && dia.is_finite() {
                                w.radius = Some(dia / 2.0);
                            }
                        }
                    }
                    Ok(())
                })?;
            }
            _ => k = skip(&ts, k, &kw)?,
        }
    }
    Ok((wells, ts.missing))
}

/// A grid as GRDECL: SPECGRID, COORD, ZCORN and ACTNUM, each number as
/// the shortest decimal that reads back to it.
pub fn grdecl(g: &CornerPointGrid) -> String {
    use std::fmt::Write;
    let mut out = format!("SPECGRID\n{} {} {} 1 F /\n\nCOORD\n", g.nx, g.ny, g.nz);
    let line = |out: &mut String, vs: &mut dyn Iterator<Item = String>| {
        for (n, v) in vs.enumerate() {
            let _ = write!(out, "{v}{}", if n % 6 == 5 { '\n' } else { ' ' });
        }
        out.push_str("/\n\n");
    };
    line(&mut out, &mut g.coord.iter().flatten().map(f64::to_string));
    out.push_str("ZCORN\n");
    line(&mut out, &mut g.zcorn.iter().map(f64::to_string));
    out.push_str("ACTNUM\n");
    line(
        &mut out,
        &mut g.actnum.iter().map(|&a| u8::from(a).to_string()),
    );
    out
}

/// Wells as a metric deck's WELSPECS and COMPDAT (1-based columns and
/// layers, COMPDAT's diameter from the wellbore radius): each completed
/// cell of `cells`, else its column's layers `k` (all `nz` where None).
pub fn wells_deck(wells: &[crate::reservoir::Well3], nz: usize) -> String {
    use std::fmt::Write;
    let mut out = String::from("RUNSPEC\nMETRIC\n\nSCHEDULE\n\nWELSPECS\n");
    for w in wells {
        let _ = writeln!(out, "'{}' 'G' {} {} 1* 'OIL' /", w.name, w.i + 1, w.j + 1);
    }
    out.push_str("/\n\nCOMPDAT\n");
    for w in wells {
        let cells: Vec<[usize; 3]> = if w.cells.is_empty() {
            let [a, b] = w.k.unwrap_or([0, nz.saturating_sub(1)]);
            (a..=b).map(|k| [w.i, w.j, k]).collect()
        } else {
            w.cells.clone()
        };
        for [i, j, k] in cells {
            let (i, j, k, d) = (i + 1, j + 1, k + 1, 2.0 * w.radius);
            let _ = writeln!(out, "'{}' {i} {j} {k} {k} 'OPEN' 1* 1* {d} /", w.name);
        }
    }
    out.push_str("/\n");
    out
}

fn unit_name(metres: f64) -> &'static str {
    match metres {
        1.0 => "metres",
        0.01 => "centimetres",
        _ => "feet",
    }
}

/// The length unit of a grid or deck in metres, and its name: GRIDUNIT's
/// (FEET, METRES, CM), else the unit system's (FIELD: feet, METRIC:
/// metres, LAB: centimetres); None when the file says neither.
pub fn length_unit(path: &Path) -> Result<Option<(f64, String)>> {
    let ts = Tokens::read(path, true)?;
    let mut system = None;
    let mut k = 0;
    while let Some(kw) = next_keyword(&ts, &mut k) {
        let unit = |u: &str| match u {
            "FEET" | "FIELD" => Some(0.3048),
            "METRES" | "METRIC" => Some(1.0),
            "CM" | "LAB" => Some(0.01),
            _ => None,
        };
        match kw.text.as_str() {
            "GRIDUNIT" => {
                let (rec, _) = record(&ts, k, &kw)?;
                let name = rec
                    .first()
                    .cloned()
                    .flatten()
                    .map(|t| t.text.trim().to_uppercase());
                let Some(f) = name.as_deref().and_then(unit) else {
                    return Err(ts.error(&kw, "GRIDUNIT is not FEET, METRES or CM".into()));
                };
                let what = format!("{} (GRIDUNIT {})", unit_name(f), name.unwrap_or_default());
                return Ok(Some((f, what)));
            }
            "FIELD" | "METRIC" | "LAB" if system.is_none() => {
                system = unit(&kw.text).map(|f| (f, format!("{} ({})", unit_name(f), kw.text)));
            }
            _ => {}
        }
    }
    Ok(system)
}

/// A deck's unit system: FIELD, METRIC (also where it names none, as
/// Eclipse takes it) or LAB.
pub fn unit_system(path: &Path) -> Result<&'static str> {
    let ts = Tokens::read(path, true)?;
    let mut k = 0;
    while let Some(kw) = next_keyword(&ts, &mut k) {
        match kw.text.as_str() {
            "FIELD" => return Ok("FIELD"),
            "LAB" => return Ok("LAB"),
            "METRIC" => return Ok("METRIC"),
            _ => {}
        }
    }
    Ok("METRIC")
}

/// Rock arrays of a grid or deck, per grid cell (i + nx (j + ny k)).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Properties {
    /// PORO.
    pub poro: Option<Vec<f64>>,
    /// PERMX, PERMY, PERMZ (mD in METRIC and FIELD alike).
    pub perm: [Option<Vec<f64>>; 3],
    /// NTG.
    pub ntg: Option<Vec<f64>>,
}

/// PORO, PERMX/Y/Z and NTG of a grid or deck with `cells` cells, later
/// files' arrays replacing earlier ones; included files that are missing
/// are named in the second value.
pub fn read_properties(paths: &[&Path], cells: usize) -> Result<(Properties, Vec<String>)> {
    let mut props = Properties::default();
    let mut missing = vec![];
    for path in paths {
        let ts = Tokens::read(path, true)?;
        missing.extend(ts.missing.iter().cloned());
        let mut k = 0;
        while let Some(kw) = next_keyword(&ts, &mut k) {
            let slot = match kw.text.as_str() {
                "PORO" => &mut props.poro,
                "PERMX" => &mut props.perm[0],
                "PERMY" => &mut props.perm[1],
                "PERMZ" => &mut props.perm[2],
                "NTG" => &mut props.ntg,
                _ => continue,
            };
            let (rec, next) = record(&ts, k, &kw)?;
            k = next;
            let values = reals(&ts, &kw, &rec, cells)?;
            if let Some(v) = values.iter().find(|v| **v < 0.0) {
                return Err(ts.error(&kw, format!("{}: negative value {v}", kw.text)));
            }
            *slot = Some(values);
        }
    }
    Ok((props, missing))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("orthomesh-eclipse-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    const ONE_CELL: &str = "-- a unit cube
SPECGRID
 1 1 1 1 F /
COORD
 0 0 0  0 0 1   1 0 0  1 0 1
 0 1 0  0 1 1   1 1 0  1 1 1 /
ZCORN 4*0 4*1 /
ACTNUM 1 /
";

    #[test]
    fn a_unit_cube_with_repeats() {
        let g = read_grid(&write("cube.grdecl", ONE_CELL)).unwrap();
        assert_eq!((g.nx, g.ny, g.nz), (1, 1, 1));
        assert_eq!(g.corner(0, 0, 0, 0), [0.0, 0.0, 0.0]);
        assert_eq!(g.corner(0, 0, 0, 7), [1.0, 1.0, 1.0]);
        assert_eq!(g.corner(0, 0, 0, 2), [0.0, 1.0, 0.0]);
        assert!(g.active(0, 0, 0));
    }

    #[test]
    fn cartesian_grids_have_box_cells() {
        let g = CornerPointGrid::cartesian([3, 2, 2], [10.0, 5.0, 2.0]);
        assert_eq!(g.corner(2, 1, 1, 7), [30.0, 10.0, 4.0]);
        assert_eq!(g.corner(1, 0, 1, 0), [10.0, 0.0, 2.0]);
    }

    #[test]
    fn bad_grids_are_errors_with_lines() {
        let short = ONE_CELL.replace("ZCORN 4*0 4*1 /", "ZCORN 4*0 3*1 /");
        let e = read_grid(&write("short.grdecl", &short))
            .unwrap_err()
            .to_string();
        assert!(e.contains("ZCORN has 7 values, the grid needs 8"), "{e}");
        let open = ONE_CELL.replace("ACTNUM 1 /", "ACTNUM 1");
        let e = read_grid(&write("open.grdecl", &open))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not ended by '/'") && e.contains(":8:"), "{e}");
        let nan = ONE_CELL.replace("ZCORN 4*0", "ZCORN 4*x");
        assert!(read_grid(&write("nan.grdecl", &nan)).is_err());
        let inc = "INCLUDE 'nowhere.grdecl' /\n";
        assert!(matches!(
            read_grid(&write("inc.grdecl", inc)),
            Err(Error::Io { .. })
        ));
    }

    #[test]
    fn includes_faults_and_wells() {
        write("part.inc", "ZCORN 4*0 4*1 /\n");
        let main = ONE_CELL.replace("ZCORN 4*0 4*1 /", "INCLUDE\n 'part.inc' /")
            + "FAULTS\n 'F1' 1 1 1 1 1 1 X /\n 'F1' 1 1 1 1 1 1 Y- /\n/\n";
        let g = read_grid(&write("main.grdecl", &main)).unwrap();
        assert_eq!(g.corner(0, 0, 0, 7), [1.0, 1.0, 1.0]);
        assert_eq!(g.faults.len(), 1);
        assert_eq!(g.faults[0].faces[1].axis, 'Y');
        assert_eq!(g.faults[0].faces[1].sign, -1);
        let deck = "RUNSPEC\nOIL\nWATER\nINCLUDE\n 'missing.inc' /\nWELSPECS\n 'P1' 'G' 3 4 1* 'OIL' /\n/\nCOMPDAT\n 'P1' 3 4 2 5 'OPEN' 1* 1* 0.5 /\n 'P1' 3 4 7 7 'OPEN' /\n 'P1' 1* 1* 9 8 'OPEN' /\n 'P1' 2 4 10 10 /\n/\nWCONPROD\n 'P1' 'OPEN' /\n/\n";
        let (wells, missing) = read_wells(&write("case.data", deck)).unwrap();
        assert_eq!(missing.len(), 1);
        assert_eq!(
            wells,
            vec![Well {
                name: "P1".into(),
                i: 2,
                j: 3,
                k: Some([1, 9]),
                radius: Some(0.25),
                // in order; a line without I, J at the head
                completions: vec![[2, 3, 1, 4], [2, 3, 6, 6], [2, 3, 7, 8], [1, 3, 9, 9]],
            }]
        );
        let w = wells[0].clone().well3(0.1);
        assert_eq!(w.cells.len(), 8);
        assert_eq!((w.cells[0], w.cells[7]), ([2, 3, 1], [1, 3, 9]));
    }

    #[test]
    fn length_units_from_gridunit_or_the_unit_system() {
        let p = write("FIELD.DATA", "FIELD\n");
        assert_eq!(length_unit(&p).unwrap().map(|u| u.0), Some(0.3048));
        let g = write("UNIT.grdecl", "GRIDUNIT\n 'METRES' /\n");
        assert_eq!(length_unit(&g).unwrap().map(|u| u.0), Some(1.0));
        let bad = write("BAD.grdecl", "GRIDUNIT\n 'FURLONGS' /\n");
        assert!(length_unit(&bad)
            .unwrap_err()
            .to_string()
            .contains("GRIDUNIT"));
    }

    #[test]
    fn rock_arrays_are_read_with_their_counts_checked() {
        let p = write(
            "ROCK.DATA",
            "PORO\n 2*0.1 0.2 0.3 /\nNTG\n 4*1 /\nPERMX\n 4*50 /\n",
        );
        let (props, missing) = read_properties(&[&p], 4).unwrap();
        assert_eq!(props.poro, Some(vec![0.1, 0.1, 0.2, 0.3]));
        assert_eq!(props.perm[0], Some(vec![50.0; 4]));
        assert!(props.perm[1].is_none() && missing.is_empty());
        let e = read_properties(&[&p], 5).unwrap_err().to_string();
        assert!(e.contains("PORO has 4 values, the grid needs 5"), "{e}");
        let bad = write("NEG.DATA", "PERMZ\n 1 -2 /\n");
        let e = read_properties(&[&bad], 2).unwrap_err().to_string();
        assert!(e.contains("negative value -2"), "{e}");
    }

    /// Written as GRDECL and a deck's wells, the well field reads back
    /// as it was (the numbers in full precision).
    #[test]
    fn a_well_field_reads_back() {
        use crate::reservoir::synthetic::well_field;
        let (g, wells) = well_field(2);
        assert_eq!((g.nx, g.ny, g.nz, wells.len()), (13, 13, 6, 4));
        let dir = std::env::temp_dir().join(format!("om-wells-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("f.grdecl"), grdecl(&g)).unwrap();
        std::fs::write(dir.join("f.DATA"), wells_deck(&wells, g.nz)).unwrap();
        let back = read_grid(&dir.join("f.grdecl")).unwrap();
        assert_eq!((back.coord, back.zcorn), (g.coord, g.zcorn));
        let (read, missing) = read_wells(&dir.join("f.DATA")).unwrap();
        let read: Vec<_> = read.into_iter().map(|w| w.well3(0.5)).collect();
        assert_eq!((read, missing.len()), (wells, 0));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
