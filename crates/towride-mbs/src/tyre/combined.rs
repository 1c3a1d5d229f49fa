//! Combined slip: the Magic Formula weighting functions G_xa, G_yk and the combined
//! aligning moment (MF 6.1, Pacejka 2012 sec. 4.3.2, (4.E50)-(4.E67) and (4.E71)-(4.E78)),
//! zero camber, and [`MagicFormula`], which puts the longitudinal, lateral and aligning
//! parts together.
//!
//! F_x = G_xa F_x0, G_xa = cos(C_xa atan(B_xa a_S - E_xa (B_xa a_S - atan(B_xa a_S)))) / G_xa0,
//! a_S = alpha + S_Hxa, S_Hxa = RHX1, B_xa = RBX1 cos(atan(RBX2 kappa)) LXAL, C_xa = RCX1,
//! E_xa = REX1 + REX2 dfz (<= 1), G_xa0 = the same at a_S = S_Hxa.
//! F_y = G_yk F_y0 + S_Vyk, G_yk = cos(C_yk atan(B_yk k_S - E_yk (...))) / G_yk0,
//! k_S = kappa + S_Hyk, S_Hyk = RHY1 + RHY2 dfz, B_yk = RBY1 cos(atan(RBY2 (alpha - RBY3))) LYKA,
//! C_yk = RCY1, E_yk = REY1 + REY2 dfz (<= 1),
//! S_Vyk = D_Vyk sin(RVY5 atan(RVY6 kappa)) LVYKA, D_Vyk = mu_y F_z (RVY1 + RVY2 dfz) cos(atan(RVY4 alpha)).
//! M_z = -t F_y' + M_zr + s F_x, F_y' = F_y - S_Vyk, t and M_zr at the equivalent slips
//! a_t,eq = atan(sqrt(tan^2 a_t + (K_xk / K_ya)^2 kappa^2)) sgn a_t (and a_r,eq likewise),
//! written with tan / atan as MF-Tyre 6.1 evaluates it (MFeval's `calculateMz`); for
//! small angles it is the book's sqrt(a_t^2 + (K_xk / K_ya)^2 kappa^2) sgn a_t (4.E77),
//! (4.E78).

use super::magic::{scaling, MfLongitudinal};
use super::magic_lateral::{sgn, MfAligning, MfLateral, TrailInputs};
use crate::input::tir::TirFile;
use crate::input::InputError;

const LONG: &str = "LONGITUDINAL_COEFFICIENTS";
const LAT: &str = "LATERAL_COEFFICIENTS";

/// Combined-slip coefficients.
#[derive(Clone, Debug)]
pub struct MfCombined {
    /// RBX1, RBX2: slope of G_xa and its reduction with kappa.
    pub rbx: [f64; 2],
    /// RCX1: shape of G_xa.
    pub rcx1: f64,
    /// REX1, REX2: curvature of G_xa.
    pub rex: [f64; 2],
    /// RHX1: slip-angle shift of G_xa.
    pub rhx1: f64,
    /// RBY1, RBY2, RBY3: slope of G_yk, its reduction with alpha and the alpha shift.
    pub rby: [f64; 3],
    /// RCY1: shape of G_yk.
    pub rcy1: f64,
    /// REY1, REY2: curvature of G_yk.
    pub rey: [f64; 2],
    /// RHY1, RHY2: kappa shift of G_yk.
    pub rhy: [f64; 2],
    /// RVY1, RVY2, RVY4, RVY5, RVY6: kappa-induced side force S_Vyk.
    pub rvy: [f64; 5],
    /// Scaling factors LXAL, LYKA, LVYKA.
    pub scale: [f64; 3],
}

impl MfCombined {
    /// Reads the R* keys of [LONGITUDINAL_COEFFICIENTS] and [LATERAL_COEFFICIENTS].
    pub fn from_tir(t: &TirFile) -> Result<MfCombined, InputError> {
        let sc = |k: &str| scaling(t, k);
        Ok(MfCombined {
            rbx: [t.positive(LONG, "RBX1")?, t.f64(LONG, "RBX2")?],
            rcx1: t.positive(LONG, "RCX1")?,
            rex: [t.f64(LONG, "REX1")?, t.f64(LONG, "REX2")?],
            rhx1: t.f64(LONG, "RHX1")?,
            rby: [
                t.positive(LAT, "RBY1")?,
                t.f64(LAT, "RBY2")?,
                t.f64(LAT, "RBY3")?,
            ],
            rcy1: t.positive(LAT, "RCY1")?,
            rey: [t.f64(LAT, "REY1")?, t.f64(LAT, "REY2")?],
            rhy: [t.f64(LAT, "RHY1")?, t.f64(LAT, "RHY2")?],
            rvy: [
                t.f64(LAT, "RVY1")?,
                t.f64(LAT, "RVY2")?,
                t.f64(LAT, "RVY4")?,
                t.f64(LAT, "RVY5")?,
                t.f64(LAT, "RVY6")?,
            ],
            scale: [sc("LXAL")?, sc("LYKA")?, sc("LVYKA")?],
        })
    }
}

/// cos(C atan(B x - E (B x - atan(B x)))): the weighting functions' shape.
fn weight(b: f64, c: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    (c * (bx - e * (bx - bx.atan())).atan()).cos()
}

/// The whole Magic Formula of a tyre file: longitudinal, lateral, aligning, combined.
#[derive(Clone, Debug)]
pub struct MagicFormula {
    /// Unloaded radius R0 [m] (trail and residual moment scale with it).
    pub r0: f64,
    /// Longitudinal force, pure slip.
    pub long: MfLongitudinal,
    /// Lateral force, pure slip.
    pub lat: MfLateral,
    /// Aligning moment.
    pub align: MfAligning,
    /// Combined-slip weighting.
    pub comb: MfCombined,
}

/// Forces and moment at one slip state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MfForces {
    /// Longitudinal force F_x [N] (combined).
    pub fx: f64,
    /// Lateral force F_y [N] (combined; ISO: along the wheel's left).
    pub fy: f64,
    /// Aligning moment M_z [N m] about the road normal at the contact centre.
    pub mz: f64,
    /// Pneumatic trail t [m] and residual moment M_zr [N m].
    pub trail: f64,
    /// Residual moment M_zr [N m].
    pub mzr: f64,
    /// Cornering stiffness K_ya [N/rad] and slip stiffness K_xk [N] at this load.
    pub kya: f64,
    /// Longitudinal slip stiffness K_xk [N].
    pub kxk: f64,
}

impl MagicFormula {
    /// Reads every Magic Formula part of a file; `fnomin` FNOMIN [N], `r0` [m].
    pub fn from_tir(t: &TirFile, fnomin: f64, r0: f64) -> Result<MagicFormula, InputError> {
        Ok(MagicFormula {
            r0,
            long: MfLongitudinal::from_tir(t, fnomin)?,
            lat: MfLateral::from_tir(t)?,
            align: MfAligning::from_tir(t)?,
            comb: MfCombined::from_tir(t)?,
        })
    }

    /// Nominal load F_z0' = FNOMIN LFZO [N].
    pub fn fz0(&self) -> f64 {
        self.long.fz0
    }

    /// Cornering stiffness K_ya [N/rad] at load `fz` [N] (negative, ISO).
    pub fn cornering_stiffness(&self, fz: f64) -> f64 {
        self.lat.cornering_stiffness(fz, self.fz0())
    }

    /// F_x, F_y, M_z at longitudinal slip `kappa`, slip angle `alpha` [rad] and load `fz`
    /// [N]; `forward` false for a wheel rolling backwards (sgn V_cx in the trail and the
    /// residual moment).
    pub fn forces(&self, kappa: f64, alpha: f64, fz: f64, forward: bool) -> MfForces {
        let fz = fz.max(0.0);
        let fz0 = self.fz0();
        let dfz = (fz - fz0) / fz0;
        let c = &self.comb;
        let [_, lmuy, _, lky, _, _] = self.lat.scale;
        // Longitudinal: pure, then G_xa (4.E50)-(4.E57).
        let fx0 = self.long.force(kappa, fz);
        let kxk = self.long.slip_stiffness(fz);
        let bxa = c.rbx[0] * (c.rbx[1] * kappa).atan().cos() * c.scale[0];
        let exa = (c.rex[0] + c.rex[1] * dfz).min(1.0);
        let gxa = weight(bxa, c.rcx1, exa, alpha + c.rhx1) / weight(bxa, c.rcx1, exa, c.rhx1);
        let fx = gxa * fx0;
        // Lateral: pure, then G_yk and S_Vyk (4.E58)-(4.E67).
        let p = self.lat.pure(alpha, fz, fz0);
        let shyk = c.rhy[0] + c.rhy[1] * dfz;
        let byk = c.rby[0] * (c.rby[1] * (alpha - c.rby[2])).atan().cos() * c.scale[1];
        let eyk = (c.rey[0] + c.rey[1] * dfz).min(1.0);
        let gyk = weight(byk, c.rcy1, eyk, kappa + shyk) / weight(byk, c.rcy1, eyk, shyk);
        let [rvy1, rvy2, rvy4, rvy5, rvy6] = c.rvy;
        let dvyk = p.muy * fz * (rvy1 + rvy2 * dfz) * (rvy4 * alpha).atan().cos();
        let svyk = dvyk * (rvy5 * (rvy6 * kappa).atan()).sin() * c.scale[2];
        let fy = gyk * p.fy0 + svyk;
        // Aligning moment (4.E71)-(4.E78).
        let q = TrailInputs {
            fz,
            fz0,
            r0: self.r0,
            cos_alpha: alpha.cos(),
            sgn_vx: if forward { 1.0 } else { -1.0 },
        };
        let a_t = alpha + self.align.trail_shift(dfz);
        // S_Hf = S_Hy + S_Vy / K_ya (4.E38); K_ya is never 0 (PKY1 < 0) unless F_z = 0,
        // where every force is 0 anyway.
        let a_r = alpha + p.shy + if p.kya != 0.0 { p.svy / p.kya } else { 0.0 };
        let ratio = if p.kya != 0.0 { kxk / p.kya } else { 0.0 };
        let k2 = (ratio * kappa).powi(2);
        let equiv = |a: f64| (a.tan().powi(2) + k2).sqrt().atan() * sgn(a);
        let trail = self.align.trail(equiv(a_t), a_t, &q, lky, lmuy);
        let mzr = self.align.residual(equiv(a_r), &q, lky, lmuy, p.by * p.cy);
        let s = self.align.fx_arm(fy, fz0, self.r0);
        let mz = -trail * (fy - svyk) + mzr + s * fx;
        MfForces {
            fx,
            fy,
            mz,
            trail,
            mzr,
            kya: p.kya,
            kxk,
        }
    }
}
