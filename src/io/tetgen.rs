//! TetGen's piecewise linear complexes: `.poly` (facets of several
//! polygons with facet holes) and `.smesh` (one polygon per facet), their
//! points possibly in a sibling `.node` file. Region attributes are read
//! past and ignored.

use super::Records;
use crate::complex::{Complex3, Facet};
use crate::error::Result;
use std::collections::HashMap;
use std::path::Path;

/// Which of TetGen's two PLC formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A `.poly` file: nodes, facets, holes.
    Poly,
    /// A `.smesh` file: the same, nodes possibly in a `.node` file.
    Smesh,
}

/// A complex as a TetGen `.poly` text (its own vertex ids; facet holes and
/// volume holes kept; no markers).
pub fn to_string(cx: &Complex3) -> String {
    use std::fmt::Write;
    let mut out = format!("{} 3 0 0\n", cx.points.len());
    for (p, id) in cx.points.iter().zip(&cx.vertex_ids) {
        let _ = writeln!(out, "{id} {:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    let _ = writeln!(out, "{} 0", cx.facets.len());
    for f in &cx.facets {
        let _ = writeln!(out, "{} {}", f.polygons.len(), f.holes.len());
        for poly in &f.polygons {
            let ids: Vec<String> = poly
                .iter()
                .map(|&v| cx.vertex_ids[v as usize].to_string())
                .collect();
            let _ = writeln!(out, "{} {}", poly.len(), ids.join(" "));
        }
        for (k, h) in f.holes.iter().enumerate() {
            let _ = writeln!(out, "{} {:?} {:?} {:?}", k + 1, h[0], h[1], h[2]);
        }
    }
    let _ = writeln!(out, "{}", cx.holes.len());
    for (k, h) in cx.holes.iter().enumerate() {
        let _ = writeln!(out, "{} {:?} {:?} {:?}", k + 1, h[0], h[1], h[2]);
    }
    out.push_str("0\n");
    out
}

/// Parses a TetGen `.poly` or `.smesh` text.
pub fn parse(text: &str, path: &Path, format: Format) -> Result<Complex3> {
    let mut r = Records::new(text, path);
    let mut cx = Complex3::default();
    let (line, head) = r.next_record("the point header 'count 3 attributes markers'")?;
    (cx.points, cx.vertex_ids) = super::read_nodes(&mut r, (line, &head), path, "point", &|dim| {
        format!("dimension {dim}: a TetGen piecewise linear complex is 3D")
    })?;
    let index = super::index_of(&cx.vertex_ids);

    let (line, head) = r.next_record("the facet header 'count markers'")?;
    let nf: usize = r.num(line, &head, 0, "facet count")?;
    let markers = r
        .num::<u8>(line, &head, 1, "boundary marker flag")
        .unwrap_or(0)
        == 1;
    for f in 1..=nf {
        let facet = match format {
            Format::Poly => {
                let (line, t) = r.next_record(&format!("facet {f} of {nf}"))?;
                let np: usize = r.num(line, &t, 0, "polygon count")?;
                let nh: usize = if t.len() > 1 {
                    r.num(line, &t, 1, "facet hole count")?
                } else {
                    0
                };
                let marker = if markers && t.len() > 2 {
                    r.num(line, &t, 2, "boundary marker")?
                } else {
                    0
                };
                let mut facet = Facet {
                    marker,
                    ..Default::default()
                };
                for k in 1..=np {
                    let (line, t) = r.next_record(&format!("polygon {k} of facet {f}"))?;
                    let (poly, _) = polygon(&r, line, &t, &index, f)?;
                    facet.polygons.push(poly);
                }
                for k in 1..=nh {
                    let (line, t) = r.next_record(&format!("hole {k} of facet {f}"))?;
                    facet.holes.push(super::coordinates(&r, line, &t)?);
                }
                facet
            }
            Format::Smesh => {
                let (line, t) = r.next_record(&format!("facet {f} of {nf}"))?;
                let (poly, rest) = polygon(&r, line, &t, &index, f)?;
                let marker = match rest.first() {
                    Some(_) if markers => r.num(line, rest, 0, "boundary marker")?,
                    _ => 0,
                };
                Facet {
                    polygons: vec![poly],
                    holes: vec![],
                    marker,
                }
            }
        };
        cx.facets.push(facet);
    }

    if r.at_end() {
        return Ok(cx); // TetGen allows the hole section to be missing
    }
    let (line, head) = r.next_record("the hole count")?;
    let nh: usize = r.num(line, &head, 0, "hole count")?;
    for k in 1..=nh {
        let (line, t) = r.next_record(&format!("hole {k} of {nh}"))?;
        cx.holes.push(super::coordinates(&r, line, &t)?);
    }
    Ok(cx)
}

/// A record `n v1 .. vn [more]`: the vertex cycle and the tokens after it.
fn polygon<'t>(
    r: &Records,
    line: usize,
    t: &'t [&'t str],
    index: &HashMap<i64, u32>,
    facet: usize,
) -> Result<(Vec<u32>, &'t [&'t str])> {
    let n: usize = r.num(line, t, 0, "corner count")?;
    if n == 0 {
        return Err(r.error(line, format!("facet {facet}: a polygon without corners")));
    }
    // (the count comes from the file: no more than the line holds)
    let mut poly = Vec::with_capacity(n.min(t.len()));
    for k in 1..=n {
        let v: i64 = r.num(line, t, k, "corner")?;
        poly.push(*index.get(&v).ok_or_else(|| {
            r.error(
                line,
                format!("facet {facet} refers to point {v}, which does not exist"),
            )
        })?);
    }
    Ok((poly, &t[n + 1..]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    const CUBE_SMESH: &str = "# unit cube\n8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n\
        5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n6 1\n4 1 2 3 4 5\n4 5 6 7 8 6\n4 1 2 6 5 1\n\
        4 2 3 7 6 1\n4 3 4 8 7 1\n4 4 1 5 8 1\n0\n0\n";

    #[test]
    fn reads_a_cube_as_smesh() {
        let c = parse(CUBE_SMESH, Path::new("cube.smesh"), Format::Smesh).unwrap();
        assert_eq!(c.points.len(), 8);
        assert_eq!(c.facets.len(), 6);
        assert_eq!(c.facets[1].polygons, vec![vec![4, 5, 6, 7]]);
        assert_eq!(c.facets[1].marker, 6);
        c.validate().unwrap();
    }

    #[test]
    fn truncated_and_wrong_files_name_the_line() {
        let cut = &CUBE_SMESH[..CUBE_SMESH.find("4 3 4 8 7").unwrap()];
        let e = parse(cut, Path::new("c.smesh"), Format::Smesh).unwrap_err();
        assert!(e.to_string().contains("facet 5 of 6"), "{e}");
        let bad = CUBE_SMESH.replace("4 4 1 5 8 1", "4 4 1 5 9 1");
        let e = parse(&bad, Path::new("c.smesh"), Format::Smesh).unwrap_err();
        assert!(matches!(e, Error::Parse { line: 17, .. }), "{e}");
        assert!(e.to_string().contains("point 9"), "{e}");
        let flat = CUBE_SMESH.replace("8 3 0 0", "8 2 0 0");
        let e = parse(&flat, Path::new("c.smesh"), Format::Smesh).unwrap_err();
        assert!(e.to_string().contains("dimension 2"), "{e}");
    }
}
