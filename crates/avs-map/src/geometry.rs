//! Small planar geometry every crate uses: distance and angle wrapping.

/// Euclidean distance between two planar points.
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// An angle wrapped to (−π, π]. The remainder is exact (`%` on floats is), so small angles
/// come back unchanged.
pub fn wrap_angle(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let mut x = a % t;
    if x <= -std::f64::consts::PI {
        x += t;
    } else if x > std::f64::consts::PI {
        x -= t;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn angles_wrap_into_the_half_open_circle_and_small_ones_stay_exact() {
        assert_eq!(wrap_angle(PI), PI);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
        assert!((wrap_angle(-7.0) - (-7.0 + 2.0 * PI)).abs() < 1e-12);
        for a in [1e-12, -3.5e-10, 0.0005755623786627988] {
            assert_eq!(wrap_angle(a), a);
        }
        assert_eq!(dist([0.0, 0.0], [3.0, 4.0]), 5.0);
    }
}
