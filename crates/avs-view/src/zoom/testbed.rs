//! A cheap robot for testing and benchmarking the zoom pipeline: rectangles in space that its
//! attention and recogniser see through [`avs_robot::Camera::project`]. Compiled into the unit
//! tests and included by `benches/zoom.rs` with `#[path]`, so it uses only `avs_robot` and
//! `avs_map` (never `crate::`).
//!
//! * **Attention.** Each object is a `width × height` rectangle centred on its point, facing
//!   the camera (perpendicular to the horizontal line of sight). Its four corners are projected
//!   and the vote of a cell for the object's class is the fraction of the cell the corners'
//!   bounding box covers (1 for a covered cell, the maximum over objects); other classes' cells
//!   stay 0. Distractor cells are fixed cells of every image with a fixed value.
//! * **Recogniser.** An object of the class whose projected width is at least
//!   [`RECOGNISABLE_SHARE`] of the image width gives [`MATCH_SHARE`] of the model's features as
//!   matches, on a grid over the part of its box inside the image, each with the scale ratio
//!   `projected width / training width`; smaller objects give none.

use avs_map::grid::OccupancyGrid;
use avs_robot::{
    ActionFailure, ActionResult, AttentionReport, Camera, FailureReason, FeatureMatch,
    ImageGeometry, MapUpdate, MoveReport, Point3, Pose2D, RecognitionReport, Robot, ViewCone,
    ViewReport, VoteMatrix,
};

/// Share of the image width an object must span for the recogniser to match it.
pub const RECOGNISABLE_SHARE: f64 = 0.3;
/// Share of the model's features matched on a recognisable object.
pub const MATCH_SHARE: f64 = 0.3;

/// One object the test robot can see.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxObject {
    /// Its class.
    pub class: String,
    /// The centre of its front face, metres.
    pub centre: Point3,
    /// Front-face width, metres.
    pub width: f64,
    /// Front-face height, metres.
    pub height: f64,
    /// Its width in the class's training image, pixels (`ObjectModel::train_px().0`).
    pub train_width_px: f64,
}

/// The test robot (module docs).
#[derive(Debug, Clone)]
pub struct BoxRobot {
    /// Its camera.
    pub camera: Camera,
    /// Where it stands.
    pub pose: Pose2D,
    /// Its images.
    pub image: ImageGeometry,
    /// What it can see.
    pub objects: Vec<BoxObject>,
    /// Fixed cells `(class, col, row, value)` in every image.
    pub distractors: Vec<(String, usize, usize, f64)>,
    /// Features of every class's model.
    pub model_features: u32,
    /// Whether it has an attention (otherwise `attention` is `Unsupported`).
    pub has_attention: bool,
    /// Seconds an attention image takes.
    pub attention_seconds: f64,
    /// Seconds a recognition image takes.
    pub recognition_seconds: f64,
    odometry: f64,
    grid: OccupancyGrid,
}

impl BoxRobot {
    /// A robot at `pose` with `camera` and the paper's images, seeing `objects`.
    pub fn new(camera: Camera, pose: Pose2D, objects: Vec<BoxObject>) -> Self {
        Self {
            camera,
            pose,
            image: ImageGeometry::default(),
            objects,
            distractors: Vec::new(),
            model_features: 200,
            has_attention: true,
            attention_seconds: 0.5,
            recognition_seconds: 2.0,
            odometry: 0.0,
            grid: OccupancyGrid::from_ascii(".", 0.5, [0.0, 0.0])
                .unwrap_or_else(|_| unreachable!("a one-cell map parses")),
        }
    }

    /// The pixel box `[u0, v0, u1, v1]` of an object in an image taken through `cone`; `None`
    /// when a corner is behind the camera.
    pub fn projected_box(&self, cone: &ViewCone, o: &BoxObject) -> Option<[f64; 4]> {
        let (dx, dy) = (o.centre.x - cone.pose.x, o.centre.y - cone.pose.y);
        let n = dx.hypot(dy).max(1e-12);
        let (rx, ry) = (-dy / n, dx / n);
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for (sw, sh) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let p = Point3 {
                x: o.centre.x + sw * o.width / 2.0 * rx,
                y: o.centre.y + sw * o.width / 2.0 * ry,
                z: o.centre.z + sh * o.height / 2.0,
            };
            let (u, v, _) = self.camera.project(cone, &self.image, p)?;
            b = [b[0].min(u), b[1].min(v), b[2].max(u), b[3].max(v)];
        }
        Some(b)
    }

    fn go(&mut self, cone: &ViewCone) -> ActionResult<f64> {
        cone.check(&self.camera)?;
        let travelled = self.pose.distance(&cone.pose);
        self.pose = cone.pose;
        self.odometry += travelled;
        Ok(travelled)
    }
}

impl Robot for BoxRobot {
    fn pose(&self) -> Pose2D {
        self.pose
    }

    fn camera(&self) -> Camera {
        self.camera
    }

    fn odometry(&self) -> f64 {
        self.odometry
    }

    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        let travelled = self.pose.distance(&goal);
        self.pose = goal;
        self.odometry += travelled;
        Ok(MoveReport {
            pose: goal,
            travelled,
        })
    }

    fn map_update(&mut self) -> MapUpdate {
        MapUpdate {
            grid: self.grid.clone(),
            newly_known: 0,
            doors: Vec::new(),
        }
    }

    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        _classes: &[String],
    ) -> ActionResult<ViewReport> {
        let travelled = self.go(cone)?;
        Ok(ViewReport {
            pose: self.pose,
            detections: Vec::new(),
            travelled,
        })
    }

    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        if !self.has_attention {
            return Err(ActionFailure::new(
                FailureReason::Unsupported,
                "this test robot has no attention",
            ));
        }
        let travelled = self.go(cone)?;
        let g = self.image;
        let cell = f64::from(g.cell_px);
        let votes = classes
            .iter()
            .map(|class| {
                let mut m = VoteMatrix::zeros(class.clone(), g.cols(), g.rows());
                for o in self.objects.iter().filter(|o| &o.class == class) {
                    let Some(b) = self.projected_box(cone, o) else {
                        continue;
                    };
                    for row in 0..g.rows() {
                        for col in 0..g.cols() {
                            let (x0, y0) = (col as f64 * cell, row as f64 * cell);
                            let w = (b[2].min(x0 + cell) - b[0].max(x0)).max(0.0);
                            let h = (b[3].min(y0 + cell) - b[1].max(y0)).max(0.0);
                            let v = &mut m.values[row * g.cols() + col];
                            *v = v.max(w * h / (cell * cell));
                        }
                    }
                }
                for (c, col, row, value) in &self.distractors {
                    if c == class && *col < g.cols() && *row < g.rows() {
                        let v = &mut m.values[row * g.cols() + col];
                        *v = v.max(*value);
                    }
                }
                m
            })
            .collect();
        Ok(AttentionReport {
            pose: self.pose,
            travelled,
            image: g,
            votes,
            seconds: self.attention_seconds,
        })
    }

    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        let travelled = self.go(cone)?;
        let g = self.image;
        let (iw, ih) = (f64::from(g.width_px), f64::from(g.height_px));
        let mut matches = Vec::new();
        for o in self.objects.iter().filter(|o| o.class == class) {
            let Some(b) = self.projected_box(cone, o) else {
                continue;
            };
            let width = b[2] - b[0];
            let seen = [b[0].max(0.0), b[1].max(0.0), b[2].min(iw), b[3].min(ih)];
            if width < RECOGNISABLE_SHARE * iw || seen[2] <= seen[0] || seen[3] <= seen[1] {
                continue;
            }
            let n = (MATCH_SHARE * f64::from(self.model_features)).round() as usize;
            // Ten a row, as many rows as needed (a 10 × 6 grid for 60).
            let rows = n.div_ceil(10).max(1);
            for k in 0..n {
                let (i, j) = (k % 10, k / 10);
                matches.push(FeatureMatch {
                    u: seen[0] + (i as f64 + 0.5) / 10.0 * (seen[2] - seen[0]),
                    v: seen[1] + (j as f64 + 0.5) / rows as f64 * (seen[3] - seen[1]),
                    scale_ratio: width / o.train_width_px,
                });
            }
        }
        Ok(RecognitionReport {
            pose: self.pose,
            travelled,
            image: g,
            class: class.to_string(),
            model_features: self.model_features,
            matches,
            seconds: self.recognition_seconds,
        })
    }
}
