//! Isotropic linear elastic material in plane stress (with thickness) or plane strain,
//! and the 3D isotropic law of solid parts ([`d_solid`], [`von_mises_3d`],
//! [`principal_stresses_3d`]; Voigt order [`super::solid::VOIGT`]).

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

    /// The 3D isotropic D of this material's E and ν ([`d_solid`]; the plane kind and
    /// thickness, which are 2D notions, play no part).
    pub fn d_solid(&self) -> [[f64; 6]; 6] {
        d_solid(self.young, self.poisson)
    }

    /// E·t: the in-plane stiffness scale of a part (force per length), used for the
    /// default coupling penalty.
    pub fn stiffness_scale(&self) -> f64 {
        self.young * self.thickness
    }
}

/// The 3D isotropic constitutive matrix D (6×6) of Young's modulus E and Poisson's
/// ratio ν, Voigt order `[xx, yy, zz, xy, yz, zx]` with engineering shear strains:
///
/// `D = E/((1+ν)(1−2ν)) [[1−ν, ν, ν, 0, 0, 0], [ν, 1−ν, ν, …], [ν, ν, 1−ν, …],
/// [0, 0, 0, (1−2ν)/2, 0, 0], [… (1−2ν)/2 …], [… (1−2ν)/2]]`,
///
/// i.e. λ = Eν/((1+ν)(1−2ν)) off the normal diagonal, λ + 2G on it and G = E/(2(1+ν))
/// on the shear diagonal. Its (xx, yy, xy) block is the plane-strain D.
pub fn d_solid(young: f64, poisson: f64) -> [[f64; 6]; 6] {
    let (e, nu) = (young, poisson);
    let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let (a, b, g) = (c * (1.0 - nu), c * nu, c * (1.0 - 2.0 * nu) / 2.0);
    [
        [a, b, b, 0.0, 0.0, 0.0],
        [b, a, b, 0.0, 0.0, 0.0],
        [b, b, a, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, g, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, g, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, g],
    ]
}

/// Von Mises equivalent stress of a 3D stress `s` (Voigt order [xx, yy, zz, xy, yz, zx]):
/// `√(½ [(σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²] + 3 (σxy² + σyz² + σzx²))`.
pub fn von_mises_3d(s: &[f64; 6]) -> f64 {
    (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2))
        + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// Principal stresses of a 3D stress `s` (Voigt order [xx, yy, zz, xy, yz, zx]),
/// largest first: the eigenvalues of the symmetric tensor in closed form
/// (the trigonometric solution of the characteristic cubic). With the mean
/// `q = tr σ / 3`, `p = √(tr (σ − qI)² / 6)` and `r = det((σ − qI)/p) / 2` clamped
/// to [−1, 1], `φ = acos(r) / 3`: `σ₁ = q + 2p cos φ`, `σ₃ = q + 2p cos(φ + 2π/3)`,
/// `σ₂ = 3q − σ₁ − σ₃`. An isotropic tensor (p = 0) gives `q` three times. Accurate
/// to round-off relative to the stress's size, except that close principal values
/// lose up to half the digits of their difference (the cubic's double root).
pub fn principal_stresses_3d(s: &[f64; 6]) -> [f64; 3] {
    let q = (s[0] + s[1] + s[2]) / 3.0;
    let off = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    let p2 = (s[0] - q).powi(2) + (s[1] - q).powi(2) + (s[2] - q).powi(2) + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    if p.is_nan() || p <= 0.0 {
        return [q; 3];
    }
    let m = [
        [(s[0] - q) / p, s[3] / p, s[5] / p],
        [s[3] / p, (s[1] - q) / p, s[4] / p],
        [s[5] / p, s[4] / p, (s[2] - q) / p],
    ];
    let r = (0.5 * super::solid::det3(&m)).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let s1 = q + 2.0 * p * phi.cos();
    let s3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    let mut out = [s1, 3.0 * q - s1 - s3, s3];
    // Near a double root σ₂ may cross its neighbour by round-off.
    out.sort_by(|a, b| b.total_cmp(a));
    out
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

    /// The 3D D is the inverse of the isotropic compliance written from E and ν
    /// (ε = [σxx − ν(σyy + σzz)]/E …, γ = 2(1+ν)τ/E), and its (xx, yy, xy) block is
    /// the plane-strain D.
    #[test]
    fn d_solid_inverts_the_compliance() {
        let (e, nu) = (210000.0, 0.3);
        let d = d_solid(e, nu);
        let sigma = [120.0, -35.0, 60.0, 25.0, -10.0, 7.5];
        let eps = [
            (sigma[0] - nu * (sigma[1] + sigma[2])) / e,
            (sigma[1] - nu * (sigma[2] + sigma[0])) / e,
            (sigma[2] - nu * (sigma[0] + sigma[1])) / e,
            2.0 * (1.0 + nu) * sigma[3] / e,
            2.0 * (1.0 + nu) * sigma[4] / e,
            2.0 * (1.0 + nu) * sigma[5] / e,
        ];
        let back = crate::fem::solid::mul6(&d, &eps);
        for i in 0..6 {
            assert!((back[i] - sigma[i]).abs() < 1e-12 * 120.0, "{i}: {back:?}");
        }
        let plane = Material::new(e, nu, PlaneKind::Strain, 1.0, "p")
            .unwrap()
            .d_matrix();
        let idx = [0, 1, 3];
        for (r, &i) in idx.iter().enumerate() {
            for (c, &j) in idx.iter().enumerate() {
                assert!((plane[r][c] - d[i][j]).abs() < 1e-9, "{i} {j}");
            }
        }
        assert!(crate::fem::solid::testing::is_exactly_symmetric(&d));
    }

    /// Von Mises in 3D: σ for uniaxial σ, √3 τ for pure shear in any plane, zero
    /// for a hydrostatic stress; equal to the plane formula with σzz.
    #[test]
    fn von_mises_3d_closed_forms() {
        assert!((von_mises_3d(&[200.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 200.0).abs() < 1e-12);
        assert!((von_mises_3d(&[0.0, 0.0, -200.0, 0.0, 0.0, 0.0]) - 200.0).abs() < 1e-12);
        for k in 3..6 {
            let mut s = [0.0; 6];
            s[k] = 10.0;
            assert!((von_mises_3d(&s) - 10.0 * 3f64.sqrt()).abs() < 1e-12);
        }
        assert!(von_mises_3d(&[-5.0, -5.0, -5.0, 0.0, 0.0, 0.0]).abs() < 1e-12);
        let m = Material::new(200.0, 0.25, PlaneKind::Strain, 1.0, "p").unwrap();
        let s2 = [30.0, -12.0, 8.0];
        let s3 = [30.0, -12.0, m.sigma_zz(30.0, -12.0), 8.0, 0.0, 0.0];
        assert!((m.von_mises(s2) - von_mises_3d(&s3)).abs() < 1e-12);
    }

    /// The closed-form principal stresses are the eigenvalues of the tensor (faer's
    /// symmetric eigensolver), largest first, for a general tensor, one with a
    /// double eigenvalue and an isotropic one; von Mises from them equals von Mises
    /// from the components.
    #[test]
    fn principal_stresses_are_the_eigenvalues() {
        use faer::{Mat, Side};
        let cases = [
            [120.0, -35.0, 60.0, 25.0, -10.0, 7.5],
            [1.0, 1.0, 4.0, 0.0, 0.0, 0.0],
            [3.0, 0.0, 0.0, 2.0, 0.0, 0.0],
            [-7.0, -7.0, -7.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ];
        for s in cases {
            let t = [[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]];
            let m = Mat::<f64>::from_fn(3, 3, |i, j| t[i][j]);
            let eig = m.self_adjoint_eigen(Side::Lower).unwrap();
            let mut want: Vec<f64> = (0..3).map(|i| eig.S()[i]).collect();
            want.sort_by(|a, b| b.total_cmp(a));
            let got = principal_stresses_3d(&s);
            let scale = s.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
            for i in 0..3 {
                assert!((got[i] - want[i]).abs() < 1e-7 * scale, "{s:?}: {got:?} vs {want:?}");
            }
            assert!(got[0] >= got[1] && got[1] >= got[2]);
            let p = [got[0], got[1], got[2], 0.0, 0.0, 0.0];
            assert!((von_mises_3d(&p) - von_mises_3d(&s)).abs() < 1e-7 * scale);
        }
    }
}
