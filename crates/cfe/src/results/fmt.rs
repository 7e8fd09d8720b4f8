//! One number format for everything cfe prints: four significant digits in
//! scientific notation without trailing zeros (`7.457e-2`, `2.1e5`, `1e9`, `0`),
//! and round-off shown as zero.

/// `v` with four significant digits: `7.457e-2`, `2.1e5`, `-1.5e3`, `0`.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return v.to_string();
    }
    let s = format!("{v:.3e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    if exp == "0" {
        mantissa.to_string()
    } else {
        format!("{mantissa}e{exp}")
    }
}

/// [`num`] of `v`, shown as `0` when it is round-off relative to `size` (a
/// length of the model, a load scale): below 1e-10 × `size`.
pub fn num_rel(v: f64, size: f64) -> String {
    if v.abs() <= 1e-10 * size.abs() {
        "0".into()
    } else {
        num(v)
    }
}

/// A position as given in the input, `(x, y)` in the shortest exact form, with a
/// coordinate that is round-off relative to the other (below 1e-10 of it) as 0.
pub fn point(p: [f64; 2]) -> String {
    let size = p[0].abs().max(p[1].abs());
    let c = |v: f64| if v.abs() <= 1e-10 * size { 0.0 } else { v };
    format!("({}, {})", c(p[0]), c(p[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four significant digits, no trailing zeros, round-off as zero.
    #[test]
    fn formats() {
        assert_eq!(num(0.07456970512880357), "7.457e-2");
        assert_eq!(num(210000.0), "2.1e5");
        assert_eq!(num(1e9), "1e9");
        assert_eq!(num(-1500.0), "-1.5e3");
        assert_eq!(num(1.0), "1");
        assert_eq!(num(0.0), "0");
        assert_eq!(num_rel(2.842e-14, 200.0), "0");
        assert_eq!(num_rel(0.5, 200.0), "5e-1");
        assert_eq!(point([6.123234e-16, 10.0]), "(0, 10)");
        assert_eq!(point([520.0, 0.5]), "(520, 0.5)");
    }
}
