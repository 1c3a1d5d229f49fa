//! BDF stability limit detection (STALD), after CVODE.
//!
//! Sources: Hindmarsh, "Detecting stability barriers in BDF solvers", in Cash & Gladwell
//! (eds.), Computational Ordinary Differential Equations, Oxford 1992, and "Avoiding BDF
//! stability barriers in the MOL solution of advection-dominated problems", Appl. Numer.
//! Math. 17 (1995); the CVODE user guide, "BDF stability limit detection" (SUNDIALS,
//! `doc/cvode/guide/source/Mathematics.rst`); the code is a port of CVODE's `cvBDFStab`
//! and `cvSLdet` (SUNDIALS `src/cvode/cvode.c`, same constants and return flags).
//!
//! BDF orders 3..5 are not A-stable: a lightly damped mode whose h*lambda lies near the
//! imaginary axis (the vehicle's hitch and trailer modes at 180-210 Hz, zeta ~ 0.07, with
//! h*omega ~ 0.8) can sit inside the instability region, where its amplitude grows until
//! the error test cuts the step, and the run carries that oscillation at the tolerance
//! level long after the input that excited it. STALD watches the norms of the scaled
//! derivatives of orders q-1, q, q+1 over the last 5 steps at constant step and order;
//! when they decay (or grow) like the powers of one characteristic root of modulus above
//! 0.99 that is consistent with the BDF formula of order q, the step is taken to be
//! stability-limited and the order is lowered.
//!
//! # The data in IDA's form
//!
//! CVODE keeps the Nordsieck array zn[j] = h^j y^(j) / j! and takes (`cvBDFStab`)
//!
//!   sigma_{q-1} = (q-1)! ||zn[q-1]||, sigma_q = q! ||zn[q]||,
//!   sigma_{q+1} = (q+1)! ||acor|| / tq[5] = ||acor||
//!
//! (for constant steps tq[5] = (q+1) q!, and acor = y_n - y_n(0) is the corrector's total
//! correction). We keep IDA's modified divided differences phi[j] instead. STALD only
//! acts after q+5 steps at the same step and order (CVODE's `nscon`), and there the
//! phi[j] are plain backward differences, phi_n[j] = nabla^j y_n, while CVODE's zn is the
//! interpolating polynomial p through y_n .. y_{n-q} written at t_n (both codes' corrector
//! makes it so), zn[j] = h^j p^(j)(t_n) / j!. With Newton's backward form
//! p(t_n + s h) = sum_m C(s+m-1, m) nabla^m y_n:
//!
//!   q! zn[q] = nabla^q y_n,
//!   (q-1)! zn[q-1] = nabla^(q-1) y_n + (q-1)/2 nabla^q y_n,
//!
//! and y_n - y_n(0) is in both codes nabla^(q+1) y_n (the predictor is the same
//! polynomial extrapolated). So, with phi* the history the step was predicted from and
//! ee its correction (phi_n[q] = phi*[q] + ee, phi_n[q-1] = phi*[q-1] + phi_n[q]):
//!
//!   sigma_{q+1} = ||ee||,
//!   sigma_q     = ||phi*[q] + ee||,
//!   sigma_{q-1} = ||phi*[q-1] + (q+1)/2 (phi*[q] + ee)||.
//!
//! The (q-1)/2 term matters: `cvSLdet` checks the root it found against the BDF formula
//! through the ratios sigma_{q+1}/sigma_q and sigma_{q-1}/sigma_q, and with the plain
//! backward difference ||nabla^(q-1) y_n|| that check rejects every root (flag -9; test
//! `bdf_sequence_gives_its_root` below). The norms are the error test's (IDA's error
//! weights, index-2 unknowns left out as the error test leaves them out).
//!
//! # What it does here
//!
//! Little, and therefore off by default (docs/solver.md, "BDF stability limit
//! detection"). IDA's controller changes the order every 2-7 steps when a mode is
//! unstable (its own estimates lower the order as soon as the growing oscillation
//! dominates the differences, and raise it again a few steps later), so the q+5 steps at
//! one order that the fit needs rarely occur, and on the vehicle, where several lightly
//! damped modes are active at once, the norms do not follow a single root (hitch variant 1
//! at rtol 1e-4: 125 of 126 fits fail, flags -6 and -5).

use super::Bdf;
use crate::problem::DaeProblem;

/// Steps of norm data `cvSLdet` fits (CVODE's ssdat rows).
const NDATA: usize = 5;
/// Lowest order STALD watches: BDF1 and BDF2 are A-stable.
const MIN_ORDER: usize = 3;
/// Constant-step, constant-order steps beyond the order before the data is used
/// (`cvBDFStab`: nscon >= q + 5).
const SETTLE: usize = 5;

// `cvSLdet`'s cutoffs and tolerances (cvode.c), and cvode.c's TINY.
/// A characteristic root with |r|^2 above this is a stability violation (rrcut).
const RRCUT: f64 = 0.98;
/// Variance of the ratios below which the data is taken as a single root (vrrtol) ...
const VRRTOL: f64 = 1.0e-4;
/// ... and the spread allowed between the three orders' ratios then (vrrt2).
const VRRT2: f64 = 5.0e-4;
/// Relative residual of the quartics accepted for the root (sqtol).
const SQTOL: f64 = 1.0e-3;
/// Agreement required between the root from the data and from the BDF formula (rrtol).
const RRTOL: f64 = 1.0e-2;
const TINY: f64 = 1.0e-10;

/// What STALD keeps between steps (CVODE's ssdat, nscon).
pub(super) struct Stald {
    /// Squared norms sigma_{q-1}^2, sigma_q^2, sigma_{q+1}^2 of the last steps at order
    /// >= 3, the newest first.
    ssdat: [[f64; 3]; NDATA],
    /// Accepted steps at the current step size and order (CVODE's nscon).
    pub(super) nscon: usize,
}

impl Stald {
    pub(super) fn new() -> Self {
        Self {
            ssdat: [[0.0; 3]; NDATA],
            nscon: 0,
        }
    }

    /// Pushes the norms of an accepted step at order q >= 3 (`cvBDFStab`'s first part).
    fn push(&mut self, sigma: [f64; 3]) {
        self.ssdat.copy_within(0..NDATA - 1, 1);
        self.ssdat[0] = sigma.map(|s| s * s);
    }
}

/// The scaled-derivative norms (sigma_{q-1}, sigma_q, sigma_{q+1}) of an accepted step of
/// order q from the history phi* it was predicted from and its correction ee, in the
/// weights w (see the module documentation for the correspondence with CVODE's zn).
pub(crate) fn scaled_derivative_norms(
    phi_qm1: &[f64],
    phi_q: &[f64],
    ee: &[f64],
    w: &[f64],
    q: usize,
) -> [f64; 3] {
    let c = 0.5 * (q as f64 + 1.0);
    let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
    for i in 0..ee.len() {
        let d_q = phi_q[i] + ee[i];
        let d_qm1 = phi_qm1[i] + c * d_q;
        s0 += (d_qm1 * w[i]).powi(2);
        s1 += (d_q * w[i]).powi(2);
        s2 += (ee[i] * w[i]).powi(2);
    }
    let n = ee.len().max(1) as f64;
    [(s0 / n).sqrt(), (s1 / n).sqrt(), (s2 / n).sqrt()]
}

impl<P: DaeProblem + ?Sized> Bdf<'_, P> {
    /// Counts the accepted step towards nscon and records its norms; call at the start of
    /// `complete_step`, before the history update.
    pub(super) fn stald_record(&mut self) {
        let ctl = &self.ctl;
        // CVODE resets nscon when it rescales the history (a new step) and counts the
        // steps completed since; a changed order changes the formula alike.
        let constant = ctl.hh == self.core.h_used && ctl.kk == ctl.kused;
        let st = &mut self.stald;
        st.nscon = if constant { st.nscon + 1 } else { 1 };
        let q = ctl.kk;
        if q >= MIN_ORDER {
            let phi = &self.hist.phi;
            let sigma =
                scaled_derivative_norms(&phi[q - 1], &phi[q], &self.work.ee, &self.wt.err, q);
            st.push(sigma);
        }
    }

    /// True when STALD finds the step of order q stability-limited (`cvBDFStab`: enough
    /// data, then `cvSLdet` returns 4, 5 or 6); `complete_step` lowers the order then,
    /// unless the error estimates already do.
    pub(super) fn stald_limited(&self) -> bool {
        let q = self.ctl.kk;
        q >= MIN_ORDER && self.stald.nscon >= q + SETTLE && sldet(&self.stald.ssdat, q) > 3
    }
}

/// CVODE's `cvSLdet`: from the squared scaled-derivative norms ssdat[i][k] (i = 0 the
/// newest of 5 steps, k = 0, 1, 2 for orders q-1, q, q+1) the modulus squared rr of the
/// dominant characteristic root, returned as CVODE's kflag:
/// 1, 2, 3: a stable root found (by the ratios directly, from the quartics, from the
/// quartics after Newton correction); 4, 5, 6: the same with rr > 0.98, a stability
/// violation; negative: no root could be determined (-1 data too small, -2/-3 ratios
/// inconsistent, -4 elimination failed, -5 root out of range, -6 Newton correction
/// failed, -7/-8 amplitudes not determined, -9 the root disagrees with the BDF formula).
pub(crate) fn sldet(ssdat: &[[f64; 3]; NDATA], q: usize) -> i32 {
    sldet_root(ssdat, q).0
}

/// `sldet`, also returning rr (0 where it was not found).
pub(crate) fn sldet_root(ssdat: &[[f64; 3]; NDATA], q: usize) -> (i32, f64) {
    let s = |i: usize, k: usize| ssdat[i][k];
    let mut smax = [0.0; 3];
    let mut ssmax = [0.0; 3];
    let mut rav = [0.0; 3];
    let mut vrat = [0.0; 3];
    // qc[j][k]: coefficient j (CVODE's qc[j+1]) of the quartic
    // qc0 rr^4 + qc1 rr^3 + qc2 rr^2 (= 0) + qc3 rr + qc4 = 0 that the five values of
    // order k satisfy if they follow one root (with its oscillating part).
    let mut qc = [[0.0; 3]; 5];
    for k in 0..3 {
        let mut smink = s(0, k);
        let mut smaxk: f64 = 0.0;
        for i in 0..NDATA {
            smink = smink.min(s(i, k));
            smaxk = smaxk.max(s(i, k));
        }
        // (CVODE lets an all-zero column through to a 0/0; so do non-finite norms.)
        if smink < TINY * smaxk || smaxk <= 0.0 || !smaxk.is_finite() {
            return (-1, 0.0);
        }
        smax[k] = smaxk;
        ssmax[k] = smaxk * smaxk;
        let (mut sumrat, mut sumrsq) = (0.0, 0.0);
        for i in 0..4 {
            let rat = s(i, k) / s(i + 1, k);
            sumrat += rat;
            sumrsq += rat * rat;
        }
        rav[k] = 0.25 * sumrat;
        vrat[k] = (0.25 * sumrsq - rav[k] * rav[k]).abs();
        qc[4][k] = s(0, k) * s(2, k) - s(1, k) * s(1, k);
        qc[3][k] = s(1, k) * s(2, k) - s(0, k) * s(3, k);
        qc[2][k] = 0.0;
        qc[1][k] = s(1, k) * s(4, k) - s(2, k) * s(3, k);
        qc[0][k] = s(3, k) * s(3, k) - s(2, k) * s(4, k);
    }
    let quartic = |k: usize, r: f64| qc[4][k] + r * (qc[3][k] + r * r * (qc[1][k] + r * qc[0][k]));

    let vmin = vrat[0].min(vrat[1]).min(vrat[2]);
    let vmax = vrat[0].max(vrat[1]).max(vrat[2]);
    let mut rr;
    let mut kflag;
    if vmin < VRRTOL * VRRTOL {
        // Normal (or nearly normal) matrix case: the ratios are constant and common.
        if vmax > VRRT2 * VRRT2 {
            return (-2, 0.0);
        }
        rr = (rav[0] + rav[1] + rav[2]) / 3.0;
        let drrmax = rav.iter().map(|r| (r - rr).abs()).fold(0.0, f64::max);
        if drrmax > VRRT2 {
            return (-3, rr);
        }
        kflag = 1;
    } else {
        // The common root of the three quartics, by elimination.
        let mut qco = qc;
        if qco[0][0].abs() < TINY * ssmax[0] {
            return (-4, 0.0);
        }
        for k in 1..3 {
            let tem = qco[0][k] / qco[0][0];
            for i in 1..5 {
                qco[i][k] -= tem * qco[i][0];
            }
            qco[0][k] = 0.0;
        }
        if qco[1][1].abs() < TINY * ssmax[1] {
            return (-4, 0.0);
        }
        let tem = qco[1][2] / qco[1][1];
        for i in 2..5 {
            qco[i][2] -= tem * qco[i][1];
        }
        if qco[3][2].abs() < TINY * ssmax[2] {
            return (-4, 0.0);
        }
        rr = -qco[4][2] / qco[3][2];
        if !(TINY..=100.0).contains(&rr) {
            return (-5, rr);
        }
        let mut qkr = [0.0; 3];
        for (k, v) in qkr.iter_mut().enumerate() {
            *v = quartic(k, rr);
        }
        let sqmax = (0..3).map(|k| qkr[k].abs() / ssmax[k]).fold(0.0, f64::max);
        if sqmax < SQTOL {
            kflag = 2;
        } else {
            // Newton corrections of rr on each quartic; keep the candidate that fits all
            // three best.
            let mut sqmin = 0.0;
            kflag = 0;
            for _ in 0..3 {
                let mut rrc = [0.0; 3];
                for k in 0..3 {
                    let qp = qc[3][k] + rr * rr * (3.0 * qc[1][k] + rr * 4.0 * qc[0][k]);
                    let drr = if qp.abs() > TINY * ssmax[k] {
                        -qkr[k] / qp
                    } else {
                        0.0
                    };
                    rrc[k] = rr + drr;
                }
                let mut qjk = [[0.0; 3]; 3];
                let mut sqmx = [0.0; 3];
                for k in 0..3 {
                    let mut m: f64 = 0.0;
                    for j in 0..3 {
                        qjk[j][k] = quartic(j, rrc[k]);
                        m = m.max(qjk[j][k].abs() / ssmax[j]);
                    }
                    sqmx[k] = m;
                }
                sqmin = sqmx[0] + 1.0;
                let mut kmin = 0;
                for k in 0..3 {
                    if sqmx[k] < sqmin {
                        kmin = k;
                        sqmin = sqmx[k];
                    }
                }
                rr = rrc[kmin];
                if sqmin < SQTOL {
                    kflag = 3;
                    break;
                }
                for j in 0..3 {
                    qkr[j] = qjk[j][kmin];
                }
            }
            if sqmin > SQTOL {
                return (-6, rr);
            }
        }
    }

    // Given rr, the amplitudes sigsq[k] of the three orders, and rr checked against the
    // relation the BDF formula of order q imposes between them.
    let mut sigsq = [0.0; 3];
    for k in 0..3 {
        let rsa = s(0, k);
        let rsb = s(1, k) * rr;
        let rsc = s(2, k) * rr * rr;
        let rsd = s(3, k) * rr * rr * rr;
        let rd1a = rsa - rsb;
        let rd1b = rsb - rsc;
        let rd1c = rsc - rsd;
        let rd2a = rd1a - rd1b;
        let rd2b = rd1b - rd1c;
        let rd3a = rd2a - rd2b;
        if rd1b.abs() < TINY * smax[k] {
            return (-7, rr);
        }
        let cest1 = -rd3a / rd1b;
        if !(TINY..=4.0).contains(&cest1) {
            return (-7, rr);
        }
        let corr1 = (rd2b / cest1) / (rr * rr);
        sigsq[k] = s(2, k) + corr1;
    }
    if sigsq[1] < TINY {
        return (-8, rr);
    }
    let qf = q as f64;
    let ratp = sigsq[2] / sigsq[1];
    let ratm = sigsq[0] / sigsq[1];
    let qfac1 = 0.25 * (qf * qf - 1.0);
    let qfac2 = 2.0 / (qf - 1.0);
    let bb = ratp * ratm - 1.0 - qfac1 * ratp;
    let tem = 1.0 - qfac2 * bb;
    if tem.abs() < TINY {
        return (-8, rr);
    }
    let rrb = 1.0 / tem;
    if (rrb - rr).abs() > RRTOL {
        return (-9, rr);
    }
    if rr > RRCUT {
        kflag += 3;
    }
    (kflag, rr)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bdf::MAXORD;

    /// Binomial coefficient as f64.
    fn binom(n: usize, k: usize) -> f64 {
        (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    }

    /// nabla^j of the sequence `ys` at index `n`.
    fn nabla(ys: &[[f64; 2]], j: usize, n: usize) -> [f64; 2] {
        let mut d = [0.0; 2];
        for i in 0..=j {
            let c = if i % 2 == 0 { 1.0 } else { -1.0 } * binom(j, i);
            d[0] += c * ys[n - i][0];
            d[1] += c * ys[n - i][1];
        }
        d
    }

    /// Constant-step BDF of order q on x'' + 2 zeta omega x' + omega^2 x = 0 (omega = 1,
    /// step h), started from the exact solution; the states (x, x') of every step.
    fn bdf_run(q: usize, h: f64, zeta: f64, steps: usize) -> Vec<[f64; 2]> {
        // sum_{j=1}^q (1/j) nabla^j y_n = h A y_n, as y_n coefficients alpha_i.
        let mut al = [0.0; MAXORD + 1];
        for j in 1..=q {
            for (i, a) in al.iter_mut().enumerate().take(j + 1) {
                *a += if i % 2 == 0 { 1.0 } else { -1.0 } * binom(j, i) / j as f64;
            }
        }
        let a = [[0.0, 1.0], [-1.0, -2.0 * zeta]];
        let wd = (1.0 - zeta * zeta).sqrt();
        let exact = |t: f64| {
            let e = (-zeta * t).exp();
            let (s, c) = (wd * t).sin_cos();
            let x = e * (c + zeta / wd * s);
            let v = -e * s / wd;
            [x, v]
        };
        let mut ys: Vec<[f64; 2]> = (0..=q).map(|j| exact((j as f64 - q as f64) * h)).collect();
        for _ in 0..steps {
            let n = ys.len();
            let mut rhs = [0.0; 2];
            for i in 1..=q {
                rhs[0] -= al[i] * ys[n - i][0];
                rhs[1] -= al[i] * ys[n - i][1];
            }
            // (al0 I - h A) y = rhs
            let m = [
                [al[0] - h * a[0][0], -h * a[0][1]],
                [-h * a[1][0], al[0] - h * a[1][1]],
            ];
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            ys.push([
                (m[1][1] * rhs[0] - m[0][1] * rhs[1]) / det,
                (m[0][0] * rhs[1] - m[1][0] * rhs[0]) / det,
            ]);
        }
        ys
    }

    /// ssdat of the last 5 steps, through `scaled_derivative_norms` as the integrator
    /// calls it (phi* = backward differences at n-1, ee = nabla^(q+1) y_n).
    fn ssdat_of(ys: &[[f64; 2]], q: usize) -> [[f64; 3]; NDATA] {
        let mut ss = [[0.0; 3]; NDATA];
        let last = ys.len() - 1;
        for (i, row) in ss.iter_mut().enumerate() {
            let n = last - i;
            let pq1 = nabla(ys, q - 1, n - 1);
            let pq = nabla(ys, q, n - 1);
            let ee = nabla(ys, q + 1, n);
            let sig = scaled_derivative_norms(&pq1, &pq, &ee, &[1.0, 1.0], q);
            *row = sig.map(|s| s * s);
        }
        ss
    }

    #[test]
    fn bdf_sequence_gives_its_root() {
        // The modulus of the dominant root, measured from the sequence itself: the ratio
        // of ||y_n||^2 averaged over a beat is |r|^2 per step.
        for (q, hw, zeta, violation) in [
            (5, 1.0, 0.02, true),  // |r|^2 = 1.254
            (4, 0.8, 0.07, true),  // 1.010
            (3, 1.0, 0.02, true),  // 1.062
            (5, 0.6, 0.07, false), // 0.909
            (4, 0.6, 0.07, false), // 0.941
        ] {
            let ys = bdf_run(q, hw, zeta, 60);
            let ss = ssdat_of(&ys, q);
            let (kflag, rr) = sldet_root(&ss, q);
            assert!(kflag > 0, "q {q} h*omega {hw}: no root found ({kflag})");
            assert_eq!(kflag > 3, violation, "q {q} h*omega {hw}: rr {rr}");
            // The same data with the plain backward difference nabla^(q-1) y_n for
            // sigma_{q-1} (no Nordsieck term) fails the check against the formula.
            let mut plain = ss;
            let last = ys.len() - 1;
            for (i, row) in plain.iter_mut().enumerate() {
                let d = nabla(&ys, q - 1, last - i);
                row[0] = 0.5 * (d[0] * d[0] + d[1] * d[1]);
            }
            assert_eq!(sldet(&plain, q), -9, "q {q} h*omega {hw}");
        }
    }

    #[test]
    fn root_matches_growth_of_the_sequence() {
        // BDF5 at h*omega = 1, zeta = 0.02: rr against the growth of ||y||^2 over 20
        // steps (both the dominant root's |r|^2).
        let ys = bdf_run(5, 1.0, 0.02, 200);
        let (kflag, rr) = sldet_root(&ssdat_of(&ys, 5), 5);
        assert_eq!(kflag, 5);
        let e = |n: usize| -> f64 {
            (n - 20..n)
                .map(|i| ys[i][0].powi(2) + ys[i][1].powi(2))
                .sum()
        };
        let n = ys.len();
        let growth = (e(n) / e(n - 20)).powf(1.0 / 20.0);
        assert!(
            (rr - growth).abs() < 1e-3 * growth,
            "rr {rr} growth {growth}"
        );
    }

    #[test]
    fn no_root_from_too_little_data() {
        let mut ss = [[1.0; 3]; NDATA];
        ss[2][1] = 0.0;
        assert_eq!(sldet(&ss, 4), -1);
        assert_eq!(sldet(&[[0.0; 3]; NDATA], 4), -1);
        assert_eq!(sldet(&[[f64::NAN; 3]; NDATA], 4), -1);
    }
}
