//! TOUGH2 `MESH` files (ELEME and CONNE blocks, fixed columns; docs/formats.md):
//! elements with their volume and node (the site, not the centroid), and
//! connections with the distances from each node to the interface (they
//! differ in a power diagram), the interface area and the gravity cosine.

use crate::error::{Error, Result};
use crate::mesh::{CellArray, Network};
use std::fmt::Write;

/// Element names: three characters (a letter, then letters or digits) and
/// two digits, as TOUGH reads them: 26 x 36 x 36 x 100 names.
pub fn name(n: usize) -> Result<String> {
    const MAX: usize = 26 * 36 * 36 * 100;
    if n >= MAX {
        return Err(Error::Usage(format!(
            "{n} elements: TOUGH's five-character names run out at {MAX}"
        )));
    }
    let digits = b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    let (head, tail) = (n / 100, n % 100);
    let c = [
        (b'A' + (head / (36 * 36)) as u8) as char,
        digits[(head / 36) % 36] as char,
        digits[head % 36] as char,
    ];
    Ok(format!("{}{}{}{tail:02}", c[0], c[1], c[2]))
}

/// The cell array `tough_element` of `n` elements: each element's name as
/// five ASCII codes, so that every VTU reader (meshio and toughio among
/// them, which refuse string arrays) maps TOUGH's results onto the mesh.
pub fn names_array(n: usize) -> Result<CellArray> {
    let mut codes = Vec::with_capacity(5 * n);
    for i in 0..n {
        codes.extend(name(i)?.bytes().map(i64::from));
    }
    Ok(CellArray::int("tough_element", 5, codes))
}

/// A real in ten columns, as many digits as fit (Fortran E10.4 or better).
fn e10(x: f64) -> String {
    for digits in (1..=5).rev() {
        let s = format!("{x:.digits$E}");
        // Rust writes 1.2345E2: give the exponent a sign and two digits.
        let (m, e) = s.split_once('E').expect("exponent");
        let e: i32 = e.parse().expect("exponent");
        let t = format!("{m}E{}{:02}", if e < 0 { '-' } else { '+' }, e.abs());
        if t.len() <= 10 {
            return format!("{t:>10}");
        }
    }
    format!("{:>10}", if x < 0.0 { "-9.9E+99" } else { "9.9E+99" })
}

/// The rock type every element gets.
const ROCK: &str = "ROCK1";

/// The MESH file text of a network; every element of rock type ROCK1.
pub fn to_string(network: &Network) -> Result<String> {
    let (elements, connections, rock) = (&network.elements, &network.connections, ROCK);
    let mut s = String::with_capacity(81 * (elements.len() + connections.len()) + 64);
    s.push_str("ELEME\n");
    let names: Vec<String> = (0..elements.len()).map(name).collect::<Result<_>>()?;
    for (e, n) in elements.iter().zip(&names) {
        if !(e.volume.is_finite() && e.node.iter().all(|x| x.is_finite())) {
            return Err(Error::Usage(format!(
                "element {n}: non-finite volume or node"
            )));
        }
        let _ = writeln!(
            s,
            "{n:5}{:10}{rock:>5}{}{:20}{}{}{}",
            "",
            e10(e.volume),
            "",
            e10(e.node[0]),
            e10(e.node[1]),
            e10(e.node[2])
        );
    }
    s.push_str("\nCONNE\n");
    for c in connections {
        let _ = writeln!(
            s,
            "{}{}{:15}{:5}{}{}{}{}",
            names[c.elements[0]],
            names[c.elements[1]],
            "",
            c.isot,
            e10(c.d[0]),
            e10(c.d[1]),
            e10(c.area),
            e10(c.cos_gravity)
        );
    }
    s.push('\n');
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Connection, Element};

    #[test]
    fn names_are_unique_with_two_digits_last() {
        assert_eq!(name(0).unwrap(), "A0000");
        assert_eq!(name(123).unwrap(), "A0123");
        assert_eq!(name(3600).unwrap(), "A1000");
        assert_eq!(name(129599).unwrap(), "AZZ99");
        assert_eq!(name(129600).unwrap(), "B0000");
        assert!(name(26 * 36 * 36 * 100).is_err());
    }

    #[test]
    fn the_names_array_spells_each_name() {
        let a = names_array(124).unwrap();
        let crate::mesh::Values::Int(v) = &a.values else {
            panic!("integer codes")
        };
        let last: String = v[5 * 123..].iter().map(|&c| c as u8 as char).collect();
        assert_eq!((a.components, last.as_str()), (Some(5), "A0123"));
    }

    #[test]
    fn reals_fill_ten_columns() {
        for (x, want) in [
            (1234.5, "1.2345E+03"),
            (-0.000125, "-1.250E-04"),
            (0.0, "0.0000E+00"),
        ] {
            assert_eq!(e10(x), want);
        }
        assert_eq!(e10(1e-300).len(), 10);
    }

    #[test]
    fn columns_are_where_tough_reads_them() {
        let e = Element {
            volume: 100.0,
            node: [5.0, 5.0, -0.5],
        };
        let c = Connection {
            elements: [0, 1],
            isot: 1,
            d: [5.0, 5.0],
            area: 10.0,
            cos_gravity: 0.0,
        };
        let network = Network {
            elements: vec![e.clone(), e],
            connections: vec![c],
        };
        let text = to_string(&network).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(&lines[1][0..5], "A0000");
        assert_eq!(&lines[1][15..20], "ROCK1");
        assert_eq!(&lines[1][20..30], "1.0000E+02");
        assert_eq!(&lines[1][50..60], "5.0000E+00");
        assert_eq!(&lines[1][70..80], "-5.000E-01");
        let conne = lines.iter().position(|l| *l == "CONNE").unwrap() + 1;
        assert_eq!(&lines[conne][0..10], "A0000A0001");
        assert_eq!(&lines[conne][25..30], "    1");
        assert_eq!(&lines[conne][50..60], "1.0000E+01");
    }
}
