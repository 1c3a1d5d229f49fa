//! The sparse set-up and start paths (issue 23) against the dense ones they replace on
//! large models, and against analytical facts: the sparse redundancy sweep reports what
//! the dense one reports on every mechanism and scene of the repository, a planar loop
//! of 3D revolute joints repeats exactly three rows, and the sparse minimum-norm
//! corrections and Schur-complement solve give the dense answers.

use std::path::Path;

use towride_app::job::Job;
use towride_app::scene::Changes;
use towride_app::study::scaling::models::{chain, ladder, Link};
use towride_mbs::input::Loader;
use towride_mbs::model::redundancy::{jacobian_rows, select_dense, select_sparse};
use towride_mbs::model::system::Redundant;
use towride_mbs::model::{ic, spec, System};
use towride_solver::SolverOptions;

const G: [f64; 3] = [0.0, 0.0, -9.81];

fn link() -> Link {
    Link {
        mass_kg: 1.0,
        length_m: 0.2,
        radius_m: 0.01,
    }
}

/// The two sweeps on `sys` at its initial state: the same kept rows, the same redundant
/// rows with the same kept rows named, coefficients equal to round-off; and the
/// system's own report is that one.
fn sweeps_agree(what: &str, sys: &System) {
    let (q, _) = sys.initial_q_v();
    let rows = jacobian_rows(sys, 0.0, &q);
    let (kd, rd) = select_dense(sys.nv, &rows);
    let (ks, rs) = select_sparse(sys.nv, &rows);
    assert_eq!(kd, ks, "{what}: kept rows");
    assert_eq!(kd.len(), sys.m, "{what}");
    same_report(what, &rd, &rs);
    same_report(what, &rd, &sys.redundant);
}

fn same_report(what: &str, a: &[Redundant], b: &[Redundant]) {
    assert_eq!(a.len(), b.len(), "{what}: redundant rows");
    for (x, y) in a.iter().zip(b) {
        assert_eq!((x.elem, x.row), (y.elem, y.row), "{what}");
        let names = |r: &Redundant| r.depends_on.iter().map(|d| (d.0, d.1)).collect::<Vec<_>>();
        assert_eq!(names(x), names(y), "{what}: row {}/{}", x.elem, x.row);
        for (c, d) in x.depends_on.iter().zip(&y.depends_on) {
            assert!(
                (c.2 - d.2).abs() <= 1e-9 * c.2.abs().max(1.0),
                "{what}: {c:?} vs {d:?}"
            );
        }
    }
}

#[test]
fn sparse_sweep_reports_what_the_dense_one_does_on_every_model() {
    for m in ["andrews", "elements", "pendulum", "two_mass_chain"] {
        let path = format!("{}/scenes/examples/{m}.toml", repo!(""));
        let mech = spec::load(Path::new(&path), &Loader::new()).unwrap_or_else(|e| panic!("{e}"));
        sweeps_agree(m, &System::new(mech.model));
    }
    for s in ["default", "bump_25mm", "car_ramp", "flexible_twist_beam"] {
        let path = format!("{}/scenes/{s}.toml", repo!(""));
        let job = Job::from_scene_file(Path::new(&path), &Changes::default(), &Loader::new())
            .unwrap_or_else(|e| panic!("{e}"));
        sweeps_agree(s, &job.system);
    }
    for n in [1, 5] {
        let sys = System::new(ladder(&link(), n, 30f64.to_radians(), G).unwrap());
        sweeps_agree(&format!("ladder of {n}"), &sys);
    }
}

/// A parallelogram of four revolutes (20 rows on 3 moving bodies, 18 velocities, one
/// degree of freedom) repeats 20 - 17 = 3 rows; 40 loops (800 rows, the sparse sweep)
/// repeat 120, each reproduced by the kept rows it names.
#[test]
fn ladder_of_loops_repeats_three_rows_a_loop() {
    let n = 40;
    let sys = System::new(ladder(&link(), n, 30f64.to_radians(), G).unwrap());
    assert_eq!(sys.redundant.len(), 3 * n);
    assert_eq!(sys.m, 17 * n);
    let (q, _) = sys.initial_q_v();
    let rows = jacobian_rows(&sys, 0.0, &q);
    let dense_row = |id: (usize, usize)| {
        let mut b = vec![0.0; sys.nv];
        for &(c, v) in &rows.iter().find(|r| r.0 == id).unwrap().1 {
            b[c] += v;
        }
        b
    };
    for r in &sys.redundant {
        let mut b = dense_row((r.elem, r.row));
        let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for &(e, k, c) in &r.depends_on {
            for (x, y) in b.iter_mut().zip(dense_row((e, k))) {
                *x -= c * y;
            }
        }
        let left = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(left < 1e-9 * scale, "{}/{}: {left}", r.elem, r.row);
    }
    sweeps_agree("ladder of 40", &sys);
}

/// On a chain of 60 links (300 rows) the sparse normal equations give the dense
/// minimum-norm assembly and velocity projection, and the sparse Schur complement the
/// dense accelerations and multipliers.
#[test]
fn sparse_start_matches_the_dense_one_on_a_chain() {
    let sys = System::new(chain(&link(), 60, G).unwrap());
    assert!(sys.m > towride_mbs::model::normal::DENSE_ROWS);
    let (mut q0, mut v0) = sys.initial_q_v();
    // Off the constraints and with velocities that break them, so both projections work.
    for (k, x) in q0.iter_mut().enumerate() {
        *x += 1e-3 * ((k as f64) * 0.7).sin();
    }
    for (k, x) in v0.iter_mut().enumerate() {
        *x += 0.1 * ((k as f64) * 1.3).cos();
    }
    let (mut qd, mut vd) = (q0.clone(), v0.clone());
    let (mut qs, mut vs) = (q0, v0);
    let rd = ic::assemble_with(&sys, 0.0, &mut qd, &mut vd, true).unwrap();
    let rs = ic::assemble_with(&sys, 0.0, &mut qs, &mut vs, false).unwrap();
    assert_eq!(rd.iterations, rs.iterations);
    assert!(rs.violation_after < 1e-10, "{rs:?}");
    let close = |a: &[f64], b: &[f64], tol: f64, what: &str| {
        let big = a.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            assert!((x - y).abs() <= tol * big, "{what}[{k}]: {x} vs {y}");
        }
    };
    close(&qd, &qs, 1e-12, "q");
    close(&vd, &vs, 1e-10, "v");
    let x = vec![0.0; sys.ne];
    let (ad, ld) = ic::accelerations_with(&sys, 0.0, &qd, &vd, &x, true).unwrap();
    let (as_, ls) = ic::accelerations_with(&sys, 0.0, &qd, &vd, &x, false).unwrap();
    close(&ad, &as_, 1e-9, "v'");
    close(&ld, &ls, 1e-9, "lambda");
}

/// The integration's sparse LU of a ladder of closed loops grows linearly with the loops.
/// Against the structure's own yardstick: the factors of 40 loops hold at most 4.5 times
/// those of 10 (linear growth is 4; the symmetric minimum-degree order alone, whose
/// prediction the multipliers' off-diagonal pivots void, gave about 12: quadratic).
#[test]
fn ladder_lu_fill_grows_linearly() {
    let opts = SolverOptions {
        rtol: 1e-4,
        atol: vec![1e-4],
        ..Default::default()
    };
    let fill = |loops: usize| {
        let sys = System::new(ladder(&link(), loops, 30f64.to_radians(), G).unwrap());
        let r = towride_mbs::model::run::simulate(
            &sys,
            0.0,
            0.01,
            1000.0,
            &opts,
            None,
            &towride_mbs::progress::Silent,
        );
        assert!(r.error.is_none(), "{:?}", r.error);
        r.stats.lu_entries
    };
    let (small, big) = (fill(10), fill(40));
    assert!(small > 0, "the ladder of 10 loops is factorised sparse");
    assert!(
        (big as f64) < 4.5 * small as f64,
        "LU entries {small} at 10 loops, {big} at 40"
    );
}
