//! What the camera's image pipeline sees (Sjöö et al. `004` §3): the attention's vote matrices
//! and a recognition's matched features, in pixels of one image.
//!
//! The agent's zoom pipeline (`avs_view::zoom`) turns these into hypotheses, distance
//! estimates, zoom windows and recognised objects; a robot only reports what its attention
//! and its recogniser computed on the image a [`crate::ViewCone`] took.

use serde::{Deserialize, Serialize};

/// The image geometry: size in pixels and the side of the attention's square vote cells.
///
/// The paper's camera gives 320 × 240 images, divided into 15 × 15 px vote cells (§3.2); an
/// image holds `width_px / cell_px` × `height_px / cell_px` whole cells (21 × 16), the
/// remainder at the right and bottom edges is not voted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ImageGeometry {
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// Side of one vote cell, pixels.
    pub cell_px: u32,
}

impl Default for ImageGeometry {
    /// The paper's 320 × 240 images with 15 × 15 px vote cells.
    fn default() -> Self {
        Self {
            width_px: 320,
            height_px: 240,
            cell_px: 15,
        }
    }
}

impl ImageGeometry {
    /// Vote cells per row (whole cells only).
    pub fn cols(&self) -> usize {
        (self.width_px / self.cell_px.max(1)) as usize
    }

    /// Vote cells per column (whole cells only).
    pub fn rows(&self) -> usize {
        (self.height_px / self.cell_px.max(1)) as usize
    }

    /// The centre of vote cell `(col, row)` in pixels from the top-left corner.
    pub fn cell_centre(&self, col: usize, row: usize) -> (f64, f64) {
        let c = f64::from(self.cell_px);
        ((col as f64 + 0.5) * c, (row as f64 + 0.5) * c)
    }

    /// Focal length in pixels of an image whose horizontal field of view is `hfov` radians
    /// (a pinhole camera: `width / (2 tan(hfov / 2))`).
    pub fn focal_px(&self, hfov: f64) -> f64 {
        f64::from(self.width_px) / (2.0 * (hfov / 2.0).tan())
    }

    /// Why this geometry is unusable, if it is: a zero size, or cells larger than the image.
    pub fn problem(&self) -> Option<String> {
        if self.width_px == 0 || self.height_px == 0 || self.cell_px == 0 {
            return Some(format!(
                "image sizes must be positive, got {} × {} px with {} px cells",
                self.width_px, self.height_px, self.cell_px
            ));
        }
        if self.cell_px > self.width_px.min(self.height_px) {
            return Some(format!(
                "a {} px vote cell does not fit a {} × {} px image",
                self.cell_px, self.width_px, self.height_px
            ));
        }
        None
    }
}

/// One class's attention map over one image: the similarity of each vote cell's histogram to
/// the class's training histograms (the paper's RFCH *vote matrix*, §3.2), higher where the
/// class is more likely. Values are similarities in `[0, 1]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VoteMatrix {
    /// The object class the cells were matched against.
    pub class: String,
    /// Cells per row.
    pub cols: usize,
    /// Cells per column.
    pub rows: usize,
    /// `cols × rows` values, row by row from the top-left cell.
    pub values: Vec<f64>,
}

impl VoteMatrix {
    /// A matrix of zeros.
    pub fn zeros(class: impl Into<String>, cols: usize, rows: usize) -> Self {
        Self {
            class: class.into(),
            cols,
            rows,
            values: vec![0.0; cols * rows],
        }
    }

    /// The value of cell `(col, row)`; `None` outside the matrix.
    pub fn get(&self, col: usize, row: usize) -> Option<f64> {
        (col < self.cols && row < self.rows)
            .then(|| self.values.get(row * self.cols + col).copied())
            .flatten()
    }

    /// Why this matrix is unusable, if it is: a value count that is not `cols × rows`, or a
    /// value that is not a finite number.
    pub fn problem(&self) -> Option<String> {
        if self.values.len() != self.cols * self.rows {
            return Some(format!(
                "{} values for a {} × {} vote matrix (expected {})",
                self.values.len(),
                self.cols,
                self.rows,
                self.cols * self.rows
            ));
        }
        self.values
            .iter()
            .position(|v| !v.is_finite())
            .map(|i| format!("vote value {i} is not a finite number"))
    }
}

/// What the attention computed on one image ([`crate::Robot::attention`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttentionReport {
    /// The robot pose the image was taken from (after moving there).
    pub pose: crate::Pose2D,
    /// Distance travelled to reach that pose, metres.
    pub travelled: f64,
    /// The image's size and vote cells.
    pub image: ImageGeometry,
    /// One vote matrix per class asked for, in the order asked.
    pub votes: Vec<VoteMatrix>,
    /// Processing time of the image (capture and attention), seconds.
    pub seconds: f64,
}

/// One feature of the class's model matched in the image (the paper's SIFT matches, §3.3.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FeatureMatch {
    /// Horizontal image position, pixels from the left edge.
    pub u: f64,
    /// Vertical image position, pixels from the top edge.
    pub v: f64,
    /// The matched keypoint's scale in this image over its scale in the training image,
    /// `S_real / S_tr`: the apparent size of the object relative to its training image.
    pub scale_ratio: f64,
}

/// What the recogniser found on one image for one class ([`crate::Robot::recognise`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecognitionReport {
    /// The robot pose the image was taken from (after moving there).
    pub pose: crate::Pose2D,
    /// Distance travelled to reach that pose, metres.
    pub travelled: f64,
    /// The image's size.
    pub image: ImageGeometry,
    /// The class matched against.
    pub class: String,
    /// Features in the class's model (the training image's keypoints).
    pub model_features: u32,
    /// The model features matched in this image, possibly none; mismatches included.
    pub matches: Vec<FeatureMatch>,
    /// Processing time of the image (capture and recognition), seconds.
    pub seconds: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_image_holds_21_by_16_whole_vote_cells() {
        let g = ImageGeometry::default();
        assert_eq!((g.cols(), g.rows()), (21, 16));
        assert_eq!(g.cell_centre(0, 0), (7.5, 7.5));
        assert!(g.problem().is_none());
        let bad = ImageGeometry { cell_px: 300, ..g };
        assert!(bad.problem().unwrap().contains("does not fit"));
    }

    #[test]
    fn focal_length_puts_the_field_of_view_edge_at_the_image_edge() {
        let g = ImageGeometry::default();
        let f = g.focal_px(60f64.to_radians());
        // A point 30° off the axis lands on the image's edge, half the width from its centre.
        assert!((f * 30f64.to_radians().tan() - 160.0).abs() < 1e-9);
    }

    #[test]
    fn vote_matrix_with_the_wrong_value_count_or_a_nan_is_a_problem() {
        let mut m = VoteMatrix::zeros("book", 3, 2);
        assert!(m.problem().is_none());
        assert_eq!(m.get(2, 1), Some(0.0));
        assert_eq!(m.get(3, 0), None);
        m.values[4] = f64::NAN;
        assert!(m.problem().unwrap().contains("vote value 4"));
        m.values.pop();
        assert!(m.problem().unwrap().contains("expected 6"));
    }
}
