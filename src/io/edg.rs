//! CGAL's `.edg` segment soups: a count, then `x1 y1 x2 y2` per line.
//! Endpoints are shared by exact coordinate equality; a zero-length segment
//! is kept as an isolated point and reported in the notes.

use super::Records;
use crate::complex::Complex;
use crate::error::Result;
use std::collections::HashMap;
use std::path::Path;

/// Parses a `.edg` file's text. Vertex ids are 0-based in order of first
/// appearance; segment ids are 1-based segment numbers in the file.
pub fn parse(text: &str, path: &Path) -> Result<Complex> {
    let mut r = Records::new(text, path);
    let (line, head) = r.next_record("the segment count")?;
    let n: usize = r.num(line, &head, 0, "segment count")?;
    let mut cx = Complex::default();
    let mut index: HashMap<[u64; 2], u32> = HashMap::new();
    let mut zero = vec![];
    for k in 0..n {
        let (line, t) = r.next_record(&format!("segment {} of {n}", k + 1))?;
        if t.len() < 4 {
            return Err(r.error(
                line,
                format!("segment {} needs 4 numbers, found {}", k + 1, t.len()),
            ));
        }
        let mut ends = [0u32; 2];
        for (e, end) in ends.iter_mut().enumerate() {
            let p: [f64; 2] = [
                r.num(line, &t, 2 * e, "x")?,
                r.num(line, &t, 2 * e + 1, "y")?,
            ];
            let key = [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits()];
            let next = cx.points.len() as u32;
            *end = *index.entry(key).or_insert_with(|| {
                cx.points.push(p);
                cx.vertex_ids.push(next as i64);
                next
            });
        }
        if ends[0] == ends[1] {
            zero.push(k + 1);
        } else {
            cx.segments.push(ends);
            cx.segment_ids.push(k as i64 + 1);
        }
    }
    if !r.at_end() {
        let (line, _) = r.next_record("")?;
        return Err(r.error(
            line,
            format!("more segments than the count ({n}) on line 1 says"),
        ));
    }
    if !zero.is_empty() {
        cx.notes.push(format!(
            "{} zero-length segment(s) kept as isolated points: {:?}",
            zero.len(),
            zero
        ));
    }
    Ok(cx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_endpoints_and_keeps_zero_length_as_points() {
        let c = parse("3\n0 0 1 0\n1 0 1 1\n2 2 2 2\n", Path::new("x.edg")).unwrap();
        assert_eq!(c.points.len(), 4);
        assert_eq!(c.segments, vec![[0, 1], [1, 2]]);
        assert_eq!(c.segment_ids, vec![1, 2]);
        assert!(c.notes[0].contains("[3]"));
    }

    #[test]
    fn short_lines_are_errors() {
        let e = parse("2\n0 0 1 0\n1 0 1\n", Path::new("x.edg")).unwrap_err();
        assert!(e.to_string().contains("x.edg:3"), "{e}");
    }
}
