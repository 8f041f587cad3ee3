//! Well trajectories as plain text, one file per well, as xtgeo and RMS
//! export them: a point per line, x, y and depth (true vertical, positive
//! down), then any further columns (measured depth) ignored. Lines that
//! are empty, start with `#` or `--`, or hold no number (a header) are
//! skipped before the first point.

use crate::error::{Error, Result};
use std::path::Path;

/// The points (x, y, depth) of a trajectory file.
pub fn read_well_path(path: &Path) -> Result<Vec<[f64; 3]>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let parse = |line: usize, message: String| Error::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut points: Vec<[f64; 3]> = vec![];
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') || line.starts_with("--") {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if points.is_empty() && numbers.first().is_some_and(Option::is_none) {
            continue; // a header
        }
        let xyz: Option<Vec<f64>> = numbers.iter().take(3).copied().collect();
        match xyz {
            Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => {
                points.push([v[0], v[1], v[2]]);
            }
            _ => {
                return Err(parse(
                    n + 1,
                    format!("expected x, y and depth (finite numbers), found '{line}'"),
                ))
            }
        }
    }
    if points.len() < 2 {
        return Err(parse(
            text.lines().count().max(1),
            format!(
                "a well path needs two points or more, found {}",
                points.len()
            ),
        ));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<[f64; 3]>> {
        let dir = std::env::temp_dir().join(format!("orthomesh-wellpath-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("{}.txt", text.len()));
        std::fs::write(&p, text).unwrap();
        read_well_path(&p)
    }

    #[test]
    fn headers_comments_and_extra_columns() {
        let pts = read("# exported\nX Y Z MD\n1 2 3 0\n4,5,6,7\n\n7 8 9\n").unwrap();
        assert_eq!(pts, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]);
    }

    #[test]
    fn bad_lines_are_named() {
        let e = read("1 2 3\n4 x 6\n").unwrap_err().to_string();
        assert!(e.contains(":2:") && e.contains("'4 x 6'"), "{e}");
        let e = read("1 2 nan\n4 5 6\n").unwrap_err().to_string();
        assert!(e.contains(":1:"), "{e}");
        let e = read("X Y Z\n1 2 3\n").unwrap_err().to_string();
        assert!(e.contains("two points or more, found 1"), "{e}");
    }
}
