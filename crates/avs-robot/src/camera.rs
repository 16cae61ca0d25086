//! The robot's pan-tilt-zoom camera, in radians.

use serde::{Deserialize, Serialize};

/// A pan-tilt-zoom camera on the robot: fields of view at zoom 1 and limits in radians, the
/// largest zoom factor and the height above the floor in metres. Zoom `z` divides the fields
/// of view by `z` (Sjöö et al. `004` §3.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    /// Horizontal field of view at zoom 1, radians.
    pub hfov: f64,
    /// Vertical field of view at zoom 1, radians.
    pub vfov: f64,
    /// Pan limits `[min, max]`, radians relative to the robot's heading (positive to the left).
    pub pan_limits: [f64; 2],
    /// Tilt limits `[min, max]`, radians (negative looks down).
    pub tilt_limits: [f64; 2],
    /// Largest zoom factor (≥ 1).
    pub max_zoom: f64,
    /// Height of the camera above the floor, metres.
    pub height: f64,
}

impl Camera {
    /// `pan` kept inside the pan limits.
    pub fn clamp_pan(&self, pan: f64) -> f64 {
        pan.clamp(self.pan_limits[0], self.pan_limits[1])
    }

    /// `tilt` kept inside the tilt limits.
    pub fn clamp_tilt(&self, tilt: f64) -> f64 {
        tilt.clamp(self.tilt_limits[0], self.tilt_limits[1])
    }

    /// Pan and tilt (radians, kept inside the limits) that centre the image of a robot at
    /// `pose` on the point `target` (x, y, height).
    pub fn aim(&self, pose: crate::Pose2D, target: crate::Point3) -> (f64, f64) {
        let (dx, dy) = (target.x - pose.x, target.y - pose.y);
        let pan = avs_map::geometry::wrap_angle(dy.atan2(dx) - pose.yaw);
        let tilt = (target.z - self.height).atan2(dx.hypot(dy));
        (self.clamp_pan(pan), self.clamp_tilt(tilt))
    }
}

impl From<&avs_format::environment::Camera> for Camera {
    /// The file's camera (degrees) in radians: the one place degrees are converted.
    fn from(c: &avs_format::environment::Camera) -> Self {
        Self {
            hfov: c.hfov_deg.to_radians(),
            vfov: c.vfov_deg.to_radians(),
            pan_limits: c.pan_deg.map(f64::to_radians),
            tilt_limits: c.tilt_deg.map(f64::to_radians),
            max_zoom: c.max_zoom,
            height: c.height,
        }
    }
}

impl Default for Camera {
    /// The environment file's default camera (45° × 35°, pan ±180°, tilt −45°…30°, zoom 4,
    /// 1.2 m high).
    fn default() -> Self {
        Self::from(&avs_format::environment::Camera::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degrees_of_the_file_become_radians_once() {
        let file = avs_format::environment::Camera::default();
        let c = Camera::from(&file);
        assert_eq!(c.hfov, file.hfov_deg.to_radians());
        assert_eq!(c.tilt_limits[0], file.tilt_deg[0].to_radians());
        assert_eq!(c.max_zoom, file.max_zoom);
        assert!((c.pan_limits[1] - std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn aiming_centres_a_point_ahead_left_and_below_within_the_limits() {
        let c = Camera::default();
        let pose = crate::Pose2D::new(1.0, 1.0, std::f64::consts::FRAC_PI_2);
        // 2 m to the robot's left (−x in the world), 1.2 m below the camera.
        let at = crate::Point3 {
            x: -1.0,
            y: 1.0,
            z: c.height - 1.2,
        };
        let (pan, tilt) = c.aim(pose, at);
        assert!((pan - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{pan}");
        assert!((tilt - (-1.2f64).atan2(2.0)).abs() < 1e-12, "{tilt}");
        // Straight down is beyond the tilt limit: clamped.
        let below = crate::Point3 {
            x: 1.0,
            y: 1.01,
            z: 0.0,
        };
        assert_eq!(c.aim(pose, below).1, c.tilt_limits[0]);
    }

    #[test]
    fn clamping_keeps_pan_and_tilt_inside_the_limits() {
        let c = Camera::default();
        assert_eq!(c.clamp_tilt(-3.0), c.tilt_limits[0]);
        assert_eq!(c.clamp_tilt(0.1), 0.1);
        assert_eq!(c.clamp_pan(9.0), c.pan_limits[1]);
    }
}
