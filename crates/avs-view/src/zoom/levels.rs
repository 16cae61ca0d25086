//! Zoom levels for view planning (Sjöö et al. `004` §3.4: at zoom `z` the fields of view are
//! divided by `z` and the detection distances multiplied by it).

/// The zoom levels view planning may use with a camera zooming up to `max_zoom`: 1, 2, 4, …
/// (each doubles the distance at which a small object is detected and halves the fields of
/// view; [`create_view_cones_zoomed`](crate::create_view_cones_zoomed) plans a level only for
/// the points the lower ones cannot cover, such as a small object on the floor beyond its
/// unzoomed range). At most 8 levels; a camera without zoom (or a nonsense maximum) has 1.
pub fn view_zooms(max_zoom: f64) -> Vec<f64> {
    std::iter::successors(Some(1.0), |z| Some(z * 2.0))
        .take_while(|z| *z <= max_zoom.max(1.0) + 1e-9)
        .take(8)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_zooms_double_from_one_up_to_the_cameras_maximum() {
        assert_eq!(view_zooms(4.0), vec![1.0, 2.0, 4.0]);
        assert_eq!(view_zooms(3.0), vec![1.0, 2.0]);
        assert_eq!(view_zooms(1.0), vec![1.0]);
        assert_eq!(view_zooms(0.5), vec![1.0]);
        assert_eq!(view_zooms(f64::NAN), vec![1.0]);
        assert_eq!(view_zooms(1e6).len(), 8);
    }
}
