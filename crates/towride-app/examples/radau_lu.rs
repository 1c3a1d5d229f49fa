//! Measures the two ways of solving Radau IIA's complex system on a scene's Newton matrix
//! (docs/solver.md, "Radau IIA: the complex system"): the complex sparse LU on the
//! structure of J, against the real 2n x 2n form [[A, -B], [B, A]] (A = J_y + alpha/h
//! J_y', B = beta/h J_y') in the real sparse LU, beside the real matrix J_y + gamma/h J_y'.
//!
//! ```sh
//! cargo run --release -p towride --example radau_lu -- scenes/default.toml 0.6 2e-3
//! ```
//! (scene, time of the state the matrix is taken at [s], step h [s]).

use std::path::Path;
use std::time::Instant;

use nalgebra::Complex;
use towride_app::prelude::*;
use towride_solver::linear::{ComplexMatrix, NewtonMatrix};
use towride_solver::radau::tableau::{ALPHA, BETA, GAMMA};
use towride_solver::{DaeProblem, JacobianSink};

/// Repetitions of each timed operation (the fastest time is kept).
const REPEAT: usize = 200;

fn fastest(mut f: impl FnMut()) -> f64 {
    (0..REPEAT)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = Path::new(args.get(1).map_or("scenes/default.toml", |s| s.as_str()));
    let t_state: f64 = args
        .get(2)
        .map_or(Ok(0.6), |s| s.parse())
        .map_err(|e| format!("{e}"))?;
    let h: f64 = args
        .get(3)
        .map_or(Ok(2e-3), |s| s.parse())
        .map_err(|e| format!("{e}"))?;
    let changes = Changes {
        duration_s: Some(t_state),
        ..Default::default()
    };
    let job = Job::from_scene_file(scene, &changes, &Loader::new())?;
    let r = job.run(&Silent)?;
    let (t, y, yp) = r.samples.last.clone().ok_or("the run failed")?;
    let sys = &job.system;
    let n = sys.size();
    let pattern = sys.jacobian_pattern().ok_or("no pattern")?;
    let cj = GAMMA / h;
    let (mut entries, mut yp_entries) = (Vec::new(), Vec::new());
    sys.jacobian(
        t,
        &y,
        &yp,
        cj,
        &mut JacobianSink::with_yp(&mut entries, &mut yp_entries),
    );
    // The real matrix and the kept parts.
    let mut real = NewtonMatrix::new(n, Some(pattern.clone()), false)?;
    for &(i, j, v) in &entries {
        real.add(i, j, v)
            .map_err(|e| format!("{e:?} outside the pattern"))?;
    }
    real.keep_as_base(cj);
    real.set_yp_part(&yp_entries);
    let ones = vec![1.0; n];
    let pivoting_real = fastest(|| {
        let mut m = NewtonMatrix::new(n, Some(pattern.clone()), false).expect("pattern");
        for &(i, j, v) in &entries {
            m.add(i, j, v).expect("in pattern");
        }
        m.factor(&ones, true).expect("regular");
    });
    real.factor(&ones, true).map_err(|e| e.detail)?;
    let refactor_real = fastest(|| real.factor(&ones, true).expect("regular"));
    let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
    let solve_real = fastest(|| {
        let mut x = b.clone();
        real.solve(&mut x).expect("solved");
    });
    // Complex LU on the same structure.
    let shift = Complex::new(ALPHA / h, BETA / h);
    let mut cm = ComplexMatrix::like(&real)?;
    cm.factor(&real, shift, &ones, true).map_err(|e| e.detail)?;
    let refactor_c = fastest(|| cm.factor(&real, shift, &ones, true).expect("regular"));
    let solve_c = fastest(|| {
        let (mut re, mut im) = (b.clone(), b.clone());
        cm.solve(&mut re, &mut im).expect("solved");
    });
    let nnz_c = cm.lu_nnz().unwrap_or(0);
    // The real 2n x 2n form: A on the diagonal blocks, -B and B off the diagonal, B on
    // the pattern of dF/dy' only.
    let (a_shift, b_shift) = (ALPHA / h, BETA / h);
    let mut yp_sum = std::collections::BTreeMap::new();
    for &(i, j, v) in &yp_entries {
        *yp_sum.entry((i, j)).or_insert(0.0) += v;
    }
    let mut block_pattern = Vec::new();
    for &(i, j) in &pattern {
        block_pattern.push((i, j));
        block_pattern.push((i + n, j + n));
    }
    for &(i, j) in yp_sum.keys() {
        block_pattern.push((i, j + n));
        block_pattern.push((i + n, j));
    }
    let mut block = NewtonMatrix::new(2 * n, Some(block_pattern.clone()), false)?;
    let fill_block = |m: &mut NewtonMatrix| {
        m.clear();
        // A = J at gamma/h + (alpha - gamma)/h dF/dy'.
        for &(i, j, v) in &entries {
            m.add(i, j, v).expect("in pattern");
            m.add(i + n, j + n, v).expect("in pattern");
        }
        for (&(i, j), &v) in &yp_sum {
            let d = (a_shift - cj) * v;
            m.add(i, j, d).expect("in pattern");
            m.add(i + n, j + n, d).expect("in pattern");
            m.add(i, j + n, -b_shift * v).expect("in pattern");
            m.add(i + n, j, b_shift * v).expect("in pattern");
        }
    };
    fill_block(&mut block);
    let ones2 = vec![1.0; 2 * n];
    block.factor(&ones2, true).map_err(|e| e.detail)?;
    let refactor_block = fastest(|| block.factor(&ones2, true).expect("regular"));
    let b2: Vec<f64> = b.iter().chain(b.iter()).copied().collect();
    let solve_block = fastest(|| {
        let mut x = b2.clone();
        block.solve(&mut x).expect("solved");
    });
    // Both must give the same solution.
    let (mut re, mut im) = (b.clone(), b.clone());
    cm.solve(&mut re, &mut im).map_err(|e| e.detail)?;
    let mut x = b2.clone();
    block.solve(&mut x).map_err(|e| e.detail)?;
    let diff = (0..n)
        .map(|i| (re[i] - x[i]).abs().max((im[i] - x[i + n]).abs()))
        .fold(0.0, f64::max);
    let big = re.iter().chain(&im).map(|v| v.abs()).fold(0.0, f64::max);
    println!(
        "{} unknowns, {} structural non-zeros (dF/dy' {}), state at t = {t:.3} s, h = {h:e} s",
        n,
        real.nnz(),
        yp_sum.len()
    );
    println!(
        "real n x n:     L+U {:>6}  set-up and first factorisation {:>7.1} us  refactorisation {:>7.1} us  solve {:>6.1} us",
        real.lu_nnz().unwrap_or(0),
        1e6 * pivoting_real,
        1e6 * refactor_real,
        1e6 * solve_real
    );
    println!(
        "complex n x n:  L+U {:>6}  refactorisation {:>7.1} us  solve {:>6.1} us",
        nnz_c,
        1e6 * refactor_c,
        1e6 * solve_c
    );
    println!(
        "real 2n x 2n:   L+U {:>6}  refactorisation {:>7.1} us  solve {:>6.1} us",
        block.lu_nnz().unwrap_or(0),
        1e6 * refactor_block,
        1e6 * solve_block
    );
    println!(
        "complex and 2n x 2n solutions agree to {:.1e} of the largest entry",
        diff / big
    );
    Ok(())
}
