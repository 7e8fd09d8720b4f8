//! Isotropic linear elastic material in plane stress (with thickness) or plane strain.

use crate::error::{Error, Result};

/// The 2D idealisation of the out-of-plane direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlaneKind {
    /// σzz = 0; the part has a thickness `t`.
    Stress,
    /// εzz = 0; stiffness is per unit thickness times `t` (usually 1).
    Strain,
    /// A solid of revolution about the y axis: x = r ≥ 0, y = z, the hoop strain
    /// u_r / r and 2πr in every integral (`fem::axisymmetric`); forces are
    /// totals over the ring, and the thickness must be 1 (it has no meaning).
    Axisymmetric,
}

/// An isotropic linear elastic material together with the 2D idealisation and the
/// out-of-plane thickness of the part that uses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Plane stress or plane strain.
    pub plane: PlaneKind,
    /// Thickness t (out of plane).
    pub thickness: f64,
}

impl Material {
    /// A validated material: E > 0, −1 < ν < 0.5, t > 0, all finite. `owner` names
    /// the part in the error message.
    pub fn new(
        young: f64,
        poisson: f64,
        plane: PlaneKind,
        thickness: f64,
        owner: &str,
    ) -> Result<Self> {
        let bad = |key: &'static str, message: String| {
            Err(Error::Material {
                part: owner.to_string(),
                key,
                message,
            })
        };
        if !(young.is_finite() && young > 0.0) {
            return bad(
                "E",
                format!("Young's modulus E = {young} must be positive and finite"),
            );
        }
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return bad(
                "nu",
                format!("Poisson's ratio nu = {poisson} must lie in (-1, 0.5)"),
            );
        }
        if !(thickness.is_finite() && thickness > 0.0) {
            return bad(
                "thickness",
                format!("thickness = {thickness} must be positive and finite"),
            );
        }
        if plane == PlaneKind::Axisymmetric && thickness != 1.0 {
            return bad(
                "thickness",
                format!(
                    "thickness = {thickness} has no meaning in an axisymmetric model (forces and stiffnesses are totals over the ring): leave it out"
                ),
            );
        }
        Ok(Material {
            young,
            poisson,
            plane,
            thickness,
        })
    }

    /// The constitutive matrix D (Voigt order xx, yy, xy with engineering shear strain):
    ///
    /// plane stress: `E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]`;
    /// plane strain: `E/((1+ν)(1−2ν)) [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]`;
    /// axisymmetric: the (rr, zz, rz) block of [`Material::d_axisymmetric`], which is
    /// plane strain's (the hoop row and column are that matrix's own).
    pub fn d_matrix(&self) -> [[f64; 3]; 3] {
        let (e, nu) = (self.young, self.poisson);
        match self.plane {
            PlaneKind::Stress => {
                let c = e / (1.0 - nu * nu);
                [
                    [c, c * nu, 0.0],
                    [c * nu, c, 0.0],
                    [0.0, 0.0, c * (1.0 - nu) / 2.0],
                ]
            }
            PlaneKind::Strain | PlaneKind::Axisymmetric => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                [
                    [c * (1.0 - nu), c * nu, 0.0],
                    [c * nu, c * (1.0 - nu), 0.0],
                    [0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0],
                ]
            }
        }
    }

    /// The isotropic 4×4 D of an axisymmetric part (whatever its `plane`), order
    /// (rr, zz, rz, θθ), engineering shear strain:
    /// `E/((1+ν)(1−2ν)) [[1−ν, ν, 0, ν], [ν, 1−ν, 0, ν], [0, 0, (1−2ν)/2, 0], [ν, ν, 0, 1−ν]]`.
    pub fn d_axisymmetric(&self) -> [[f64; 4]; 4] {
        let (e, nu) = (self.young, self.poisson);
        let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let (a, b, s) = (c * (1.0 - nu), c * nu, c * (1.0 - 2.0 * nu) / 2.0);
        [
            [a, b, 0.0, b],
            [b, a, 0.0, b],
            [0.0, 0.0, s, 0.0],
            [b, b, 0.0, a],
        ]
    }

    /// Whether the part is axisymmetric.
    pub fn is_axisymmetric(&self) -> bool {
        self.plane == PlaneKind::Axisymmetric
    }

    /// The out-of-plane normal stress σzz for in-plane stresses (zero in plane stress,
    /// ν (σxx + σyy) in plane strain). In an axisymmetric part the out-of-plane
    /// stress is σθθ, which the stresses alone do not give: it is recovered with
    /// them ([`super::recovery::PartStress::hoop`]); NaN here.
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        match self.plane {
            PlaneKind::Stress => 0.0,
            PlaneKind::Strain => self.poisson * (sxx + syy),
            PlaneKind::Axisymmetric => f64::NAN,
        }
    }

    /// Von Mises equivalent stress of (σxx, σyy, σxy), including σzz (an
    /// axisymmetric part's needs its σθθ: [`Material::von_mises_with`]).
    pub fn von_mises(&self, s: [f64; 3]) -> f64 {
        let szz = self.sigma_zz(s[0], s[1]);
        (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - szz).powi(2) + (szz - s[0]).powi(2))
            + 3.0 * s[2] * s[2])
            .sqrt()
    }

    /// Von Mises equivalent stress of (σxx, σyy, σxy) with the out-of-plane
    /// stress `out`: σθθ in an axisymmetric part; elsewhere [`Material::von_mises`].
    pub fn von_mises_with(&self, s: [f64; 3], out: Option<f64>) -> f64 {
        match out {
            Some(h) if self.is_axisymmetric() => (0.5
                * ((s[0] - s[1]).powi(2) + (s[1] - h).powi(2) + (h - s[0]).powi(2))
                + 3.0 * s[2] * s[2])
                .sqrt(),
            _ => self.von_mises(s),
        }
    }

    /// E·t: the in-plane stiffness scale of a part (force per length), used for the
    /// default coupling penalty.
    pub fn stiffness_scale(&self) -> f64 {
        self.young * self.thickness
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plane-stress D maps a uniaxial strain state to uniaxial stress (σyy = 0 when
    /// εyy = −ν εxx), and plane-strain D gives σzz from ν(σxx+σyy).
    #[test]
    fn d_matrix_uniaxial_states() {
        let m = Material::new(200.0, 0.25, PlaneKind::Stress, 1.0, "p").unwrap();
        let d = m.d_matrix();
        let eps = [1.0, -0.25, 0.0];
        let s: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| d[i][j] * eps[j]).sum())
            .collect();
        assert!((s[0] - 200.0).abs() < 1e-12 && s[1].abs() < 1e-12);
        assert!((m.von_mises([s[0], s[1], s[2]]) - 200.0).abs() < 1e-12);
        let p = Material::new(200.0, 0.25, PlaneKind::Strain, 1.0, "p").unwrap();
        assert_eq!(p.sigma_zz(1.0, 2.0), 0.75);
    }

    /// Invalid constants are errors naming the part and the constant.
    #[test]
    fn invalid_constants_are_errors() {
        let e = Material::new(-1.0, 0.3, PlaneKind::Stress, 1.0, "base").unwrap_err();
        assert!(e.to_string().contains("base") && e.to_string().contains("Young"));
        assert!(Material::new(1.0, 0.5, PlaneKind::Strain, 1.0, "b").is_err());
        assert!(Material::new(1.0, 0.3, PlaneKind::Stress, 0.0, "b").is_err());
    }
}
