//! Beam cross-sections and their properties in the section's local axes.
//!
//! Local axes of a beam: x along the element, y across (the "width" direction), z the
//! third ("height"). Iy = integral of z^2 dA (bending in the x-z plane), Iz = integral of
//! y^2 dA (bending in the x-y plane), J the Saint-Venant torsion constant. The
//! rotary inertia of torsion uses the polar moment Iy + Iz, not J. Shear areas
//! A_s = kappa A enter Timoshenko's shear flexibility; a section without them is
//! Euler-Bernoulli (shear-rigid).

use std::f64::consts::PI;

/// A cross-section shape with its dimensions (SI units).
#[derive(Clone, Debug, PartialEq)]
pub enum Section {
    /// Closed rectangular tube of uniform wall, sharp corners; width along y, height along z.
    RectangularHollow {
        /// Outer width along local y [m].
        width_m: f64,
        /// Outer height along local z [m].
        height_m: f64,
        /// Wall thickness [m].
        wall_m: f64,
    },
    /// Solid rectangle (flat bars, bracket plates).
    RectangularSolid {
        /// Width along local y [m].
        width_m: f64,
        /// Height along local z [m].
        height_m: f64,
    },
    /// Solid circular bar.
    RoundSolid {
        /// Diameter [m].
        diameter_m: f64,
    },
    /// Circular tube of uniform wall.
    RoundHollow {
        /// Outer diameter [m].
        outer_diameter_m: f64,
        /// Wall thickness [m].
        wall_m: f64,
    },
    /// Properties given directly; shear areas optional (absent: shear-rigid).
    General {
        /// Cross-section area [m^2].
        area_m2: f64,
        /// Second moment of area Iy = integral of z^2 dA [m^4].
        iy_m4: f64,
        /// Second moment of area Iz = integral of y^2 dA [m^4].
        iz_m4: f64,
        /// Saint-Venant torsion constant J [m^4].
        torsion_constant_m4: f64,
        /// Shear area for shear along local y [m^2]; `None`: shear-rigid in that direction.
        shear_area_y_m2: Option<f64>,
        /// Shear area for shear along local z [m^2]; `None`: shear-rigid in that direction.
        shear_area_z_m2: Option<f64>,
    },
}

/// Section properties used by the beam element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionProperties {
    /// Cross-section area [m^2].
    pub area_m2: f64,
    /// Second moment of area Iy = integral of z^2 dA (bending in the x-z plane) [m^4].
    pub iy_m4: f64,
    /// Second moment of area Iz = integral of y^2 dA (bending in the x-y plane) [m^4].
    pub iz_m4: f64,
    /// Saint-Venant torsion constant J [m^4].
    pub torsion_constant_m4: f64,
    /// Shear area for shear force along local y (bending in the x-y plane).
    pub shear_area_y_m2: Option<f64>,
    /// Shear area for shear force along local z (bending in the x-z plane).
    pub shear_area_z_m2: Option<f64>,
}

/// A dimension that makes the section impossible: which field, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionError {
    /// Name of the offending dimension, as in the file.
    pub field: &'static str,
    /// Why the value is refused.
    pub message: String,
}

fn positive(field: &'static str, v: f64) -> Result<(), SectionError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SectionError {
            field,
            message: format!("must be positive, got {v}"),
        })
    }
}

impl Section {
    /// The section's kind as written in the input files.
    pub fn shape_name(&self) -> &'static str {
        match self {
            Section::RectangularHollow { .. } => "rectangular_hollow",
            Section::RectangularSolid { .. } => "rectangular_solid",
            Section::RoundSolid { .. } => "round_solid",
            Section::RoundHollow { .. } => "round_hollow",
            Section::General { .. } => "general",
        }
    }

    /// Checks the dimensions: all positive, walls thinner than half the section.
    pub fn validate(&self) -> Result<(), SectionError> {
        match *self {
            Section::RectangularHollow {
                width_m,
                height_m,
                wall_m,
            } => {
                positive("width_m", width_m)?;
                positive("height_m", height_m)?;
                positive("wall_m", wall_m)?;
                if 2.0 * wall_m >= width_m.min(height_m) {
                    return Err(SectionError {
                        field: "wall_m",
                        message: format!(
                            "wall {wall_m} m leaves no hollow in a {width_m} x {height_m} m section"
                        ),
                    });
                }
                Ok(())
            }
            Section::RectangularSolid { width_m, height_m } => {
                positive("width_m", width_m)?;
                positive("height_m", height_m)
            }
            Section::RoundSolid { diameter_m } => positive("diameter_m", diameter_m),
            Section::RoundHollow {
                outer_diameter_m,
                wall_m,
            } => {
                positive("outer_diameter_m", outer_diameter_m)?;
                positive("wall_m", wall_m)?;
                if 2.0 * wall_m >= outer_diameter_m {
                    return Err(SectionError {
                        field: "wall_m",
                        message: format!(
                            "wall {wall_m} m leaves no hollow in a {outer_diameter_m} m tube"
                        ),
                    });
                }
                Ok(())
            }
            Section::General {
                area_m2,
                iy_m4,
                iz_m4,
                torsion_constant_m4,
                shear_area_y_m2,
                shear_area_z_m2,
            } => {
                positive("area_m2", area_m2)?;
                positive("iy_m4", iy_m4)?;
                positive("iz_m4", iz_m4)?;
                positive("torsion_constant_m4", torsion_constant_m4)?;
                if let Some(a) = shear_area_y_m2 {
                    positive("shear_area_y_m2", a)?;
                }
                if let Some(a) = shear_area_z_m2 {
                    positive("shear_area_z_m2", a)?;
                }
                Ok(())
            }
        }
    }

    /// Area, second moments, torsion constant and shear areas. `poissons_ratio` enters
    /// Cowper's shear coefficients of the solid and round sections.
    pub fn properties(&self, poissons_ratio: f64) -> SectionProperties {
        let nu = poissons_ratio;
        match *self {
            Section::RectangularHollow {
                width_m: b,
                height_m: h,
                wall_m: t,
            } => {
                let (bi, hi) = (b - 2.0 * t, h - 2.0 * t);
                let area = b * h - bi * hi;
                // Bredt-Batho thin-walled closed section: J = 4 Am^2 t / pm, Am the area
                // enclosed by the wall mid-line (b - t)(h - t), pm its perimeter
                // 2 (b + h - 2t) (Roark's Formulas for Stress and Strain, 7th ed.,
                // table 10.7 case 16; Timoshenko & Goodier, Theory of Elasticity, 3rd ed.,
                // sec. 115).
                let am = (b - t) * (h - t);
                let pm = 2.0 * (b + h - 2.0 * t);
                SectionProperties {
                    area_m2: area,
                    iy_m4: (b * h.powi(3) - bi * hi.powi(3)) / 12.0,
                    iz_m4: (h * b.powi(3) - hi * bi.powi(3)) / 12.0,
                    torsion_constant_m4: 4.0 * am * am * t / pm,
                    // Shear carried by the walls parallel to the force: the area share of
                    // EN 1993-1-1 6.2.6(3)(a) for hollow sections of uniform thickness,
                    // A_v = A h / (b + h) for a load parallel to the depth h.
                    shear_area_y_m2: Some(area * b / (b + h)),
                    shear_area_z_m2: Some(area * h / (b + h)),
                }
            }
            Section::RectangularSolid {
                width_m: b,
                height_m: h,
            } => {
                let area = b * h;
                // Saint-Venant torsion of a solid rectangle, Roark table 10.7 case 4:
                // K = a c^3 (16/3 - 3.36 (c/a) (1 - c^4 / (12 a^4))), a >= c half-sides.
                let (a, c) = (0.5 * b.max(h), 0.5 * b.min(h));
                let j = a
                    * c.powi(3)
                    * (16.0 / 3.0 - 3.36 * (c / a) * (1.0 - c.powi(4) / (12.0 * a.powi(4))));
                // Cowper (1966), J. Appl. Mech. 33, 335-340, table 1: rectangle.
                let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
                SectionProperties {
                    area_m2: area,
                    iy_m4: b * h.powi(3) / 12.0,
                    iz_m4: h * b.powi(3) / 12.0,
                    torsion_constant_m4: j,
                    shear_area_y_m2: Some(kappa * area),
                    shear_area_z_m2: Some(kappa * area),
                }
            }
            Section::RoundSolid { diameter_m: d } => {
                let area = PI * d * d / 4.0;
                let i = PI * d.powi(4) / 64.0;
                // Cowper (1966) table 1: solid circle.
                let kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
                SectionProperties {
                    area_m2: area,
                    iy_m4: i,
                    iz_m4: i,
                    torsion_constant_m4: 2.0 * i,
                    shear_area_y_m2: Some(kappa * area),
                    shear_area_z_m2: Some(kappa * area),
                }
            }
            Section::RoundHollow {
                outer_diameter_m: d,
                wall_m: t,
            } => {
                let di = d - 2.0 * t;
                let area = PI * (d * d - di * di) / 4.0;
                let i = PI * (d.powi(4) - di.powi(4)) / 64.0;
                // Cowper (1966) table 1: hollow circle, m = inner / outer radius.
                let m2 = (di / d).powi(2);
                let kappa = 6.0 * (1.0 + nu) * (1.0 + m2).powi(2)
                    / ((7.0 + 6.0 * nu) * (1.0 + m2).powi(2) + (20.0 + 12.0 * nu) * m2);
                SectionProperties {
                    area_m2: area,
                    iy_m4: i,
                    iz_m4: i,
                    torsion_constant_m4: 2.0 * i,
                    shear_area_y_m2: Some(kappa * area),
                    shear_area_z_m2: Some(kappa * area),
                }
            }
            Section::General {
                area_m2,
                iy_m4,
                iz_m4,
                torsion_constant_m4,
                shear_area_y_m2,
                shear_area_z_m2,
            } => SectionProperties {
                area_m2,
                iy_m4,
                iz_m4,
                torsion_constant_m4,
                shear_area_y_m2,
                shear_area_z_m2,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    #[test]
    fn thin_square_tube_torsion_matches_bredt_thin_limit() {
        // Thin square tube, side a (mid-line), wall t: J -> a^3 t (Bredt: 4 a^4 t / 4a).
        let (a, t) = (0.1, 1e-4);
        let s = Section::RectangularHollow {
            width_m: a + t,
            height_m: a + t,
            wall_m: t,
        };
        let p = s.properties(0.3);
        assert!(close(p.torsion_constant_m4, a.powi(3) * t, 1e-9));
        // Thin-walled second moment: 2/3 a^3 t.
        assert!(close(p.iy_m4, 2.0 / 3.0 * a.powi(3) * t, 1e-2));
    }

    #[test]
    fn round_sections_are_exact() {
        let d = 0.03;
        let p = Section::RoundSolid { diameter_m: d }.properties(0.3);
        assert!(close(p.torsion_constant_m4, PI * d.powi(4) / 32.0, 1e-14));
        // A tube of zero wall would be the solid bar; check the thin-walled shear
        // coefficient limit 2 (1 + nu) / (4 + 3 nu) instead (Cowper 1966).
        let p = Section::RoundHollow {
            outer_diameter_m: 0.1,
            wall_m: 1e-6,
        }
        .properties(0.3);
        assert!(close(
            p.shear_area_y_m2.unwrap() / p.area_m2,
            2.0 * 1.3 / 4.9,
            1e-4
        ));
    }

    #[test]
    fn square_bar_torsion_matches_saint_venant() {
        // Saint-Venant square, side s: J = 0.1406 s^4 (Timoshenko & Goodier sec. 109).
        let s = 0.02;
        let p = Section::RectangularSolid {
            width_m: s,
            height_m: s,
        }
        .properties(0.3);
        assert!(close(p.torsion_constant_m4, 0.1406 * s.powi(4), 2e-3));
        // Thin strip b x t: J = b t^3 / 3 (1 - 0.630 t / b) (Timoshenko & Goodier
        // sec. 109, the end correction of the membrane analogy).
        let (b, t) = (0.6, 0.006);
        let p = Section::RectangularSolid {
            width_m: t,
            height_m: b,
        }
        .properties(0.3);
        let want = b * t.powi(3) / 3.0 * (1.0 - 0.630 * t / b);
        assert!(close(p.torsion_constant_m4, want, 1e-4));
    }

    #[test]
    fn walls_must_leave_a_hollow() {
        let s = Section::RectangularHollow {
            width_m: 0.06,
            height_m: 0.04,
            wall_m: 0.02,
        };
        assert_eq!(s.validate().unwrap_err().field, "wall_m");
        let s = Section::RectangularHollow {
            width_m: 0.06,
            height_m: 0.04,
            wall_m: 0.0,
        };
        assert_eq!(s.validate().unwrap_err().field, "wall_m");
    }
}
