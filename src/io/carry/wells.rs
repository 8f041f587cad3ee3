//! The wells of a carried deck: WELSPECS heads on the deck's cells, a
//! meshed well's COMPDAT lines replaced by its innermost ring's
//! connections with the exact radial factor (the line's state and skin, in
//! its layer range), SUMMARY's block and connection keywords on the cells
//! that hold the original blocks.

use super::cells::{num, Table};
use super::{record_text, records, verbatim, Kw, Said};
use crate::error::Result;
use crate::io::eclipse::{Record, Tok, Tokens};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The radially meshed wells, by name: their links (element, geometric
/// factor in grid units) and ln(rho / r_w).
pub(super) struct Wells<'a> {
    table: &'a Table<'a>,
    meshed: BTreeMap<String, usize>,
}

/// An item of a record as text, trimmed; None where defaulted.
fn item(rec: &Record, n: usize) -> Option<String> {
    rec.get(n)
        .cloned()
        .flatten()
        .map(|t| t.text.trim().to_string())
}

/// A 1-based integer item, 0-based; None where defaulted.
fn index(ts: &Tokens, at: &Tok, rec: &Record, n: usize) -> Result<Option<usize>> {
    match item(rec, n) {
        None => Ok(None),
        Some(t) => match t.parse::<usize>() {
            Ok(v) if v >= 1 => Ok(Some(v - 1)),
            _ => Err(ts.error(
                at,
                format!("{}: item {} '{t}' is not an index from 1", at.text, n + 1),
            )),
        },
    }
}

impl<'a> Wells<'a> {
    pub fn new(table: &'a Table<'a>) -> Wells<'a> {
        let meshed = table
            .mesh
            .wells
            .iter()
            .enumerate()
            .map(|(n, w)| (w.name.clone(), n))
            .collect();
        Wells { table, meshed }
    }

    /// The most connections a well has: a ring's cells in every layer.
    fn most(&self) -> usize {
        self.table
            .mesh
            .wells
            .iter()
            .map(|w| w.links.len())
            .max()
            .unwrap_or(0)
    }

    /// WELLDIMS with room for the rings' connections.
    pub fn welldims(&self, ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
        let mut rec = records(ts, kw)?.into_iter().next().unwrap_or_default();
        let given: usize = item(&rec, 1).and_then(|t| t.parse().ok()).unwrap_or(0);
        if given < self.most() {
            while rec.len() < 2 {
                rec.push(None);
            }
            rec[1] = Some(Tok {
                text: self.most().to_string(),
                ..ts.toks[kw.start].clone()
            });
            said.notes.push(format!(
                "WELLDIMS: up to {} connections per well (a radial mesh's innermost ring in each layer)",
                self.most()
            ));
        }
        Ok(format!("WELLDIMS\n{}\n", record_text(&rec, said)))
    }

    /// Well `name`'s index among the meshed ones; Err naming it if it has
    /// no radial mesh.
    fn meshed(&self, ts: &Tokens, at: &Tok, name: &str) -> Result<usize> {
        self.meshed.get(name).copied().ok_or_else(|| {
            ts.error(
                at,
                format!(
                    "well {name} has no radial mesh: the hybrid deck carries only meshed wells"
                ),
            )
        })
    }

    fn name(rec: &Record) -> String {
        item(rec, 0).unwrap_or_default()
    }

    /// WELSPECS: each meshed well's head on its first connection's cell,
    /// then COMPORD INPUT for them (the rings' order as written).
    pub fn welspecs(&self, ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
        let at = &ts.toks[kw.start];
        let mut s = String::from("WELSPECS\n");
        let mut named = vec![];
        for mut rec in records(ts, kw)? {
            let name = Self::name(&rec);
            let w = self.meshed(ts, at, &name)?;
            let Some(&(e, _)) = self.table.mesh.wells[w].links.first() else {
                return Err(ts.error(
                    at,
                    format!("well {name}: its radial mesh has no connection"),
                ));
            };
            while rec.len() < 4 {
                rec.push(None);
            }
            let cell = self.table.position[e] + 1;
            for (n, v) in [(2, cell), (3, 1)] {
                rec[n] = Some(Tok {
                    text: v.to_string(),
                    quoted: false,
                    ..at.clone()
                });
            }
            s.push_str(&record_text(&rec, said));
            named.push(name);
        }
        s.push_str("/\n\nCOMPORD\n");
        for n in named {
            let _ = writeln!(s, " '{n}' 'INPUT' /");
        }
        s.push_str("/\n\n");
        Ok(s)
    }

    /// COMPDAT: a meshed well's lines become its ring's connections in
    /// their layers, each with the radial factor and the line's skin, state
    /// and the rest of its items.
    pub fn compdat(&self, ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
        let at = &ts.toks[kw.start];
        let t = self.table;
        let mut s = String::from("COMPDAT\n");
        for rec in records(ts, kw)? {
            let name = Self::name(&rec);
            let w = self.meshed(ts, at, &name)?;
            let well = &t.mesh.wells[w];
            let nz = t.mesh.grid.nz;
            let k1 = index(ts, at, &rec, 3)?.unwrap_or(0);
            let k2 = index(ts, at, &rec, 4)?.unwrap_or(nz - 1);
            let skin: f64 = item(&rec, 9).and_then(|v| v.parse().ok()).unwrap_or(0.0);
            // the input's own factor for the line, where it gives one
            let given: f64 = item(&rec, 7)
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN);
            let sums = said.factors.entry(name.clone()).or_insert([0.0, 0.0]);
            sums[1] += given;
            let text = |n: usize| {
                item(&rec, n).map_or("1*".to_string(), |v| match rec[n].as_ref() {
                    Some(tok) if tok.quoted => format!("'{v}'"),
                    _ => v,
                })
            };
            for &(e, g) in &well.links {
                let k = t.mesh.host[e][2];
                if !(k1..=k2).contains(&k) {
                    continue;
                }
                let perm = (t.perm(e, 0) * t.perm(e, 1)).sqrt();
                let factor = t.darcy * perm * g * t.f * well.log / (well.log + skin);
                if let Some(sums) = said.factors.get_mut(&name) {
                    sums[0] += factor;
                }
                let _ = writeln!(
                    s,
                    " '{name}' {} 1 1 1 {} {} {} {} 1* 0 {} {} /",
                    t.position[e] + 1,
                    text(5),
                    text(6),
                    num(factor),
                    text(8),
                    text(10),
                    text(11),
                );
            }
        }
        s.push_str("/\n\n");
        said.rings = true;
        Ok(s)
    }

    /// A SUMMARY keyword: block ones (I J K) on the cells that hold the
    /// blocks' centres, connection ones naming a cell on the well's first
    /// ring cell in that block; the rest as given.
    pub fn summary(&self, ts: &Tokens, kw: &Kw, w: &str, said: &mut Said) -> Result<String> {
        let has_records = kw.end > kw.start + 1;
        let (block, conn) = (w.starts_with('B'), w.starts_with('C'));
        if !has_records || !(block || conn) {
            return Ok(verbatim(ts, kw, said));
        }
        let at = &ts.toks[kw.start];
        let recs = records(ts, kw)?;
        let first = if block { 0 } else { 1 };
        let ijk = |rec: &Record| -> Result<Option<[usize; 3]>> {
            let i = index(ts, at, rec, first)?;
            let j = index(ts, at, rec, first + 1)?;
            let k = index(ts, at, rec, first + 2)?;
            Ok(i.zip(j).zip(k).map(|((i, j), k)| [i, j, k]))
        };
        let mut s = format!("{w}\n");
        for rec in &recs {
            let Some(c) = ijk(rec)? else {
                s.push_str(&record_text(rec, said));
                continue;
            };
            let cell = match block {
                true => self.table.block(c),
                false => self.ring_cell(&Self::name(rec), c),
            };
            let Some(cell) = cell else {
                return Err(ts.error(
                    at,
                    format!(
                        "{w}: no cell of the mesh holds block {:?}",
                        c.map(|x| x + 1)
                    ),
                ));
            };
            let head = if conn {
                format!("'{}' ", Self::name(rec))
            } else {
                String::new()
            };
            let _ = writeln!(s, " {head}{} 1 1 /", cell + 1);
        }
        s.push_str("/\n\n");
        said.blocks = true;
        Ok(s)
    }

    /// The deck cell of well `name`'s first ring cell hosted in block c.
    fn ring_cell(&self, name: &str, c: [usize; 3]) -> Option<usize> {
        let w = *self.meshed.get(name)?;
        let t = self.table;
        t.mesh.wells[w]
            .links
            .iter()
            .find(|&&(e, _)| t.mesh.host[e] == c)
            .map(|&(e, _)| t.position[e])
    }

    /// Any other SCHEDULE keyword, as given; those that name a well's
    /// connections by I J K are refused.
    pub fn other(&self, ts: &Tokens, kw: &Kw, w: &str, said: &mut Said) -> Result<String> {
        let by_cell = match w {
            "WELOPEN" => Some(2),
            "WPIMULT" => Some(2),
            "COMPLUMP" => Some(1),
            _ => None,
        };
        if let Some(first) = by_cell {
            for rec in records(ts, kw)? {
                if (first..first + 3).any(|n| item(&rec, n).is_some()) {
                    return Err(ts.error(
                        &ts.toks[kw.start],
                        format!("{w} names connections by I J K: the hybrid deck does not carry that yet"),
                    ));
                }
            }
        }
        Ok(verbatim(ts, kw, said))
    }
}
