use super::*;
use crate::lp::cancellable;
use crate::lp::{plane_rows, sys3_rows};

/// The margin system of one segment among four points.
fn small_system() -> System {
    let p = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.9], [0.4, -0.8], [2.0, 0.1]];
    let mut sys = System {
        n: 5,
        free: vec![true; 5],
        verdict: true,
        unit2: 1.0,
        l2: vec![1.0; 5],
        ..Default::default()
    };
    plane_rows(&mut sys, &p, 0, 0, &[1], &[2, 3, 4], 1.0);
    sys.rows.extend(sys3_rows(&p, 0, 0, 1, &[2, 3, 4]));
    sys
}

/// A raised flag stops a run before it starts (the error is the one
/// callers discard); a lowered one changes nothing.
#[test]
fn a_raised_flag_cancels_runs() {
    let sys = small_system();
    let run = |sys: &System| {
        let mut report = WeightsReport::started("test");
        Lp::build(sys, true, None, &Mode::Margin)?.solve(sys, &mut report, f64::NEG_INFINITY)
    };
    let free = run(&sys).unwrap().delta;
    let lowered = Arc::new(AtomicBool::new(false));
    assert_eq!(cancellable(&lowered, || run(&sys)).unwrap().delta, free);
    let raised = Arc::new(AtomicBool::new(true));
    let err = cancellable(&raised, || run(&sys)).err().expect("cancelled");
    assert!(matches!(err, Error::Internal(m) if m.contains("cancelled")));
}

/// A run that stops at its iteration limit (a stall) is run again from
/// scratch with presolve, to the same optimum.
#[test]
fn a_stalled_run_is_finished_with_presolve() {
    let sys = small_system();
    let mut report = WeightsReport::started("test");
    let mut lp = Lp::build(&sys, true, None, &Mode::Margin).unwrap();
    let free = lp
        .solve(&sys, &mut report, f64::NEG_INFINITY)
        .unwrap()
        .delta;
    let mut lp = Lp::build(&sys, true, None, &Mode::Margin).unwrap();
    let model = lp.model.as_mut().unwrap();
    let (status, cols) = run_model(model, 0).unwrap();
    assert_eq!(status, HighsModelStatus::Optimal);
    let delta = cols.expect("optimal")[lp.delta.index()];
    assert!(
        (delta - free).abs() <= 1e-9 * free.abs().max(1.0),
        "{delta} {free}"
    );
}

/// Lazy rows that enter a face's or segment's most violated first
/// (`ENTER_ALL`) reach the optimum that entering all of them reaches.
#[test]
fn rows_entering_by_groups_reach_the_same_optimum() {
    let sys = crate::lp::jittered_lattice();
    let solve = |enter_all: usize| {
        let mut report = WeightsReport::started("test");
        let mut lp = Lp::build(&sys, true, None, &Mode::Margin).unwrap();
        assert!(lp.lazy.len() > 100, "{}", lp.lazy.len());
        lp.enter_all = enter_all;
        let delta = lp
            .solve(&sys, &mut report, f64::NEG_INFINITY)
            .unwrap()
            .delta;
        (delta, report.lp_solves)
    };
    let (all, runs_all) = solve(usize::MAX);
    let (grouped, runs) = solve(0);
    assert!(
        all > 0.1 && (all - grouped).abs() <= 1e-9,
        "{all} {grouped}"
    );
    // (the groups took more rounds: the path was taken)
    assert!(runs > runs_all, "{runs} {runs_all}");
}
