//! The heights at which an object is looked for: the tops of the surfaces it rests on.

use crate::surface::surface_classes;
use avs_format::knowledge::{Knowledge, ObjectClass};

/// The heights at which an object of `class` is looked for in a room: half its height for
/// furniture; for a small object, the tops of the landmark classes the knowledge puts it
/// *on* (the lowest and the highest, or their middle when less than `height_step` apart; the
/// detector sees an object at its surface plus half its height), or `small_object_z` when
/// the knowledge names none. With `cover` (a coverage that looks wherever an object may rest
/// because the knowledge has proved wrong): the tops of every [`surface_classes`] instead of
/// the class's own, and the floor (where the rates "anywhere in a room" may put it).
pub fn search_heights(
    knowledge: &Knowledge,
    class: &ObjectClass,
    cover: bool,
    height_step: f64,
    small_object_z: f64,
) -> Vec<f64> {
    let half = 0.5 * class.size[2];
    if class.landmark {
        return vec![half];
    }
    let of = (!cover).then_some(class.name.as_str());
    let tops: Vec<f64> = surface_classes(knowledge, of)
        .into_iter()
        .filter_map(|l| knowledge.class(l))
        .map(|l| l.size[2] + half)
        .collect();
    let lo = tops.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = tops.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut zs = if tops.is_empty() {
        vec![small_object_z]
    } else if hi - lo < height_step {
        vec![0.5 * (lo + hi)]
    } else {
        vec![lo, hi]
    };
    if cover {
        zs.insert(0, half);
    }
    zs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::tests::office;

    const STEP: f64 = 0.2;
    const SMALL_Z: f64 = 0.8;

    #[test]
    fn search_heights_are_the_tops_of_the_surfaces_the_knowledge_names() {
        let k = office();
        let class = |n: &str| k.class(n).unwrap().clone();
        // A cereal box lies on tables (0.75 m) and counters (0.9 m); seen at its middle, 0.14 m
        // up; the two tops are less than the step apart: one height, their middle.
        let cereal = search_heights(&k, &class("cerealbox"), false, STEP, SMALL_Z);
        assert_eq!(cereal.len(), 1);
        assert!((cereal[0] - (0.825 + 0.14)).abs() < 1e-9, "{cereal:?}");
        // With the floor: half its height first.
        let with_floor = search_heights(&k, &class("cerealbox"), true, STEP, SMALL_Z);
        assert!((with_floor[0] - 0.14).abs() < 1e-9, "{with_floor:?}");
        assert_eq!(&with_floor[1..], &cereal[..]);
        // Furniture is looked for at half its height, with or without the floor.
        assert_eq!(
            search_heights(&k, &class("table"), true, STEP, SMALL_Z),
            vec![0.375]
        );
        // A stapler lies on desks only (its desk rate; the shelf is "in").
        let stapler = search_heights(&k, &class("stapler"), false, STEP, SMALL_Z);
        assert_eq!(stapler.len(), 1);
        assert!((stapler[0] - (0.75 + 0.035)).abs() < 1e-9, "{stapler:?}");
        // With a step below the tops' difference, both tops.
        assert_eq!(
            search_heights(&k, &class("cerealbox"), false, 0.1, SMALL_Z).len(),
            2
        );
    }

    #[test]
    fn the_coverage_looks_on_every_surface_and_the_floor() {
        let k = office();
        let stapler = k.class("stapler").unwrap().clone();
        // Staplers lie on desks (0.75 m) by the knowledge; the coverage also looks on tables
        // (0.75 m) and counters (0.9 m), less than the step apart: their middle, and the
        // floor first.
        let h = search_heights(&k, &stapler, true, STEP, SMALL_Z);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!((h[0] - 0.035).abs() < 1e-9, "{h:?}");
        assert!((h[1] - (0.5 * (0.75 + 0.9) + 0.035)).abs() < 1e-9, "{h:?}");
    }

    #[test]
    fn an_object_the_knowledge_puts_on_nothing_is_looked_for_at_the_default_height() {
        let mut k = office();
        k.landmark_rates.retain(|r| r.object != "stapler");
        let stapler = k.class("stapler").unwrap().clone();
        assert_eq!(
            search_heights(&k, &stapler, false, STEP, SMALL_Z),
            vec![SMALL_Z]
        );
    }
}
