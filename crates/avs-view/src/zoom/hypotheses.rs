//! Object hypotheses in a vote matrix (Sjöö et al. `004` §3.2) and the cells associated with
//! each (§3.3.1).
//!
//! What the paper says:
//! * §3.2: "A cell is a hypothesis if its value is higher than those of its 8-connected
//!   neighbors, as well as higher than an object-dependent threshold."
//! * §3.3.1: "cells are considered to be associated with a hypothesis if their degree of match
//!   is above the threshold and if there is an 8-connected path to the hypothesis with cells of
//!   monotonically increasing value"; the width of the bounding box of those cells is the
//!   `D_vote` of the distance estimate, and "only the strongest hypothesis and its associated
//!   8-connected cells are taken into account".
//!
//! ## Choices where the paper is vague
//! * **Strictly higher, and plateaus.** A cell whose value is strictly higher than each of its
//!   (up to 8, fewer at the borders and corners) neighbours and strictly higher than the
//!   threshold is a hypothesis — the paper's rule. Read literally, that rule gives *no*
//!   hypothesis for a flat maximum: two or more equal neighbouring cells with nothing higher
//!   around them, as a saturated attention gives when an object covers several cells
//!   completely. That would lose exactly the objects that are largest in the image, so a
//!   *plateau* — an 8-connected set of cells of exactly equal value above the threshold none
//!   of which has a strictly higher neighbour — counts as one maximum, and its hypothesis is
//!   the plateau cell nearest the plateau's centroid (ties to the smaller row, then the smaller
//!   column). Where no two neighbours are equal this is the paper's rule exactly; a plateau
//!   with a strictly higher neighbour anywhere along it is a shoulder, not a maximum, and gives
//!   nothing. Values are compared exactly (no tolerance).
//! * **Monotonically increasing, non-strictly.** A cell is associated with a hypothesis when
//!   it is above the threshold and a path of 8-connected cells leads from it to the hypothesis
//!   whose values never decrease on the way (each step towards the peak is `≥` the previous):
//!   the flood fill goes downhill from the peak and may walk along flat stretches. With strict
//!   increase a saturated object would be associated with its peak cell alone and its
//!   distance overestimated by its width in cells. A cell may be associated with several
//!   hypotheses (two peaks on one ridge); each keeps its own bounding box.
//! * **Order.** Hypotheses come strongest first, ties by row, then column (top-left first).

use super::error::ZoomError;
use avs_robot::{ImageGeometry, VoteMatrix};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// One object hypothesis: a local maximum of a class's vote matrix above the class's threshold
/// (§3.2), with the bounding box of its associated cells (§3.3.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hypothesis {
    /// The class whose vote matrix it came from.
    pub class: String,
    /// Column of its peak cell (from the left).
    pub col: usize,
    /// Row of its peak cell (from the top).
    pub row: usize,
    /// The vote value of its peak cell.
    pub value: f64,
    /// Inclusive bounding box of the cells associated with it, in cell indices: first column.
    pub min_col: usize,
    /// First row of the bounding box.
    pub min_row: usize,
    /// Last column of the bounding box (inclusive).
    pub max_col: usize,
    /// Last row of the bounding box (inclusive).
    pub max_row: usize,
}

impl Hypothesis {
    /// The centre of its peak cell, pixels `(u, v)` from the image's top-left corner.
    pub fn centre_px(&self, image: &ImageGeometry) -> (f64, f64) {
        image.cell_centre(self.col, self.row)
    }

    /// The width in pixels of the bounding box of its associated cells: `D_vote` of §3.3.1,
    /// `(max_col − min_col + 1) × cell_px`.
    pub fn vote_width_px(&self, image: &ImageGeometry) -> f64 {
        (self.max_col.saturating_sub(self.min_col) + 1) as f64 * f64::from(image.cell_px)
    }

    /// The bounding box of its associated cells in pixels, `[u0, v0, u1, v1]` (left, top,
    /// right, bottom edges of the outermost cells).
    pub fn vote_box_px(&self, image: &ImageGeometry) -> [f64; 4] {
        let c = f64::from(image.cell_px);
        [
            self.min_col as f64 * c,
            self.min_row as f64 * c,
            (self.max_col + 1) as f64 * c,
            (self.max_row + 1) as f64 * c,
        ]
    }

    /// The centre of [`Hypothesis::vote_box_px`]: where the associated cells say the object is.
    pub fn vote_box_centre_px(&self, image: &ImageGeometry) -> (f64, f64) {
        let [u0, v0, u1, v1] = self.vote_box_px(image);
        ((u0 + u1) / 2.0, (v0 + v1) / 2.0)
    }
}

/// The 8-connected neighbours of `(col, row)` inside a `cols × rows` grid.
fn neighbours(
    col: usize,
    row: usize,
    cols: usize,
    rows: usize,
) -> impl Iterator<Item = (usize, usize)> {
    (-1i64..=1)
        .flat_map(|dr| (-1i64..=1).map(move |dc| (dc, dr)))
        .filter(|&(dc, dr)| dc != 0 || dr != 0)
        .filter_map(move |(dc, dr)| {
            let (c, r) = (col as i64 + dc, row as i64 + dr);
            (c >= 0 && r >= 0 && (c as usize) < cols && (r as usize) < rows)
                .then_some((c as usize, r as usize))
        })
}

/// The hypotheses of a class's vote matrix above `threshold`, strongest first (module docs:
/// strict local maxima, one per flat maximum, each with the bounding box of its associated
/// cells). An empty matrix has none.
///
/// Errors: a malformed matrix ([`VoteMatrix::problem`]) or a NaN threshold.
pub fn hypotheses(votes: &VoteMatrix, threshold: f64) -> Result<Vec<Hypothesis>, ZoomError> {
    if let Some(message) = votes.problem() {
        return Err(ZoomError::MalformedVotes {
            class: votes.class.clone(),
            message,
        });
    }
    if threshold.is_nan() {
        return Err(ZoomError::InvalidInput {
            field: "threshold",
            message: "the vote threshold is NaN; expected a number".into(),
        });
    }
    let (cols, rows) = (votes.cols, votes.rows);
    let value = |c: usize, r: usize| votes.values[r * cols + c];
    let mut seen = vec![false; cols * rows];
    let mut out = Vec::new();
    for row in 0..rows {
        for col in 0..cols {
            let v = value(col, row);
            if seen[row * cols + col] || v <= threshold {
                continue;
            }
            // The plateau of equal cells through (col, row), and whether anything around it is
            // higher.
            let mut plateau = vec![(col, row)];
            let mut queue = VecDeque::from([(col, row)]);
            seen[row * cols + col] = true;
            let mut shoulder = false;
            while let Some((c, r)) = queue.pop_front() {
                for (nc, nr) in neighbours(c, r, cols, rows) {
                    let nv = value(nc, nr);
                    if nv > v {
                        shoulder = true;
                    } else if nv == v && !seen[nr * cols + nc] {
                        seen[nr * cols + nc] = true;
                        plateau.push((nc, nr));
                        queue.push_back((nc, nr));
                    }
                }
            }
            if shoulder {
                continue;
            }
            let n = plateau.len() as f64;
            let cx = plateau.iter().map(|p| p.0 as f64).sum::<f64>() / n;
            let cy = plateau.iter().map(|p| p.1 as f64).sum::<f64>() / n;
            let d2 = |&(c, r): &(usize, usize)| (c as f64 - cx).powi(2) + (r as f64 - cy).powi(2);
            let peak = plateau
                .iter()
                .copied()
                .min_by(|a, b| d2(a).total_cmp(&d2(b)).then((a.1, a.0).cmp(&(b.1, b.0))))
                .unwrap_or((col, row));
            out.push(associated(votes, threshold, peak));
        }
    }
    out.sort_by(|a, b| {
        b.value
            .total_cmp(&a.value)
            .then(a.row.cmp(&b.row))
            .then(a.col.cmp(&b.col))
    });
    Ok(out)
}

/// The hypothesis at `peak` with the bounding box of its associated cells: a flood fill from the
/// peak to neighbours above the threshold whose value is not higher than the cell it is
/// reached from (module docs).
fn associated(votes: &VoteMatrix, threshold: f64, (col, row): (usize, usize)) -> Hypothesis {
    let (cols, rows) = (votes.cols, votes.rows);
    let value = |c: usize, r: usize| votes.values[r * cols + c];
    let mut h = Hypothesis {
        class: votes.class.clone(),
        col,
        row,
        value: value(col, row),
        min_col: col,
        min_row: row,
        max_col: col,
        max_row: row,
    };
    let mut seen = vec![false; cols * rows];
    seen[row * cols + col] = true;
    let mut queue = VecDeque::from([(col, row)]);
    while let Some((c, r)) = queue.pop_front() {
        h.min_col = h.min_col.min(c);
        h.max_col = h.max_col.max(c);
        h.min_row = h.min_row.min(r);
        h.max_row = h.max_row.max(r);
        let v = value(c, r);
        for (nc, nr) in neighbours(c, r, cols, rows) {
            let nv = value(nc, nr);
            if !seen[nr * cols + nc] && nv > threshold && nv <= v {
                seen[nr * cols + nc] = true;
                queue.push_back((nc, nr));
            }
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix from rows of values (top row first).
    fn matrix(rows: &[&[f64]]) -> VoteMatrix {
        VoteMatrix {
            class: "book".into(),
            cols: rows[0].len(),
            rows: rows.len(),
            values: rows.iter().flat_map(|r| r.iter().copied()).collect(),
        }
    }

    fn peaks(h: &[Hypothesis]) -> Vec<(usize, usize)> {
        h.iter().map(|h| (h.col, h.row)).collect()
    }

    #[test]
    fn strict_local_maxima_above_the_threshold_are_hypotheses_strongest_first() {
        let m = matrix(&[
            &[0.1, 0.2, 0.1, 0.0, 0.0],
            &[0.2, 0.6, 0.3, 0.0, 0.4],
            &[0.1, 0.3, 0.2, 0.0, 0.3],
            &[0.0, 0.0, 0.0, 0.9, 0.0],
        ]);
        let h = hypotheses(&m, 0.35).unwrap();
        // (1,1) = 0.6 and (4,1) = 0.4 beat all their neighbours; (3,3) = 0.9 is the strongest.
        assert_eq!(peaks(&h), vec![(3, 3), (1, 1), (4, 1)]);
        assert_eq!(h[0].value, 0.9);
        assert!(h.iter().all(|h| h.class == "book"));
        // Raising the threshold above 0.4 drops the weakest; above 0.9 drops all.
        assert_eq!(peaks(&hypotheses(&m, 0.4).unwrap()), vec![(3, 3), (1, 1)]);
        assert!(hypotheses(&m, 0.9).unwrap().is_empty());
    }

    #[test]
    fn a_maximum_on_the_border_or_in_a_corner_is_a_hypothesis() {
        let m = matrix(&[&[0.8, 0.1, 0.1], &[0.1, 0.1, 0.7], &[0.1, 0.1, 0.1]]);
        let h = hypotheses(&m, 0.35).unwrap();
        assert_eq!(peaks(&h), vec![(0, 0), (2, 1)]);
    }

    #[test]
    fn a_cell_beaten_by_a_neighbour_and_a_plateau_touching_a_higher_cell_are_no_hypotheses() {
        // (1,1) = 0.6 is beaten by (2,1) = 0.7; the plateau (0,0)-(1,0) of 0.5 touches 0.6.
        let m = matrix(&[&[0.5, 0.5, 0.1], &[0.1, 0.6, 0.7], &[0.1, 0.1, 0.1]]);
        let h = hypotheses(&m, 0.35).unwrap();
        assert_eq!(peaks(&h), vec![(2, 1)]);
    }

    #[test]
    fn a_flat_maximum_gives_one_hypothesis_at_its_middle_and_a_shoulder_none() {
        // A 3 × 3 plateau of 1.0 (a saturated object) in a 5 × 5 matrix: one hypothesis at its
        // centre cell.
        let mut rows = vec![vec![0.2; 5]; 5];
        for row in rows.iter_mut().take(4).skip(1) {
            for v in row.iter_mut().take(4).skip(1) {
                *v = 1.0;
            }
        }
        let refs: Vec<&[f64]> = rows.iter().map(|r| r.as_slice()).collect();
        let h = hypotheses(&matrix(&refs), 0.35).unwrap();
        assert_eq!(peaks(&h), vec![(2, 2)]);
        // An even plateau (two cells) takes the top-left of the two middle cells.
        let m = matrix(&[&[0.1, 0.8, 0.8, 0.1]]);
        assert_eq!(peaks(&hypotheses(&m, 0.35).unwrap()), vec![(1, 0)]);
        // A plateau with a higher cell at one end is a shoulder: only that cell.
        let m = matrix(&[&[0.8, 0.8, 0.8, 0.9]]);
        assert_eq!(peaks(&hypotheses(&m, 0.35).unwrap()), vec![(3, 0)]);
        // The same plateau below the threshold gives nothing.
        let m = matrix(&[&[0.3, 0.3, 0.3]]);
        assert!(hypotheses(&m, 0.35).unwrap().is_empty());
    }

    #[test]
    fn equal_hypotheses_are_ordered_top_left_first() {
        let m = matrix(&[
            &[0.1, 0.1, 0.1, 0.1, 0.1],
            &[0.7, 0.1, 0.1, 0.1, 0.7],
            &[0.1, 0.1, 0.7, 0.1, 0.1],
        ]);
        assert_eq!(
            peaks(&hypotheses(&m, 0.35).unwrap()),
            vec![(0, 1), (4, 1), (2, 2)]
        );
    }

    #[test]
    fn associated_cells_run_downhill_from_the_peak_above_the_threshold() {
        let m = matrix(&[
            &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            &[0.0, 0.4, 0.5, 0.6, 0.0, 0.0],
            &[0.0, 0.5, 0.9, 0.7, 0.2, 0.5],
            &[0.0, 0.0, 0.6, 0.8, 0.0, 0.45],
            &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ]);
        let h = hypotheses(&m, 0.35).unwrap();
        assert_eq!(peaks(&h), vec![(2, 2), (5, 2)]);
        let top = &h[0];
        // Everything above 0.35 around the peak, but not the separate (5, 2)-(5, 3) blob
        // (reached only through 0.2, below the threshold).
        assert_eq!(
            (top.min_col, top.min_row, top.max_col, top.max_row),
            (1, 1, 3, 3)
        );
        let g = ImageGeometry::default();
        assert_eq!(top.vote_width_px(&g), 45.0);
        assert_eq!(top.vote_box_px(&g), [15.0, 15.0, 60.0, 60.0]);
        assert_eq!(top.centre_px(&g), (37.5, 37.5));
        assert_eq!(top.vote_box_centre_px(&g), (37.5, 37.5));
        let low = &h[1];
        assert_eq!(
            (low.min_col, low.min_row, low.max_col, low.max_row),
            (5, 2, 5, 3)
        );
    }

    #[test]
    fn an_uphill_step_away_from_the_peak_ends_the_associated_region() {
        // From the peak 0.9 down to 0.5, then up to 0.6 (another peak's slope): the 0.6 cell
        // and beyond are not associated with the first peak.
        let m = matrix(&[&[0.9, 0.5, 0.6, 0.95]]);
        let h = hypotheses(&m, 0.35).unwrap();
        assert_eq!(peaks(&h), vec![(3, 0), (0, 0)]);
        let first = h.iter().find(|h| h.col == 0).unwrap();
        assert_eq!((first.min_col, first.max_col), (0, 1));
        // The strongest runs down through 0.6 and 0.5 (non-increasing away from it) but not up
        // to 0.9.
        assert_eq!((h[0].min_col, h[0].max_col), (1, 3));
    }

    #[test]
    fn a_flat_region_is_associated_with_its_plateau_hypothesis() {
        let m = matrix(&[&[0.1, 1.0, 1.0, 1.0, 1.0, 0.5, 0.1]]);
        let h = hypotheses(&m, 0.35).unwrap();
        assert_eq!(h.len(), 1);
        assert_eq!((h[0].min_col, h[0].max_col), (1, 5));
    }

    #[test]
    fn malformed_matrices_and_a_nan_threshold_are_errors_and_an_empty_matrix_has_none() {
        let mut m = matrix(&[&[0.1, 0.9]]);
        m.values[0] = f64::NAN;
        assert!(matches!(
            hypotheses(&m, 0.35),
            Err(ZoomError::MalformedVotes { .. })
        ));
        m.values = vec![0.1];
        assert!(matches!(
            hypotheses(&m, 0.35),
            Err(ZoomError::MalformedVotes { .. })
        ));
        let ok = matrix(&[&[0.1, 0.9]]);
        assert!(matches!(
            hypotheses(&ok, f64::NAN),
            Err(ZoomError::InvalidInput { .. })
        ));
        assert!(hypotheses(&VoteMatrix::zeros("x", 0, 0), 0.35)
            .unwrap()
            .is_empty());
        assert_eq!(hypotheses(&ok, f64::NEG_INFINITY).unwrap().len(), 1);
    }
}
