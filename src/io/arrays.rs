//! A deck's per-cell arrays as the simulator evaluates them on the
//! original grid: the arrays given (PORO, PERMX, NTG, SATNUM, SWATINIT,
//! PRESSURE, ...), then the operations on them in the order they come, in
//! every section: EQUALS, COPY, ADD, MULTIPLY, MINVALUE, MAXVALUE, each
//! within its own box or the one BOX sets (ENDBOX ends it). An array given
//! inside a BOX fills that box. Operations this reader does not evaluate
//! (OPERATE, MULTREGP, ...) are errors naming them.

use super::eclipse::{each_record, next_keyword, number, reals, record, skip, Record, Tok, Tokens};
use crate::error::{Error, Result};
use crate::reservoir::{trans, CornerPointGrid};
use std::collections::BTreeMap;
use std::path::Path;

/// The per-cell arrays this reader keeps: every keyword ending in NUM (the
/// region arrays) and these.
const ARRAYS: &[&str] = &[
    "PORO", "PERMX", "PERMY", "PERMZ", "NTG", "MULTX", "MULTY", "MULTZ", "MULTX-", "MULTY-",
    "MULTZ-", "MULTPV", "PORV", "SWATINIT", "SWL", "SWCR", "SWU", "SGL", "SGCR", "SGU", "SOWCR",
    "SOGCR", "ISWL", "ISWCR", "ISWU", "ISGL", "ISGCR", "ISGU", "KRW", "KRO", "KRG", "KRWR",
    "KRORW", "KRORG", "KRGR", "PCW", "PCG", "PRESSURE", "SWAT", "SGAS", "SOIL", "RS", "RV", "PBUB",
    "PDEW", "TEMPI", "SALT",
];

/// Operations on arrays, and keywords that change transmissibilities or
/// pore volumes, that this reader does not evaluate.
const UNSUPPORTED: &[&str] = &[
    "OPERATE", "OPERATER", "MULTREGP", "ADDREG", "MULTIREG", "EQUALREG", "COPYREG", "COPYBOX",
    "MINPVV", "MINPORV", "EDITNNC", "NNC",
];

/// The value an array holds where the deck sets none: 1 for NTG, the
/// multipliers and the region numbers, else 0.
fn default(name: &str) -> f64 {
    match name == "NTG" || name.starts_with("MULT") || name.ends_with("NUM") {
        true => 1.0,
        false => 0.0,
    }
}

fn is_array(name: &str) -> bool {
    ARRAYS.contains(&name) || (name.ends_with("NUM") && name.len() > 3)
}

/// The arrays of a deck with dimensions `d`, by name, per cell
/// (i + nx (j + ny k)), and the scalars that go with them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Arrays {
    /// Each array, per cell.
    pub values: BTreeMap<String, Vec<f64>>,
    /// MULTFLT's records (fault name or stem with `*`, multiplier) in order.
    pub multflt: Vec<(String, f64)>,
    /// MULTREGT's records in order.
    pub multregt: Vec<trans::RegionMultiplier>,
    /// MINPV, where given.
    pub minpv: Option<f64>,
    /// Whether the deck has PINCH (its default options: `pinch`).
    pub pinch: bool,
    /// The deck they come from.
    pub path: std::path::PathBuf,
}

impl Arrays {
    /// Each cell's pore volume as Flow computes it on the original grid:
    /// PORV where the deck gives it, else PORO times NTG times the cell's
    /// bulk volume; times MULTPV.
    pub fn pore_volumes(&self, g: &CornerPointGrid) -> Vec<f64> {
        let mut out = Vec::with_capacity(g.actnum.len());
        for k in 0..g.nz {
            for j in 0..g.ny {
                for i in 0..g.nx {
                    let c = g.cell_index(i, j, k);
                    out.push(match self.values.get("PORV") {
                        Some(p) => p[c] * self.value("MULTPV", c),
                        None => self.pore_fraction(c) * trans::bulk_volume(g, i, j, k),
                    });
                }
            }
        }
        out
    }

    /// Array `name`'s value in cell c, its default where the deck sets none.
    pub fn value(&self, name: &str, c: usize) -> f64 {
        self.values.get(name).map_or(default(name), |a| a[c])
    }

    /// The share of cell c's bulk volume that is pore volume: PORO times
    /// NTG times MULTPV.
    pub fn pore_fraction(&self, c: usize) -> f64 {
        self.value("PORO", c) * self.value("NTG", c) * self.value("MULTPV", c)
    }

    /// The transmissibilities between the cells of the original grid as
    /// Flow computes them (`reservoir::trans`): the cells it keeps
    /// (ACTNUM, pore volume above MINPV), PERMX/Y/Z, NTG, the face
    /// multipliers with MULTFLT folded in, MULTREGT. `darcy` is the deck's units'
    /// constant.
    pub fn transmissibilities(
        &self,
        g: &CornerPointGrid,
        darcy: f64,
    ) -> Result<Vec<trans::Transmissibility>> {
        let v = &self.values;
        let n = g.actnum.len();
        let get = |name: &str| {
            v.get(name).ok_or_else(|| Error::Parse {
                path: self.path.clone(),
                line: 0,
                message: format!("the deck sets no {name}; the transmissibilities need it"),
            })
        };
        let (px, py, pz) = (get("PERMX")?, get("PERMY")?, get("PERMZ")?);
        let perm: Vec<[f64; 3]> = (0..n).map(|c| [px[c], py[c], pz[c]]).collect();
        let ntg = v.get("NTG").cloned().unwrap_or(vec![1.0; n]);
        let names = ["MULTX", "MULTX-", "MULTY", "MULTY-", "MULTZ", "MULTZ-"];
        let mut mult = names.map(|m| v.get(m).cloned().unwrap_or(vec![1.0; n]));
        trans::apply_multflt(g, &self.multflt, &mut mult);
        let active = trans::active_cells(g, &self.pore_volumes(g), self.minpv.unwrap_or(1e-6));
        let props = trans::CellProps {
            pinch: self.pinch,
            active: &active,
            perm: &perm,
            ntg: &ntg,
            mult: std::array::from_fn(|m| Some(&mult[m][..])),
        };
        let mut out = trans::transmissibilities(g, &props, darcy);
        let sets = (self.multregt.iter())
            .map(|r| {
                let cells = v.get(&r.set).ok_or_else(|| Error::Parse {
                    path: self.path.clone(),
                    line: 0,
                    message: format!("MULTREGT names {}, which the deck does not set", r.set),
                })?;
                Ok((r.set.clone(), cells.iter().map(|&x| x as i64).collect()))
            })
            .collect::<Result<_>>()?;
        trans::apply_multregt(g, &self.multregt, &sets, &mut out);
        Ok(out)
    }
}

/// A box of cells, 0-based and inclusive, per axis.
type Cube = [[usize; 2]; 3];

fn cells(b: Cube, d: [usize; 3]) -> impl Iterator<Item = usize> {
    (b[2][0]..=b[2][1]).flat_map(move |k| {
        (b[1][0]..=b[1][1])
            .flat_map(move |j| (b[0][0]..=b[0][1]).map(move |i| i + d[0] * (j + d[1] * k)))
    })
}

/// The box of items `from..from + 6` of a record (1-based, inclusive),
/// defaulted items taken from `current`.
fn cube(
    ts: &Tokens,
    kw: &Tok,
    rec: &Record,
    from: usize,
    current: Cube,
    d: [usize; 3],
) -> Result<Cube> {
    let mut b = current;
    for n in 0..6 {
        let Some(Some(t)) = rec.get(from + n) else {
            continue;
        };
        let x: usize = number(ts, &Some(t.clone()), kw, &format!("{} box", kw.text))?;
        let (axis, end) = (n / 2, n % 2);
        if x == 0 || x > d[axis] {
            return Err(ts.error(
                t,
                format!("{}: box index {x} outside 1..{}", kw.text, d[axis]),
            ));
        }
        b[axis][end] = x - 1;
    }
    if (0..3).any(|a| b[a][0] > b[a][1]) {
        return Err(ts.error(kw, format!("{}: an empty box {b:?}", kw.text)));
    }
    Ok(b)
}

fn name(ts: &Tokens, kw: &Tok, t: &Option<Tok>) -> Result<String> {
    t.as_ref()
        .map(|t| t.text.to_ascii_uppercase())
        .ok_or_else(|| {
            ts.error(
                kw,
                format!("{}: an array's name may not be defaulted", kw.text),
            )
        })
}

/// Reads the arrays of a deck (with its includes) whose grid has
/// dimensions `d`.
pub fn read_arrays(path: &Path, d: [usize; 3]) -> Result<Arrays> {
    let ts = Tokens::read(path, false)?;
    let n = d[0] * d[1] * d[2];
    let whole: Cube = [[0, d[0] - 1], [0, d[1] - 1], [0, d[2] - 1]];
    let mut current = whole;
    let mut a = Arrays {
        path: path.into(),
        ..Arrays::default()
    };
    let mut k = 0;
    // MULTREGT's default region set: MULTNUM where GRIDOPTS counts them
    let mut multnum = false;
    while let Some(kw) = next_keyword(&ts, &mut k) {
        let word = kw.text.as_str();
        if UNSUPPORTED.contains(&word) {
            return Err(ts.error(
                &kw,
                format!("{word}: this operation on arrays is not evaluated"),
            ));
        }
        match word {
            "BOX" => {
                let (rec, next) = record(&ts, k, &kw)?;
                current = cube(&ts, &kw, &rec, 0, whole, d)?;
                k = next;
            }
            "ENDBOX" => current = whole,
            "MULTFLT" => {
                k = each_record(&ts, k, &kw, |rec| {
                    let fault = name(&ts, &kw, rec.first().unwrap_or(&None))?;
                    let m = number(&ts, rec.get(1).unwrap_or(&None), &kw, "MULTFLT value")?;
                    a.multflt.push((fault, m));
                    Ok(())
                })?;
            }
            "GRIDOPTS" => {
                let (rec, next) = record(&ts, k, &kw)?;
                let nrmult = rec.get(1).cloned().flatten();
                multnum = nrmult.is_some_and(|t| t.text.parse::<i64>().is_ok_and(|n| n > 0));
                k = next;
            }
            "MULTREGT" => {
                k = each_record(&ts, k, &kw, |rec| {
                    let set = match a.multregt.last() {
                        Some(p) => p.set.as_str(),
                        None if multnum => "MULTNUM",
                        None => "FLUXNUM",
                    };
                    let r = region_multiplier(&ts, &kw, &rec, set)?;
                    a.multregt.push(r);
                    Ok(())
                })?;
            }
            "PINCH" => {
                let (rec, next) = record(&ts, k, &kw)?;
                pinch(&ts, &kw, &rec)?;
                a.pinch = true;
                k = next;
            }
            "MINPV" => {
                let (rec, next) = record(&ts, k, &kw)?;
                a.minpv = Some(number(&ts, rec.first().unwrap_or(&None), &kw, "MINPV")?);
                k = next;
            }
            "EQUALS" | "ADD" | "MULTIPLY" | "MINVALUE" | "MAXVALUE" | "COPY" => {
                k = each_record(&ts, k, &kw, |rec| {
                    operate(&ts, &kw, &rec, current, d, &mut a)
                })?;
            }
            w if is_array(w) => {
                let (rec, next) = record(&ts, k, &kw)?;
                k = next;
                let inside: Vec<usize> = cells(current, d).collect();
                let v = reals(&ts, &kw, &rec, inside.len())?;
                let slot = a
                    .values
                    .entry(w.to_string())
                    .or_insert_with(|| vec![default(w); n]);
                for (c, x) in inside.into_iter().zip(v) {
                    slot[c] = x;
                }
            }
            _ => k = skip(&ts, k, &kw)?,
        }
    }
    Ok(a)
}

/// PINCH's options as far as they are evaluated: the threshold and the
/// largest gap are read, and have no effect in Flow 2022.10 (measured: a
/// 0.5 ft layer under a 1 ft threshold, inactive layers of any thickness
/// and emerald's zero-porosity cells connect as without PINCH); GAP,
/// TOPBOT and TOP only (NOGAP and ALL refused by name).
fn pinch(ts: &Tokens, kw: &Tok, rec: &[Option<Tok>]) -> Result<()> {
    let word = |i: usize| {
        let t = rec.get(i).cloned().flatten();
        t.map(|t| t.text.trim_matches('\'').to_uppercase())
    };
    for (i, kept) in [(1, "GAP"), (3, "TOPBOT"), (4, "TOP")] {
        if let Some(w) = word(i).filter(|w| w != kept) {
            let what = format!("PINCH item {} '{w}' is not evaluated (only {kept})", i + 1);
            return Err(ts.error(kw, what));
        }
    }
    for i in [0, 2] {
        if let Some(t @ Some(_)) = rec.get(i) {
            number::<f64>(ts, t, kw, "PINCH")?;
        }
    }
    Ok(())
}

/// A MULTREGT record: regions (defaulted or negative: all), multiplier,
/// directions (default XYZ), NNC behaviour (default ALL), region set (M,
/// F or O; `default` where not given: as Flow 2022.10, the previous
/// record's, else MULTNUM where GRIDOPTS counts MULTNUM regions, else
/// FLUXNUM).
fn region_multiplier(
    ts: &Tokens,
    kw: &Tok,
    rec: &Record,
    default: &str,
) -> Result<trans::RegionMultiplier> {
    let item = |n: usize| rec.get(n).cloned().flatten();
    let region = |n: usize| -> Result<Option<i64>> {
        match item(n) {
            None => Ok(None),
            t => Ok(Some(number::<i64>(ts, &t, kw, "MULTREGT region")?).filter(|&r| r >= 0)),
        }
    };
    let word = |n: usize, default: &str| {
        item(n).map_or(default.to_string(), |t| t.text.trim().to_ascii_uppercase())
    };
    let dirs = word(3, "XYZ");
    let axes = ["X", "Y", "Z"].map(|a| dirs.contains(a));
    let nnc = match word(4, "ALL").as_str() {
        "ALL" => None,
        "NNC" => Some(true),
        "NONNC" => Some(false),
        other => {
            return Err(ts.error(
                kw,
                format!("MULTREGT: NNC item '{other}' (ALL, NNC or NONNC)"),
            ))
        }
    };
    let set = match item(5).map(|t| t.text.trim().to_ascii_uppercase()) {
        None => default.to_string(),
        Some(s) => match s.as_str() {
            "M" => "MULTNUM".into(),
            "F" => "FLUXNUM".into(),
            "O" => "OPERNUM".into(),
            _ => return Err(ts.error(kw, format!("MULTREGT: region set '{s}' (M, F or O)"))),
        },
    };
    let regions = [region(0)?, region(1)?];
    if regions[0].is_some() && regions[0] == regions[1] {
        return Err(ts.error(
            kw,
            "MULTREGT inside one region is not evaluated (as in Flow)".to_string(),
        ));
    }
    Ok(trans::RegionMultiplier {
        regions,
        value: number(ts, &item(2), kw, "MULTREGT multiplier")?,
        axes,
        nnc,
        set,
    })
}

/// One record of EQUALS, ADD, MULTIPLY, MINVALUE, MAXVALUE or COPY.
fn operate(
    ts: &Tokens,
    kw: &Tok,
    rec: &Record,
    current: Cube,
    d: [usize; 3],
    a: &mut Arrays,
) -> Result<()> {
    let n = d[0] * d[1] * d[2];
    let target = name(ts, kw, rec.first().unwrap_or(&None))?;
    let b = cube(ts, kw, rec, 2, current, d)?;
    if kw.text == "COPY" {
        let to = name(ts, kw, rec.get(1).unwrap_or(&None))?;
        let from = a
            .values
            .get(&target)
            .cloned()
            .ok_or_else(|| ts.error(kw, format!("COPY from {target}, which is not set")))?;
        let fill = default(&to);
        let slot = a.values.entry(to).or_insert_with(|| vec![fill; n]);
        for c in cells(b, d) {
            slot[c] = from[c];
        }
        return Ok(());
    }
    let x: f64 = number(
        ts,
        rec.get(1).unwrap_or(&None),
        kw,
        &format!("{} value", kw.text),
    )?;
    let slot = match kw.text.as_str() {
        "EQUALS" => {
            let fill = default(&target);
            a.values.entry(target).or_insert_with(|| vec![fill; n])
        }
        _ => a
            .values
            .get_mut(&target)
            .ok_or_else(|| ts.error(kw, format!("{} on {target}, which is not set", kw.text)))?,
    };
    for c in cells(b, d) {
        let v = &mut slot[c];
        *v = match kw.text.as_str() {
            "EQUALS" => x,
            "ADD" => *v + x,
            "MULTIPLY" => *v * x,
            "MINVALUE" => v.max(x),
            _ => v.min(x),
        };
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deck(text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("orthomesh-arrays-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("d{}.DATA", text.len()));
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn operations_in_order_and_boxes() {
        let p = deck(
            "GRID\nPERMX\n 1 2 3 4 5 6 7 8 /\nCOPY\n 'PERMX' 'PERMZ' /\n/\n\
             MULTIPLY\n 'PERMZ' 0.1 1 1 1 2 1 2 /\n/\n\
             BOX\n 2 2 1 1 1 2 /\nPORO\n 0.3 0.4 /\nENDBOX\n\
             EQUALS\n 'SATNUM' 2 /\n 'SATNUM' 1 1 1 /\n/\nADD\n 'PERMX' 10 2 2 2 2 2 2 /\n/\n\
             MINVALUE\n 'PERMX' 4 /\n/\n",
        );
        let a = read_arrays(&p, [2, 2, 2]).unwrap();
        assert_eq!(
            a.values["PERMX"],
            vec![4.0, 4.0, 4.0, 4.0, 5.0, 6.0, 7.0, 18.0]
        );
        let z = &a.values["PERMZ"];
        assert!((z[0] - 0.1).abs() < 1e-15 && (z[6] - 0.7).abs() < 1e-15 && z[1] == 2.0);
        assert_eq!(
            a.values["PORO"],
            vec![0.0, 0.3, 0.0, 0.0, 0.0, 0.4, 0.0, 0.0]
        );
        assert_eq!(
            a.values["SATNUM"],
            vec![1.0, 2.0, 1.0, 2.0, 1.0, 2.0, 1.0, 2.0]
        );
    }

    #[test]
    fn what_cannot_be_evaluated_is_named() {
        let e = read_arrays(&deck("GRID\nOPERATE\n/\n"), [1, 1, 1]).unwrap_err();
        assert!(e.to_string().contains("OPERATE"), "{e}");
        let e = read_arrays(&deck("GRID\nMULTIPLY\n 'PERMX' 2 /\n/\n"), [1, 1, 1]).unwrap_err();
        assert!(e.to_string().contains("PERMX, which is not set"), "{e}");
        let e = read_arrays(&deck("GRID\nPORO\n 0.1 0.2 /\n"), [1, 1, 1]).unwrap_err();
        assert!(e.to_string().contains("PORO has 2 values"), "{e}");
        // PINCH with its default options is evaluated, the others named
        let a = read_arrays(&deck("GRID\nPINCH\n 0.5 GAP 1* TOPBOT /\n"), [1, 1, 1]).unwrap();
        assert!(a.pinch);
        for (options, item) in [
            ("1* NOGAP", "2 'NOGAP'"),
            ("3* ALL", "4 'ALL'"),
            ("4* ALL", "5 'ALL'"),
        ] {
            let text = format!("GRID\nPINCH\n {options} /\n");
            let e = read_arrays(&deck(&text), [1, 1, 1]).unwrap_err();
            assert!(e.to_string().contains(&format!("PINCH item {item}")), "{e}");
        }
    }
}
