//! The local form's system split into independent pieces, solved in
//! parallel.

use super::warm::{keys, serves, Warm};
use super::{solve_rows, Answer, Origin, Row, System, WeightsReport};
use crate::error::Result;
use crate::progress::Progress;

/// A part of a local system whose rows share no free weight with the
/// rest: its LP is independent. Columns are the part's free weights only
/// (the others are zero, so their terms vanish exactly).
pub(crate) struct Piece {
    pub(crate) sys: System,
    /// Column k of `sys` is weight `cols[k]`.
    pub(crate) cols: Vec<usize>,
}

/// Splits a local system (no auxiliary columns) into independent pieces:
/// weights joined by a row inside the domain (union-find) form a piece,
/// numbered by its smallest weight, so the split does not depend on row
/// order. A row outside the domain that joins m pieces (the gap between
/// two cavities) is split: each piece gets its own terms, and rhs / m and
/// delta / m when zero weights meet the row with slack (the parts' sum is
/// the row with the mean of the pieces' margins); otherwise the piece of
/// its first weight gets all of rhs and delta, the others 0. Weak rows
/// between pieces are left out. The weights of all pieces are then checked
/// exactly together (RT(w)), as every LP answer is.
pub(crate) fn pieces(mut sys: System) -> Vec<Piece> {
    debug_assert_eq!(sys.aux, 0);
    let mut parent: Vec<usize> = (0..sys.n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    // Rows move into their pieces one by one: one copy in memory at a time.
    let (rows, eqs) = (std::mem::take(&mut sys.rows), std::mem::take(&mut sys.eqs));
    // A row's free weights, into a buffer reused row after row.
    let free_terms = |r: &Row, f: &mut Vec<usize>| {
        f.clear();
        f.extend(r.terms.iter().map(|t| t.0).filter(|&c| sys.free[c]));
    };
    let (mut f, mut joined) = (vec![], vec![]);
    for r in rows.iter().chain(&eqs) {
        if r.outside {
            continue;
        }
        free_terms(r, &mut f);
        for w in f.windows(2) {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[1]));
            // The smaller index is the root: pieces come out in weight order.
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut piece_of = vec![usize::MAX; sys.n];
    let mut local = vec![usize::MAX; sys.n];
    let mut out: Vec<Piece> = vec![];
    for v in (0..sys.n).filter(|&v| sys.free[v]) {
        let r = root(&mut parent, v);
        if piece_of[r] == usize::MAX {
            piece_of[r] = out.len();
            out.push(Piece {
                sys: System {
                    verdict: sys.verdict,
                    unit2: sys.unit2,
                    ..Default::default()
                },
                cols: vec![],
            });
        }
        piece_of[v] = piece_of[r];
        local[v] = out[piece_of[r]].cols.len();
        out[piece_of[r]].cols.push(v);
        out[piece_of[r]].sys.l2.push(sys.l2[v]);
    }
    // Room for each piece's rows (by its first weight's), so that they
    // are not copied as they grow (measured: a third of the split's time).
    let mut count = vec![0usize; out.len()];
    for r in &rows {
        if let Some(&(c, _)) = r.terms.iter().find(|t| sys.free[t.0]) {
            count[piece_of[c]] += 1;
        }
    }
    for (p, &k) in out.iter_mut().zip(&count) {
        p.sys.rows.reserve_exact(k);
    }
    for (row, eq) in rows
        .into_iter()
        .map(|r| (r, false))
        .chain(eqs.into_iter().map(|r| (r, true)))
    {
        let r = &row;
        free_terms(r, &mut f);
        let owner = f.first().map(|&c| piece_of[c]);
        joined.clear();
        joined.extend(f.iter().map(|&c| piece_of[c]));
        joined.sort_unstable();
        joined.dedup();
        let m = joined.len() as f64;
        if let [k] = joined[..] {
            // Whole in one piece (most rows): moved, its terms renumbered.
            let mut r = row;
            r.terms.retain(|t| sys.free[t.0]);
            r.terms.iter_mut().for_each(|t| t.0 = local[t.0]);
            let piece = &mut out[k].sys;
            if eq {
                piece.eqs.push(r);
            } else {
                piece.rows.push(r);
            }
            continue;
        }
        for &k in &joined {
            if m > 1.0 && r.weak {
                // Left to the exact check of RT(w).
                continue;
            }
            // Slack at zero weights is shared out; a row that zero weights
            // do not meet is the burden of the piece of its first weight
            // (the segment's or the edge's end), the others must not
            // worsen it.
            let (rhs, share) = if m == 1.0 {
                (r.rhs, r.share)
            } else if r.rhs < 0.0 {
                (r.rhs / m, r.share / m)
            } else if Some(k) == owner {
                (r.rhs, r.share)
            } else {
                (0.0, 0.0)
            };
            let row = Row {
                terms: r
                    .terms
                    .iter()
                    .filter(|t| sys.free[t.0] && piece_of[t.0] == k)
                    .map(|&(c, v)| (local[c], v))
                    .collect(),
                rhs,
                family: r.family,
                share,
                outside: r.outside,
                weak: r.weak,
                origin: Origin::Other,
            };
            let piece = &mut out[k].sys;
            if eq {
                piece.eqs.push(row);
            } else {
                piece.rows.push(row);
            }
        }
    }
    for p in &mut out {
        p.sys.n = p.cols.len();
        p.sys.free = vec![true; p.sys.n];
    }
    out
}

/// The local form's LP, piece by piece (in parallel): weights when every
/// piece has systems 1 and 3 with a trusted margin, else None.
pub(crate) fn solve_pieces(
    sys: System,
    report: &mut WeightsReport,
    progress: Option<Progress>,
) -> Result<Option<Vec<f64>>> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    let n = sys.n;
    let mut parts = pieces(sys);
    let count = parts.len();
    let done = AtomicUsize::new(0);
    let outer = super::flags();
    // A piece is solved, or takes the weights of its pattern's first piece
    // where they serve it (`serves`).
    let solve = |p: &Piece, first: Option<&(Result<Answer>, WeightsReport)>| {
        let (answer, r) = match first {
            Some((Ok(Answer::Weights(w, true, _)), by)) if serves(&p.sys, w, by) => (
                Ok(Answer::Weights(w.clone(), true, vec![])),
                WeightsReport::served_by(by),
            ),
            _ => {
                let mut r = WeightsReport {
                    deadline: report.deadline,
                    ..Default::default()
                };
                (
                    super::carried(&outer, || solve_rows(&p.sys, false, &mut r)),
                    r,
                )
            }
        };
        let k = done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(f) = progress.filter(|_| k % 64 == 0 || k == count) {
            f("weights: LP pieces", k, count);
        }
        (answer, r)
    };
    // The first piece of each pattern, then the others from it.
    let keys: Vec<(u64, Vec<u64>)> = parts.par_iter().map(|p| keys(&p.sys)).collect();
    let mut first = crate::FastMap::default();
    let leader: Vec<usize> = (keys.iter().enumerate())
        .map(|(i, k)| *first.entry(k.0).or_insert(i))
        .collect();
    let mut alike = vec![0usize; parts.len()];
    leader.iter().for_each(|&l| alike[l] += 1);
    let mut keys: Vec<Vec<u64>> = keys.into_iter().map(|k| k.1).collect();
    let mut answers: Vec<Option<(Result<Answer>, WeightsReport)>> =
        (0..parts.len()).map(|_| None).collect();
    for leads in [true, false] {
        let now: Vec<usize> = (0..parts.len())
            .filter(|&i| (leader[i] == i) == leads)
            .collect();
        // A first piece's steps, taken once for all that follow it.
        let mut steps = crate::FastMap::default();
        for &i in &now {
            let keys = std::mem::take(&mut keys[i]);
            let warm = match leads {
                true => Warm::leader(keys, alike[i] > 1),
                false => {
                    let l = leader[i];
                    let warm = |l: usize| parts[l].sys.warm.as_ref().and_then(|w| w.steps());
                    Warm::follower(keys, steps.entry(l).or_insert_with(|| warm(l)).clone())
                }
            };
            parts[i].sys.warm = Some(Arc::new(warm));
        }
        let solved: Vec<_> = (now.par_iter())
            .map(|&i| solve(&parts[i], answers[leader[i]].as_ref().filter(|_| !leads)))
            .collect();
        for (&i, a) in now.iter().zip(solved) {
            answers[i] = Some(a);
        }
    }
    let answers = answers.into_iter().map(|a| a.expect("every piece solved"));
    report.lp_pieces = parts.len();
    let mut w = vec![0.0; n];
    let mut all = true;
    for ((answer, r), part) in answers.zip(&parts) {
        report.absorb(&r);
        match answer? {
            Answer::Weights(pw, ..) => {
                for (k, &v) in part.cols.iter().enumerate() {
                    w[v] = pw[k];
                }
            }
            _ => all = false,
        }
    }
    Ok(all.then_some(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lp::Family;

    #[test]
    fn pieces_split_rows_between_them() {
        let row = |terms: Vec<(usize, f64)>, rhs: f64, outside: bool, weak: bool| Row {
            terms,
            rhs,
            family: Family::Sys1,
            share: 1.0,
            outside,
            weak,
            origin: crate::lp::Origin::Other,
        };
        let sys = System {
            n: 5,
            free: vec![true, true, true, true, false],
            unit2: 1.0,
            l2: vec![1.0, 2.0, 3.0, 4.0, 5.0],
            rows: vec![
                row(vec![(0, 1.0), (1, 1.0), (4, 7.0)], -1.0, false, false),
                row(vec![(2, 1.0), (3, 1.0)], -1.0, false, false),
                // outside with slack: halved between the two pieces
                row(vec![(1, 2.0), (2, 3.0)], -2.0, true, false),
                // outside, violated at zero: the first weight's piece's
                row(vec![(3, 1.0), (0, 1.0)], 0.5, true, false),
                // outside and weak between pieces: left out
                row(vec![(0, 1.0), (3, -1.0)], 0.0, true, true),
            ],
            ..Default::default()
        };
        let p = pieces(sys);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].cols, vec![0, 1]);
        assert_eq!(p[1].cols, vec![2, 3]);
        assert_eq!(p[0].sys.l2, vec![1.0, 2.0]);
        // (terms, rhs, share) of each row of a piece
        type Summary = Vec<(Vec<(usize, f64)>, f64, f64)>;
        let summary = |s: &System| -> Summary {
            s.rows
                .iter()
                .map(|r| (r.terms.clone(), r.rhs, r.share))
                .collect()
        };
        let expected: [Summary; 2] = [
            // The fixed weight 4 drops out of the first row.
            vec![
                (vec![(0, 1.0), (1, 1.0)], -1.0, 1.0),
                (vec![(1, 2.0)], -1.0, 0.5),
                (vec![(0, 1.0)], 0.0, 0.0),
            ],
            vec![
                (vec![(0, 1.0), (1, 1.0)], -1.0, 1.0),
                (vec![(0, 3.0)], -1.0, 0.5),
                (vec![(1, 1.0)], 0.5, 1.0),
            ],
        ];
        for (piece, want) in p.iter().zip(expected) {
            assert_eq!(summary(&piece.sys), want);
        }
    }
}
