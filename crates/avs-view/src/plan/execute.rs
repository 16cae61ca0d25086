//! Executing a view plan (Sjöö et al. `004` §2.1.4): "visiting the closest navigation graph node
//! that has a view being part of the list, performing object search for all its views, then
//! moving on to the next closest node and so on. If an object known to be unique is found during
//! search, it is eliminated from the plan; if any views in the plan are rendered empty by this,
//! they can be removed as well … which operation has linear time complexity."

use super::ViewPlan;

/// The order to take the plan's views in, as indices into `plan.views`: from `start`, the
/// closest standpoint with views left by `distance(from, to)` (the straight line, or a path
/// length), all of its views, then the next closest from there. Ties go to the standpoint
/// planned first.
pub fn nearest_first(
    plan: &ViewPlan,
    start: [f64; 2],
    distance: impl Fn([f64; 2], [f64; 2]) -> f64,
) -> Vec<usize> {
    // Standpoints in the order first planned, each with its views in plan order.
    let mut groups: Vec<([f64; 2], Vec<usize>)> = Vec::new();
    for (i, v) in plan.views.iter().enumerate() {
        match groups.iter_mut().find(|(at, _)| *at == v.at) {
            Some((_, views)) => views.push(i),
            None => groups.push((v.at, vec![i])),
        }
    }
    let mut order = Vec::with_capacity(plan.views.len());
    let mut here = start;
    while !groups.is_empty() {
        let next = groups
            .iter()
            .enumerate()
            .map(|(g, (at, _))| (g, distance(here, *at)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|(g, _)| g)
            .unwrap_or(0);
        let (at, views) = groups.remove(next);
        order.extend(views);
        here = at;
    }
    order
}

/// Remove class `class` (an index into the problem's classes) from every view, and the views
/// left looking for nothing: a unique object was found (linear in the plan's size).
pub fn drop_class(plan: &mut ViewPlan, class: usize) {
    for v in &mut plan.views {
        v.classes.retain(|c| *c != class);
        v.pairs.retain(|p| p.class != class);
    }
    plan.views.retain(|v| !v.classes.is_empty());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{Pair, View};

    fn view(at: [f64; 2], classes: &[usize]) -> View {
        View {
            standpoint: 0,
            at,
            yaw: 0.0,
            tilt: 0.0,
            zoom: 1.0,
            classes: classes.to_vec(),
            pairs: classes
                .iter()
                .map(|&c| Pair { class: c, cell: 0 })
                .collect(),
            unit: 0,
        }
    }

    fn straight(a: [f64; 2], b: [f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    #[test]
    fn views_are_taken_standpoint_by_standpoint_nearest_first() {
        let plan = ViewPlan {
            views: vec![
                view([5.0, 0.0], &[0]),
                view([1.0, 0.0], &[0]),
                view([5.0, 0.0], &[1]),
                view([3.0, 0.0], &[1]),
                view([1.0, 0.0], &[1]),
            ],
            uncoverable: vec![],
            coverage: vec![1.0, 1.0],
        };
        assert_eq!(
            nearest_first(&plan, [0.0, 0.0], straight),
            vec![1, 4, 3, 0, 2]
        );
        // From the far end the order reverses, each standpoint's views together.
        assert_eq!(
            nearest_first(&plan, [6.0, 0.0], straight),
            vec![0, 2, 3, 1, 4]
        );
        // A path length may say otherwise: here the far standpoint is the closest.
        let odd = |a: [f64; 2], b: [f64; 2]| if b[0] == 5.0 { 0.1 } else { straight(a, b) };
        assert_eq!(nearest_first(&plan, [0.0, 0.0], odd)[..2], [0, 2]);
    }

    #[test]
    fn a_found_unique_class_leaves_the_plan_and_empty_views_go() {
        let mut plan = ViewPlan {
            views: vec![
                view([0.0, 0.0], &[0, 1]),
                view([1.0, 0.0], &[0]),
                view([2.0, 0.0], &[1]),
            ],
            uncoverable: vec![],
            coverage: vec![1.0, 1.0],
        };
        drop_class(&mut plan, 0);
        assert_eq!(plan.views.len(), 2);
        assert!(plan.views.iter().all(|v| v.classes == vec![1]));
        assert!(plan
            .views
            .iter()
            .all(|v| v.pairs.iter().all(|p| p.class == 1)));
    }
}
