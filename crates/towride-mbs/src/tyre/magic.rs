//! Magic Formula longitudinal force, pure slip (MF 5.2 / 6.1 as in Pacejka, "Tire and
//! Vehicle Dynamics" 3rd ed. 2012, sec. 4.3.2, eqs. (4.E9)-(4.E18); camber and pressure
//! terms left out).
//!
//! F_x = D sin(C atan(B k - E (B k - atan(B k)))) + S_V with k = kappa + S_H and
//! dfz = (F_z - F_z0') / F_z0', F_z0' = FNOMIN LFZO,
//! C = PCX1 LCX, D = (PDX1 + PDX2 dfz) LMUX F_z,
//! K = F_z (PKX1 + PKX2 dfz) exp(PKX3 dfz) LKX, B = K / (C D),
//! E = (PEX1 + PEX2 dfz + PEX3 dfz^2)(1 - PEX4 sgn k) LEX (<= 1),
//! S_H = (PHX1 + PHX2 dfz) LHX, S_V = F_z (PVX1 + PVX2 dfz) LVX LMUX' with the
//! degressive friction scaling LMUX' = A LMUX / (1 + (A - 1) LMUX), A = 10 (4.E8).
//! B is formed with F_z divided out, so the force goes to zero smoothly with F_z (a wheel
//! leaving the road) without 0/0. The lateral force, the aligning moment and the
//! combined-slip weighting are in `magic_lateral.rs` and `combined.rs`.

use crate::input::InputError;

use crate::input::tir::TirFile;

/// Longitudinal Magic Formula coefficients (scaling factors folded in).
#[derive(Clone, Debug)]
pub struct MfLongitudinal {
    /// Nominal load F_z0' = FNOMIN LFZO [N].
    pub fz0: f64,
    /// PCX1: shape factor C.
    pub pcx1: f64,
    /// PDX1: friction at the nominal load.
    pub pdx1: f64,
    /// PDX2: friction variation with load.
    pub pdx2: f64,
    /// PEX1..PEX4: curvature E.
    pub pex: [f64; 4],
    /// PKX1..PKX3: slip stiffness.
    pub pkx: [f64; 3],
    /// PHX1, PHX2: horizontal shift.
    pub phx: [f64; 2],
    /// PVX1, PVX2: vertical shift.
    pub pvx: [f64; 2],
    /// Scaling factors LCX, LMUX, LEX, LKX, LHX, LVX (LFZO is folded into fz0).
    pub scale: [f64; 6],
}

const SEC: &str = "LONGITUDINAL_COEFFICIENTS";
pub(crate) const SCALE: &str = "SCALING_COEFFICIENTS";

/// The MF's constant of the degressive friction scaling, lambda' = A lambda / (1 + (A - 1)
/// lambda) (Pacejka 2012, (4.E8): "A = 10, say"); it only matters when a friction scaling
/// factor differs from 1.
pub(crate) const A_MU: f64 = 10.0;

/// lambda' of a friction scaling factor lambda (4.E8).
pub(crate) fn degressive(lambda: f64) -> f64 {
    A_MU * lambda / (1.0 + (A_MU - 1.0) * lambda)
}

/// A scaling factor of [SCALING_COEFFICIENTS]: optional (1 when absent), positive.
pub(crate) fn scaling(t: &TirFile, k: &str) -> Result<f64, InputError> {
    let v = t.f64_or(SCALE, k, 1.0)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(t.error(SCALE, k, format!("must be positive, got {v}")))
    }
}

impl MfLongitudinal {
    /// Reads [LONGITUDINAL_COEFFICIENTS] and the longitudinal scaling factors.
    pub fn from_tir(t: &TirFile, fnomin: f64) -> Result<MfLongitudinal, InputError> {
        let sc = |k: &str| scaling(t, k);
        let lfzo = sc("LFZO")?;
        let mf = MfLongitudinal {
            fz0: fnomin * lfzo,
            pcx1: t.in_range(SEC, "PCX1", 1.0, 2.0)?,
            pdx1: t.positive(SEC, "PDX1")?,
            pdx2: t.f64(SEC, "PDX2")?,
            pex: [
                t.f64(SEC, "PEX1")?,
                t.f64(SEC, "PEX2")?,
                t.f64(SEC, "PEX3")?,
                t.f64(SEC, "PEX4")?,
            ],
            pkx: [
                t.positive(SEC, "PKX1")?,
                t.f64(SEC, "PKX2")?,
                t.f64(SEC, "PKX3")?,
            ],
            phx: [t.f64(SEC, "PHX1")?, t.f64(SEC, "PHX2")?],
            pvx: [t.f64(SEC, "PVX1")?, t.f64(SEC, "PVX2")?],
            scale: [
                sc("LCX")?,
                sc("LMUX")?,
                sc("LEX")?,
                sc("LKX")?,
                sc("LHX")?,
                sc("LVX")?,
            ],
        };
        // The friction coefficient must stay positive up to twice the nominal load.
        for dfz in [-1.0, 1.0] {
            if mf.pdx1 + mf.pdx2 * dfz <= 0.0 {
                return Err(t.error(
                    SEC,
                    "PDX2",
                    format!("friction PDX1 + PDX2 dfz is not positive at dfz = {dfz}"),
                ));
            }
        }
        Ok(mf)
    }

    fn dfz(&self, fz: f64) -> f64 {
        (fz - self.fz0) / self.fz0
    }

    /// Slip stiffness dF_x/dkappa at kappa = 0 [N] (= K).
    pub fn slip_stiffness(&self, fz: f64) -> f64 {
        let dfz = self.dfz(fz);
        fz * (self.pkx[0] + self.pkx[1] * dfz) * (self.pkx[2] * dfz).exp() * self.scale[3]
    }

    /// Pure-slip F_x0 [N] at longitudinal slip `kappa` and vertical load `fz` >= 0 [N]
    /// (4.E9).
    pub fn force(&self, kappa: f64, fz: f64) -> f64 {
        let fz = fz.max(0.0);
        let dfz = self.dfz(fz);
        let [lcx, lmux, lex, lkx, lhx, lvx] = self.scale;
        let c = self.pcx1 * lcx;
        let mu = (self.pdx1 + self.pdx2 * dfz) * lmux;
        let k = kappa + (self.phx[0] + self.phx[1] * dfz) * lhx;
        // B = K / (C D) with F_z cancelled.
        let b = (self.pkx[0] + self.pkx[1] * dfz) * (self.pkx[2] * dfz).exp() * lkx / (c * mu);
        let e = ((self.pex[0] + self.pex[1] * dfz + self.pex[2] * dfz * dfz)
            * (1.0 - self.pex[3] * k.signum())
            * lex)
            .min(1.0);
        let bk = b * k;
        let sv = fz * (self.pvx[0] + self.pvx[1] * dfz) * lvx * degressive(lmux);
        mu * fz * (c * (bk - e * (bk - bk.atan())).atan()).sin() + sv
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mf() -> MfLongitudinal {
        MfLongitudinal {
            fz0: 4000.0,
            pcx1: 1.6,
            pdx1: 1.1,
            pdx2: -0.08,
            pex: [0.2, 0.0, 0.0, 0.0],
            pkx: [21.0, 0.0, 0.0],
            phx: [0.0, 0.0],
            pvx: [0.0, 0.0],
            scale: [1.0; 6],
        }
    }

    #[test]
    fn slope_at_origin_is_the_slip_stiffness() {
        let m = mf();
        let h = 1e-7;
        let d = (m.force(h, 4000.0) - m.force(-h, 4000.0)) / (2.0 * h);
        assert!((d / m.slip_stiffness(4000.0) - 1.0).abs() < 1e-6, "{d}");
        assert_eq!(m.force(0.0, 4000.0), 0.0);
        assert_eq!(m.force(0.3, 0.0), 0.0);
        // The peak is D = mu F_z.
        let peak = (1..400)
            .map(|i| m.force(i as f64 * 0.0025, 4000.0))
            .fold(0.0, f64::max);
        assert!((peak / (1.1 * 4000.0) - 1.0).abs() < 1e-3, "{peak}");
    }
}
