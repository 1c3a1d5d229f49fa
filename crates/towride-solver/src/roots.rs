//! Event location shared by the integrators: sign changes of the problem's event
//! functions g(t, y, y') between steps, refined on the integrator's interpolant with the
//! Illinois variant of regula falsi (as IDA's IDARcheck3 and IDARootfind).

use crate::problem::DaeProblem;
use crate::Advance;

const UROUND: f64 = f64::EPSILON;
/// Root bracket width at which the search stops, in units of the rounding unit times
/// |t| + |h| (IDA's ttol = 100 uround (|tn| + |h|)).
const TTOL_UROUNDS: f64 = 100.0;
/// Illinois iterations at most (never reached in practice: the bracket halves at least
/// every second iteration).
const MAX_ITERATIONS: usize = 200;

/// The interpolant of the last step: value and derivative at a time.
pub(crate) type Interpolant<'a> = &'a dyn Fn(f64, &mut [f64], &mut [f64]);

/// The event functions' values at the last point searched past, and the search.
#[derive(Default)]
pub(crate) struct Roots {
    g_lo: Vec<f64>,
    t_lo: f64,
    g_hi: Vec<f64>,
}

impl Roots {
    /// Evaluates the event functions at (t0, y0, y'0); `root_evals` counts evaluations.
    pub fn new<P: DaeProblem + ?Sized>(
        prob: &P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        root_evals: &mut usize,
    ) -> Self {
        let nr = prob.n_roots();
        let mut s = Roots {
            g_lo: vec![0.0; nr],
            t_lo: t0,
            g_hi: vec![0.0; nr],
        };
        s.restart(prob, t0, y0, yp0, root_evals);
        s
    }

    /// Starts the search anew at (t, y, y') (after a reinitialisation).
    pub fn restart<P: DaeProblem + ?Sized>(
        &mut self,
        prob: &P,
        t: f64,
        y: &[f64],
        yp: &[f64],
        root_evals: &mut usize,
    ) {
        self.t_lo = t;
        if !self.g_lo.is_empty() {
            prob.roots(t, y, yp, &mut self.g_lo);
            *root_evals += 1;
        }
    }

    /// Whether the problem has event functions.
    pub fn is_empty(&self) -> bool {
        self.g_lo.is_empty()
    }

    /// Looks for a sign change over (t_lo, tn] and locates it on `interp` (the interpolant
    /// of the last step, value and derivative at a time); `h` is the last step.
    pub fn check<P: DaeProblem + ?Sized>(
        &mut self,
        prob: &P,
        tn: f64,
        h: f64,
        interp: Interpolant,
        root_evals: &mut usize,
    ) -> Option<Advance> {
        let nr = self.g_lo.len();
        if nr == 0 || tn <= self.t_lo {
            return None;
        }
        let n = prob.size();
        let (mut y, mut yp) = (vec![0.0; n], vec![0.0; n]);
        let mut g_hi = std::mem::take(&mut self.g_hi);
        interp(tn, &mut y, &mut yp);
        prob.roots(tn, &y, &yp, &mut g_hi);
        *root_evals += 1;
        let changed = |glo: &[f64], ghi: &[f64]| -> Option<usize> {
            let mut best: Option<(usize, f64)> = None;
            for i in 0..glo.len() {
                if glo[i] != 0.0 && (ghi[i] == 0.0 || glo[i].signum() != ghi[i].signum()) {
                    let frac = (glo[i] / (glo[i] - ghi[i])).abs();
                    if best.is_none_or(|(_, f)| frac < f) {
                        best = Some((i, frac));
                    }
                }
            }
            best.map(|b| b.0)
        };
        let Some(mut idx) = changed(&self.g_lo, &g_hi) else {
            self.t_lo = tn;
            self.g_lo.copy_from_slice(&g_hi);
            self.g_hi = g_hi;
            return None;
        };
        let ttol = TTOL_UROUNDS * UROUND * (tn.abs() + h.abs());
        let (mut tlo, mut thi) = (self.t_lo, tn);
        let mut glo = self.g_lo.clone();
        let mut ghi = g_hi.clone();
        let mut gmid = vec![0.0; nr];
        let mut side = 0i32;
        for _ in 0..MAX_ITERATIONS {
            if thi - tlo <= ttol {
                break;
            }
            let (a, b) = (glo[idx], ghi[idx]);
            // Illinois: halve the weight of an end point kept twice in a row.
            let (mut wa, mut wb) = (1.0, 1.0);
            if side == 1 {
                wb = 0.5;
            } else if side == -1 {
                wa = 0.5;
            }
            let mut tmid = thi - (thi - tlo) * (wb * b) / (wb * b - wa * a);
            let margin = 0.5 * ttol;
            tmid = tmid.clamp(tlo + margin, thi - margin);
            interp(tmid, &mut y, &mut yp);
            prob.roots(tmid, &y, &yp, &mut gmid);
            *root_evals += 1;
            if let Some(i) = changed(&glo, &gmid) {
                thi = tmid;
                ghi.copy_from_slice(&gmid);
                idx = i;
                side = if side == 1 { 2 } else { 1 };
            } else {
                tlo = tmid;
                glo.copy_from_slice(&gmid);
                side = if side == -1 { -2 } else { -1 };
            }
        }
        // Continue the next search just past the root.
        self.t_lo = thi;
        self.g_lo.copy_from_slice(&ghi);
        for g in self.g_lo.iter_mut() {
            if *g == 0.0 {
                *g = f64::MIN_POSITIVE; // a root exactly at t_lo is not reported twice
            }
        }
        self.g_hi = g_hi;
        Some(Advance::Root { t: thi, index: idx })
    }
}
