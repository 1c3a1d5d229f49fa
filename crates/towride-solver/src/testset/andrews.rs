//! Andrews' squeezing mechanism (test set problem `andrews`, index-3 DAE, 27 unknowns,
//! t in [0, 0.03]).
//!
//! Seven rigid bodies joined without friction, driven by a constant torque `mom` and a
//! spring c0. With the angles q = (beta, theta, gamma, phi, delta, omega, epsilon),
//! velocities v = q', accelerations w = v' and multipliers lambda (6 constraints), the
//! test set writes y = (q, v, w, lambda) and the residual
//!
//! ```text
//! 0 = q' - v                                   (rows 1..7)
//! 0 = v' - w                                   (rows 8..14)
//! 0 = f(q, v) - M(q) w - G(q)^T lambda         (rows 15..21)
//! 0 = -g(q)                                    (rows 22..27)
//! ```
//!
//! with the 7x7 mass matrix M(q), the force vector f(q, v), the six position constraints
//! g(q) and their Jacobian G = dg/dq (the `gp` array of the Fortran code). The iteration
//! matrix here is the complete one, including the derivatives of M, f and G with respect
//! to q and of f with respect to v; the Fortran `andjac` is the approximation of
//! Hairer & Wanner (Solving ODEs II, p. 540) that drops those terms.
//!
//! # Sources
//!
//! * Residual (`andres`), right-hand side (`andfunc`: mass matrix, forces, `gp`, `g`):
//!   repository `rforge/bvpsolve`, file `pkg/deTestSet/src/Ex_andrews.f` (header: test
//!   set file `andrews.f`, `$Id: andrews.F,v 1.2 2006/10/02 10:29:13 testset Exp $`).
//! * The 42 parameters, y0 (30-digit values) and the rule y'0 = (y8..y21, 0, ..., 0):
//!   `rforge/bvpsolve`, `pkg/deTestSet/R/ex_andrews.R`; the same values are in
//!   `SciML/SciMLBenchmarks.jl`, `benchmarks/DAE/andrews_mechanism.jmd`.
//! * Index of the unknowns: `ind <- c(7, 7, 13)` in `ex_andrews.R`.
//! * Reference at t = 0.03, all 27 components: subroutine `andsoln` of `Ex_andrews.f`
//!   (PSIDE on a Cray C90, rtol = atol = 1e-14), identical in `andrews_mechanism.jmd`.
//!   The scd is taken over y1..y7 only, as in the test set driver (`report.f` rev. 1.20,
//!   `getscd`: `problm.eq.'andrews'.and. i.gt.7` is skipped).
//!
//! # Published statistics
//!
//! MEBDFI with rtol = atol = 1e-9: 506 steps, 2026 residual evaluations. These figures
//! were supplied with the task as coming from the test-set report; they could not be
//! checked against a stored copy of the report.

use super::{Benchmark, PublishedStats};
use crate::problem::{DaeProblem, JacobianSink, VarKind};

/// Reference solution at t = 0.03 (`andsoln` in `Ex_andrews.f`).
#[allow(clippy::excessive_precision)] // digits kept exactly as published
pub const REFERENCE: [f64; 27] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948e+0,
    0.5244099658805304e+0,
    0.5347301163226948e+0,
    0.1048080741042263e+1,
    0.1139920302151208e+4,
    -0.1424379294994111e+4,
    0.1103291221937134e+2,
    0.1929337464421385e+2,
    0.5735699284790808e+0,
    -0.1929337464421385e+2,
    0.3231791658026955e+0,
    -0.2463176316945196e+5,
    0.5185037701610329e+5,
    0.3241025686413781e+6,
    0.5667493645176213e+6,
    0.1674362929479361e+5,
    -0.5667493645176222e+6,
    0.9826520791458422e+4,
    0.1991753333731910e+3,
    -0.2975531228015052e+2,
    0.2306654119098399e+2,
    0.3145271365475927e+2,
    0.2264249232082739e+2,
    0.1161740700019673e+2,
];

/// The parameters of the mechanism (names as in the Fortran common block `andcom`).
#[derive(Clone, Debug)]
pub struct Andrews {
    /// Mass of body 1, the crank turned by `mom` (angle beta) [kg].
    pub m1: f64,
    /// Mass of body 2 (angle theta) [kg].
    pub m2: f64,
    /// Mass of body 3 (angle gamma), which carries the spring [kg].
    pub m3: f64,
    /// Mass of body 4 (angle phi) [kg].
    pub m4: f64,
    /// Mass of body 5 (angle delta) [kg].
    pub m5: f64,
    /// Mass of body 6 (angle omega) [kg].
    pub m6: f64,
    /// Mass of body 7 (angle epsilon) [kg].
    pub m7: f64,
    /// x of the fixed pivot A of bodies 5 and 7 [m].
    pub xa: f64,
    /// y of the fixed pivot A [m].
    pub ya: f64,
    /// x of the fixed pivot B of body 3 [m].
    pub xb: f64,
    /// y of the fixed pivot B [m].
    pub yb: f64,
    /// x of the fixed spring anchor C [m].
    pub xc: f64,
    /// y of the fixed spring anchor C [m].
    pub yc: f64,
    /// Spring stiffness [N/m].
    pub c0: f64,
    /// Moment of inertia of body 1 about its centre of mass [kg m^2].
    pub i1: f64,
    /// Moment of inertia of body 2 about its centre of mass [kg m^2].
    pub i2: f64,
    /// Moment of inertia of body 3 about its centre of mass [kg m^2].
    pub i3: f64,
    /// Moment of inertia of body 4 about its centre of mass [kg m^2].
    pub i4: f64,
    /// Moment of inertia of body 5 about its centre of mass [kg m^2].
    pub i5: f64,
    /// Moment of inertia of body 6 about its centre of mass [kg m^2].
    pub i6: f64,
    /// Moment of inertia of body 7 about its centre of mass [kg m^2].
    pub i7: f64,
    /// Length of body 2, from its joint with body 1 to the common joint E [m].
    pub d: f64,
    /// Distance of body 2's centre of mass from its joint with body 1 [m].
    pub da: f64,
    /// Length of body 4, from E to its joint with body 5 [m].
    pub e: f64,
    /// Distance of body 4's centre of mass from E (lever e - ea about the joint with body
    /// 5) [m].
    pub ea: f64,
    /// Length of the crank (body 1), from its pivot O to the joint with body 2 [m].
    pub rr: f64,
    /// Distance of body 1's centre of mass from its pivot O [m].
    pub ra: f64,
    /// Unstretched length of the spring [m].
    pub l0: f64,
    /// Distance from pivot B to the joint E on body 3 [m].
    pub ss: f64,
    /// Centre of mass of body 3 relative to B, first body-axis coordinate [m].
    pub sa: f64,
    /// Centre of mass of body 3 relative to B, second body-axis coordinate [m].
    pub sb: f64,
    /// Spring attachment D on body 3 relative to B, first body-axis coordinate [m].
    pub sc: f64,
    /// Spring attachment D on body 3 relative to B, second body-axis coordinate [m].
    pub sd: f64,
    /// Centre of mass of body 5 relative to A, first body-axis coordinate [m].
    pub ta: f64,
    /// Centre of mass of body 5 relative to A, second body-axis coordinate [m].
    pub tb: f64,
    /// Length of body 7, from A to its joint with body 6 [m].
    pub u: f64,
    /// Centre of mass of body 7 relative to A, first body-axis coordinate [m].
    pub ua: f64,
    /// Centre of mass of body 7 relative to A, second body-axis coordinate [m].
    pub ub: f64,
    /// Length of body 6, from E to its joint with body 7 [m].
    pub zf: f64,
    /// Length of body 5, from A to its joint with body 4 [m].
    pub zt: f64,
    /// Distance of body 6's centre of mass from E (lever zf - fa about the joint with body
    /// 7) [m].
    pub fa: f64,
    /// Constant driving torque on the crank [N m].
    pub mom: f64,
}

impl Default for Andrews {
    /// The test-set parameters (`ex_andrews.R`).
    fn default() -> Self {
        Andrews {
            m1: 0.04325,
            m2: 0.00365,
            m3: 0.02373,
            m4: 0.00706,
            m5: 0.07050,
            m6: 0.00706,
            m7: 0.05498,
            xa: -0.06934,
            ya: -0.00227,
            xb: -0.03635,
            yb: 0.03273,
            xc: 0.014,
            yc: 0.072,
            c0: 4530.0,
            i1: 2.194e-6,
            i2: 4.410e-7,
            i3: 5.255e-6,
            i4: 5.667e-7,
            i5: 1.169e-5,
            i6: 5.667e-7,
            i7: 1.912e-5,
            d: 28e-3,
            da: 115e-4,
            e: 2e-2,
            ea: 1421e-5,
            rr: 7e-3,
            ra: 92e-5,
            l0: 7785e-5,
            ss: 35e-3,
            sa: 1874e-5,
            sb: 1043e-5,
            sc: 18e-3,
            sd: 2e-2,
            ta: 2308e-5,
            tb: 916e-5,
            u: 4e-2,
            ua: 1228e-5,
            ub: 449e-5,
            zf: 2e-2,
            zt: 4e-2,
            fa: 1421e-5,
            mom: 33e-3,
        }
    }
}

const ANGLES: [&str; 7] = ["beta", "theta", "gamma", "phi", "delta", "omega", "epsilon"];

/// Groups of angles that are coupled in M, f and the Hessians of g.
const BLOCKS: [&[usize]; 4] = [&[0, 1], &[2], &[3, 4], &[5, 6]];

/// Which block an angle belongs to.
fn block_of(q: usize) -> usize {
    match q {
        0 | 1 => 0,
        2 => 1,
        3 | 4 => 2,
        _ => 3,
    }
}

/// Sines and cosines of the angles and of the three angle sums.
pub(crate) struct Trig {
    s: [f64; 7],
    c: [f64; 7],
    sibeth: f64,
    cobeth: f64,
    siphde: f64,
    cophde: f64,
    siomep: f64,
    coomep: f64,
}

impl Trig {
    pub(crate) fn new(q: &[f64]) -> Self {
        let mut s = [0.0; 7];
        let mut c = [0.0; 7];
        for i in 0..7 {
            s[i] = q[i].sin();
            c[i] = q[i].cos();
        }
        Trig {
            s,
            c,
            sibeth: (q[0] + q[1]).sin(),
            cobeth: (q[0] + q[1]).cos(),
            siphde: (q[3] + q[4]).sin(),
            cophde: (q[3] + q[4]).cos(),
            siomep: (q[5] + q[6]).sin(),
            coomep: (q[5] + q[6]).cos(),
        }
    }
}

/// Spring geometry of body 3 as a function of gamma: (X, Y, A, B, lang) with
/// X = xd - xc, Y = yd - yc, A = dxd/dgamma, B = dyd/dgamma.
struct Spring {
    x: f64,
    y: f64,
    a: f64,
    b: f64,
    lang: f64,
}

impl Andrews {
    fn spring(&self, tr: &Trig) -> Spring {
        let (siga, coga) = (tr.s[2], tr.c[2]);
        let xd = self.sd * coga + self.sc * siga + self.xb;
        let yd = self.sd * siga - self.sc * coga + self.yb;
        let x = xd - self.xc;
        let y = yd - self.yc;
        Spring {
            x,
            y,
            a: self.sc * coga - self.sd * siga,
            b: self.sd * coga + self.sc * siga,
            lang: (x * x + y * y).sqrt(),
        }
    }

    /// The symmetric 7x7 mass matrix M(q).
    pub(crate) fn mass(&self, tr: &Trig) -> [[f64; 7]; 7] {
        let (coth, siph, siom) = (tr.c[1], tr.s[3], tr.s[5]);
        let ee = self.e - self.ea;
        let zz = self.zf - self.fa;
        let mut m = [[0.0; 7]; 7];
        m[0][0] = self.m1 * self.ra.powi(2)
            + self.m2 * (self.rr.powi(2) - 2.0 * self.da * self.rr * coth + self.da.powi(2))
            + self.i1
            + self.i2;
        m[1][0] = self.m2 * (self.da.powi(2) - self.da * self.rr * coth) + self.i2;
        m[1][1] = self.m2 * self.da.powi(2) + self.i2;
        m[2][2] = self.m3 * (self.sa.powi(2) + self.sb.powi(2)) + self.i3;
        m[3][3] = self.m4 * ee.powi(2) + self.i4;
        m[4][3] = self.m4 * (ee.powi(2) + self.zt * ee * siph) + self.i4;
        m[4][4] = self.m4 * (self.zt.powi(2) + 2.0 * self.zt * ee * siph + ee.powi(2))
            + self.m5 * (self.ta.powi(2) + self.tb.powi(2))
            + self.i4
            + self.i5;
        m[5][5] = self.m6 * zz.powi(2) + self.i6;
        m[6][5] = self.m6 * (zz.powi(2) - self.u * zz * siom) + self.i6;
        m[6][6] = self.m6 * (zz.powi(2) - 2.0 * self.u * zz * siom + self.u.powi(2))
            + self.m7 * (self.ua.powi(2) + self.ub.powi(2))
            + self.i6
            + self.i7;
        m[0][1] = m[1][0];
        m[3][4] = m[4][3];
        m[5][6] = m[6][5];
        m
    }

    /// The force vector f(q, v) (`ff` of the Fortran code).
    pub(crate) fn forces(&self, tr: &Trig, v: &[f64]) -> [f64; 7] {
        let (bep, thp, php, dep, omp, epp) = (v[0], v[1], v[3], v[4], v[5], v[6]);
        let (sith, coph, coom) = (tr.s[1], tr.c[3], tr.c[5]);
        let sp = self.spring(tr);
        let force = -self.c0 * (sp.lang - self.l0) / sp.lang;
        let fx = force * sp.x;
        let fy = force * sp.y;
        let k2 = self.m2 * self.da * self.rr;
        let k4 = self.m4 * self.zt * (self.e - self.ea);
        let k6 = self.m6 * self.u * (self.zf - self.fa);
        [
            self.mom - k2 * thp * (thp + 2.0 * bep) * sith,
            k2 * bep * bep * sith,
            fx * sp.a + fy * sp.b,
            k4 * dep * dep * coph,
            -k4 * php * (php + 2.0 * dep) * coph,
            -k6 * epp * epp * coom,
            k6 * omp * (omp + 2.0 * epp) * coom,
        ]
    }

    /// G = dg/dq, 6x7 (`gp` of the Fortran code).
    /// M(q) w - f(q, v) + G(q)^T lambda, the equations of motion with accelerations w.
    pub(crate) fn equations_of_motion(
        &self,
        tr: &Trig,
        v: &[f64],
        w: &[f64],
        lam: &[f64],
    ) -> [f64; 7] {
        let m = self.mass(tr);
        let f = self.forces(tr, v);
        let gp = self.gp(tr);
        let mut out = [0.0; 7];
        for r in 0..7 {
            let mut acc = -f[r];
            for j in 0..7 {
                acc += m[r][j] * w[j];
            }
            for k in 0..6 {
                acc += gp[k][r] * lam[k];
            }
            out[r] = acc;
        }
        out
    }

    pub(crate) fn gp(&self, tr: &Trig) -> [[f64; 7]; 6] {
        let (rr, d, ss, e, zt, zf, u) =
            (self.rr, self.d, self.ss, self.e, self.zt, self.zf, self.u);
        let (sibe, cobe, siga, coga) = (tr.s[0], tr.c[0], tr.s[2], tr.c[2]);
        let (side, code, siep, coep) = (tr.s[4], tr.c[4], tr.s[6], tr.c[6]);
        let mut g = [[0.0; 7]; 6];
        let s1 = -rr * sibe + d * tr.sibeth;
        let s2 = d * tr.sibeth;
        let c1 = rr * cobe - d * tr.cobeth;
        let c2 = -d * tr.cobeth;
        for k in [0, 2, 4] {
            g[k][0] = s1;
            g[k][1] = s2;
            g[k + 1][0] = c1;
            g[k + 1][1] = c2;
        }
        g[0][2] = -ss * coga;
        g[1][2] = -ss * siga;
        g[2][3] = -e * tr.cophde;
        g[2][4] = -e * tr.cophde + zt * side;
        g[3][3] = -e * tr.siphde;
        g[3][4] = -e * tr.siphde - zt * code;
        g[4][5] = zf * tr.siomep;
        g[4][6] = zf * tr.siomep - u * coep;
        g[5][5] = -zf * tr.coomep;
        g[5][6] = -zf * tr.coomep - u * siep;
        g
    }

    /// The position constraints g(q).
    pub(crate) fn constraints(&self, tr: &Trig) -> [f64; 6] {
        let (rr, d, ss, e, zt, zf, u) =
            (self.rr, self.d, self.ss, self.e, self.zt, self.zf, self.u);
        let (sibe, cobe, siga, coga) = (tr.s[0], tr.c[0], tr.s[2], tr.c[2]);
        let (side, code, siep, coep) = (tr.s[4], tr.c[4], tr.s[6], tr.c[6]);
        let cx = rr * cobe - d * tr.cobeth;
        let cy = rr * sibe - d * tr.sibeth;
        [
            cx - ss * siga - self.xb,
            cy + ss * coga - self.yb,
            cx - e * tr.siphde - zt * code - self.xa,
            cy + e * tr.cophde - zt * side - self.ya,
            cx - zf * tr.coomep - u * siep - self.xa,
            cy - zf * tr.siomep + u * coep - self.ya,
        ]
    }

    /// d(f_r)/dq_l and d(f_r)/dv_l.
    fn dforces(&self, tr: &Trig, v: &[f64]) -> ([[f64; 7]; 7], [[f64; 7]; 7]) {
        let (bep, thp, php, dep, omp, epp) = (v[0], v[1], v[3], v[4], v[5], v[6]);
        let (sith, coth) = (tr.s[1], tr.c[1]);
        let (siph, coph) = (tr.s[3], tr.c[3]);
        let (siom, coom) = (tr.s[5], tr.c[5]);
        let k2 = self.m2 * self.da * self.rr;
        let k4 = self.m4 * self.zt * (self.e - self.ea);
        let k6 = self.m6 * self.u * (self.zf - self.fa);
        let mut dq = [[0.0; 7]; 7];
        let mut dv = [[0.0; 7]; 7];

        // f1 = mom - k2 thp (thp + 2 bep) sin(theta)
        dq[0][1] = -k2 * thp * (thp + 2.0 * bep) * coth;
        dv[0][0] = -2.0 * k2 * thp * sith;
        dv[0][1] = -2.0 * k2 * (thp + bep) * sith;
        // f2 = k2 bep^2 sin(theta)
        dq[1][1] = k2 * bep * bep * coth;
        dv[1][0] = 2.0 * k2 * bep * sith;

        // f3 = force (X A + Y B), force = -c0 (lang - l0) / lang, X A + Y B = lang lang'.
        // dA/dgamma = -B, dB/dgamma = A.
        let sp = self.spring(tr);
        let force = -self.c0 * (sp.lang - self.l0) / sp.lang;
        let s = sp.x * sp.a + sp.y * sp.b;
        let ds = sp.a * sp.a + sp.b * sp.b - sp.x * sp.b + sp.y * sp.a;
        let dforce = -self.c0 * self.l0 * s / sp.lang.powi(3);
        dq[2][2] = dforce * s + force * ds;

        // f4 = k4 dep^2 cos(phi)
        dq[3][3] = -k4 * dep * dep * siph;
        dv[3][4] = 2.0 * k4 * dep * coph;
        // f5 = -k4 php (php + 2 dep) cos(phi)
        dq[4][3] = k4 * php * (php + 2.0 * dep) * siph;
        dv[4][3] = -2.0 * k4 * (php + dep) * coph;
        dv[4][4] = -2.0 * k4 * php * coph;
        // f6 = -k6 epp^2 cos(omega)
        dq[5][5] = k6 * epp * epp * siom;
        dv[5][6] = -2.0 * k6 * epp * coom;
        // f7 = k6 omp (omp + 2 epp) cos(omega)
        dq[6][5] = -k6 * omp * (omp + 2.0 * epp) * siom;
        dv[6][5] = 2.0 * k6 * (omp + epp) * coom;
        dv[6][6] = 2.0 * k6 * omp * coom;
        (dq, dv)
    }

    /// d(M(q) w)_r / dq_l.
    fn dmass_w(&self, tr: &Trig, w: &[f64]) -> [[f64; 7]; 7] {
        let (sith, coph, coom) = (tr.s[1], tr.c[3], tr.c[5]);
        let ee = self.e - self.ea;
        let zz = self.zf - self.fa;
        // dM11/dtheta = 2 m2 da rr sin(theta), dM21/dtheta = m2 da rr sin(theta)
        let d11 = 2.0 * self.m2 * self.da * self.rr * sith;
        let d21 = self.m2 * self.da * self.rr * sith;
        // dM54/dphi = m4 zt (e-ea) cos(phi), dM55/dphi = 2 m4 zt (e-ea) cos(phi)
        let d54 = self.m4 * self.zt * ee * coph;
        let d55 = 2.0 * d54;
        // dM76/domega = -m6 u (zf-fa) cos(omega), dM77/domega = 2 dM76/domega
        let d76 = -self.m6 * self.u * zz * coom;
        let d77 = 2.0 * d76;
        let mut out = [[0.0; 7]; 7];
        out[0][1] = d11 * w[0] + d21 * w[1];
        out[1][1] = d21 * w[0];
        out[3][3] = d54 * w[4];
        out[4][3] = d54 * w[3] + d55 * w[4];
        out[5][5] = d76 * w[6];
        out[6][5] = d76 * w[5] + d77 * w[6];
        out
    }

    /// sum_k lambda_k d(G_kr)/dq_l, i.e. the lambda-weighted Hessian of g (symmetric).
    fn dgp_lam(&self, tr: &Trig, lam: &[f64]) -> [[f64; 7]; 7] {
        let (rr, d, ss, e, zt, zf, u) =
            (self.rr, self.d, self.ss, self.e, self.zt, self.zf, self.u);
        let (sibe, cobe, siga, coga) = (tr.s[0], tr.c[0], tr.s[2], tr.c[2]);
        let (side, code, siep, coep) = (tr.s[4], tr.c[4], tr.s[6], tr.c[6]);
        let mut h = [[0.0; 7]; 7];
        // Odd constraints (1, 3, 5) share G_k1 = -rr sin(beta) + d sin(beta+theta),
        // G_k2 = d sin(beta+theta); even ones (2, 4, 6) share G_k1 = rr cos(beta)
        // - d cos(beta+theta), G_k2 = -d cos(beta+theta).
        let lo = lam[0] + lam[2] + lam[4];
        let le = lam[1] + lam[3] + lam[5];
        let h_bb = lo * (-rr * cobe + d * tr.cobeth) + le * (-rr * sibe + d * tr.sibeth);
        let h_bt = lo * (d * tr.cobeth) + le * (d * tr.sibeth);
        h[0][0] = h_bb;
        h[0][1] = h_bt;
        h[1][0] = h_bt;
        h[1][1] = h_bt;
        // gamma: G_13 = -ss cos(gamma), G_23 = -ss sin(gamma).
        h[2][2] = lam[0] * ss * siga - lam[1] * ss * coga;
        // phi, delta: constraints 3 and 4.
        let h_pp = lam[2] * e * tr.siphde - lam[3] * e * tr.cophde;
        h[3][3] = h_pp;
        h[3][4] = h_pp;
        h[4][3] = h_pp;
        h[4][4] = h_pp + lam[2] * zt * code + lam[3] * zt * side;
        // omega, epsilon: constraints 5 and 6.
        let h_oo = lam[4] * zf * tr.coomep + lam[5] * zf * tr.siomep;
        h[5][5] = h_oo;
        h[5][6] = h_oo;
        h[6][5] = h_oo;
        h[6][6] = h_oo + lam[4] * u * siep - lam[5] * u * coep;
        h
    }

    /// The structural non-zeros of the iteration matrix, row by row.
    fn pattern() -> Vec<(usize, usize)> {
        let mut p = Vec::new();
        for i in 0..14 {
            p.push((i, i));
            p.push((i, i + 7));
        }
        for r in 0..7 {
            let row = 14 + r;
            let blk = BLOCKS[block_of(r)];
            for &c in blk {
                p.push((row, c)); // d/dq
                if r != 2 {
                    p.push((row, 7 + c)); // d/dv (gamma's force has no velocity)
                }
                p.push((row, 14 + c)); // -M
            }
            for k in 0..6 {
                if Self::gp_nonzero(k, r) {
                    p.push((row, 21 + k)); // -G^T
                }
            }
        }
        for k in 0..6 {
            for c in 0..7 {
                if Self::gp_nonzero(k, c) {
                    p.push((21 + k, c)); // -G
                }
            }
        }
        p
    }

    /// Whether G_kc is structurally non-zero.
    pub(crate) fn gp_nonzero(k: usize, c: usize) -> bool {
        c < 2 || block_of(c) == 1 + k / 2
    }
}

impl DaeProblem for Andrews {
    fn size(&self) -> usize {
        27
    }

    fn residual(&self, _t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        let (q, rest) = y.split_at(7);
        let (v, rest) = rest.split_at(7);
        let (w, lam) = rest.split_at(7);
        let tr = Trig::new(q);
        for i in 0..14 {
            res[i] = yp[i] - y[i + 7];
        }
        let dyn_res = self.equations_of_motion(&tr, v, w, lam);
        for r in 0..7 {
            res[14 + r] = -dyn_res[r];
        }
        let g = self.constraints(&tr);
        for k in 0..6 {
            res[21 + k] = -g[k];
        }
    }

    fn var_kinds(&self) -> Vec<VarKind> {
        let mut kinds = vec![VarKind::Differential; 7];
        kinds.extend([VarKind::Index2; 7]);
        kinds.extend([VarKind::Index3; 13]);
        kinds
    }

    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        Some(Self::pattern())
    }

    fn jacobian(&self, _t: f64, y: &[f64], _yp: &[f64], cj: f64, jac: &mut JacobianSink) -> bool {
        let (q, rest) = y.split_at(7);
        let (v, rest) = rest.split_at(7);
        let (w, lam) = rest.split_at(7);
        let tr = Trig::new(q);
        let m = self.mass(&tr);
        let gp = self.gp(&tr);
        let (dfq, dfv) = self.dforces(&tr, v);
        let dmw = self.dmass_w(&tr, w);
        let hl = self.dgp_lam(&tr, lam);
        for (row, col) in Self::pattern() {
            if row <= 13 && col == row {
                // dF/dy' of the kinematic rows, reported apart (JacobianSink::add_scaled).
                jac.add_scaled(row, col, cj, 1.0);
                continue;
            }
            let value = match row {
                0..=13 => -1.0, // col == row + 7
                14..=20 => {
                    let r = row - 14;
                    match col {
                        0..=6 => dfq[r][col] - dmw[r][col] - hl[r][col],
                        7..=13 => dfv[r][col - 7],
                        14..=20 => -m[r][col - 14],
                        _ => -gp[col - 21][r],
                    }
                }
                _ => -gp[row - 21][col],
            };
            jac.add(row, col, value);
        }
        true
    }

    fn var_name(&self, i: usize) -> String {
        match i {
            0..=6 => ANGLES[i].to_string(),
            7..=13 => format!("{}'", ANGLES[i - 7]),
            14..=20 => format!("{}''", ANGLES[i - 14]),
            21..=26 => format!("lambda{}", i - 20),
            _ => format!("y[{i}]"),
        }
    }

    fn eq_name(&self, i: usize) -> String {
        match i {
            0..=6 => format!("{0}' = v({0})", ANGLES[i]),
            7..=13 => format!("v({0})' = w({0})", ANGLES[i - 7]),
            14..=20 => format!("equation of motion ({})", ANGLES[i - 14]),
            21..=26 => format!("constraint g{}", i - 20),
            _ => format!("F[{i}]"),
        }
    }
}

/// Consistent initial values y0 and derivatives y'0 of the test set (`ex_andrews.R`).
#[allow(clippy::excessive_precision)] // digits kept exactly as published
pub fn initial() -> (Vec<f64>, Vec<f64>) {
    let mut y0 = vec![0.0; 27];
    y0[0] = -0.0617138900142764496358948458001;
    y0[1] = 0.0;
    y0[2] = 0.455279819163070380255912382449;
    y0[3] = 0.222668390165885884674473185609;
    y0[4] = 0.487364979543842550225598953530;
    y0[5] = -0.222668390165885884674473185609;
    y0[6] = 1.23054744454982119249735015568;
    // y8..y14 (velocities) are zero.
    y0[14] = 14222.4439199541138705911625887;
    y0[15] = -10666.8329399655854029433719415;
    // y17..y21 (accelerations) are zero.
    y0[21] = 98.5668703962410896057654982170;
    y0[22] = -6.12268834425566265503114393122;
    // y24..y27 (multipliers) are zero.
    let mut yp0 = vec![0.0; 27];
    yp0[..14].copy_from_slice(&y0[7..21]);
    (y0, yp0)
}

/// Andrews' squeezing mechanism with the test-set data.
pub fn benchmark() -> Benchmark {
    let (y0, yp0) = initial();
    let (y0_copy, yp0_copy) = (y0.clone(), yp0.clone());
    Benchmark {
        name: "andrews",
        title: "Andrews' squeezing mechanism (index 3, 27 unknowns)",
        problem: Box::new(Andrews::default()),
        t0: 0.0,
        t_end: 0.03,
        y0,
        yp0,
        reference: REFERENCE.to_vec(),
        scd_components: (0..7).collect(),
        published_steps: Some(PublishedStats {
            code: "MEBDFI",
            tol: 1e-9,
            steps: 506,
            residual_evals: Some(2026),
            jacobian_evals: None,
        }),
        source: "Test Set for IVP Solvers (Mazzia, Magherini, Iavernaro; Bari), problem \
                 'andrews' (andrews.f rev 1.2, 2006). Residual and reference (andsoln, \
                 PSIDE on Cray C90, tol 1e-14) from rforge/bvpsolve \
                 pkg/deTestSet/src/Ex_andrews.f; parameters, y0 and y'0 rule from \
                 pkg/deTestSet/R/ex_andrews.R; scd over y1..y7 as in report.f getscd. \
                 Published MEBDFI figures supplied with the task (test-set report), not \
                 re-checked.",
        atol_scale: 1.0,
        ggl: Some({
            let (p, y, yp) = super::ggl_forms::andrews_ggl(&y0_copy, &yp0_copy);
            super::GglForm {
                problem: Box::new(p),
                y0: y,
                yp0: yp,
                to_testset: super::ggl_forms::andrews_from_ggl,
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::*;
    use super::*;

    #[test]
    fn initial_values_are_consistent() {
        let b = benchmark();
        check_benchmark_shape(&b);
        let r = residual_norm(b.problem.as_ref(), b.t0, &b.y0, &b.yp0);
        assert!(r < 1e-12, "|F(0, y0, yp0)| = {r:e}");
        // The accelerations and multipliers are not zero: a solver that starts from
        // y'0 = 0 or lambda = 0 is not consistent.
        assert!(b.yp0[7] > 1e4 && b.yp0[8] < -1e4);
        assert!(b.y0[21] > 98.0 && b.y0[22] < -6.0);
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let b = benchmark();
        let p = b.problem.as_ref();
        // A point with moving bodies and non-zero multipliers: velocities of order 50,
        // accelerations of order 1e3, multipliers of order 20.
        let mut y1 = perturbed(&b.y0, 0.05);
        for (i, v) in y1.iter_mut().enumerate() {
            match i {
                7..=13 => *v = 50.0 * (1.3 * i as f64).sin(),
                14..=20 => *v = 1e3 * (0.7 * i as f64).cos(),
                21..=26 => *v = 20.0 * (2.1 * i as f64).sin(),
                _ => {}
            }
        }
        let yp1 = perturbed(&b.yp0, 1.0);
        for cj in [1.0, 3.7e3] {
            check_jacobian(p, 0.0, &b.y0, &b.yp0, cj, 1e-6);
            check_jacobian(p, 0.011, &y1, &yp1, cj, 1e-6);
            check_jacobian(p, 0.03, &REFERENCE, &yp1, cj, 1e-6);
        }
    }

    #[test]
    fn pattern_covers_jacobian() {
        let b = benchmark();
        let p = b.problem.as_ref();
        check_pattern(p, 0.0, &b.y0, &b.yp0, 1.0);
        check_pattern(p, 0.03, &REFERENCE, &b.yp0, 100.0);
        let pattern = p.jacobian_pattern().unwrap();
        let mut sorted = pattern.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), pattern.len(), "pattern has duplicates");
    }

    #[test]
    fn reference_satisfies_the_constraints() {
        // The reference positions lie on the constraint manifold (a check on the
        // transcription of g and of the reference).
        let tr = Trig::new(&REFERENCE[..7]);
        let g = Andrews::default().constraints(&tr);
        for (k, gk) in g.iter().enumerate() {
            assert!(gk.abs() < 1e-12, "g{} = {gk:e}", k + 1);
        }
    }

    #[test]
    fn reference_satisfies_hidden_constraints_and_equations_of_motion() {
        // The reference holds v, w and lambda too, so the velocity- and acceleration-level
        // constraints and the equations of motion can be checked against it. This tests
        // the transcription of G, of its derivatives (the Hessian used in the Jacobian),
        // of M and of f against the independently computed PSIDE solution.
        let p = Andrews::default();
        let (q, v, w, lam) = (
            &REFERENCE[..7],
            &REFERENCE[7..14],
            &REFERENCE[14..21],
            &REFERENCE[21..],
        );
        let tr = Trig::new(q);
        let gp = p.gp(&tr);
        for k in 0..6 {
            // d/dt g_k = G_k v.
            let terms: Vec<f64> = (0..7).map(|r| gp[k][r] * v[r]).collect();
            let scale = terms.iter().map(|x| x.abs()).sum::<f64>();
            let gv: f64 = terms.iter().sum();
            assert!(
                gv.abs() < 1e-9 * scale,
                "G{} v = {gv:e} (scale {scale:e})",
                k + 1
            );
            // d2/dt2 g_k = G_k w + v^T (d G_k / dq) v.
            let mut e = [0.0; 6];
            e[k] = 1.0;
            let h = p.dgp_lam(&tr, &e);
            let mut acc = 0.0;
            let mut scale = 0.0;
            for r in 0..7 {
                acc += gp[k][r] * w[r];
                scale += (gp[k][r] * w[r]).abs();
                for l in 0..7 {
                    acc += h[r][l] * v[r] * v[l];
                    scale += (h[r][l] * v[r] * v[l]).abs();
                }
            }
            // Holds to ~1e-7 only: the accelerations w of the reference are index-3
            // components, computed less accurately than q and v.
            assert!(
                acc.abs() < 1e-6 * scale,
                "g{}'' = {acc:e} (scale {scale:e})",
                k + 1
            );
        }
        // f - M w - G^T lambda = 0.
        let m = p.mass(&tr);
        let f = p.forces(&tr, v);
        for r in 0..7 {
            let mut res = f[r];
            let mut scale = f[r].abs();
            for j in 0..7 {
                res -= m[r][j] * w[j];
                scale += (m[r][j] * w[j]).abs();
            }
            for k in 0..6 {
                res -= gp[k][r] * lam[k];
                scale += (gp[k][r] * lam[k]).abs();
            }
            assert!(
                res.abs() < 1e-9 * scale,
                "equation {}: {res:e} (scale {scale:e})",
                r + 15
            );
        }
    }

    #[test]
    fn var_kinds_follow_ind() {
        let kinds = Andrews::default().var_kinds();
        assert!(kinds[..7].iter().all(|&k| k == VarKind::Differential));
        assert!(kinds[7..14].iter().all(|&k| k == VarKind::Index2));
        assert!(kinds[14..].iter().all(|&k| k == VarKind::Index3));
    }
}
