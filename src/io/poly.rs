//! Triangle's `.poly`: vertices (possibly in a sibling `.node` file),
//! segments, holes. Regional attributes are read past and ignored.

use super::Records;
use crate::complex::Complex;
use crate::error::Result;
use std::path::Path;

/// Writes a complex as a `.poly` text (its own vertex and segment ids,
/// coordinates in shortest round-trip form): what `parse` reads back as the
/// same complex, and what Triangle reads.
pub fn to_string(cx: &Complex) -> String {
    use std::fmt::Write;
    let mut t = format!("# written by orthomesh\n{} 2 0 0\n", cx.points.len());
    for (p, id) in cx.points.iter().zip(&cx.vertex_ids) {
        let _ = writeln!(t, "{id} {:?} {:?}", p[0], p[1]);
    }
    let _ = writeln!(t, "{} 0", cx.segments.len());
    for (s, id) in cx.segments.iter().zip(&cx.segment_ids) {
        let v = |k: usize| cx.vertex_ids[s[k] as usize];
        let _ = writeln!(t, "{id} {} {}", v(0), v(1));
    }
    let _ = writeln!(t, "{}", cx.holes.len());
    for (k, h) in cx.holes.iter().enumerate() {
        let _ = writeln!(t, "{k} {:?} {:?}", h[0], h[1]);
    }
    t
}

/// Parses a `.poly` file's text.
pub fn parse(text: &str, path: &Path) -> Result<Complex> {
    let mut r = Records::new(text, path);
    let mut cx = Complex::default();
    let (line, head) = r.next_record("the vertex header 'count 2 attributes markers'")?;
    (cx.points, cx.vertex_ids) =
        super::read_nodes(&mut r, (line, &head), path, "vertex", &|dim| {
            format!(
                "dimension {dim}: this reader takes 2D .poly files (a 3D one is TetGen's \
                 piecewise linear complex, which `io::read_complex3` reads)"
            )
        })?;
    let index = super::index_of(&cx.vertex_ids);

    let (line, head) = r.next_record("the segment header 'count markers'")?;
    let ns: usize = r.num(line, &head, 0, "segment count")?;
    for k in 0..ns {
        let (line, t) = r.next_record(&format!("segment {} of {ns}", k + 1))?;
        let id: i64 = r.num(line, &t, 0, "segment id")?;
        let mut ends = [0u32; 2];
        for (e, end) in ends.iter_mut().enumerate() {
            let v: i64 = r.num(line, &t, 1 + e, "segment endpoint")?;
            *end = *index.get(&v).ok_or_else(|| {
                r.error(
                    line,
                    format!("segment {id} refers to vertex {v}, which does not exist"),
                )
            })?;
        }
        cx.segments.push(ends);
        cx.segment_ids.push(id);
    }

    if r.at_end() {
        return Ok(cx); // Triangle allows the hole section to be missing
    }
    let (line, head) = r.next_record("the hole count")?;
    let nh: usize = r.num(line, &head, 0, "hole count")?;
    for k in 0..nh {
        let (line, t) = r.next_record(&format!("hole {} of {nh}", k + 1))?;
        cx.holes
            .push([r.num(line, &t, 1, "hole x")?, r.num(line, &t, 2, "hole y")?]);
    }
    Ok(cx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    #[test]
    fn reads_a_square_with_a_hole_and_one_based_ids() {
        let text = "# square\n4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 0.5 0.5\n";
        let c = parse(text, Path::new("sq.poly")).unwrap();
        assert_eq!(c.points.len(), 4);
        assert_eq!(c.segments, vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
        assert_eq!(c.holes, vec![[0.5, 0.5]]);
        assert_eq!(c.vertex_ids, vec![1, 2, 3, 4]);
    }

    #[test]
    fn truncated_and_garbage_files_name_the_line() {
        let e = parse("3 2 0 0\n0 0 0\n1 1 0\n", Path::new("t.poly")).unwrap_err();
        assert!(matches!(e, Error::Parse { line: 4, .. }), "{e}");
        assert!(e.to_string().contains("vertex 3 of 3"), "{e}");
        let e = parse("2 2 0 0\n0 0 0\n1 abc 0\n", Path::new("t.poly")).unwrap_err();
        assert!(matches!(e, Error::Parse { line: 3, .. }), "{e}");
        let e = parse("2 2 0 0\n0 0 0\n1 1 0\n1 0\n0 0 7\n", Path::new("t.poly")).unwrap_err();
        assert!(e.to_string().contains("vertex 7"), "{e}");
    }

    #[test]
    fn writes_what_it_reads() {
        let mut cx = crate::generate::mixed(2, 2, 3);
        cx.points[0][0] = 0.1 + 0.2; // not a short decimal
        let back = parse(&to_string(&cx), Path::new("m.poly")).unwrap();
        assert_eq!(back.points, cx.points);
        assert_eq!(back.segments, cx.segments);
        assert_eq!(back.holes, cx.holes);
        assert_eq!(back.vertex_ids, cx.vertex_ids);
        assert_eq!(back.segment_ids, cx.segment_ids);
    }
}
