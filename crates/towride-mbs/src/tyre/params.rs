//! Tyre parameters read from a `.tir` file, checked, plus the quantities derived from them.
//!
//! Every physical number of the tyre models comes from here. The derivations (rigid-ring
//! sidewall stiffness from the ring frequencies, residual stiffness in series, contact
//! length, tandem-cam geometry) follow Pacejka, "Tire and Vehicle Dynamics" (3rd ed. 2012),
//! ch. 9 (rigid ring, after Zegelaar 1998) and ch. 10 (enveloping, after Schmeitz 2004);
//! the interpretation of each key is listed in `docs/road_tyre.md`.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use crate::input::InputError;

use super::combined::MagicFormula;
use crate::input::tir::TirFile;

/// Checked tyre data (SI units).
#[derive(Clone, Debug)]
pub struct TyreParams {
    /// The `.tir` file read.
    pub file: PathBuf,
    // [MODEL]
    /// Reference speed LONGVL [m/s] (speed term of the free rolling radius).
    pub longvl: f64,
    /// Width of the C1 blend of the normal force at touch-down, TOWRIDE_CONTACT_BLEND [m].
    pub contact_blend: f64,
    // [DIMENSION]
    /// Unloaded radius r0 [m].
    pub r0: f64,
    /// Tread width [m] (spread of the parallel tandems).
    pub width: f64,
    // [INERTIA]
    /// Whole tyre mass and spin inertia (tyre without rim) [kg], [kg m^2].
    pub mass: f64,
    /// Spin inertia of the whole tyre IYY [kg m^2].
    pub iyy: f64,
    /// Belt (ring) mass and spin inertia [kg], [kg m^2].
    pub belt_mass: f64,
    /// Spin inertia of the belt BELT_IYY [kg m^2].
    pub belt_iyy: f64,
    /// Gravity along world z [m/s^2] (negative: MF convention GRAVITY = -9.81).
    pub gravity: f64,
    // [VERTICAL]
    /// Nominal wheel load FNOMIN [N].
    pub fnomin: f64,
    /// Overall vertical stiffness C_z [N/m] and damping [N s/m] (point follower).
    pub cz: f64,
    /// Vertical damping of the point follower VERTICAL_DAMPING [N s/m].
    pub vertical_damping: f64,
    /// BREFF: B of the effective-rolling-radius law (steepness of its atan term) [-].
    pub breff: f64,
    /// DREFF: D of the effective-rolling-radius law (height of its atan term) [-].
    pub dreff: f64,
    /// FREFF: F of the effective-rolling-radius law (its linear term) [-].
    pub freff: f64,
    /// Q_RE0: ratio of free to unloaded radius at zero speed [-].
    pub q_re0: f64,
    /// Q_V1: growth of the free radius with (r0 Omega / LONGVL)^2 [-].
    pub q_v1: f64,
    // [STRUCTURAL]
    /// Overall longitudinal stiffness of the standing tyre [N/m].
    pub cx: f64,
    /// LATERAL_STIFFNESS: overall lateral stiffness of the standing tyre [N/m] (sets the
    /// lateral relaxation length).
    pub cy: f64,
    /// FREQ_LONG: natural frequency of the belt on its sidewall springs, in-plane
    /// translation (longitudinal and vertical), rim fixed [Hz].
    pub freq_long: f64,
    /// FREQ_WINDUP: natural frequency of the belt's rotation (wind-up), rim fixed [Hz].
    pub freq_windup: f64,
    /// DAMP_LONG: damping ratio of the in-plane translation mode [-].
    pub damp_long: f64,
    /// DAMP_WINDUP: damping ratio of the wind-up mode [-].
    pub damp_windup: f64,
    /// Residual damping time constant DAMP_RESIDUAL [s] (damping = value x stiffness).
    pub damp_residual: f64,
    /// Low-speed damping time constant DAMP_VLOW [s] (damping = value x the overall
    /// longitudinal or lateral stiffness, faded in below VXLOW); 0 when the file has none.
    pub damp_vlow: f64,
    /// VXLOW: speed below which the low-speed damping fades in [m/s] (MODEL section).
    pub vxlow: f64,
    // [CONTACT_PATCH]
    /// Q_RA1: square-root term of the contact-length law [-].
    pub q_ra1: f64,
    /// Q_RA2: linear term of the contact-length law [-].
    pub q_ra2: f64,
    /// ELLIPS_SHIFT: tandem base as a multiple of the nominal contact length [-].
    pub ellips_shift: f64,
    /// ELLIPS_LENGTH: cam semi-axis a_e as a multiple of the unloaded radius [-].
    pub ellips_length: f64,
    /// ELLIPS_HEIGHT: cam semi-axis b_e as a multiple of the unloaded radius [-].
    pub ellips_height: f64,
    /// ELLIPS_ORDER: cam contour exponent c_e, 1..20 [-].
    pub ellips_order: f64,
    /// ELLIPS_MAX_STEP: highest obstacle step the cam search covers [m].
    pub ellips_max_step: f64,
    /// ELLIPS_NWIDTH: number of tandems side by side across the tread.
    pub ellips_nwidth: usize,
    // [LONGITUDINAL_COEFFICIENTS], [LATERAL_COEFFICIENTS], [ALIGNING_COEFFICIENTS] with
    // [SCALING_COEFFICIENTS]
    /// The Magic Formula: longitudinal and lateral force, aligning moment, combined slip.
    pub mf: MagicFormula,
    /// Quantities derived from the above.
    pub d: Derived,
}

/// Derived model constants.
#[derive(Clone, Debug)]
pub struct Derived {
    /// Sidewall translational stiffness (longitudinal = vertical) [N/m] and damping [N s/m].
    pub c_b: f64,
    /// Sidewall translational damping [N s/m].
    pub k_b: f64,
    /// Sidewall rotational (wind-up) stiffness [N m/rad] and damping [N m s/rad].
    pub c_theta: f64,
    /// Sidewall rotational damping [N m s/rad].
    pub k_theta: f64,
    /// Residual vertical and longitudinal stiffness [N/m] and damping [N s/m].
    pub c_rz: f64,
    /// Residual vertical damping [N s/m].
    pub k_rz: f64,
    /// Residual longitudinal stiffness [N/m].
    pub c_rx: f64,
    /// Residual longitudinal damping [N s/m].
    pub k_rx: f64,
    /// Half contact length at the nominal load [m] (tread relaxation length).
    pub a0: f64,
    /// Loaded radius at the nominal load [m].
    pub r_loaded0: f64,
    /// Tandem base l_s [m], cam semi-axes a_e, b_e [m], cam exponent.
    pub l_s: f64,
    /// Cam semi-axis a_e along the heading [m].
    pub a_e: f64,
    /// Cam semi-axis b_e, vertical [m].
    pub b_e: f64,
    /// Cam contour exponent c_e [-].
    pub c_e: f64,
    /// Longitudinal slip stiffness at the nominal load [N] and the point follower's
    /// relaxation length sigma = C_Fk / C_x [m].
    pub k_slip0: f64,
    /// Relaxation length of the point follower sigma = C_Fk / C_x [m].
    pub sigma_point: f64,
    /// Cornering stiffness at the nominal load |K_ya(FNOMIN)| [N/rad].
    pub k_alpha0: f64,
    /// Lateral relaxation length sigma_alpha = |K_ya(FNOMIN)| / C_y [m] (both models: the
    /// ring has no lateral freedom, so the whole lateral compliance is in the slip state).
    pub sigma_alpha: f64,
    /// Low-speed damping at standstill, k_Vlow0 = DAMP_VLOW x C_x (longitudinal) and
    /// DAMP_VLOW x C_y (lateral) [N s/m].
    pub k_vlow_x: f64,
    /// Lateral low-speed damping at standstill [N s/m].
    pub k_vlow_y: f64,
}

impl TyreParams {
    /// Reads and checks a `.tir` file.
    pub fn from_file(path: &Path, loader: &crate::input::Loader) -> Result<TyreParams, InputError> {
        TyreParams::from_tir(&TirFile::read(path, loader)?)
    }

    /// Checks a parsed file.
    pub fn from_tir(t: &TirFile) -> Result<TyreParams, InputError> {
        for (key, want) in [
            ("LENGTH", &["meter", "m"][..]),
            ("FORCE", &["newton", "n"][..]),
            ("ANGLE", &["radians", "radian", "rad"][..]),
            ("MASS", &["kg", "kilogram"][..]),
            ("TIME", &["second", "s"][..]),
        ] {
            let v = t.string("UNITS", key)?;
            if !want.contains(&v.to_lowercase().as_str()) {
                return Err(t.error(
                    "UNITS",
                    key,
                    format!("only SI units are supported ({}), got '{v}'", want[0]),
                ));
            }
        }
        let longvl = t.positive("MODEL", "LONGVL")?;
        let contact_blend = t.positive("MODEL", "TOWRIDE_CONTACT_BLEND")?;
        let r0 = t.positive("DIMENSION", "UNLOADED_RADIUS")?;
        let width = t.positive("DIMENSION", "WIDTH")?;
        let mass = t.positive("INERTIA", "MASS")?;
        let iyy = t.positive("INERTIA", "IYY")?;
        let belt_mass = t.positive("INERTIA", "BELT_MASS")?;
        let belt_iyy = t.positive("INERTIA", "BELT_IYY")?;
        let gravity = t.f64("INERTIA", "GRAVITY")?;
        if belt_mass >= mass {
            return Err(t.error(
                "INERTIA",
                "BELT_MASS",
                format!("must be below MASS ({mass} kg)"),
            ));
        }
        if belt_iyy >= iyy {
            return Err(t.error(
                "INERTIA",
                "BELT_IYY",
                format!("must be below IYY ({iyy} kg m^2)"),
            ));
        }
        let fnomin = t.positive("VERTICAL", "FNOMIN")?;
        let cz = t.positive("VERTICAL", "VERTICAL_STIFFNESS")?;
        let vertical_damping = t.non_negative("VERTICAL", "VERTICAL_DAMPING")?;
        let breff = t.non_negative("VERTICAL", "BREFF")?;
        let dreff = t.non_negative("VERTICAL", "DREFF")?;
        let freff = t.non_negative("VERTICAL", "FREFF")?;
        let q_re0 = t.positive("VERTICAL", "Q_RE0")?;
        let q_v1 = t.non_negative("VERTICAL", "Q_V1")?;
        let cx = t.positive("STRUCTURAL", "LONGITUDINAL_STIFFNESS")?;
        let cy = t.positive("STRUCTURAL", "LATERAL_STIFFNESS")?;
        let freq_long = t.positive("STRUCTURAL", "FREQ_LONG")?;
        let freq_windup = t.positive("STRUCTURAL", "FREQ_WINDUP")?;
        let damp_long = t.in_range("STRUCTURAL", "DAMP_LONG", 0.0, 2.0)?;
        let damp_windup = t.in_range("STRUCTURAL", "DAMP_WINDUP", 0.0, 2.0)?;
        let damp_residual = t.positive("STRUCTURAL", "DAMP_RESIDUAL")?;
        // Optional, as in MF-Tyre files that carry no low-speed model: absent means none.
        let damp_vlow = t.f64_or("STRUCTURAL", "DAMP_VLOW", 0.0)?;
        if damp_vlow < 0.0 {
            return Err(t.error(
                "STRUCTURAL",
                "DAMP_VLOW",
                format!("must not be negative, got {damp_vlow}"),
            ));
        }
        // The fade-in speed is needed only with a low-speed damping.
        let vxlow = if damp_vlow > 0.0 {
            t.positive("MODEL", "VXLOW")?
        } else {
            t.f64_or("MODEL", "VXLOW", 0.0)?
        };
        let q_ra1 = t.non_negative("CONTACT_PATCH", "Q_RA1")?;
        let q_ra2 = t.non_negative("CONTACT_PATCH", "Q_RA2")?;
        if q_ra1 + q_ra2 <= 0.0 {
            return Err(t.error(
                "CONTACT_PATCH",
                "Q_RA1",
                "Q_RA1 and Q_RA2 cannot both be zero",
            ));
        }
        let ellips_shift = t.positive("CONTACT_PATCH", "ELLIPS_SHIFT")?;
        let ellips_length = t.positive("CONTACT_PATCH", "ELLIPS_LENGTH")?;
        let ellips_height = t.positive("CONTACT_PATCH", "ELLIPS_HEIGHT")?;
        // Exponents below 1 make the cam contour convex and the maximisation non-unique.
        let ellips_order = t.in_range("CONTACT_PATCH", "ELLIPS_ORDER", 1.0, 20.0)?;
        let ellips_max_step = t.positive("CONTACT_PATCH", "ELLIPS_MAX_STEP")?;
        let nw = t.in_range("CONTACT_PATCH", "ELLIPS_NWIDTH", 1.0, 50.0)?;
        if nw.fract() != 0.0 {
            return Err(t.error(
                "CONTACT_PATCH",
                "ELLIPS_NWIDTH",
                format!("must be a whole number, got {nw}"),
            ));
        }
        let mf = MagicFormula::from_tir(t, fnomin, r0)?;

        // Rigid ring (Pacejka 2012, sec. 9.2; Zegelaar 1998): the free ring on its sidewall
        // springs with the rim fixed vibrates at the file's frequencies, so
        // c = m (2 pi f)^2 and k = 2 zeta sqrt(c m); the same for wind-up with the belt
        // inertia. Longitudinal and vertical sidewall stiffness are equal (MF-Swift's
        // FREQ_LONG serves both modes), which keeps the ring isotropic in the rim plane.
        let w_long = 2.0 * PI * freq_long;
        let c_b = belt_mass * w_long * w_long;
        let k_b = 2.0 * damp_long * (c_b * belt_mass).sqrt();
        let w_wind = 2.0 * PI * freq_windup;
        let c_theta = belt_iyy * w_wind * w_wind;
        let k_theta = 2.0 * damp_windup * (c_theta * belt_iyy).sqrt();
        // Residual stiffness in series, so that the standing tyre has the file's overall
        // stiffness (Pacejka 2012, sec. 9.2: c_r = C c_b / (c_b - C)).
        if c_b <= cz {
            return Err(t.error(
                "STRUCTURAL",
                "FREQ_LONG",
                format!(
                    "sidewall stiffness BELT_MASS (2 pi FREQ_LONG)^2 = {c_b:.4e} N/m must exceed \
                     VERTICAL_STIFFNESS = {cz:.4e} N/m (no room for a residual spring)"
                ),
            ));
        }
        let c_rz = cz * c_b / (c_b - cz);
        let r_loaded0 = r0 - fnomin / cz;
        // Longitudinally a force at the contact point moves it by the ring's translation, the
        // ring's rotation times the loaded radius and the residual spring, all in series.
        let ring_compliance = 1.0 / c_b + r_loaded0 * r_loaded0 / c_theta;
        let residual_compliance = 1.0 / cx - ring_compliance;
        if residual_compliance <= 0.0 {
            return Err(t.error(
                "STRUCTURAL",
                "LONGITUDINAL_STIFFNESS",
                format!(
                    "must stay below the ring's own longitudinal stiffness {:.4e} N/m \
                     (1 / (1/c_b + r^2/c_theta) from FREQ_LONG, FREQ_WINDUP and the belt inertia)",
                    1.0 / ring_compliance
                ),
            ));
        }
        let c_rx = 1.0 / residual_compliance;
        let a0 = half_contact_length(r0, q_ra1, q_ra2, fnomin / cz);
        let k_slip0 = mf.long.slip_stiffness(fnomin);
        // MF 6.1 / 6.2 carry no lateral relaxation length of their own (PTY1, PTY2 are
        // MF 5.2's): it follows from the cornering stiffness and the overall lateral
        // stiffness, sigma_alpha = K_ya / C_Fy (Pacejka 2012 sec. 7.2; MFeval's
        // `calculateRelax`), here at the nominal load.
        let k_alpha0 = mf.cornering_stiffness(fnomin).abs();
        Ok(TyreParams {
            file: t.path.clone(),
            longvl,
            contact_blend,
            r0,
            width,
            mass,
            iyy,
            belt_mass,
            belt_iyy,
            gravity,
            fnomin,
            cz,
            vertical_damping,
            breff,
            dreff,
            freff,
            q_re0,
            q_v1,
            cx,
            cy,
            freq_long,
            freq_windup,
            damp_long,
            damp_windup,
            damp_residual,
            damp_vlow,
            vxlow,
            q_ra1,
            q_ra2,
            ellips_shift,
            ellips_length,
            ellips_height,
            ellips_order,
            ellips_max_step,
            ellips_nwidth: nw as usize,
            mf,
            d: Derived {
                c_b,
                k_b,
                c_theta,
                k_theta,
                c_rz,
                k_rz: damp_residual * c_rz,
                c_rx,
                k_rx: damp_residual * c_rx,
                a0,
                r_loaded0,
                // Tandem base = ELLIPS_SHIFT x contact length at the nominal load (Schmeitz
                // 2004: about 0.8 x 2a); cam semi-axes scale with the unloaded radius.
                l_s: ellips_shift * 2.0 * a0,
                a_e: ellips_length * r0,
                b_e: ellips_height * r0,
                c_e: ellips_order,
                k_slip0,
                // Pacejka 2012, sec. 7.2: sigma_kappa = C_Fkappa / C_Fx.
                sigma_point: k_slip0 / cx,
                k_alpha0,
                sigma_alpha: k_alpha0 / cy,
                k_vlow_x: damp_vlow * cx,
                k_vlow_y: damp_vlow * cy,
            },
        })
    }

    /// Weight of the low-speed damping at forward speed `v_x` [m/s]: 1/2 (1 + cos(pi |v_x| /
    /// VXLOW)) below VXLOW, 0 above (Pacejka 2012 sec. 7.2.2; smooth at both ends).
    pub fn low_speed_weight(&self, v_x: f64) -> f64 {
        let v = v_x.abs();
        if self.damp_vlow == 0.0 || v >= self.vxlow {
            0.0
        } else {
            0.5 * (1.0 + (std::f64::consts::PI * v / self.vxlow).cos())
        }
    }

    /// Slips with the low-speed damping (Pacejka 2012 sec. 7.2.2): at standstill the
    /// relaxation states are undamped springs, so below VXLOW the slips take a term
    /// proportional to the sliding velocity, kappa - k_Vlow V_sx / C_Fkappa and
    /// tan(alpha) + k_Vlow V_cy / |C_Falpha| (ISO: a positive alpha gives a negative F_y);
    /// in the linear range this adds -k_Vlow V_s to the force, and the Magic Formula still
    /// caps it at the friction limit. `kappa`, `tan_alpha` the undamped slips, `v_slip`
    /// the longitudinal sliding velocity V_c - V_r, `v_cx`, `v_cy` the contact point's
    /// velocity, `f_n` the load. Returns (kappa, alpha).
    pub fn damped_slips(
        &self,
        kappa: f64,
        tan_alpha: f64,
        v_slip: f64,
        v_cx: f64,
        v_cy: f64,
        f_n: f64,
    ) -> (f64, f64) {
        let w = self.low_speed_weight(v_cx);
        if w == 0.0 {
            return (kappa, tan_alpha.atan());
        }
        let kxk = self.mf.long.slip_stiffness(f_n);
        let kya = self.mf.cornering_stiffness(f_n).abs();
        // Without load the Magic Formula gives no force whatever the slip.
        let dk = if kxk > 0.0 {
            w * self.d.k_vlow_x * v_slip / kxk
        } else {
            0.0
        };
        let da = if kya > 0.0 {
            w * self.d.k_vlow_y * v_cy / kya
        } else {
            0.0
        };
        (kappa - dk, (tan_alpha + da).atan())
    }

    /// Effective rolling radius [m] at total deflection `rho` [m] and spin `omega` [rad/s]
    /// (MF 6.1 / Pacejka 2012 sec. 4.3.2: R_e = R_Omega - rho_Fz0 (D atan(B rho_d) +
    /// F rho_d), rho_d = rho / rho_Fz0, rho_Fz0 = FNOMIN / C_z, and the free radius growing
    /// with speed, R_Omega = r0 (Q_RE0 + Q_V1 (r0 Omega / LONGVL)^2)).
    pub fn rolling_radius(&self, rho: f64, omega: f64) -> f64 {
        let r_free = self.r0 * (self.q_re0 + self.q_v1 * (self.r0 * omega / self.longvl).powi(2));
        let rho_fz0 = self.fnomin / self.cz;
        let rd = rho.max(0.0) / rho_fz0;
        r_free - rho_fz0 * (self.dreff * (self.breff * rd).atan() + self.freff * rd)
    }

    /// Mass and spin inertia of the tyre that move with the rim (tyre minus belt): add them
    /// to the rim body of a multibody model that uses the rigid-ring tyre.
    pub fn rim_share(&self) -> (f64, f64) {
        (self.mass - self.belt_mass, self.iyy - self.belt_iyy)
    }
}

/// Half contact length at vertical deflection `rho`, the MF-Swift contact-length law
/// a = r0 (Q_RA2 rho/r0 + Q_RA1 sqrt(rho/r0)) (Pacejka 2012, ch. 9-10).
pub fn half_contact_length(r0: f64, q_ra1: f64, q_ra2: f64, rho: f64) -> f64 {
    let q = rho.max(0.0) / r0;
    r0 * (q_ra2 * q + q_ra1 * q.sqrt())
}
