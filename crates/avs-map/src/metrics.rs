//! Scoring a room segmentation against ground truth.
//!
//! Independent of the segmentation code: it sees two label arrays of equal length (segment
//! labels and truth room labels, 0 = none) and nothing else. Definitions follow Bormann et al.,
//! *Room segmentation: survey, implementation, and analysis* (ICRA 2016, §IV-A), with Matthews'
//! correlation as a third view (Mielle, Magnusson, Lilienthal, *A method to segment maps from
//! different modalities using free space layout — MAORIS*, ICRA 2018).
//!
//! Let the *domain* be the cells inside some truth room (truth label ≠ 0); cells outside it
//! (walls, the lines drawn across doorways, unknown space) are not scored. Over the domain, let
//! `n_ij` be the overlap matrix: cells of segment `i` in truth room `j`; `a_i = Σ_j n_ij` the
//! size of segment `i` inside the domain, `b_j = Σ_i n_ij` that of room `j` (segment 0,
//! "unlabelled", counts in `b_j` but is never a segment).
//!
//! * per-room recall of room `j`: `max_i n_ij / b_j` (share of the room covered by its
//!   best-matching segment); `recall_per_room` is its mean over truth rooms;
//! * per-room precision of segment `i`: `max_j n_ij / a_i` (share of the segment inside its
//!   best-matching room); `precision_per_room` is its mean over segments with `a_i > 0`;
//! * pooled per pixel: `recall_pixel = Σ_j max_i n_ij / Σ_j b_j`,
//!   `precision_pixel = Σ_i max_j n_ij / Σ_i a_i`;
//! * MCC: Matthews' correlation of the pair-counting confusion matrix — every unordered pair
//!   of domain cells is a positive if both lie in the same segment and a true case if both lie
//!   in the same truth room (unlabelled cells are singletons). With `TP = Σ_ij C(n_ij, 2)`,
//!   `P = Σ_i C(a_i, 2)`, `T = Σ_j C(b_j, 2)`, `N = C(Σ_j b_j, 2)`: `FP = P − TP`,
//!   `FN = T − TP`, `TN = N − TP − FP − FN` and
//!   `MCC = (TP·TN − FP·FN) / √((TP+FP)(TP+FN)(TN+FP)(TN+FN))` (0 when a factor vanishes).
//!   It penalises over- and under-segmentation alike; this pairwise reading is ours (Mielle et
//!   al. do not spell out how segments are matched).
//!
//! Truth images ([`load_truth_image`]): connected white regions (every channel ≥ 250) of more
//! than 100 px, found by 8-connected flood fill, as the benchmark's own tooling does.
//!
//! ```
//! use avs_map::metrics::score;
//! let truth = [1, 1, 1, 2, 2, 2];
//! let seg = [5, 5, 5, 5, 7, 7];
//! let s = score(&seg, &truth).unwrap();
//! assert_eq!(s.truth_rooms, 2);
//! assert!((s.recall_per_room - 5.0 / 6.0).abs() < 1e-12);
//! assert!((s.precision_per_room - 7.0 / 8.0).abs() < 1e-12);
//! ```

use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Errors of scoring.
#[derive(Debug, thiserror::Error)]
pub enum MetricsError {
    /// The two labellings have different sizes.
    #[error("segmentation has {segmentation} cells but the truth has {truth}; expected the same map size")]
    SizeMismatch {
        /// Cells in the segmentation.
        segmentation: usize,
        /// Cells in the truth.
        truth: usize,
    },
    /// The truth image could not be read or decoded.
    #[error("{path}: cannot read ground-truth image: {message}")]
    Image {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
}

/// Scores of a segmentation against truth (see the module docs for definitions).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentationScore {
    /// Segments with at least one cell in the domain.
    pub segments: usize,
    /// Truth rooms.
    pub truth_rooms: usize,
    /// Mean over segments of the share inside the best-matching truth room.
    pub precision_per_room: f64,
    /// Mean over truth rooms of the share covered by the best-matching segment.
    pub recall_per_room: f64,
    /// Pooled precision: cells in their segment's best room over all segmented domain cells.
    pub precision_pixel: f64,
    /// Pooled recall: cells in their room's best segment over all domain cells.
    pub recall_pixel: f64,
    /// Pair-counting Matthews correlation coefficient.
    pub mcc: f64,
    /// Per truth room (ascending label): its recall.
    pub recall_by_room: Vec<f64>,
}

/// Score `segmentation` against `truth` (label arrays in the same cell order; 0 = none).
pub fn score(segmentation: &[u32], truth: &[u32]) -> Result<SegmentationScore, MetricsError> {
    if segmentation.len() != truth.len() {
        return Err(MetricsError::SizeMismatch {
            segmentation: segmentation.len(),
            truth: truth.len(),
        });
    }
    let mut overlap: HashMap<(u32, u32), u64> = HashMap::new();
    let mut seg_size: HashMap<u32, u64> = HashMap::new();
    let mut room_size: HashMap<u32, u64> = HashMap::new();
    for (&s, &t) in segmentation.iter().zip(truth) {
        if t == 0 {
            continue;
        }
        *room_size.entry(t).or_default() += 1;
        if s != 0 {
            *overlap.entry((s, t)).or_default() += 1;
            *seg_size.entry(s).or_default() += 1;
        }
    }
    let mut best_for_seg: HashMap<u32, u64> = HashMap::new();
    let mut best_for_room: HashMap<u32, u64> = HashMap::new();
    for (&(s, t), &n) in &overlap {
        let e = best_for_seg.entry(s).or_default();
        *e = (*e).max(n);
        let e = best_for_room.entry(t).or_default();
        *e = (*e).max(n);
    }
    let mut rooms: Vec<u32> = room_size.keys().copied().collect();
    rooms.sort_unstable();
    let recall_by_room: Vec<f64> = rooms
        .iter()
        .map(|t| best_for_room.get(t).copied().unwrap_or(0) as f64 / room_size[t] as f64)
        .collect();
    let mean = |v: &[f64]| {
        if v.is_empty() {
            0.0
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    let precisions: Vec<f64> = seg_size
        .iter()
        .map(|(s, &a)| best_for_seg[s] as f64 / a as f64)
        .collect();
    let ratio = |num: u64, den: u64| {
        if den == 0 {
            0.0
        } else {
            num as f64 / den as f64
        }
    };
    let domain: u64 = room_size.values().sum();
    let segmented: u64 = seg_size.values().sum();
    let pairs = |n: u64| n as f64 * (n as f64 - 1.0) / 2.0;
    let tp: f64 = overlap.values().map(|&n| pairs(n)).sum();
    let p: f64 = seg_size.values().map(|&n| pairs(n)).sum();
    let t: f64 = room_size.values().map(|&n| pairs(n)).sum();
    let all = pairs(domain);
    let (fp, fneg) = (p - tp, t - tp);
    let tn = all - tp - fp - fneg;
    let den = ((tp + fp) * (tp + fneg) * (tn + fp) * (tn + fneg)).sqrt();
    let mcc = if den > 0.0 {
        (tp * tn - fp * fneg) / den
    } else {
        0.0
    };
    Ok(SegmentationScore {
        segments: seg_size.len(),
        truth_rooms: rooms.len(),
        precision_per_room: mean(&precisions),
        recall_per_room: mean(&recall_by_room),
        precision_pixel: ratio(best_for_seg.values().sum(), segmented),
        recall_pixel: ratio(best_for_room.values().sum(), domain),
        mcc,
        recall_by_room,
    })
}

/// A ground-truth labelling read from an image.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthLabels {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Room of every pixel, bottom row first (the order of `OccupancyGrid::index`); 0 = none.
    pub labels: Vec<u32>,
    /// Number of rooms.
    pub rooms: usize,
}

/// White threshold of the benchmark's truth images.
pub const TRUTH_WHITE: u8 = 250;
/// Regions of at most this many pixels are not rooms.
pub const TRUTH_MIN_PIXELS: usize = 100;

/// Read a ground-truth segmentation image: rooms are the 8-connected regions of white pixels
/// (every colour channel ≥ [`TRUTH_WHITE`]) larger than [`TRUTH_MIN_PIXELS`].
///
/// The image is read within the limits of [`crate::image_io`] (at most
/// [`crate::grid::MAX_CELLS`] pixels, checked from the header before decoding).
pub fn load_truth_image(path: &Path) -> Result<TruthLabels, MetricsError> {
    let img = crate::image_io::open_image(path).map_err(|e| MetricsError::Image {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let rgb = img.to_rgb8();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let mut white = vec![false; w * h];
    for (x, y, p) in rgb.enumerate_pixels() {
        // Bottom row first, as the occupancy grid.
        let row = h - 1 - y as usize;
        white[row * w + x as usize] = p.0.iter().all(|&c| c >= TRUTH_WHITE);
    }
    Ok(truth_from_mask(w, h, &white, TRUTH_MIN_PIXELS))
}

/// Rooms as 8-connected regions of `mask` with more than `min_pixels` cells.
pub fn truth_from_mask(w: usize, h: usize, mask: &[bool], min_pixels: usize) -> TruthLabels {
    let mut labels = vec![0u32; w * h];
    let mut visited = vec![false; w * h];
    let mut rooms = 0u32;
    let mut stack = Vec::new();
    let mut region = Vec::new();
    for start in 0..w * h {
        if !mask[start] || visited[start] {
            continue;
        }
        region.clear();
        visited[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            region.push(i);
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let n = ny as usize * w + nx as usize;
                    if mask[n] && !visited[n] {
                        visited[n] = true;
                        stack.push(n);
                    }
                }
            }
        }
        if region.len() > min_pixels {
            rooms += 1;
            for &i in &region {
                labels[i] = rooms;
            }
        }
    }
    TruthLabels {
        width: w,
        height: h,
        labels,
        rooms: rooms as usize,
    }
}
