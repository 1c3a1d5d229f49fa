//! RADAU5's own figures on the test-set problems: Hairer & Wanner's Fortran code run on
//! the test set's problem routines at rtol = atol = h0 = tol (Robertson: atol = 1e-4 tol).
//! The numbers and how they were measured are in `docs/data/radau5_testset.csv`, which is
//! read here as it is.

use super::{scd, Benchmark};

const DATA: &str = include_str!("../../../../docs/data/radau5_testset.csv");

/// One RADAU5 run.
#[derive(Clone, Debug, PartialEq)]
pub struct Radau5Run {
    /// The benchmark's name ("caraxis", ...).
    pub problem: String,
    /// Relative and absolute tolerance of the run (the first step was rtol).
    pub rtol: f64,
    /// Absolute tolerance of the run.
    pub atol: f64,
    /// Step attempts (NSTEP).
    pub steps: usize,
    /// Accepted steps (NACCPT).
    pub accepted: usize,
    /// Error-test rejections after the first accepted step (NREJCT).
    pub rejected: usize,
    /// Evaluations of f (NFCN).
    pub f_evals: usize,
    /// Jacobian evaluations (NJAC).
    pub jac_evals: usize,
    /// LU decompositions, each one real and one complex (NDEC).
    pub lu_decompositions: usize,
    /// CPU time of one run [s].
    pub cpu_s: f64,
    /// Solution at the end of the interval, all components in test-set order.
    pub y_end: Vec<f64>,
}

impl Radau5Run {
    /// Significant correct digits over the benchmark's scd components, as for our runs.
    pub fn scd(&self, b: &Benchmark) -> f64 {
        scd(&self.y_end, &b.reference, &b.scd_components)
    }
}

/// All runs of the data file.
///
/// # Panics
/// If the data file is malformed (it is part of the source tree; a test reads it).
pub fn all() -> Vec<Radau5Run> {
    DATA.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1) // column names
        .map(|l| {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            assert_eq!(f.len(), 14, "radau5_testset.csv: {l}");
            let num = |i: usize| f[i].parse::<f64>().expect("a number");
            let int = |i: usize| f[i].parse::<usize>().expect("a count");
            Radau5Run {
                problem: f[0].to_string(),
                rtol: num(1),
                atol: num(2),
                steps: int(4),
                accepted: int(5),
                rejected: int(6),
                f_evals: int(7),
                jac_evals: int(8),
                lu_decompositions: int(9),
                cpu_s: num(12),
                y_end: f[13]
                    .split_whitespace()
                    .map(|v| v.parse().expect("a number"))
                    .collect(),
            }
        })
        .collect()
}

/// The run of `problem` at relative tolerance `rtol`, if measured.
pub fn find(problem: &str, rtol: f64) -> Option<Radau5Run> {
    all()
        .into_iter()
        .find(|r| r.problem == problem && (r.rtol / rtol - 1.0).abs() < 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_run_parses_and_fits_its_benchmark() {
        let runs = all();
        assert_eq!(runs.len(), 35, "five problems at seven tolerances");
        for r in &runs {
            let b = super::super::by_name(&r.problem).expect("a benchmark");
            assert_eq!(r.y_end.len(), b.reference.len(), "{}", r.problem);
            assert!(r.accepted <= r.steps && r.accepted > 0);
            // RADAU5 reached the reference to at least a digit at every tolerance.
            assert!(r.scd(&b) > 0.1, "{} {:e}: {}", r.problem, r.rtol, r.scd(&b));
        }
        assert_eq!(find("hires", 1e-6).map(|r| r.accepted), Some(51));
    }
}
