//! The wells of a carried deck: WELSPECS heads on the deck's cells, a
//! meshed well's COMPDAT lines replaced by its innermost ring's
//! connections with the exact radial factor (the line's state and skin, in
//! its layer range), SUMMARY's block and connection keywords on the cells
//! that hold the original blocks.

use super::cells::{num, Table};
use super::{record_text, records, verbatim, Kw, Said};
use crate::error::Result;
use crate::io::eclipse::{Record, Tok, Tokens};
use crate::reservoir::trans;
use std::collections::BTreeMap;
use std::fmt::Write;

/// The radially meshed wells, by name: their links (element, geometric
/// factor in grid units) and ln(rho / r_w).
pub(super) struct Wells<'a> {
    table: &'a Table<'a>,
    meshed: BTreeMap<String, usize>,
    /// The other wells' heads (I, J), as WELSPECS gives them.
    heads: BTreeMap<String, [usize; 2]>,
}

/// An item of a record as text, trimmed; None where defaulted.
fn item(rec: &Record, n: usize) -> Option<String> {
    rec.get(n)
        .cloned()
        .flatten()
        .map(|t| t.text.trim().to_string())
}

/// A number item; None where defaulted or not a number.
fn number(rec: &Record, n: usize) -> Option<f64> {
    item(rec, n).and_then(|v| v.parse().ok())
}

/// An item as the deck writes it again (quoted if it was), `1*` where
/// defaulted.
fn text(rec: &Record, n: usize) -> String {
    item(rec, n).map_or("1*".to_string(), |v| match rec[n].as_ref() {
        Some(tok) if tok.quoted => format!("'{v}'"),
        _ => v,
    })
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
        Wells {
            table,
            meshed,
            heads: BTreeMap::new(),
        }
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

    fn name(rec: &Record) -> String {
        item(rec, 0).unwrap_or_default()
    }

    /// WELSPECS: a meshed well's head on its first connection's cell,
    /// another's on the first cell of its column left unchanged; then
    /// COMPORD INPUT for them (the connections' order as written).
    pub fn welspecs(&mut self, ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
        let at = &ts.toks[kw.start];
        let t = self.table;
        let g = t.mesh.grid;
        let mut s = String::from("WELSPECS\n");
        let mut named = vec![];
        for mut rec in records(ts, kw)? {
            let name = Self::name(&rec);
            let cell = match self.meshed.get(&name) {
                Some(&w) => match t.mesh.wells[w].links.first() {
                    Some(&(e, _)) => t.position[e],
                    None => {
                        return Err(ts.error(
                            at,
                            format!("well {name}: its radial mesh has no connection"),
                        ))
                    }
                },
                None => {
                    let (i, j) = (index(ts, at, &rec, 2)?, index(ts, at, &rec, 3)?);
                    let Some([i, j]) = i
                        .zip(j)
                        .map(|(i, j)| [i, j])
                        .filter(|&[i, j]| i < g.nx && j < g.ny)
                    else {
                        return Err(ts.error(
                            at,
                            format!("WELSPECS: well {name}'s head is not a column of the grid"),
                        ));
                    };
                    self.heads.insert(name.clone(), [i, j]);
                    let cell = (0..g.nz).find_map(|k| t.unchanged([i, j, k]));
                    cell.ok_or_else(|| ts.error(at, format!("well {name} (column {} {}) has no radial mesh and its column lies in a cavity of the meshed wells: mesh it too", i + 1, j + 1)))?
                }
            };
            while rec.len() < 4 {
                rec.push(None);
            }
            for (n, v) in [(2, cell + 1), (3, 1)] {
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
    /// and the rest of its items; another well's keep their cells (each
    /// layer a line), with the input's factor or Flow's own (Peaceman's).
    pub fn compdat(&self, ts: &Tokens, kw: &Kw, said: &mut Said) -> Result<String> {
        let at = &ts.toks[kw.start];
        let mut s = String::from("COMPDAT\n");
        for rec in records(ts, kw)? {
            let name = Self::name(&rec);
            match self.meshed.get(&name) {
                Some(&w) => self.rings(ts, at, &rec, w, said, &mut s)?,
                None => self.kept(ts, at, &rec, said, &mut s)?,
            }
        }
        s.push_str("/\n\n");
        Ok(s)
    }

    /// A meshed well's COMPDAT line as its innermost ring's connections.
    fn rings(
        &self,
        ts: &Tokens,
        at: &Tok,
        rec: &Record,
        w: usize,
        said: &mut Said,
        s: &mut String,
    ) -> Result<()> {
        let t = self.table;
        let name = Self::name(rec);
        let well = &t.mesh.wells[w];
        let nz = t.mesh.grid.nz;
        let k1 = index(ts, at, rec, 3)?.unwrap_or(0);
        let k2 = index(ts, at, rec, 4)?.unwrap_or(nz - 1);
        let skin = number(rec, 10).unwrap_or(0.0);
        // the input's own factor for the line, where it gives one
        let sums = said.factors.entry(name.clone()).or_insert([0.0, 0.0]);
        sums[1] += number(rec, 7).unwrap_or(f64::NAN);
        // per deck cell its factor: the ring's sectors an annulus where
        // the deck merged them (carry::merge), their factors added
        let mut cells: Vec<(usize, f64)> = vec![];
        for &(e, g) in &well.links {
            let k = t.mesh.host[e][2];
            if !(k1..=k2).contains(&k) {
                continue;
            }
            let perm = (t.perm(e, 0) * t.perm(e, 1)).sqrt();
            let mut factor = t.darcy * perm * g * t.f * well.log / (well.log + skin);
            // on through the rings merged into its cell, in series
            if let Some(r) = t.outward.get(&e) {
                factor = 1.0 / (1.0 / factor + r);
            }
            if let Some(sums) = said.factors.get_mut(&name) {
                sums[0] += factor;
            }
            match cells.iter_mut().find(|c| c.0 == t.position[e]) {
                Some(c) => c.1 += factor,
                None => cells.push((t.position[e], factor)),
            }
        }
        for (cell, factor) in cells {
            // KH defaulted and skin 0: both are in the factor
            let _ = writeln!(
                s,
                " '{name}' {} 1 1 1 {} {} {} {} 1* 0 {} {} /",
                cell + 1,
                text(rec, 5),
                text(rec, 6),
                num(factor),
                text(rec, 8),
                text(rec, 11),
                text(rec, 12),
            );
        }
        said.rings = true;
        Ok(())
    }

    /// A COMPDAT line of a well without a radial mesh, a line per layer on
    /// the cells left unchanged; connections to cells Flow leaves out are
    /// left out as Flow leaves them, one into a cavity is an error.
    fn kept(
        &self,
        ts: &Tokens,
        at: &Tok,
        rec: &Record,
        said: &mut Said,
        s: &mut String,
    ) -> Result<()> {
        let t = self.table;
        let g = t.mesh.grid;
        let name = Self::name(rec);
        let Some(&[hi, hj]) = self.heads.get(&name) else {
            return Err(ts.error(at, format!("COMPDAT: well {name} before its WELSPECS")));
        };
        let i = index(ts, at, rec, 1)?.unwrap_or(hi);
        let j = index(ts, at, rec, 2)?.unwrap_or(hj);
        let k1 = index(ts, at, rec, 3)?.unwrap_or(0);
        let k2 = index(ts, at, rec, 4)?.unwrap_or(g.nz - 1);
        if i >= g.nx || j >= g.ny || k2 >= g.nz || k1 > k2 {
            return Err(ts.error(
                at,
                format!(
                    "COMPDAT: well {name}'s cells {} {} {}-{} are not the grid's",
                    i + 1,
                    j + 1,
                    k1 + 1,
                    k2 + 1
                ),
            ));
        }
        for k in k1..=k2 {
            let c = [i, j, k];
            let Some(cell) = t.unchanged(c) else {
                if t.hosts(c) {
                    return Err(ts.error(at, format!("well {name} has no radial mesh and its connection in cell {} {} {} lies in a cavity of the meshed wells: mesh it too", i + 1, j + 1, k + 1)));
                }
                said.skipped
                    .insert(format!("{name} {} {} {}", i + 1, j + 1, k + 1));
                continue;
            };
            let factor = match number(rec, 7) {
                Some(v) => v,
                None => self.peaceman(ts, at, rec, c)?,
            };
            let _ = writeln!(
                s,
                " '{name}' {} 1 1 1 {} {} {} {} {} {} {} {} {} /",
                cell + 1,
                text(rec, 5),
                text(rec, 6),
                num(factor),
                text(rec, 8),
                text(rec, 9),
                text(rec, 10),
                text(rec, 11),
                text(rec, 12),
                text(rec, 13),
            );
        }
        said.kept.insert(name);
        Ok(())
    }

    /// Flow's own factor for a vertical connection to grid cell c whose
    /// COMPDAT line gives none: Peaceman's on the cell as it is.
    fn peaceman(&self, ts: &Tokens, at: &Tok, rec: &Record, c: [usize; 3]) -> Result<f64> {
        let t = self.table;
        let name = Self::name(rec);
        let [i, j, k] = c;
        let cell = format!(
            "well {name}'s connection in cell {} {} {}",
            i + 1,
            j + 1,
            k + 1
        );
        if item(rec, 12).is_some_and(|d| !d.eq_ignore_ascii_case("Z")) {
            return Err(ts.error(at, format!("{cell}: a horizontal connection without a factor; give COMPDAT's factor (item 8)")));
        }
        let Some(diameter) = number(rec, 8).filter(|d| *d > 0.0) else {
            return Err(ts.error(
                at,
                format!("{cell}: neither a factor nor a wellbore diameter (COMPDAT items 8, 9)"),
            ));
        };
        let w = trans::Completion {
            radius: diameter / 2.0,
            skin: number(rec, 10).unwrap_or(0.0),
            kh: number(rec, 9),
            r0: number(rec, 13),
        };
        let (g, a) = (t.mesh.grid, &t.arrays);
        let at_c = g.cell_index(i, j, k);
        let perm = [a.value("PERMX", at_c), a.value("PERMY", at_c)];
        trans::peaceman_factor(g, c, perm, a.value("NTG", at_c), t.f, t.darcy, &w).ok_or_else(
            || {
                ts.error(
                    at,
                    format!("{cell}: the wellbore is as wide as the cell's equivalent radius"),
                )
            },
        )
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

    /// The deck cell of well `name`'s first ring cell hosted in block c; a
    /// well without a radial mesh, the block's own cell.
    fn ring_cell(&self, name: &str, c: [usize; 3]) -> Option<usize> {
        let t = self.table;
        let Some(&w) = self.meshed.get(name) else {
            return t.unchanged(c);
        };
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
