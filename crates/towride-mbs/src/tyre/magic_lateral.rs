//! Magic Formula lateral force and aligning moment, pure side slip (MF 6.1 as in Pacejka,
//! "Tire and Vehicle Dynamics" 3rd ed. 2012, sec. 4.3.2: F_y0 (4.E19)-(4.E30), M_z0
//! (4.E31)-(4.E49)), at zero camber, nominal inflation pressure and without turn slip
//! (every zeta factor 1). ISO / TNO signs: the slip angle is alpha = atan(V_cy / |V_cx|),
//! PKY1 < 0, so F_y opposes the lateral slip and M_z (positive about the road normal)
//! turns the wheel towards its velocity.
//!
//! F_y0 = D_y sin(C_y atan(B_y a_y - E_y (B_y a_y - atan(B_y a_y)))) + S_Vy,
//! a_y = alpha + S_Hy, C_y = PCY1 LCY, mu_y = (PDY1 + PDY2 dfz) LMUY, D_y = mu_y F_z,
//! E_y = (PEY1 + PEY2 dfz)(1 - PEY3 sgn a_y) LEY (<= 1),
//! K_ya = PKY1 F_z0' sin(PKY4 atan(F_z / (PKY2 F_z0'))) LKY, B_y = K_ya / (C_y D_y),
//! S_Hy = (PHY1 + PHY2 dfz) LHY, S_Vy = F_z (PVY1 + PVY2 dfz) LVY LMUY'.
//!
//! Pneumatic trail and residual moment (the combined forms, which reduce to the pure ones
//! at zero longitudinal slip, are in `combined.rs`):
//! t = D_t cos(C_t atan(B_t a - E_t (B_t a - atan(B_t a)))) cos(alpha),
//! B_t = (QBZ1 + QBZ2 dfz + QBZ3 dfz^2) LKY / LMUY, C_t = QCZ1,
//! D_t = F_z (R0 / F_z0') (QDZ1 + QDZ2 dfz) LTR sgn V_cx,
//! E_t = (QEZ1 + QEZ2 dfz + QEZ3 dfz^2)(1 + QEZ4 (2/pi) atan(B_t C_t a_t)) (<= 1),
//! a_t = alpha + S_Ht, S_Ht = QHZ1 + QHZ2 dfz;
//! M_zr = D_r cos(atan(B_r a_r)), B_r = QBZ9 LKY / LMUY + QBZ10 B_y C_y,
//! D_r = F_z R0 (QDZ6 + QDZ7 dfz) LRES LMUY cos(alpha) sgn V_cx,
//! a_r = alpha + S_Hy + S_Vy / K_ya.

use super::magic::{degressive, scaling};
use crate::input::tir::TirFile;
use crate::input::InputError;

const LAT: &str = "LATERAL_COEFFICIENTS";
const ALIGN: &str = "ALIGNING_COEFFICIENTS";

/// Lateral Magic Formula coefficients, pure side slip.
#[derive(Clone, Debug)]
pub struct MfLateral {
    /// PCY1: shape factor C_y.
    pub pcy1: f64,
    /// PDY1, PDY2: lateral friction and its load dependence.
    pub pdy: [f64; 2],
    /// PEY1, PEY2, PEY3: curvature E_y (PEY3 acts with sgn(a_y)).
    pub pey: [f64; 3],
    /// PKY1, PKY2, PKY4: cornering stiffness K_ya / F_z0', the load of its peak, its
    /// curvature.
    pub pky: [f64; 3],
    /// PHY1, PHY2: horizontal shift S_Hy.
    pub phy: [f64; 2],
    /// PVY1, PVY2: vertical shift S_Vy / F_z.
    pub pvy: [f64; 2],
    /// Scaling factors LCY, LMUY, LEY, LKY, LHY, LVY.
    pub scale: [f64; 6],
}

/// What the pure lateral formula gives, with the intermediate values the aligning moment
/// and the combined slip need.
#[derive(Clone, Copy, Debug)]
pub struct PureLateral {
    /// F_y0 [N].
    pub fy0: f64,
    /// Cornering stiffness K_ya [N/rad] (negative: ISO signs).
    pub kya: f64,
    /// B_y and C_y.
    pub by: f64,
    /// Shape factor C_y.
    pub cy: f64,
    /// Friction mu_y.
    pub muy: f64,
    /// Shifts S_Hy [rad] and S_Vy [N].
    pub shy: f64,
    /// Vertical shift S_Vy [N].
    pub svy: f64,
}

impl MfLateral {
    /// Reads [LATERAL_COEFFICIENTS] and the lateral scaling factors.
    pub fn from_tir(t: &TirFile) -> Result<MfLateral, InputError> {
        let sc = |k: &str| scaling(t, k);
        let pky1 = t.f64(LAT, "PKY1")?;
        if pky1 >= 0.0 {
            return Err(t.error(
                LAT,
                "PKY1",
                format!(
                    "must be negative (ISO / TNO signs: the lateral force opposes the side \
                     slip), got {pky1}"
                ),
            ));
        }
        let m = MfLateral {
            pcy1: t.in_range(LAT, "PCY1", 0.5, 2.0)?,
            pdy: [t.positive(LAT, "PDY1")?, t.f64(LAT, "PDY2")?],
            pey: [
                t.f64(LAT, "PEY1")?,
                t.f64(LAT, "PEY2")?,
                t.f64(LAT, "PEY3")?,
            ],
            pky: [pky1, t.positive(LAT, "PKY2")?, t.positive(LAT, "PKY4")?],
            phy: [t.f64(LAT, "PHY1")?, t.f64(LAT, "PHY2")?],
            pvy: [t.f64(LAT, "PVY1")?, t.f64(LAT, "PVY2")?],
            scale: [
                sc("LCY")?,
                sc("LMUY")?,
                sc("LEY")?,
                sc("LKY")?,
                sc("LHY")?,
                sc("LVY")?,
            ],
        };
        for dfz in [-1.0, 1.0] {
            if m.pdy[0] + m.pdy[1] * dfz <= 0.0 {
                return Err(t.error(
                    LAT,
                    "PDY2",
                    format!("friction PDY1 + PDY2 dfz is not positive at dfz = {dfz}"),
                ));
            }
        }
        Ok(m)
    }

    /// Cornering stiffness K_ya [N/rad] at load `fz` (4.E25), nominal load `fz0`.
    pub fn cornering_stiffness(&self, fz: f64, fz0: f64) -> f64 {
        let [pky1, pky2, pky4] = self.pky;
        pky1 * fz0 * (pky4 * (fz / (pky2 * fz0)).atan()).sin() * self.scale[3]
    }

    /// Pure-slip lateral force at slip angle `alpha` [rad] and load `fz` >= 0 [N]
    /// ((4.E19)-(4.E30)); `fz0` = F_z0'.
    pub fn pure(&self, alpha: f64, fz: f64, fz0: f64) -> PureLateral {
        let fz = fz.max(0.0);
        let dfz = (fz - fz0) / fz0;
        let [lcy, lmuy, ley, _lky, lhy, lvy] = self.scale;
        let cy = self.pcy1 * lcy;
        let muy = (self.pdy[0] + self.pdy[1] * dfz) * lmuy;
        let shy = (self.phy[0] + self.phy[1] * dfz) * lhy;
        let svy = fz * (self.pvy[0] + self.pvy[1] * dfz) * lvy * degressive(lmuy);
        let kya = self.cornering_stiffness(fz, fz0);
        // B_y = K_ya / (C_y D_y) with F_z cancelled (K_ya / F_z stays finite as F_z -> 0:
        // sin(PKY4 atan(F_z / ...)) ~ F_z).
        let kya_per_fz = if fz > 0.0 {
            kya / fz
        } else {
            self.pky[0] * self.pky[2] / self.pky[1] * self.scale[3]
        };
        let by = kya_per_fz / (cy * muy);
        let ay = alpha + shy;
        let ey = ((self.pey[0] + self.pey[1] * dfz) * (1.0 - self.pey[2] * sgn(ay)) * ley).min(1.0);
        let ba = by * ay;
        let fy0 = muy * fz * (cy * (ba - ey * (ba - ba.atan())).atan()).sin() + svy;
        PureLateral {
            fy0,
            kya,
            by,
            cy,
            muy,
            shy,
            svy,
        }
    }
}

/// sgn with sgn(0) = 1 (the MF's sign functions; only the shifted slips reach zero).
pub(crate) fn sgn(v: f64) -> f64 {
    if v < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Aligning moment coefficients (pneumatic trail, residual moment, F_x arm).
#[derive(Clone, Debug)]
pub struct MfAligning {
    /// QBZ1, QBZ2, QBZ3: trail slope B_t and its load dependence.
    pub qbz: [f64; 3],
    /// QBZ9, QBZ10: slope B_r of the residual moment.
    pub qbz9_10: [f64; 2],
    /// QCZ1: trail shape C_t.
    pub qcz1: f64,
    /// QDZ1, QDZ2: peak trail D_t / (F_z R0 / F_z0').
    pub qdz: [f64; 2],
    /// QDZ6, QDZ7: peak residual moment D_r / (F_z R0).
    pub qdz6_7: [f64; 2],
    /// QEZ1..QEZ4: trail curvature E_t (QEZ4 with the sign of a_t).
    pub qez: [f64; 4],
    /// QHZ1, QHZ2: trail shift S_Ht.
    pub qhz: [f64; 2],
    /// SSZ1, SSZ2: arm s / R0 of F_x.
    pub ssz: [f64; 2],
    /// Scaling factors LTR, LRES, LS.
    pub scale: [f64; 3],
}

/// Pneumatic trail and residual moment at the (equivalent) slip angles.
#[derive(Clone, Copy, Debug)]
pub struct TrailInputs {
    /// Load [N], nominal load F_z0' [N], unloaded radius [m].
    pub fz: f64,
    /// Nominal load F_z0' [N].
    pub fz0: f64,
    /// Unloaded radius R0 [m].
    pub r0: f64,
    /// cos(alpha) (the MF's cos'(alpha) = V_cx / V_c).
    pub cos_alpha: f64,
    /// sgn(V_cx): +1 rolling forward.
    pub sgn_vx: f64,
}

impl MfAligning {
    /// Reads [ALIGNING_COEFFICIENTS] and LTR, LRES, LS.
    pub fn from_tir(t: &TirFile) -> Result<MfAligning, InputError> {
        let sc = |k: &str| scaling(t, k);
        Ok(MfAligning {
            qbz: [
                t.positive(ALIGN, "QBZ1")?,
                t.f64(ALIGN, "QBZ2")?,
                t.f64(ALIGN, "QBZ3")?,
            ],
            qbz9_10: [
                t.non_negative(ALIGN, "QBZ9")?,
                t.non_negative(ALIGN, "QBZ10")?,
            ],
            qcz1: t.positive(ALIGN, "QCZ1")?,
            qdz: [t.f64(ALIGN, "QDZ1")?, t.f64(ALIGN, "QDZ2")?],
            qdz6_7: [t.f64(ALIGN, "QDZ6")?, t.f64(ALIGN, "QDZ7")?],
            qez: [
                t.f64(ALIGN, "QEZ1")?,
                t.f64(ALIGN, "QEZ2")?,
                t.f64(ALIGN, "QEZ3")?,
                t.f64(ALIGN, "QEZ4")?,
            ],
            qhz: [t.f64(ALIGN, "QHZ1")?, t.f64(ALIGN, "QHZ2")?],
            ssz: [t.f64(ALIGN, "SSZ1")?, t.f64(ALIGN, "SSZ2")?],
            scale: [sc("LTR")?, sc("LRES")?, sc("LS")?],
        })
    }

    /// Trail shift S_Ht [rad] (4.E35).
    pub fn trail_shift(&self, dfz: f64) -> f64 {
        self.qhz[0] + self.qhz[1] * dfz
    }

    /// Pneumatic trail t [m] at the (equivalent) trail slip `a_eq`; `a_t` is the shifted
    /// slip angle that sets the sign term of E_t ((4.E33), (4.E40)-(4.E45)); `lky`,
    /// `lmuy` the lateral scaling factors.
    pub fn trail(&self, a_eq: f64, a_t: f64, q: &TrailInputs, lky: f64, lmuy: f64) -> f64 {
        let dfz = (q.fz - q.fz0) / q.fz0;
        let bt = (self.qbz[0] + self.qbz[1] * dfz + self.qbz[2] * dfz * dfz) * lky / lmuy;
        let ct = self.qcz1;
        let dt =
            q.fz * (q.r0 / q.fz0) * (self.qdz[0] + self.qdz[1] * dfz) * self.scale[0] * q.sgn_vx;
        let et = ((self.qez[0] + self.qez[1] * dfz + self.qez[2] * dfz * dfz)
            * (1.0 + self.qez[3] * std::f64::consts::FRAC_2_PI * (bt * ct * a_t).atan()))
        .min(1.0);
        let ba = bt * a_eq;
        dt * (ct * (ba - et * (ba - ba.atan())).atan()).cos() * q.cos_alpha
    }

    /// Residual moment M_zr [N m] at the (equivalent) residual slip `a_eq` ((4.E36),
    /// (4.E46)-(4.E48)); `by_cy` = B_y C_y of the lateral force.
    pub fn residual(&self, a_eq: f64, q: &TrailInputs, lky: f64, lmuy: f64, by_cy: f64) -> f64 {
        let dfz = (q.fz - q.fz0) / q.fz0;
        let br = self.qbz9_10[0] * lky / lmuy + self.qbz9_10[1] * by_cy;
        let dr = q.fz
            * q.r0
            * (self.qdz6_7[0] + self.qdz6_7[1] * dfz)
            * self.scale[1]
            * lmuy
            * q.cos_alpha
            * q.sgn_vx;
        dr * (br * a_eq).atan().cos()
    }

    /// Arm s [m] of F_x about the contact centre (4.E76).
    pub fn fx_arm(&self, fy: f64, fz0: f64, r0: f64) -> f64 {
        r0 * (self.ssz[0] + self.ssz[1] * fy / fz0) * self.scale[2]
    }
}
