//! Vantage points: where the robot looks at a candidate from, relative to the candidate.
//!
//! Velez et al. 2012 §5.3: a vantage point `v = F(x, y)` maps a robot waypoint `x` to the
//! configuration of the robot relative to the hypothesised object — here, as in the paper, the
//! range `r` and the aspect `φ` with the robot turned to face the object (Fig. 2a). The aspect is
//! the angle between the object's facing (the normal of a door or a sign) and the direction from
//! the object to the robot: 0 straight in front, ±π/2 edge-on, ±π from behind.

use crate::gp::SeKernel;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A vantage point relative to a candidate: range (metres) and aspect (radians, in (−π, π]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Vantage {
    /// Planar distance from the candidate to the robot, metres.
    pub range: f64,
    /// Angle from the candidate's facing to the direction of the robot, radians in (−π, π].
    pub aspect: f64,
}

impl Vantage {
    /// A vantage point from its parts (the aspect is wrapped into (−π, π]).
    pub fn new(range: f64, aspect: f64) -> Self {
        Self {
            range,
            aspect: wrap(aspect),
        }
    }

    /// The vantage point of a robot at `waypoint` looking at a candidate at `object` that faces
    /// `facing` (radians; `None` for a candidate whose facing is unknown, whose aspect is then
    /// the bearing from the candidate to the robot, measured from +x: a sensor model that does
    /// not depend on the aspect gives it a long length scale).
    pub fn of(waypoint: [f64; 2], object: [f64; 2], facing: Option<f64>) -> Self {
        let dx = waypoint[0] - object[0];
        let dy = waypoint[1] - object[1];
        let range = dx.hypot(dy);
        let aspect = if range > 0.0 {
            wrap(dy.atan2(dx) - facing.unwrap_or(0.0))
        } else {
            0.0
        };
        Self { range, aspect }
    }

    /// The waypoint this vantage point puts the robot on, for a candidate at `object` facing
    /// `facing` (the inverse of [`Vantage::of`]).
    pub fn waypoint(&self, object: [f64; 2], facing: Option<f64>) -> [f64; 2] {
        let a = self.aspect + facing.unwrap_or(0.0);
        [
            object[0] + self.range * a.cos(),
            object[1] + self.range * a.sin(),
        ]
    }

    /// The GP input of this vantage point: `[range, aspect]`; the aspect is an angle
    /// ([`ANGULAR`]).
    pub fn features(&self) -> [f64; 2] {
        [self.range, self.aspect]
    }

    /// `kernel` as a kernel over vantage points: its second input, the aspect, an angle
    /// ([`SeKernel::angular`]), so that two looks from either side of the bearing ±π (a robot
    /// west of a candidate whose facing is unknown, measured from +x) are as near as they are.
    pub fn kernel(kernel: SeKernel) -> SeKernel {
        kernel.with_angular(&ANGULAR)
    }
}

/// Which of a vantage point's GP inputs ([`Vantage::features`]) are angles: the aspect.
pub const ANGULAR: [bool; 2] = [false, true];

/// An angle wrapped into (−π, π].
pub fn wrap(a: f64) -> f64 {
    let mut a = a.rem_euclid(2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_waypoint_round_trips_through_its_vantage_point() {
        let obj = [2.0, -1.0];
        for facing in [None, Some(0.3), Some(-2.9)] {
            for (x, y) in [(4.0, -1.0), (2.0, 3.0), (-0.5, -2.0)] {
                let v = Vantage::of([x, y], obj, facing);
                let w = v.waypoint(obj, facing);
                assert!((w[0] - x).abs() < 1e-9 && (w[1] - y).abs() < 1e-9, "{w:?}");
                assert!((v.range - (x - obj[0]).hypot(y - obj[1])).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_aspect_is_zero_in_front_and_a_right_angle_edge_on() {
        let v = Vantage::of([0.0, 2.0], [0.0, 0.0], Some(std::f64::consts::FRAC_PI_2));
        assert!(v.aspect.abs() < 1e-12 && (v.range - 2.0).abs() < 1e-12);
        let v = Vantage::of([2.0, 0.0], [0.0, 0.0], Some(std::f64::consts::FRAC_PI_2));
        assert!((v.aspect + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-12);
    }
}
