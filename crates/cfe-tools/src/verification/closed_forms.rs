//! The closed forms of the contact validation cases (plane strain), each a small
//! pure function checked by unit tests against hand values or the equations they
//! come from, and the extraction of a contact half-width and peak pressure from
//! a discrete pressure profile.
//!
//! **Hertz** (K. L. Johnson, *Contact Mechanics*, Cambridge 1985, §4.2 and §5.6):
//! two cylinders (here a cylinder of radius R on a flat, R₂ = ∞) pressed by a
//! force P′ per unit length, in plane strain:
//!
//! ```text
//!   1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂
//!   a  = √(4 P′ R / (π E*))          contact half-width
//!   p₀ = 2 P′ / (π a)  = √(P′ E* / (π R))   peak pressure
//!   p(x) = p₀ √(1 − x²/a²),  |x| ≤ a     (∫ p dx = π a p₀ / 2 = P′)
//! ```
//!
//! **Cattaneo–Mindlin** for cylinders (Johnson §7.1): after P′, a tangential force
//! Q < μ P′, with elastically similar bodies (Dundurs' β = 0, so that the shear
//! does not change the pressure): a central stick zone |x| < c and slip zones
//! c < |x| < a,
//!
//! ```text
//!   c / a = √(1 − Q / (μ P′))
//!   q(x) = μ p₀ √(1 − x²/a²) − μ p₀ (c/a) √(1 − x²/c²)   |x| < c   (stick)
//!   q(x) = μ p₀ √(1 − x²/a²)                              c ≤ |x| ≤ a (slip)
//! ```
//!
//! (∫ q dx = μ π p₀ (a² − c²) / (2a) = μ P′ (1 − c²/a²) = Q.)
//!
//! **Shrink fit** (Lamé; S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*,
//! 1970, §28): a hollow shaft a_s ≤ r ≤ b + δ in a ring b ≤ r ≤ c, radial
//! interference δ, plane strain, small strains (so both meet at r ≈ b). Lamé's
//! cylinder a₀ ≤ r ≤ a₁ under inner pressure p_i and outer pressure p_o:
//! `σ_r = A − B/r²`, `u_r = (1 + ν)/E · [(1 − 2ν) A r + B/r]` with
//! `A = (p_i a₀² − p_o a₁²)/(a₁² − a₀²)`, `B = (p_i − p_o) a₀² a₁²/(a₁² − a₀²)`.
//! The ring (p_i = p, p_o = 0) opens by
//! `u_ring(b) = p b (1 + ν_r)/E_r · [(1 − 2ν_r) b² + c²]/(c² − b²)`;
//! the shaft (p_i = 0, p_o = p) closes by
//! `u_shaft(b) = −p b (1 + ν_s)/E_s · [(1 − 2ν_s) b² + a_s²]/(b² − a_s²)`
//! (a_s = 0: the solid shaft's `−p b (1 + ν_s)(1 − 2ν_s)/E_s`, from σ_r = σ_θ = −p,
//! ε_z = 0). The surfaces meet when `u_ring(b) − u_shaft(b) = δ`:
//!
//! ```text
//!   p = δ / ( b (1 + ν_r)/E_r · [(1 − 2ν_r) b² + c²]/(c² − b²)
//!           + b (1 + ν_s)/E_s · [(1 − 2ν_s) b² + a_s²]/(b² − a_s²) )
//! ```

/// The plane-strain contact modulus E* of two bodies (E₁, ν₁) and (E₂, ν₂).
pub fn contact_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Hertz's contact half-width a = √(4 P′ R / (π E*)) of a cylinder of radius `r`
/// on a flat under `p` per unit length.
pub fn hertz_half_width(p: f64, r: f64, e_star: f64) -> f64 {
    (4.0 * p * r / (std::f64::consts::PI * e_star)).sqrt()
}

/// Hertz's peak pressure p₀ = 2 P′ / (π a).
pub fn hertz_peak(p: f64, a: f64) -> f64 {
    2.0 * p / (std::f64::consts::PI * a)
}

/// Hertz's pressure p₀ √(1 − x²/a²) (0 outside the contact).
pub fn hertz_pressure(x: f64, a: f64, p0: f64) -> f64 {
    p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt()
}

/// Cattaneo–Mindlin's stick half-width c = a √(1 − Q/(μ P′)).
pub fn stick_half_width(a: f64, q: f64, mu: f64, p: f64) -> f64 {
    a * (1.0 - q / (mu * p)).max(0.0).sqrt()
}

/// Cattaneo–Mindlin's shear traction at x (stick zone half-width `c`).
pub fn mindlin_shear(x: f64, a: f64, c: f64, mu: f64, p0: f64) -> f64 {
    let slip = mu * hertz_pressure(x, a, p0);
    if x.abs() < c {
        slip - mu * p0 * (c / a) * (1.0 - (x / c).powi(2)).sqrt()
    } else {
        slip
    }
}

/// The shrink-fit pressure of a shaft a_s ≤ r ≤ b (E_s, ν_s; a_s = 0: solid) in a
/// ring b ≤ r ≤ c (E_r, ν_r) with radial interference δ, plane strain (module doc).
pub fn shrink_fit_pressure(
    delta: f64,
    [a_s, b, c]: [f64; 3],
    shaft: (f64, f64),
    ring: (f64, f64),
) -> f64 {
    let (es, nus) = shaft;
    let (er, nur) = ring;
    let ring_compliance =
        b * (1.0 + nur) / er * ((1.0 - 2.0 * nur) * b * b + c * c) / (c * c - b * b);
    let shaft_compliance =
        b * (1.0 + nus) / es * ((1.0 - 2.0 * nus) * b * b + a_s * a_s) / (b * b - a_s * a_s);
    delta / (ring_compliance + shaft_compliance)
}

/// Lamé's radial displacement of the ring b ≤ r ≤ c under inner pressure `p`
/// (plane strain), at radius r.
pub fn ring_ur(p: f64, b: f64, c: f64, ring: (f64, f64), r: f64) -> f64 {
    let (er, nur) = ring;
    let ca = p * b * b / (c * c - b * b);
    let cb = p * b * b * c * c / (c * c - b * b);
    (1.0 + nur) / er * ((1.0 - 2.0 * nur) * ca * r + cb / r)
}

/// A contact half-width and peak pressure from a discrete pressure profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fitted {
    /// Half-width a.
    pub a: f64,
    /// Peak pressure p₀.
    pub p0: f64,
    /// Centre of the fitted ellipse (its x offset).
    pub x0: f64,
}

/// Fits Hertz's elliptic profile to the points (x, p) with p > 0: since
/// p² = p₀² − (p₀²/a²)(x − x₀)² is a quadratic in x, a least-squares parabola
/// p² ≈ α + β x + γ x² gives γ = −p₀²/a², x₀ = −β/(2γ), p₀² = α − β²/(4γ), and
/// a = √(−p₀²/γ). Every point carrying pressure counts except the outermost on
/// each side (when there are more than 10): the outermost pair's tributary length
/// straddles the edge of contact, so its pressure (force / tributary length)
/// underestimates the local one; on coarser profiles every point is needed. `None` with fewer than 3 points or a parabola
/// that does not open downwards.
pub fn fit_ellipse(points: &[(f64, f64)]) -> Option<Fitted> {
    let mut pts: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.1 > 0.0).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    if pts.len() > 10 {
        pts = pts[1..pts.len() - 1].to_vec();
    }
    if pts.len() < 3 {
        return None;
    }
    // Normal equations of the least-squares fit of p² to [1, x, x²], x centred
    // and scaled for conditioning.
    let n = pts.len() as f64;
    let xm = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let s = pts
        .iter()
        .map(|p| (p.0 - xm).abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for &(x, p) in &pts {
        let t = (x - xm) / s;
        let phi = [1.0, t, t * t];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += phi[i] * phi[j];
            }
            r[i] += phi[i] * p * p;
        }
    }
    let [al, be, ga] = solve3(m, r)?;
    if ga >= 0.0 {
        return None;
    }
    // Back to x: p² = al + be t + ga t², t = (x − xm)/s.
    let t0 = -be / (2.0 * ga);
    let p0sq = al - be * be / (4.0 * ga);
    if p0sq <= 0.0 {
        return None;
    }
    Some(Fitted {
        a: (-p0sq / ga).sqrt() * s,
        p0: p0sq.sqrt(),
        x0: xm + t0 * s,
    })
}

/// Solves a 3 × 3 system by Cramer's rule (`None` when singular).
fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    if d.abs() < 1e-300 {
        return None;
    }
    Some(std::array::from_fn(|k| {
        let mut a = m;
        for i in 0..3 {
            a[i][k] = r[i];
        }
        det(a) / d
    }))
}

/// The outermost points carrying pressure on each side, widened by half the
/// distance to the next point outside (the edge of a discrete contact zone:
/// the pair's tributary length reaches half-way to its open neighbour); the
/// half-width is half the distance between the two edges. `points` are
/// (x, p), open points p = 0; `None` when no point carries pressure.
pub fn edge_half_width(points: &[(f64, f64)]) -> Option<f64> {
    let mut pts = points.to_vec();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = pts.iter().position(|p| p.1 > 0.0)?;
    let last = pts.iter().rposition(|p| p.1 > 0.0)?;
    let lo = if first > 0 {
        (pts[first].0 + pts[first - 1].0) / 2.0
    } else {
        pts[first].0
    };
    let hi = if last + 1 < pts.len() {
        (pts[last].0 + pts[last + 1].0) / 2.0
    } else {
        pts[last].0
    };
    Some((hi - lo) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Hertz: P′ = ∫ p dx (π a p₀ / 2), p₀ = √(P′E*/(πR)), and E* of equal
    /// materials is E / (2 (1 − ν²)).
    #[test]
    fn hertz_balances_the_load() {
        let es = contact_modulus(210000.0, 0.3, 70000.0, 0.33);
        let (p, r) = (4000.0, 10.0);
        let a = hertz_half_width(p, r, es);
        let p0 = hertz_peak(p, a);
        assert!((PI * a * p0 / 2.0 - p).abs() < 1e-9 * p);
        assert!((p0 - (p * es / (PI * r)).sqrt()).abs() < 1e-9 * p0);
        // Numerical ∫ p dx by the midpoint rule.
        let n = 200000;
        let integral: f64 = (0..n)
            .map(|i| {
                let x = -a + (i as f64 + 0.5) * 2.0 * a / n as f64;
                hertz_pressure(x, a, p0) * 2.0 * a / n as f64
            })
            .sum();
        assert!((integral - p).abs() < 1e-5 * p);
        let same = contact_modulus(200.0, 0.25, 200.0, 0.25);
        assert!((same - 200.0 / (2.0 * (1.0 - 0.0625))).abs() < 1e-12);
    }

    /// Cattaneo–Mindlin: ∫ q dx = Q, |q| ≤ μ p everywhere, q = μ p in the slip zone.
    #[test]
    fn mindlin_carries_q() {
        let (a, p0, mu) = (1.0, 1000.0, 0.3);
        let p = PI * a * p0 / 2.0;
        let q = 0.6 * mu * p;
        let c = stick_half_width(a, q, mu, p);
        assert!((c - a * 0.4f64.sqrt()).abs() < 1e-12);
        let n = 200000;
        let dx = 2.0 * a / n as f64;
        let mut integral = 0.0;
        for i in 0..n {
            let x = -a + (i as f64 + 0.5) * dx;
            let s = mindlin_shear(x, a, c, mu, p0);
            assert!(s <= mu * hertz_pressure(x, a, p0) + 1e-9);
            assert!(s >= 0.0);
            integral += s * dx;
        }
        assert!((integral - q).abs() < 1e-4 * q, "{integral} vs {q}");
        assert_eq!(
            mindlin_shear(0.9, a, c, mu, p0),
            mu * hertz_pressure(0.9, a, p0)
        );
    }

    /// Shrink fit: the ring's u_r(b) minus the solid shaft's is δ at the
    /// closed-form pressure; a rigid shaft (E_s → ∞) leaves the ring's compliance
    /// alone; the hollow shaft's u_r(b) is Lamé's with outer pressure (checked
    /// through its strain: σ_r(b) = −p, σ_r(a_s) = 0 and u_r = r ε_θ).
    #[test]
    fn shrink_fit_closes_the_interference() {
        let (b, c, delta) = (10.0, 20.0, 0.01);
        let shaft = (210000.0, 0.3);
        let ring = (70000.0, 0.33);
        let p = shrink_fit_pressure(delta, [0.0, b, c], shaft, ring);
        let shaft_u = -p * b * (1.0 + shaft.1) * (1.0 - 2.0 * shaft.1) / shaft.0;
        assert!((ring_ur(p, b, c, ring, b) - shaft_u - delta).abs() < 1e-12 * delta);
        let rigid = shrink_fit_pressure(delta, [0.0, b, c], (1e30, 0.3), ring);
        assert!((ring_ur(rigid, b, c, ring, b) - delta).abs() < 1e-12 * delta);
        // Hollow shaft a_s = 5: A = −p b²/(b² − a_s²), B = −p a_s² b²/(b² − a_s²).
        let a_s = 5.0;
        let ph = shrink_fit_pressure(delta, [a_s, b, c], shaft, ring);
        let (ca, cb) = (
            -ph * b * b / (b * b - a_s * a_s),
            -ph * a_s * a_s * b * b / (b * b - a_s * a_s),
        );
        assert!((ca - cb / (b * b) + ph).abs() < 1e-9 * ph);
        assert!((ca - cb / (a_s * a_s)).abs() < 1e-9 * ph);
        let (e, nu) = shaft;
        let (sr, st) = (ca - cb / (b * b), ca + cb / (b * b));
        let u_b = b * (1.0 + nu) / e * ((1.0 - nu) * st - nu * sr);
        assert!((ring_ur(ph, b, c, ring, b) - u_b - delta).abs() < 1e-9 * delta);
        assert!(ph < p);
    }

    /// The ellipse fit recovers a, p₀ and the centre of sampled Hertz profiles
    /// (uneven spacing, open points around); the edge estimate brackets a
    /// within a spacing.
    #[test]
    fn fit_recovers_an_ellipse() {
        let (a, p0, x0) = (0.93, 2700.0, 0.01);
        let pts: Vec<(f64, f64)> = (0..60)
            .map(|i| {
                let x = -1.5 + 3.0 * (i as f64 / 59.0).powf(1.1);
                (x, hertz_pressure(x - x0, a, p0))
            })
            .collect();
        let f = fit_ellipse(&pts).unwrap();
        assert!((f.a - a).abs() < 1e-9, "{f:?}");
        assert!((f.p0 - p0).abs() < 1e-6);
        assert!((f.x0 - x0).abs() < 1e-9);
        let e = edge_half_width(&pts).unwrap();
        assert!((e - a).abs() < 0.06, "{e}");
        assert!(fit_ellipse(&[(0.0, 1.0), (1.0, 0.0)]).is_none());
    }
}
