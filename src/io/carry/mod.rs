//! The engineer's deck carried whole into a hybrid mesh's deck: every
//! section and keyword of the input, with its includes, is written again
//! unless it is one this module changes. RUNSPEC's DIMENS becomes the dummy
//! N x 1 x 1 grid, WELLDIMS counts the radial meshes' connections; GRID and
//! EDIT become the mesh (`cells`): pore volumes, depths and every
//! connection an NNC, the far field's transmissibilities as OPM Flow
//! computes them for the original grid; the per-cell arrays of PROPS,
//! REGIONS and SOLUTION, evaluated on the original grid, are mapped through
//! each cell's host cell; SUMMARY's block and connection keywords and
//! SCHEDULE's well heads and connections point at the deck's cells, a
//! meshed well's COMPDAT lines becoming its innermost ring's connections
//! (`wells`). What OPM Flow 2022.10 refuses is mended and said.

mod cells;
mod merge;
mod wells;

use super::eclipse::{is_keyword, record, Record, Tok, Tokens};
use crate::error::{Error, Result};
pub use cells::{extents, Mesh};
pub use merge::SUGGESTED as MERGE_STIFF;
use std::collections::BTreeSet;
use std::fmt::Write;
use std::path::Path;

const SECTIONS: [&str; 8] = [
    "RUNSPEC", "GRID", "EDIT", "PROPS", "REGIONS", "SOLUTION", "SUMMARY", "SCHEDULE",
];

/// Operations on arrays: evaluated on the original grid (`io::arrays`), so
/// not written again.
const OPERATIONS: [&str; 8] = [
    "EQUALS", "COPY", "ADD", "MULTIPLY", "MINVALUE", "MAXVALUE", "BOX", "ENDBOX",
];

/// Keywords that change the grid or its transmissibilities during the run:
/// the mesh cannot carry them.
const GRID_IN_SCHEDULE: [&str; 12] = [
    "MULTX", "MULTY", "MULTZ", "MULTX-", "MULTY-", "MULTZ-", "MULTFLT", "MULTREGT", "BOX",
    "EQUALS", "MULTIPLY", "NNC",
];

/// A keyword of the input and its tokens `start..end` (the keyword first).
#[derive(Debug, Clone)]
struct Kw {
    name: String,
    start: usize,
    end: usize,
    section: usize,
}

/// Whether token k starts a keyword: a keyword's shape, first on its line
/// and alone there (a section's name may carry a decoration). Unquoted
/// names at a record's start share the shape but not the line.
fn starts_keyword(ts: &Tokens, k: usize) -> bool {
    let t = &ts.toks[k];
    let line = |n: usize| ts.toks.get(n).map(|u| (u.file, u.line));
    let first = k == 0 || line(k - 1) != Some((t.file, t.line));
    let alone = line(k + 1) != Some((t.file, t.line));
    is_keyword(t) && first && (alone || SECTIONS.contains(&t.text.as_str()))
}

/// The input's keywords in order, each with its section (index in
/// `SECTIONS`; RUNSPEC before any).
fn keywords(ts: &Tokens) -> Vec<Kw> {
    let mut out: Vec<Kw> = vec![];
    let mut section = 0;
    let mut k = 0;
    while k < ts.toks.len() {
        if !starts_keyword(ts, k) {
            k += 1;
            continue;
        }
        let name = ts.toks[k].text.clone();
        if let Some(s) = SECTIONS.iter().position(|s| *s == name) {
            section = s;
        }
        if let Some(last) = out.last_mut() {
            last.end = k;
        }
        let start = k;
        k += 1;
        // TITLE's line is free text; a section's decoration is no record
        let own = match name.as_str() {
            "TITLE" => ts.toks.get(k).map(|t| (t.file, t.line)),
            w if SECTIONS.contains(&w) => Some((ts.toks[start].file, ts.toks[start].line)),
            _ => None,
        };
        while own.is_some() && ts.toks.get(k).map(|t| (t.file, t.line)) == own {
            k += 1;
        }
        out.push(Kw {
            name,
            start,
            end: ts.toks.len(),
            section,
        });
    }
    out
}

/// A token as the deck reads it; a quoted one trimmed of the spaces that
/// pad it (Flow 2022.10 takes `'PROD1 '` for another well than `'PROD1'`).
fn token_text(t: &Tok, mended: &mut bool) -> String {
    match t.quoted {
        true => {
            let trimmed = t.text.trim();
            *mended |= trimmed != t.text;
            format!("'{trimmed}'")
        }
        false => t.text.clone(),
    }
}

/// A keyword's text as the input gives it, line by line, `BASIC=` above
/// 5 lowered to 5 (Flow 2022.10 takes no higher).
fn verbatim(ts: &Tokens, kw: &Kw, said: &mut Said) -> String {
    let mut s = String::new();
    let mut line = None;
    for t in &ts.toks[kw.start..kw.end] {
        let here = (t.file, t.line);
        if line.is_some_and(|l| l != here) {
            s.push('\n');
        } else if line.is_some() {
            s.push(' ');
        }
        line = Some(here);
        let mut text = token_text(t, &mut said.padded);
        if let Some(n) = text
            .strip_prefix("BASIC=")
            .and_then(|n| n.parse::<u32>().ok())
        {
            if n > 5 {
                said.basic = true;
                text = "BASIC=5".into();
            }
        }
        s.push_str(&text);
    }
    s.push_str("\n\n");
    s
}

/// A record's items as the deck reads them (defaulted ones as `1*`).
fn record_text(rec: &Record, said: &mut Said) -> String {
    let items: Vec<String> = rec
        .iter()
        .map(|t| match t {
            Some(t) => token_text(t, &mut said.padded),
            None => "1*".into(),
        })
        .collect();
    format!(" {} /\n", items.join(" "))
}

/// The records of a keyword that ends with an empty one (or at the next
/// keyword), in order.
fn records(ts: &Tokens, kw: &Kw) -> Result<Vec<Record>> {
    let at = ts.toks[kw.start].clone();
    let mut k = kw.start + 1;
    let mut out = vec![];
    while k < kw.end {
        let (rec, next) = record(ts, k, &at)?;
        k = next;
        if rec.is_empty() {
            break;
        }
        out.push(rec);
    }
    Ok(out)
}

/// The arrays an operation names (COPY's target is its second item).
fn targets(ts: &Tokens, kw: &Kw) -> Result<Vec<String>> {
    if kw.name == "BOX" || kw.name == "ENDBOX" {
        return Ok(vec![]);
    }
    let at = if kw.name == "COPY" { 1 } else { 0 };
    Ok(records(ts, kw)?
        .iter()
        .filter_map(|r| r.get(at).cloned().flatten())
        .map(|t| t.text.trim().to_ascii_uppercase())
        .collect())
}

/// What the carrying mended or changed, said in the deck's header and on
/// standard error.
#[derive(Debug, Default)]
struct Said {
    /// Per meshed well, its ring's connection factors added up and the
    /// input's (NaN where a line defaults its factor).
    factors: std::collections::BTreeMap<String, [f64; 2]>,
    rings: bool,
    /// The wells without a radial mesh, whose connections are kept.
    kept: BTreeSet<String>,
    /// Connections to cells Flow leaves out (well I J K), left out.
    skipped: BTreeSet<String>,
    blocks: bool,
    padded: bool,
    basic: bool,
    equil: bool,
    dropped: BTreeSet<String>,
    notes: Vec<String>,
}

impl Said {
    fn lines(&self) -> Vec<String> {
        let mut out = self.notes.clone();
        if self.rings {
            out.push(
                "COMPDAT of the meshed wells: each line's layers connected through the innermost \
                 ring's cells with the radial flow's exact factor (the line's skin added to its \
                 log term; its state and other items kept)"
                    .into(),
            );
        }
        if !self.kept.is_empty() {
            let list: Vec<&str> = self.kept.iter().map(|s| s.as_str()).collect();
            out.push(format!(
                "COMPDAT of the wells without a radial mesh ({}): their connections on their \
                 cells, unchanged, a line per layer, with the input's factor or, where it gives \
                 none, Flow's own (Peaceman's on the cell)",
                list.join(", ")
            ));
        }
        if !self.skipped.is_empty() {
            let list: Vec<&str> = self.skipped.iter().map(|s| s.as_str()).collect();
            out.push(format!(
                "connections to cells Flow leaves out (inactive or without pore volume) left \
                 out, as Flow leaves them: {}",
                list.join(", ")
            ));
        }
        if !self.factors.is_empty() {
            let each: Vec<String> = self
                .factors
                .iter()
                .map(|(w, [ours, input])| match input.is_nan() {
                    true => format!("{w} {ours:.4}"),
                    false => format!("{w} {ours:.4} ({input:.4})"),
                })
                .collect();
            out.push(format!(
                "the meshed wells' connection factors added up, from the wellbore to the \
                 sites of the ring their deck cells stand for (the innermost, or the outer one \
                 --merge-stiff merged it into), with the input's in brackets where its COMPDAT \
                 gives them (to the grid block's equivalent radius): {}",
                each.join(", ")
            ));
        }
        if self.blocks {
            out.push(
                "SUMMARY's blocks on the deck cells that hold their centres (the nearest node \
                 where a block is in a cavity)"
                    .into(),
            );
        }
        if self.padded {
            out.push("quoted names padded with spaces trimmed (Flow 2022.10 refuses them)".into());
        }
        if self.basic {
            out.push("RPTRST BASIC above 5 lowered to 5 (Flow 2022.10 takes no higher)".into());
        }
        if self.equil {
            out.push(
                "EQUIL item 9 (the initialisation's accuracy) positive set to its default -5 \
                 (Flow 2022.10 takes only non-positive ones)"
                    .into(),
            );
        }
        if !self.dropped.is_empty() {
            let list: Vec<&str> = self.dropped.iter().map(|s| s.as_str()).collect();
            out.push(format!(
                "GRID and EDIT are the mesh's (their arrays evaluated on the original grid); \
                 not written again: {}",
                list.join(", ")
            ));
        }
        out
    }
}

/// EQUIL with item 9 made non-positive where it is positive.
fn equil(ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
    let mut s = String::from("EQUIL\n");
    for mut rec in records(ts, kw)? {
        if let Some(Some(t)) = rec.get_mut(8) {
            if t.text.parse::<f64>().is_ok_and(|v| v > 0.0) {
                t.text = "-5".into();
                said.equil = true;
            }
        }
        s.push_str(&record_text(&rec, said));
    }
    s.push_str("/\n\n");
    Ok(s)
}

/// Whether a deck has a section (PROPS: whether it is whole, not only
/// wells).
pub fn has_section(path: &Path, name: &str) -> Result<bool> {
    let ts = Tokens::read(path, true)?;
    Ok(keywords(&ts).iter().any(|k| k.name == name))
}

/// A deck carried whole onto a hybrid mesh.
#[derive(Debug, Clone)]
pub struct Carried {
    /// The deck's text.
    pub text: String,
    /// What it mended or assumed.
    pub notes: Vec<String>,
    /// Per mesh cell, its deck cell (0-based; merged cells share one).
    pub position: Vec<usize>,
    /// Per deck cell, the mesh cell whose host gives its rock and regions.
    pub rock: Vec<usize>,
}

/// The deck of a hybrid mesh that carries the input deck `path` whole;
/// with `merge`, its cavities' cells stiffer than that share of the
/// original grid's stiffest cell merged (`merge`). Err naming a keyword it
/// cannot carry.
pub fn carry(path: &Path, mesh: &Mesh, merge: Option<f64>) -> Result<Carried> {
    let ts = Tokens::read(path, false)?;
    let kws = keywords(&ts);
    let mut table = cells::Table::new(path, mesh)?;
    if let Some(share) = merge {
        let gone = table.merge_stiff(share);
        table.notes.push(format!(
            "--merge-stiff {share}: {gone} cells of the cavities merged with a neighbour (an \
             innermost ring's sectors into an annulus per layer, with the next ring where the \
             annulus stays stiff), their transmissibilities over their pore volume above \
             {share} of the original grid's stiffest cell's"
        ));
    }
    let mut said = Said::default();
    said.notes.extend(table.notes.iter().cloned());
    let mut wells = wells::Wells::new(&table);
    let mut body = String::new();
    let mut written = BTreeSet::new();
    let mut edit_done = false;
    for kw in &kws {
        let name = kw.name.as_str();
        let section = SECTIONS[kw.section];
        match (section, name) {
            ("RUNSPEC", "DIMENS") => {
                let _ = write!(body, "DIMENS\n {} 1 1 /\n\n", table.cells.len());
            }
            ("RUNSPEC", "WELLDIMS") => body.push_str(&wells.welldims(&ts, kw, &mut said)?),
            ("RUNSPEC", "NONNC") => said
                .notes
                .push("NONNC left out: the mesh's connections are NNCs".into()),
            (_, "GRID") => {
                body.push_str("GRID\n\n");
                if kws.iter().any(|k| k.name == "INIT" && SECTIONS[k.section] == "GRID") {
                    body.push_str("INIT\n\n");
                }
                table.grid(&mut body);
            }
            ("GRID" | "EDIT", w) => {
                if !(w == "INIT" || w == "EDIT") {
                    said.dropped.insert(w.to_string());
                }
            }
            (_, "PROPS") => {
                table.edit(&mut body);
                edit_done = true;
                body.push_str("PROPS\n\n");
            }
            ("PROPS" | "REGIONS" | "SOLUTION", w) if OPERATIONS.contains(&w) => {
                for target in targets(&ts, kw)? {
                    if written.insert(target.clone()) {
                        table.section_array(&mut body, section, &target)?;
                    }
                }
            }
            ("PROPS" | "REGIONS" | "SOLUTION", w) if table.is_array(w) => {
                if written.insert(w.to_string()) {
                    table.section_array(&mut body, section, w)?;
                }
            }
            ("SOLUTION", "EQUIL") => body.push_str(&equil(&ts, kw, &mut said)?),
            ("SUMMARY", w) => body.push_str(&wells.summary(&ts, kw, w, &mut said)?),
            ("SCHEDULE", "WELSPECS") => body.push_str(&wells.welspecs(&ts, kw, &mut said)?),
            ("SCHEDULE", "COMPDAT") => body.push_str(&wells.compdat(&ts, kw, &mut said)?),
            ("SCHEDULE", w) if GRID_IN_SCHEDULE.contains(&w) || w == "COMPDATL" => {
                return Err(ts.error(
                    &ts.toks[kw.start],
                    format!("{w} in SCHEDULE changes the grid or its connections during the run; the hybrid deck cannot carry it"),
                ))
            }
            ("SCHEDULE", w) => body.push_str(&wells.other(&ts, kw, w, &mut said)?),
            _ => body.push_str(&verbatim(&ts, kw, &mut said)),
        }
    }
    if !edit_done {
        return Err(Error::Parse {
            path: path.into(),
            line: 0,
            message:
                "no PROPS section: a deck carried whole needs its fluids (else --single-phase)"
                    .into(),
        });
    }
    let mut s = String::with_capacity(body.len() + 4096);
    s.push_str("-- Written by orthomesh: the input deck carried whole onto a hybrid mesh, a\n");
    s.push_str("-- dummy N x 1 x 1 grid whose connections are all NNCs with their final\n");
    let _ = writeln!(s, "-- transmissibilities. Input: {}", path.display());
    let notes = said.lines();
    for n in &notes {
        let _ = writeln!(s, "-- {n}");
    }
    s.push('\n');
    s.push_str(&body);
    Ok(Carried {
        text: s,
        notes,
        position: table.position.clone(),
        rock: table.cells.iter().map(|c| c.element).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cells::num;

    /// A mesh without wells on a row of grid cells, 2 units tall.
    pub(super) fn row<'a>(
        g: &'a crate::reservoir::CornerPointGrid,
        network: &'a crate::mesh::Network,
        host: &'a [[usize; 3]],
        ijk: &'a [Option<[usize; 3]>],
        region: &'a [crate::reservoir::Region],
    ) -> Mesh<'a> {
        Mesh {
            grid: g,
            network,
            host,
            ijk,
            wells: &[],
            region,
            extent: &[2.0; 8][..host.len()],
        }
    }

    /// A deck of an n x 1 x 1 grid of 10 x 10 x 2 cells, `tail` after its
    /// GRID, written as STEM.DATA in a scratch folder.
    pub(super) fn row_deck(stem: &str, n: usize, tail: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("orthomesh-carry-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("{stem}.DATA"));
        let deck = format!(
            "RUNSPEC\nDIMENS\n {n} 1 1 /\nOIL\nWATER\nMETRIC\nGRID\nDX\n {n}*10 /\nDY\n {n}*10 /\n\
             DZ\n {n}*2 /\nTOPS\n {n}*0 /\nPORO\n {n}*0.2 /\nPERMX\n {n}*100 /\nPERMY\n {n}*100 /\n\
             PERMZ\n {n}*10 /\n{tail}END\n"
        );
        std::fs::write(&p, deck).unwrap();
        p
    }

    /// A 2 x 1 x 1 grid as its own mesh (two reservoir cells, no well).
    fn refused(schedule: &str) -> String {
        use crate::mesh::{Connection, Element, Network};
        let g = crate::reservoir::CornerPointGrid::cartesian([2, 1, 1], [10.0, 10.0, 2.0]);
        let e = |x: f64| Element {
            volume: 200.0,
            node: [x, 5.0, -1.0],
        };
        let network = Network {
            elements: vec![e(5.0), e(15.0)],
            connections: vec![Connection {
                elements: [0, 1],
                isot: 1,
                d: [5.0, 5.0],
                area: 20.0,
                cos_gravity: 0.0,
            }],
        };
        let host = [[0, 0, 0], [1, 0, 0]];
        let ijk = host.map(Some);
        let region = [crate::reservoir::Region::Reservoir; 2];
        let mesh = row(&g, &network, &host, &ijk, &region);
        let p = row_deck(
            &format!("R{}", schedule.len()),
            2,
            &format!("PROPS\nSOLUTION\nSCHEDULE\n{schedule}"),
        );
        match carry(&p, &mesh, None) {
            Ok(c) => c.text,
            Err(e) => format!("error: {e}"),
        }
    }

    #[test]
    fn what_cannot_be_carried_is_named() {
        // a well without a radial mesh keeps its cells, its factor Flow's
        let kept = refused(
            "WELSPECS\n 'W1' 'G' 2 1 1* 'OIL' /\n/\nCOMPDAT\n 'W1' 2* 1 1 'OPEN' 1* 1* 0.2 1* 1.5 /\n\
             'W1' 2* 1 1 'OPEN' 1* 7.5 /\n/\n",
        );
        let w = crate::reservoir::trans::Completion {
            radius: 0.1,
            skin: 1.5,
            ..Default::default()
        };
        let g = crate::reservoir::CornerPointGrid::cartesian([2, 1, 1], [10.0, 10.0, 2.0]);
        let darcy = crate::reservoir::trans::darcy(false);
        let cf = crate::reservoir::trans::peaceman_factor(
            &g,
            [1, 0, 0],
            [100.0; 2],
            1.0,
            1.0,
            darcy,
            &w,
        );
        let line = format!(
            " 'W1' 2 1 1 1 'OPEN' 1* {} 0.2 1* 1.5 1* 1* 1* /",
            num(cf.unwrap())
        );
        assert!(kept.contains(&line), "{line}\n{kept}");
        assert!(
            kept.contains(" 'W1' 2 1 1 1 'OPEN' 1* 7.5 1* 1* 1* 1* 1* 1* /"),
            "{kept}"
        );
        assert!(
            kept.contains("WELSPECS\n 'W1' 'G' 2 1 1* 'OIL' /"),
            "{kept}"
        );
        let e = refused("WELSPECS\n 'W1' 'G' 3 1 1* 'OIL' /\n/\n");
        assert!(e.contains("error") && e.contains("W1's head"), "{e}");
        let e =
            refused("WELSPECS\n 'W1' 'G' 1 1 1* 'OIL' /\n/\nCOMPDAT\n 'W1' 2* 1 1 'OPEN' /\n/\n");
        assert!(
            e.contains("neither a factor nor a wellbore diameter"),
            "{e}"
        );
        let e = refused("MULTX\n 2*0.5 /\n");
        assert!(
            e.contains("error") && e.contains("MULTX in SCHEDULE"),
            "{e}"
        );
        let e = refused("WELOPEN\n 'W1' 'SHUT' 1 1 1 /\n/\n");
        assert!(e.contains("WELOPEN names connections by I J K"), "{e}");
        // a deck that only carries: its cells, connection and sections
        let ok = refused("TSTEP\n 1 /\n");
        assert!(
            ok.contains("DIMENS\n 2 1 1 /") && ok.contains("TSTEP\n1 /"),
            "{ok}"
        );
        assert!(ok.contains("NNC\n 1 1 1 2 1 1 "), "{ok}");
    }

    #[test]
    fn keywords_are_alone_on_their_line() {
        let dir = std::env::temp_dir().join(format!("orthomesh-carry-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("K.DATA");
        std::fs::write(
            &p,
            "RUNSPEC ====\nTITLE\nA TEST\nOIL\nSCHEDULE\nWELSPECS\n PROD1 G1 1 1 /\n/\nWCONPROD\n\
             'P' OPEN ORAT 5 /\n/\nEND\n",
        )
        .unwrap();
        let ts = Tokens::read(&p, false).unwrap();
        let names: Vec<String> = keywords(&ts).into_iter().map(|k| k.name).collect();
        assert_eq!(
            names,
            ["RUNSPEC", "TITLE", "OIL", "SCHEDULE", "WELSPECS", "WCONPROD", "END"]
        );
        let kws = keywords(&ts);
        let mut said = Said::default();
        let w = verbatim(&ts, &kws[4], &mut said);
        assert_eq!(w, "WELSPECS\nPROD1 G1 1 1 /\n/\n\n");
    }
}
