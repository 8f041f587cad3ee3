//! A picture of a 2D mesh: cells, sites (red when outside their cell), the
//! constraint segments drawn thick on top.

use crate::complex::Complex;
use crate::mesh::Mesh;
use std::fmt::Write;

/// SVG text of the mesh and its constraints.
pub fn to_string(mesh: &Mesh, site_inside: &[bool], cx: &Complex) -> String {
    // Sites outside their cells may lie outside the domain: keep them in view.
    let pts = mesh.points.iter().chain(&cx.points).chain(&mesh.sites);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let pad = 0.03 * size;
    let px = 1000.0 / (size + 2.0 * pad);
    let (w, h) = (
        (hi[0] - lo[0] + 2.0 * pad) * px,
        (hi[1] - lo[1] + 2.0 * pad) * px,
    );
    // pixel coordinates, y up
    let x = |p: [f64; 2]| ((p[0] - lo[0] + pad) * px, (hi[1] - p[1] + pad) * px);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.2} {h:.2}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
    );
    s.push_str("<g stroke=\"#555\" stroke-width=\"0.6\" stroke-linejoin=\"round\">\n");
    for (c, cell) in mesh.cells.iter().enumerate() {
        let hue = (c * 47) % 360;
        let path: Vec<String> = cell
            .iter()
            .map(|&v| {
                let (a, b) = x(mesh.points[v as usize]);
                format!("{a:.2},{b:.2}")
            })
            .collect();
        let _ = writeln!(
            s,
            "<polygon points=\"{}\" fill=\"hsl({hue},55%,88%)\"/>",
            path.join(" ")
        );
    }
    s.push_str("</g>\n<g stroke=\"#c00\" stroke-width=\"2.4\" stroke-linecap=\"round\">\n");
    for &[a, b] in &cx.segments {
        let (p, q) = (x(cx.points[a as usize]), x(cx.points[b as usize]));
        let _ = writeln!(
            s,
            "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\"/>",
            p.0, p.1, q.0, q.1
        );
    }
    s.push_str("</g>\n<g fill=\"black\">\n");
    for p in &cx.points {
        let (a, b) = x(*p);
        let _ = writeln!(s, "<circle cx=\"{a:.2}\" cy=\"{b:.2}\" r=\"2.2\"/>");
    }
    s.push_str("</g>\n<g>\n");
    for (c, site) in mesh.sites.iter().enumerate() {
        let (a, b) = x(*site);
        let colour = if site_inside.get(c).copied().unwrap_or(true) {
            "#1f4fbf"
        } else {
            "#ff2020"
        };
        let r = if site_inside.get(c).copied().unwrap_or(true) {
            1.8
        } else {
            4.0
        };
        let _ = writeln!(
            s,
            "<circle cx=\"{a:.2}\" cy=\"{b:.2}\" r=\"{r}\" fill=\"{colour}\"/>"
        );
    }
    s.push_str("</g>\n</svg>\n");
    s
}
