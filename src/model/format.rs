//! Numbers for people and small numeric helpers shared by the layers: the
//! report's and the charts' short numbers, a NaN-keeping max.

/// A number for an axis label or a table: 3 significant digits, plain or
/// with an exponent.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-3..1e4).contains(&a) {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

/// A user-given or derived number echoed in a message: exact (the shortest
/// text that reads back as the same f64), but with an exponent outside
/// [1e-4, 1e6), so 1e300 is `1e300`, never 300 digits. The one helper for
/// every number a message repeats.
pub fn fmt_value(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// max that keeps a NaN (f64::max drops it).
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmt_num_is_short() {
        assert_eq!(fmt_num(0.1), "0.1");
        assert_eq!(fmt_num(12.3456), "12.3");
        assert_eq!(fmt_num(1234.0), "1234");
        assert_eq!(fmt_num(1.5e-5), "1.50e-5");
    }

    #[test]
    fn fmt_value_is_exact_and_short() {
        assert_eq!(fmt_value(1e300), "1e300");
        assert_eq!(fmt_value(-2.5e-300), "-2.5e-300");
        assert_eq!(fmt_value(0.1), "0.1");
        assert_eq!(fmt_value(123456.0), "123456");
        assert_eq!(fmt_value(f64::NAN), "NaN");
        assert_eq!(fmt_value(f64::INFINITY), "inf");
        for v in [1e300, 3.7e-12, 0.30000000000000004, 9.99e5, 1.234e6] {
            assert_eq!(fmt_value(v).parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn nan_max_keeps_nan() {
        assert!(nan_max(f64::NAN, 1.0).is_nan());
        assert!(nan_max(1.0, f64::NAN).is_nan());
        assert_eq!(nan_max(1.0, 2.0), 2.0);
    }
}
