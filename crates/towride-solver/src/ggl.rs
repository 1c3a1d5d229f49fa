//! Stabilised index-2 form of constrained mechanical systems (Gear, Gupta & Leimkuhler,
//! "Automatic integration of Euler-Lagrange equations with constraints", J. Comput. Appl.
//! Math. 12-13 (1985) 77-90), the formulation MSC.ADAMS calls SI2.
//!
//! A mechanical system M(q) v' = f(t, q, v) - G(t, q)^T lambda with position constraints
//! g(t, q) = 0 is index 3. GGL adds the velocity constraints and a second multiplier mu:
//!
//! ```text
//! q' - v + G^T mu           = 0
//! M v' - f + G^T lambda     = 0
//! g(t, q)                   = 0
//! G v + dg/dt               = 0
//! ```
//!
//! The exact solution has mu = 0; both constraint levels hold at every step, positions
//! and velocities are index-1-like and enter the error test in full, and only lambda and
//! mu (index 2) are h-scaled or left out. The cost is m more unknowns and equations for m
//! constraints; in exchange the BDF error estimate is valid for q and v and no step-size
//! restriction of index-3 BDF applies.

use super::problem::{DaeProblem, VarKind};

/// A constrained mechanical system in first-order form with n positions (and n
/// velocities v = q' in the unconstrained sense) and m position constraints.
pub trait MechanicalDae {
    /// Number of positions n (equal to the number of velocities).
    fn n_pos(&self) -> usize;
    /// Number of position constraints m.
    fn n_con(&self) -> usize;
    /// Dynamics residual M(q) v' - f(t, q, v) + G(t, q)^T lambda, length n.
    fn dynamics(&self, t: f64, q: &[f64], v: &[f64], vdot: &[f64], lambda: &[f64], out: &mut [f64]);
    /// Position constraints g(t, q), length m.
    fn constraints(&self, t: f64, q: &[f64], out: &mut [f64]);
    /// Constraint Jacobian G = dg/dq as (row < m, col < n, value) entries, appended.
    fn constraint_jacobian(&self, t: f64, q: &[f64], out: &mut Vec<(usize, usize, f64)>);
    /// Partial time derivative dg/dt (rheonomic constraints); zero by default.
    fn constraint_time_derivative(&self, _t: f64, _q: &[f64], out: &mut [f64]) {
        out.fill(0.0);
    }
    /// Name of position `i`, used in error messages.
    fn pos_name(&self, i: usize) -> String {
        format!("q[{i}]")
    }
}

/// The GGL form of a [`MechanicalDae`] as a [`DaeProblem`]; unknowns are laid out as
/// (q, v, lambda, mu), 2n + 2m in all.
pub struct Ggl<M: MechanicalDae> {
    /// The underlying mechanical system.
    pub sys: M,
}

impl<M: MechanicalDae> Ggl<M> {
    /// Wraps `sys` in its GGL form.
    pub fn new(sys: M) -> Self {
        Self { sys }
    }

    /// Builds the GGL state (y, y') from q, v, v' and lambda, with mu = 0.
    pub fn state(
        &self,
        q: &[f64],
        v: &[f64],
        vdot: &[f64],
        lambda: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        let m = self.sys.n_con();
        let mut y = [q, v, lambda].concat();
        y.extend(std::iter::repeat_n(0.0, m));
        let mut yp = [v, vdot].concat();
        yp.extend(std::iter::repeat_n(0.0, 2 * m));
        (y, yp)
    }
}

impl<M: MechanicalDae> DaeProblem for Ggl<M> {
    fn size(&self) -> usize {
        2 * (self.sys.n_pos() + self.sys.n_con())
    }

    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        let (n, m) = (self.sys.n_pos(), self.sys.n_con());
        let (q, rest) = y.split_at(n);
        let (v, rest) = rest.split_at(n);
        let (lambda, mu) = rest.split_at(m);
        let (r_q, rest) = res.split_at_mut(n);
        let (r_v, rest) = rest.split_at_mut(n);
        let (r_g, r_gv) = rest.split_at_mut(m);
        let mut g_entries = Vec::new();
        self.sys.constraint_jacobian(t, q, &mut g_entries);
        for i in 0..n {
            r_q[i] = yp[i] - v[i];
        }
        r_gv.fill(0.0);
        for &(r, c, val) in &g_entries {
            r_q[c] += val * mu[r];
            r_gv[r] += val * v[c];
        }
        let mut gt = vec![0.0; m];
        self.sys.constraint_time_derivative(t, q, &mut gt);
        for (a, b) in r_gv.iter_mut().zip(&gt) {
            *a += b;
        }
        self.sys.dynamics(t, q, v, &yp[n..2 * n], lambda, r_v);
        self.sys.constraints(t, q, r_g);
    }

    fn var_kinds(&self) -> Vec<VarKind> {
        let (n, m) = (self.sys.n_pos(), self.sys.n_con());
        let mut k = vec![VarKind::Differential; 2 * n];
        k.extend(std::iter::repeat_n(VarKind::Index2, 2 * m));
        k
    }

    fn var_name(&self, i: usize) -> String {
        let (n, m) = (self.sys.n_pos(), self.sys.n_con());
        if i < n {
            self.sys.pos_name(i)
        } else if i < 2 * n {
            format!("d/dt {}", self.sys.pos_name(i - n))
        } else if i < 2 * n + m {
            format!("lambda[{}]", i - 2 * n)
        } else {
            format!("mu[{}]", i - 2 * n - m)
        }
    }

    fn eq_name(&self, i: usize) -> String {
        let (n, m) = (self.sys.n_pos(), self.sys.n_con());
        if i < n {
            format!("kinematics of {}", self.sys.pos_name(i))
        } else if i < 2 * n {
            format!("dynamics of {}", self.sys.pos_name(i - n))
        } else if i < 2 * n + m {
            format!("position constraint {}", i - 2 * n)
        } else {
            format!("velocity constraint {}", i - 2 * n - m)
        }
    }
}
