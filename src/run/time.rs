//! The time of a step as a run writes it: `step × dt` computed in decimal from `dt` as written
//! ([`time_text`]): `0.009`, not the float product `0.009000000000000001`.

/// The time `step × dt` as the exact decimal product of `step` and `dt`'s shortest decimal form
/// (the double nearest to it, when read back). `dt = 1e-3`, step 9: `0.009`.
pub fn time_text(step: u64, dt: f64) -> String {
    let s = format!("{dt:e}");
    let decimal = s.split_once('e').and_then(|(mantissa, exp)| {
        let exp: i32 = exp.parse().ok()?;
        let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let digits: u128 = format!("{int}{frac}").parse().ok()?;
        let product = digits.checked_mul(u128::from(step))?;
        Some((product, exp - frac.len() as i32))
    });
    let Some((product, e10)) = decimal else {
        return format!("{}", step as f64 * dt);
    };
    if product == 0 {
        return "0".into();
    }
    let p = product.to_string();
    let len = p.len() as i32;
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (0..=6).contains(&e10) {
        format!("{p}{}", "0".repeat(e10 as usize))
    } else if e10 < 0 && len + e10 > 0 {
        let cut = (len + e10) as usize;
        trim(format!("{}.{}", &p[..cut], &p[cut..]))
    } else if e10 < 0 && len + e10 > -6 {
        trim(format!("0.{}{p}", "0".repeat((-(len + e10)) as usize)))
    } else {
        let mantissa = trim(format!("{}.{}", &p[..1], &p[1..]));
        format!("{mantissa}e{}", e10 + len - 1)
    }
}

/// The time `step × dt` as a number (the double nearest to [`time_text`]).
pub fn time_value(step: u64, dt: f64) -> f64 {
    time_text(step, dt).parse().unwrap_or(step as f64 * dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_the_decimal_products_of_step_and_dt() {
        // Against the decimal text written by hand, and against the float product where that
        // is exact.
        assert_eq!(time_text(9, 1e-3), "0.009");
        assert_eq!(9.0 * 1e-3, 0.009000000000000001); // what the float product gives
        assert_eq!(time_value(9, 1e-3), 0.009);
        assert_eq!(time_text(0, 1e-5), "0");
        assert_eq!(time_text(7493, 1e-5), "0.07493");
        assert_eq!(time_text(120000, 1e-5), "1.2");
        assert_eq!(time_text(3, 2.5e-6), "0.0000075");
        assert_eq!(time_text(4, 2.5), "10");
        assert_eq!(time_text(3, 1e10), "3e10");
        assert_eq!(time_text(12, 1e-30), "1.2e-29");
        assert_eq!(time_text(1, 0.1), "0.1");
        assert_eq!(time_text(3, 0.1), "0.3");
        assert_eq!(time_text(1_000_000, 1e-6), "1");
        // Against the exact rational product, for dt's with long decimal forms.
        for (step, dt) in [(12345u64, 1.0 / 3.0), (987, std::f64::consts::PI * 1e-7)] {
            let v = time_value(step, dt);
            assert!(
                (v - step as f64 * dt).abs() <= 2.0 * f64::EPSILON * v,
                "{v}"
            );
        }
    }
}
