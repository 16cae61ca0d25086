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

/// The camera's frame for one image: where it is and its three unit axes in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Frame {
    origin: [f64; 3],
    forward: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    /// Focal lengths in pixels, horizontal and vertical, at the image's zoom.
    fx: f64,
    fy: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Camera {
    /// The pinhole frame of an image taken through `cone` (module conventions: pixel `u` grows
    /// to the right, `v` downwards; the optical axis through the image centre).
    fn frame(&self, cone: &crate::ViewCone, image: &crate::ImageGeometry) -> Frame {
        let (yaw, tilt) = (cone.camera_yaw(), cone.tilt);
        let (sy, cy, st, ct) = (yaw.sin(), yaw.cos(), tilt.sin(), tilt.cos());
        let zoom = cone.zoom.max(1.0);
        Frame {
            origin: [cone.pose.x, cone.pose.y, self.height],
            forward: [ct * cy, ct * sy, st],
            right: [sy, -cy, 0.0],
            up: [-st * cy, -st * sy, ct],
            fx: f64::from(image.width_px) / (2.0 * (self.hfov / zoom / 2.0).tan()),
            fy: f64::from(image.height_px) / (2.0 * (self.vfov / zoom / 2.0).tan()),
        }
    }

    /// Where `point` appears in an image taken through `cone`: pixel `(u, v)` from the
    /// top-left corner (possibly outside the image), and its depth along the optical axis in
    /// metres; `None` behind the camera. A pinhole camera whose fields of view at zoom `z` are
    /// the zoom-1 fields divided by `z`.
    pub fn project(
        &self,
        cone: &crate::ViewCone,
        image: &crate::ImageGeometry,
        point: crate::Point3,
    ) -> Option<(f64, f64, f64)> {
        let f = self.frame(cone, image);
        let w = [
            point.x - f.origin[0],
            point.y - f.origin[1],
            point.z - f.origin[2],
        ];
        let depth = dot(w, f.forward);
        if depth <= 1e-9 {
            return None;
        }
        let u = f64::from(image.width_px) / 2.0 + f.fx * dot(w, f.right) / depth;
        let v = f64::from(image.height_px) / 2.0 - f.fy * dot(w, f.up) / depth;
        Some((u, v, depth))
    }

    /// The point at `distance` metres from the camera along the ray through pixel `(u, v)` of
    /// an image taken through `cone` (the inverse of [`Camera::project`]): where a recognised
    /// object is, given its distance estimate (Sjöö et al. `004` §3.5).
    pub fn unproject(
        &self,
        cone: &crate::ViewCone,
        image: &crate::ImageGeometry,
        (u, v): (f64, f64),
        distance: f64,
    ) -> crate::Point3 {
        let f = self.frame(cone, image);
        let a = (u - f64::from(image.width_px) / 2.0) / f.fx;
        let b = (f64::from(image.height_px) / 2.0 - v) / f.fy;
        let ray: Vec<f64> = (0..3)
            .map(|i| f.forward[i] + a * f.right[i] + b * f.up[i])
            .collect();
        let n = (ray[0] * ray[0] + ray[1] * ray[1] + ray[2] * ray[2]).sqrt();
        crate::Point3 {
            x: f.origin[0] + distance * ray[0] / n,
            y: f.origin[1] + distance * ray[1] / n,
            z: f.origin[2] + distance * ray[2] / n,
        }
    }

    /// Pan and tilt (radians, not clamped) that centre an image taken through `cone` on its
    /// pixel `(u, v)`: where the camera turns to zoom onto a window (Sjöö et al. `004` §3.4).
    pub fn pan_tilt_towards(
        &self,
        cone: &crate::ViewCone,
        image: &crate::ImageGeometry,
        (u, v): (f64, f64),
    ) -> (f64, f64) {
        let cam = self.frame(cone, image).origin;
        let p = self.unproject(cone, image, (u, v), 1.0);
        let (dx, dy, dz) = (p.x - cam[0], p.y - cam[1], p.z - cam[2]);
        let pan = avs_map::geometry::wrap_angle(dy.atan2(dx) - cone.pose.yaw);
        (pan, dz.atan2(dx.hypot(dy)))
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
    fn projection_and_unprojection_are_inverse_and_follow_the_pixel_conventions() {
        let c = Camera::default();
        let g = crate::ImageGeometry::default();
        let cone = crate::ViewCone::new(crate::Pose2D::new(1.0, 2.0, 0.3), 0.4, -0.2, 2.0);
        for (u, v) in [(160.0, 120.0), (10.0, 5.0), (300.0, 230.0)] {
            let p = c.unproject(&cone, &g, (u, v), 2.5);
            let (u2, v2, depth) = c.project(&cone, &g, p).unwrap();
            assert!((u - u2).abs() < 1e-9 && (v - v2).abs() < 1e-9, "{u2} {v2}");
            assert!(depth > 0.0 && depth <= 2.5 + 1e-12);
        }
        // The image centre lies on the optical axis: along the camera yaw, at the tilt.
        let centre = c.unproject(&cone, &g, (160.0, 120.0), 1.0);
        let yaw = (centre.y - 2.0).atan2(centre.x - 1.0);
        assert!((yaw - 0.7).abs() < 1e-12);
        assert!(((centre.z - c.height) - (-0.2f64).sin()).abs() < 1e-12);
        // A point to the camera's left and above appears left of and above the centre.
        let left_up = crate::Point3 {
            x: 1.0 + 3.0 * 0.7f64.cos() - 0.3 * 0.7f64.sin(),
            y: 2.0 + 3.0 * 0.7f64.sin() + 0.3 * 0.7f64.cos(),
            z: c.height,
        };
        let (u, v, _) = c.project(&cone, &g, left_up).unwrap();
        assert!(u < 160.0 && v < 120.0, "{u} {v}");
        // Behind the camera: nothing.
        let behind = crate::Point3 {
            x: 0.0,
            y: 1.0,
            z: 1.0,
        };
        assert!(c.project(&cone, &g, behind).is_none());
        // Turning towards a pixel centres it.
        let (pan, tilt) = c.pan_tilt_towards(&cone, &g, (40.0, 200.0));
        let p = c.unproject(&cone, &g, (40.0, 200.0), 2.0);
        let turned = crate::ViewCone { pan, tilt, ..cone };
        let (u, v, _) = c.project(&turned, &g, p).unwrap();
        assert!(
            (u - 160.0).abs() < 1e-6 && (v - 120.0).abs() < 1e-6,
            "{u} {v}"
        );
    }

    #[test]
    fn clamping_keeps_pan_and_tilt_inside_the_limits() {
        let c = Camera::default();
        assert_eq!(c.clamp_tilt(-3.0), c.tilt_limits[0]);
        assert_eq!(c.clamp_tilt(0.1), 0.1);
        assert_eq!(c.clamp_pan(9.0), c.pan_limits[1]);
    }
}
