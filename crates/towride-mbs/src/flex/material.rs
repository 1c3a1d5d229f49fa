//! Isotropic linear-elastic materials of beam models.

/// An isotropic linear-elastic material (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub youngs_modulus_pa: f64,
    /// G; from the file, or E / (2 (1 + nu)) when only Poisson's ratio is given.
    pub shear_modulus_pa: f64,
    /// nu; also enters Cowper's shear coefficients of solid and round sections.
    pub poissons_ratio: f64,
    pub density_kg_m3: f64,
}

impl Material {
    /// Builds a material; G defaults to the isotropic relation G = E / (2 (1 + nu)).
    pub fn new(
        name: &str,
        youngs_modulus_pa: f64,
        poissons_ratio: f64,
        shear_modulus_pa: Option<f64>,
        density_kg_m3: f64,
    ) -> Material {
        Material {
            name: name.to_string(),
            youngs_modulus_pa,
            shear_modulus_pa: shear_modulus_pa
                .unwrap_or(youngs_modulus_pa / (2.0 * (1.0 + poissons_ratio))),
            poissons_ratio,
            density_kg_m3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isotropic_shear_modulus() {
        let m = Material::new("steel", 210e9, 0.3, None, 7850.0);
        assert!((m.shear_modulus_pa - 210e9 / 2.6).abs() < 1.0);
        let m = Material::new("given", 210e9, 0.3, Some(80e9), 7850.0);
        assert_eq!(m.shear_modulus_pa, 80e9);
    }
}
