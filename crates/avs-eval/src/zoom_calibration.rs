//! The calibration bench of the simulated camera image (`avs zoom-bench`): Sjöö et al. `004`
//! §4.1–4.2 re-enacted on [`avs_sim::image`], so that the attention and the recogniser the zoom
//! pipeline works on show the paper's figures' trends.
//!
//! # Protocol (the paper's)
//!
//! Five test objects ([`TestObject::paper_objects`]) stand at eight distances, 0.5–4 m, in
//! front of the camera, before two backgrounds (a plain wall, clutter 0, and an office scene,
//! clutter 1), with [`CalibrationParams::images_per_position`] images per position (the paper
//! took five), each with a small random perturbation: the object turned by up to
//! [`CalibrationParams::yaw_jitter`] off facing the camera and shifted within the middle of
//! the image ([`CalibrationParams::offset_share`]). For each image, on the unzoomed image:
//!
//! * the object class's hypotheses ([`avs_view::zoom::hypotheses`], the class threshold
//!   [`avs_view::zoom::DEFAULT_VOTE_THRESHOLD`]); a hypothesis is *true* when its peak cell
//!   overlaps the object's projected box (the paper labelled them by hand: "true if they
//!   overlapped with a part of the object");
//! * the RFCH distance from the strongest hypothesis's vote area
//!   ([`avs_view::zoom::distance_from_votes`]) and the SIFT distance, the median of the
//!   matches' distances when there are at least four ([`avs_view::zoom::distance_from_matches`]).
//!
//! Per distance, pooled over objects, backgrounds and images:
//!
//! * **Fig. 7** — the share of all hypotheses that are false;
//! * **Fig. 8** — the share of images whose strongest hypothesis is true (an image without a
//!   hypothesis counts as not);
//! * **Fig. 9** — mean, standard deviation, minimum and maximum of each method's estimate, over
//!   the images that have one, and its mean absolute error;
//! * **Fig. 10** — the share of images in which RFCH's absolute error is smaller than SIFT's
//!   and the reverse; a method with no estimate loses to one with an estimate, and an image
//!   where neither has one counts for neither.
//!
//! # Choices where the paper is vague
//!
//! * **Test objects.** Only the cup's face is given (14 × 10 cm); the others are ordinary
//!   sizes of such things ([`TestObject::paper_objects`]).
//! * **Geometry.** The paper's camera (a Canon VC-C4R: 47.5° × 36.4° at zoom 1, 1 m high,
//!   [`paper_camera`]) looks level; the object's face centre is at the camera's height, the
//!   nominal distance along the optical axis, so the true distance is the depth both estimates
//!   measure. The background stands [`CalibrationParams::background_gap`] behind the object.
//! * **Seeds.** Every image has its own generator, stream `i` of the bench's seed (`i` its
//!   index in the order object, background, distance, image), so an image does not depend on
//!   how many others were taken.

use avs_robot::{Camera, ImageGeometry, Point3, Pose2D, ViewCone};
use avs_sim::image::{
    attention, cell_cover, face_image, recognition, Background, ClassAppearance, ImageModel,
    ImageScene, SceneObject,
};
use avs_view::zoom::{
    distance_from_matches, distance_from_votes, hypotheses, ObjectModel, DEFAULT_VOTE_THRESHOLD,
    RECOGNITION_SHARE,
};
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What stops the bench or its charts.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// A parameter is out of range: the field and what is expected.
    #[error("{field}: {message}")]
    Params {
        /// The parameter.
        field: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The zoom pipeline refused a vote matrix.
    #[error("hypotheses: {0}")]
    Zoom(String),
    /// A chart could not be written.
    #[error("{file}: {message}")]
    Draw {
        /// The chart's file.
        file: String,
        /// What went wrong.
        message: String,
    },
}

/// One test object: its class and front face.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestObject {
    /// The class name.
    pub class: String,
    /// Width of the front face, metres.
    pub width: f64,
    /// Height of the front face, metres.
    pub height: f64,
}

impl TestObject {
    fn new(class: &str, width: f64, height: f64) -> Self {
        Self {
            class: class.to_string(),
            width,
            height,
        }
    }

    /// The paper's five test objects (§4.1): the printed cup (14 × 10 cm, the paper's own
    /// figure), a trackball's box (16 × 16 cm), a rice carton (13 × 20 cm, standing), a book
    /// (16 × 23 cm, standing, cover forward) and a printed mouse pad (23 × 19 cm, standing).
    pub fn paper_objects() -> Vec<TestObject> {
        vec![
            Self::new("cup", 0.14, 0.10),
            Self::new("trackball_box", 0.16, 0.16),
            Self::new("rice_carton", 0.13, 0.20),
            Self::new("book", 0.16, 0.23),
            Self::new("mouse_pad", 0.23, 0.19),
        ]
    }

    fn model(&self) -> ObjectModel {
        ObjectModel {
            class: self.class.clone(),
            width: self.width,
            height: self.height,
            vote_threshold: DEFAULT_VOTE_THRESHOLD,
        }
    }

    fn appearance(&self) -> ClassAppearance {
        ClassAppearance {
            name: self.class.clone(),
            width: self.width,
            height: self.height,
        }
    }
}

/// One background of the bench.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BackgroundSpec {
    /// Its name in the tables.
    pub name: String,
    /// Its clutter (0 a plain wall, 1 an office scene).
    pub clutter: f64,
}

/// The paper's camera, a Canon VC-C4R (§1.2): 47.5° × 36.4° at zoom 1, up to 13×, 1 m above the
/// floor.
pub fn paper_camera() -> Camera {
    Camera {
        hfov: 47.5f64.to_radians(),
        vfov: 36.4f64.to_radians(),
        pan_limits: [-100f64.to_radians(), 100f64.to_radians()],
        tilt_limits: [-30f64.to_radians(), 90f64.to_radians()],
        max_zoom: 13.0,
        height: 1.0,
    }
}

/// The bench's parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationParams {
    /// The bench's seed.
    pub seed: u64,
    /// Images per object, background and distance (the paper: 5).
    pub images_per_position: usize,
    /// The distances, metres.
    pub distances: Vec<f64>,
    /// The test objects.
    pub objects: Vec<TestObject>,
    /// The backgrounds.
    pub backgrounds: Vec<BackgroundSpec>,
    /// How far behind the object the background stands, metres.
    pub background_gap: f64,
    /// Largest turn of the object off facing the camera, radians.
    pub yaw_jitter: f64,
    /// Largest shift of the object off the optical axis, as a share of the half field of view
    /// at its distance (horizontally and vertically).
    pub offset_share: f64,
    /// The camera.
    pub camera: Camera,
    /// The image geometry.
    pub image: ImageGeometry,
    /// The simulated image's parameters.
    pub model: ImageModel,
}

impl Default for CalibrationParams {
    /// The paper's protocol with 20 images per position (four times the paper's five, for
    /// steadier shares), seed 1.
    fn default() -> Self {
        Self {
            seed: 1,
            images_per_position: 20,
            distances: (1..=8).map(|i| f64::from(i) * 0.5).collect(),
            objects: TestObject::paper_objects(),
            backgrounds: vec![
                BackgroundSpec {
                    name: "plain wall".into(),
                    clutter: 0.0,
                },
                BackgroundSpec {
                    name: "office scene".into(),
                    clutter: 1.0,
                },
            ],
            background_gap: 0.5,
            yaw_jitter: 15f64.to_radians(),
            offset_share: 0.4,
            camera: paper_camera(),
            image: ImageGeometry::default(),
            model: ImageModel::default(),
        }
    }
}

impl CalibrationParams {
    fn check(&self) -> Result<(), CalibrationError> {
        let bad = |field, message: String| Err(CalibrationError::Params { field, message });
        if self.images_per_position == 0 || self.images_per_position > 10_000 {
            return bad(
                "images_per_position",
                format!("{}: expected 1 to 10000", self.images_per_position),
            );
        }
        if self.distances.is_empty() || self.distances.iter().any(|d| !(*d > 0.0 && d.is_finite()))
        {
            return bad(
                "distances",
                format!("{:?}: expected positive distances", self.distances),
            );
        }
        if self.objects.is_empty()
            || self
                .objects
                .iter()
                .any(|o| !(o.width > 0.0 && o.height > 0.0 && o.width.is_finite()))
        {
            return bad(
                "objects",
                "expected at least one object with a positive face".into(),
            );
        }
        if self.backgrounds.is_empty() {
            return bad("backgrounds", "expected at least one background".into());
        }
        if let Some(p) = self.image.problem() {
            return bad("image", p);
        }
        Ok(())
    }
}

/// What one image gave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImageRecord {
    /// The object's class.
    pub class: String,
    /// The background's name.
    pub background: String,
    /// The true distance (depth), metres.
    pub distance: f64,
    /// Hypotheses of the object's class.
    pub hypotheses: usize,
    /// How many of them are false.
    pub false_hypotheses: usize,
    /// Whether the strongest hypothesis is true (false without a hypothesis).
    pub strongest_true: bool,
    /// RFCH's distance estimate (the strongest hypothesis's vote area), metres.
    pub rfch: Option<f64>,
    /// SIFT's distance estimate (median of at least four matches), metres.
    pub sift: Option<f64>,
    /// Matched features (true and mismatched).
    pub matches: usize,
    /// Whether the matches reach the recognition share of the model's features.
    pub recognised: bool,
}

impl ImageRecord {
    /// Absolute error of RFCH's estimate, metres.
    pub fn rfch_error(&self) -> Option<f64> {
        self.rfch.map(|e| (e - self.distance).abs())
    }

    /// Absolute error of SIFT's estimate, metres.
    pub fn sift_error(&self) -> Option<f64> {
        self.sift.map(|e| (e - self.distance).abs())
    }

    /// Which method's estimate is better: `Some(true)` RFCH, `Some(false)` SIFT, `None` neither
    /// (module docs, Fig. 10).
    pub fn rfch_better(&self) -> Option<bool> {
        match (self.rfch_error(), self.sift_error()) {
            (Some(r), Some(s)) if r < s => Some(true),
            (Some(r), Some(s)) if s < r => Some(false),
            (Some(_), None) => Some(true),
            (None, Some(_)) => Some(false),
            _ => None,
        }
    }
}

/// Fig. 7 at one distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FalseHypotheses {
    /// Distance, metres.
    pub distance: f64,
    /// All hypotheses.
    pub hypotheses: usize,
    /// False ones.
    pub false_hypotheses: usize,
    /// Their share, percent.
    pub percent_false: f64,
}

/// Fig. 8 at one distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CorrectStrongest {
    /// Distance, metres.
    pub distance: f64,
    /// Images.
    pub images: usize,
    /// Images whose strongest hypothesis is true.
    pub correct: usize,
    /// Their share, percent.
    pub percent_correct: f64,
}

/// One method's estimates at one distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EstimateStats {
    /// Images with an estimate.
    pub estimates: usize,
    /// Mean estimate, metres.
    pub mean: Option<f64>,
    /// Standard deviation of the estimates, metres.
    pub sd: Option<f64>,
    /// Smallest estimate, metres.
    pub min: Option<f64>,
    /// Largest estimate, metres.
    pub max: Option<f64>,
    /// Mean absolute error, metres.
    pub mean_abs_error: Option<f64>,
}

impl EstimateStats {
    fn of(values: &[f64], truth: f64) -> Self {
        let n = values.len();
        if n == 0 {
            return Self {
                estimates: 0,
                mean: None,
                sd: None,
                min: None,
                max: None,
                mean_abs_error: None,
            };
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        Self {
            estimates: n,
            mean: Some(mean),
            sd: Some(var.sqrt()),
            min: values.iter().copied().reduce(f64::min),
            max: values.iter().copied().reduce(f64::max),
            mean_abs_error: Some(values.iter().map(|v| (v - truth).abs()).sum::<f64>() / n as f64),
        }
    }
}

/// Fig. 9 at one distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DistanceEstimates {
    /// True distance, metres.
    pub distance: f64,
    /// RFCH's estimates (strongest hypothesis).
    pub rfch: EstimateStats,
    /// SIFT's estimates (median of the matches).
    pub sift: EstimateStats,
    /// Mean number of matches per image.
    pub mean_matches: f64,
    /// Share of images recognised (matches ≥ the recognition share of the model), percent.
    pub percent_recognised: f64,
}

/// Fig. 10 at one distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BetterEstimate {
    /// Distance, metres.
    pub distance: f64,
    /// Images.
    pub images: usize,
    /// Images where RFCH's estimate is the better one, percent.
    pub percent_rfch: f64,
    /// Images where SIFT's estimate is the better one, percent.
    pub percent_sift: f64,
}

/// The bench's result: the four figures' series, one entry per distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationReport {
    /// The bench's seed.
    pub seed: u64,
    /// Images per object, background and distance.
    pub images_per_position: usize,
    /// Images in all.
    pub images: usize,
    /// The test objects.
    pub objects: Vec<TestObject>,
    /// The backgrounds.
    pub backgrounds: Vec<BackgroundSpec>,
    /// Fig. 7: false hypotheses.
    pub fig7_false_hypotheses: Vec<FalseHypotheses>,
    /// Fig. 8: images whose strongest hypothesis is true.
    pub fig8_correct_strongest: Vec<CorrectStrongest>,
    /// Fig. 9: distance estimates of both methods.
    pub fig9_distance: Vec<DistanceEstimates>,
    /// Fig. 10: which method's estimate is better.
    pub fig10_better_estimate: Vec<BetterEstimate>,
    /// Every image's outcome (for tests and further analysis; not serialised).
    #[serde(skip)]
    pub records: Vec<ImageRecord>,
}

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// Run the bench (module docs). Errors name the parameter that is out of range.
pub fn run_calibration(params: &CalibrationParams) -> Result<CalibrationReport, CalibrationError> {
    params.check()?;
    let mut records = Vec::new();
    let mut index = 0u64;
    for object in &params.objects {
        for bg in &params.backgrounds {
            for &d in &params.distances {
                for _ in 0..params.images_per_position {
                    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
                    rng.set_stream(index);
                    index += 1;
                    records.push(one_image(params, object, bg, d, &mut rng)?);
                }
            }
        }
    }
    let at = |d: f64| records.iter().filter(move |r| r.distance == d);
    let mut report = CalibrationReport {
        seed: params.seed,
        images_per_position: params.images_per_position,
        images: records.len(),
        objects: params.objects.clone(),
        backgrounds: params.backgrounds.clone(),
        fig7_false_hypotheses: Vec::new(),
        fig8_correct_strongest: Vec::new(),
        fig9_distance: Vec::new(),
        fig10_better_estimate: Vec::new(),
        records: Vec::new(),
    };
    for &d in &params.distances {
        let images = at(d).count();
        let hyps: usize = at(d).map(|r| r.hypotheses).sum();
        let false_hyps: usize = at(d).map(|r| r.false_hypotheses).sum();
        report.fig7_false_hypotheses.push(FalseHypotheses {
            distance: d,
            hypotheses: hyps,
            false_hypotheses: false_hyps,
            percent_false: percent(false_hyps, hyps),
        });
        let correct = at(d).filter(|r| r.strongest_true).count();
        report.fig8_correct_strongest.push(CorrectStrongest {
            distance: d,
            images,
            correct,
            percent_correct: percent(correct, images),
        });
        let rfch: Vec<f64> = at(d).filter_map(|r| r.rfch).collect();
        let sift: Vec<f64> = at(d).filter_map(|r| r.sift).collect();
        let matches: usize = at(d).map(|r| r.matches).sum();
        report.fig9_distance.push(DistanceEstimates {
            distance: d,
            rfch: EstimateStats::of(&rfch, d),
            sift: EstimateStats::of(&sift, d),
            mean_matches: matches as f64 / images.max(1) as f64,
            percent_recognised: percent(at(d).filter(|r| r.recognised).count(), images),
        });
        let better: Vec<bool> = at(d).filter_map(ImageRecord::rfch_better).collect();
        report.fig10_better_estimate.push(BetterEstimate {
            distance: d,
            images,
            percent_rfch: percent(better.iter().filter(|b| **b).count(), images),
            percent_sift: percent(better.iter().filter(|b| !**b).count(), images),
        });
    }
    report.records = records;
    Ok(report)
}

/// One perturbed image of `object` at distance `d` before `bg`, and what the pipeline makes of
/// it.
fn one_image(
    params: &CalibrationParams,
    object: &TestObject,
    bg: &BackgroundSpec,
    d: f64,
    rng: &mut ChaCha8Rng,
) -> Result<ImageRecord, CalibrationError> {
    let camera = &params.camera;
    let image = &params.image;
    let cone = ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0);
    let mut sym = |x: f64| (2.0 * rng.gen::<f64>() - 1.0) * x;
    let yaw = std::f64::consts::PI + sym(params.yaw_jitter);
    let dy = sym(params.offset_share * d * (camera.hfov / 2.0).tan());
    let dz = sym(params.offset_share * d * (camera.vfov / 2.0).tan());
    let scene = ImageScene {
        objects: vec![SceneObject {
            class: object.class.clone(),
            centre: Point3 {
                x: d,
                y: dy,
                z: camera.height + dz,
            },
            width: object.width,
            height: object.height,
            yaw,
            lookalike: false,
        }],
        background: Background {
            clutter: bg.clutter,
            depth: d + params.background_gap,
        },
    };
    let classes = [object.class.clone()];
    let votes = attention(&params.model, &scene, camera, &cone, image, &classes, rng);
    let hyps = hypotheses(&votes[0], DEFAULT_VOTE_THRESHOLD)
        .map_err(|e| CalibrationError::Zoom(e.to_string()))?;
    let face = face_image(&scene.objects[0], camera, &cone, image);
    let is_true =
        |col: usize, row: usize| face.is_some_and(|f| cell_cover(f.bbox, col, row, image) > 0.0);
    let false_hypotheses = hyps.iter().filter(|h| !is_true(h.col, h.row)).count();
    let model = object.model();
    let strongest = hyps.first();
    let rfch = strongest
        .map(|h| distance_from_votes(&model, h, camera.hfov, image))
        .filter(|x| x.is_finite());
    let seen = recognition(
        &params.model,
        &scene,
        camera,
        &cone,
        image,
        &object.appearance(),
        rng,
    );
    let sift = distance_from_matches(&model, &seen.matches, camera.hfov, image);
    Ok(ImageRecord {
        class: object.class.clone(),
        background: bg.name.clone(),
        distance: d,
        hypotheses: hyps.len(),
        false_hypotheses,
        strongest_true: strongest.is_some_and(|h| is_true(h.col, h.row)),
        rfch,
        sift,
        matches: seen.matches.len(),
        recognised: seen.matches.len() as f64 >= RECOGNITION_SHARE * f64::from(seen.model_features),
    })
}

impl CalibrationReport {
    /// The four figures as text tables.
    pub fn tables(&self) -> String {
        let mut s = String::new();
        let f = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.2}"));
        s.push_str(&format!(
            "zoom calibration · seed {} · {} images per position · {} images\n\n",
            self.seed, self.images_per_position, self.images
        ));
        s.push_str("Fig. 7  false hypotheses\n  distance  hypotheses  false  % false\n");
        for r in &self.fig7_false_hypotheses {
            s.push_str(&format!(
                "  {:>6.1} m  {:>10}  {:>5}  {:>7.1}\n",
                r.distance, r.hypotheses, r.false_hypotheses, r.percent_false
            ));
        }
        s.push_str("\nFig. 8  strongest hypothesis is the object\n  distance  images  correct  % correct\n");
        for r in &self.fig8_correct_strongest {
            s.push_str(&format!(
                "  {:>6.1} m  {:>6}  {:>7}  {:>9.1}\n",
                r.distance, r.images, r.correct, r.percent_correct
            ));
        }
        s.push_str("\nFig. 9  distance estimates, metres (mean ± sd [min, max], mean |error|)\n");
        s.push_str("  distance  RFCH                              SIFT                              matches  % recognised\n");
        for r in &self.fig9_distance {
            let e = |x: &EstimateStats| {
                format!(
                    "{} ± {} [{}, {}] {}",
                    f(x.mean),
                    f(x.sd),
                    f(x.min),
                    f(x.max),
                    f(x.mean_abs_error)
                )
            };
            s.push_str(&format!(
                "  {:>6.1} m  {:<32}  {:<32}  {:>7.1}  {:>12.1}\n",
                r.distance,
                e(&r.rfch),
                e(&r.sift),
                r.mean_matches,
                r.percent_recognised
            ));
        }
        s.push_str("\nFig. 10  the better estimate, % of images\n  distance  RFCH  SIFT\n");
        for r in &self.fig10_better_estimate {
            s.push_str(&format!(
                "  {:>6.1} m  {:>4.0}  {:>4.0}\n",
                r.distance, r.percent_rfch, r.percent_sift
            ));
        }
        s
    }
}

/// Write the four figures as SVG charts into `dir` (created if missing):
/// `fig7_false_hypotheses.svg`, `fig8_correct_strongest.svg`, `fig9_distance.svg` (both
/// methods' mean ± one standard deviation, and their extremes, against the true distance) and
/// `fig10_better_estimate.svg`. Returns the files written.
pub fn draw(report: &CalibrationReport, dir: &Path) -> Result<Vec<PathBuf>, CalibrationError> {
    std::fs::create_dir_all(dir).map_err(|e| CalibrationError::Draw {
        file: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let mut out = Vec::new();
    let fig7: Vec<(f64, f64)> = report
        .fig7_false_hypotheses
        .iter()
        .map(|r| (r.distance, r.percent_false))
        .collect();
    out.push(chart::percent(
        &dir.join("fig7_false_hypotheses.svg"),
        "Fig. 7: false hypotheses (RFCH attention)",
        "% false hypotheses",
        &[("false hypotheses", &fig7)],
    )?);
    let fig8: Vec<(f64, f64)> = report
        .fig8_correct_strongest
        .iter()
        .map(|r| (r.distance, r.percent_correct))
        .collect();
    out.push(chart::percent(
        &dir.join("fig8_correct_strongest.svg"),
        "Fig. 8: strongest hypothesis is the object",
        "% images",
        &[("strongest hypothesis true", &fig8)],
    )?);
    out.push(chart::distances(&dir.join("fig9_distance.svg"), report)?);
    let rfch: Vec<(f64, f64)> = report
        .fig10_better_estimate
        .iter()
        .map(|r| (r.distance, r.percent_rfch))
        .collect();
    let sift: Vec<(f64, f64)> = report
        .fig10_better_estimate
        .iter()
        .map(|r| (r.distance, r.percent_sift))
        .collect();
    out.push(chart::percent(
        &dir.join("fig10_better_estimate.svg"),
        "Fig. 10: the better distance estimate",
        "% images",
        &[("RFCH better", &rfch), ("SIFT better", &sift)],
    )?);
    Ok(out)
}

/// The charts, drawn with plotters' SVG backend.
mod chart {
    use super::{CalibrationError, CalibrationReport};
    use plotters::prelude::*;
    use std::path::{Path, PathBuf};

    const SIZE: (u32, u32) = (640, 420);

    /// Which method's estimates of a distance a chart draws.
    type Pick = fn(&super::DistanceEstimates) -> &super::EstimateStats;

    /// One method's estimates at one distance, as drawn.
    struct Bar {
        x: f64,
        mean: f64,
        sd: f64,
        min: f64,
        max: f64,
    }
    const COLOURS: [RGBColor; 2] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];

    fn failed(path: &Path, e: impl std::fmt::Display) -> CalibrationError {
        CalibrationError::Draw {
            file: path.display().to_string(),
            message: e.to_string(),
        }
    }

    fn x_range(series: &[(f64, f64)]) -> std::ops::Range<f64> {
        let hi = series.iter().map(|p| p.0).fold(0.0, f64::max);
        0.0..hi + 0.5
    }

    /// Percentages against distance, one line per series.
    pub(super) fn percent(
        path: &Path,
        caption: &str,
        y_desc: &str,
        series: &[(&str, &[(f64, f64)])],
    ) -> Result<PathBuf, CalibrationError> {
        let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.1.iter().copied()).collect();
        {
            let root = SVGBackend::new(path, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(|e| failed(path, e))?;
            let mut chart = ChartBuilder::on(&root)
                .caption(caption, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(x_range(&all), 0.0..100.0)
                .map_err(|e| failed(path, e))?;
            chart
                .configure_mesh()
                .x_desc("distance (m)")
                .y_desc(y_desc)
                .draw()
                .map_err(|e| failed(path, e))?;
            for (i, (name, points)) in series.iter().enumerate() {
                let colour = COLOURS[i % COLOURS.len()];
                chart
                    .draw_series(LineSeries::new(
                        points.iter().copied(),
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| failed(path, e))?
                    .label(*name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                    .map_err(|e| failed(path, e))?;
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| failed(path, e))?;
            root.present().map_err(|e| failed(path, e))?;
        }
        Ok(path.to_path_buf())
    }

    /// Fig. 9: each method's mean ± sd (thick bars) and extremes (thin bars) against the true
    /// distance (the diagonal).
    pub(super) fn distances(
        path: &Path,
        report: &CalibrationReport,
    ) -> Result<PathBuf, CalibrationError> {
        let rows = &report.fig9_distance;
        let hi = rows
            .iter()
            .flat_map(|r| {
                [
                    r.distance,
                    r.rfch.max.unwrap_or(0.0),
                    r.sift.max.unwrap_or(0.0),
                ]
            })
            .fold(0.0, f64::max)
            .min(12.0)
            + 0.5;
        let x_hi = rows.iter().map(|r| r.distance).fold(0.0, f64::max) + 0.5;
        {
            let root = SVGBackend::new(path, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(|e| failed(path, e))?;
            let mut chart = ChartBuilder::on(&root)
                .caption(
                    "Fig. 9: distance estimates (mean ± sd, extremes)",
                    ("sans-serif", 18),
                )
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(0.0..x_hi, 0.0..hi)
                .map_err(|e| failed(path, e))?;
            chart
                .configure_mesh()
                .x_desc("true distance (m)")
                .y_desc("estimated distance (m)")
                .draw()
                .map_err(|e| failed(path, e))?;
            chart
                .draw_series(LineSeries::new(
                    [(0.0, 0.0), (x_hi, x_hi)],
                    BLACK.stroke_width(1),
                ))
                .map_err(|e| failed(path, e))?
                .label("true distance")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
            let methods: [(&str, f64, Pick); 2] = [
                ("RFCH (strongest hypothesis)", -0.06, |r| &r.rfch),
                ("SIFT (median of matches)", 0.06, |r| &r.sift),
            ];
            for (i, (name, dx, pick)) in methods.into_iter().enumerate() {
                let colour = COLOURS[i];
                let stats: Vec<Bar> = rows
                    .iter()
                    .filter_map(|r| {
                        let s = pick(r);
                        Some(Bar {
                            x: r.distance + dx,
                            mean: s.mean?,
                            sd: s.sd?,
                            min: s.min?,
                            max: s.max?,
                        })
                    })
                    .collect();
                // The extremes: a thin line from the smallest to the largest estimate.
                chart
                    .draw_series(stats.iter().map(|s| {
                        PathElement::new(vec![(s.x, s.min), (s.x, s.max)], colour.stroke_width(1))
                    }))
                    .map_err(|e| failed(path, e))?;
                // One standard deviation about the mean: a thick bar with caps.
                chart
                    .draw_series(stats.iter().map(|s| {
                        ErrorBar::new_vertical(
                            s.x,
                            (s.mean - s.sd).max(0.0),
                            s.mean,
                            s.mean + s.sd,
                            colour.stroke_width(3),
                            10,
                        )
                    }))
                    .map_err(|e| failed(path, e))?;
                chart
                    .draw_series(LineSeries::new(
                        stats.iter().map(|s| (s.x, s.mean)),
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| failed(path, e))?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
                chart
                    .draw_series(
                        stats
                            .iter()
                            .map(|s| Circle::new((s.x, s.mean), 3, colour.filled())),
                    )
                    .map_err(|e| failed(path, e))?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| failed(path, e))?;
            root.present().map_err(|e| failed(path, e))?;
        }
        Ok(path.to_path_buf())
    }
}
