//! The properties a scenario expects of its goal's search (`avs_format::scenario::Expect`),
//! read off the trace: the plans' listing lines (the papers' form), the executed searches, and
//! the true rooms of the robot's poses and views (the world's ground truth, which only the
//! judge sees).

use super::ScenarioRun;
use avs_agent::Event;
use avs_format::scenario::Scenario;
use avs_sim::score::{report_error, SUCCESS_RADIUS};
use avs_sim::World;
use serde::Serialize;

fn plans(trace: &[Event]) -> impl Iterator<Item = &Vec<String>> {
    trace.iter().filter_map(|e| match e {
        Event::PlanMade { steps, .. } => Some(steps),
        _ => None,
    })
}

/// The true room of a point, by name.
pub fn room_name(world: &World, x: f64, y: f64) -> Option<String> {
    world.room_at(x, y).map(|i| world.env.rooms[i].name.clone())
}

/// The true rooms along the robot's trail (every position it passed, at most 0.25 m apart),
/// with consecutive repeats merged; positions in no room (door cells) are skipped. (Sampled
/// at action ends only, a MOVE from an office through the corridor into the kitchen read as
/// office → kitchen.)
pub fn rooms_along_path(world: &World, trail: &[[f64; 2]]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in trail.iter().filter_map(|p| room_name(world, p[0], p[1])) {
        if out.last() != Some(&r) {
            out.push(r);
        }
    }
    out
}

/// The true rooms of the processed view cones, in order, consecutive repeats merged.
pub fn view_rooms(world: &World, trace: &[Event]) -> Vec<String> {
    trace
        .iter()
        .filter_map(|e| match e {
            Event::DtAction {
                action,
                view: Some(v),
                ..
            } if action.starts_with("PROCESSVIEWCONE") => Some((v.x, v.y)),
            _ => None,
        })
        .map(|(x, y)| room_name(world, x, y).unwrap_or_else(|| "a doorway".into()))
        .fold(Vec::new(), |mut v: Vec<String>, r| {
            if v.last() != Some(&r) {
                v.push(r);
            }
            v
        })
}

/// Executed SEARCHFOROBJECT steps as `(searched class, landmark class if ON)`. The landmark's
/// class comes from the listing of the plan being executed: its ASSUME-OBJECT-EXISTS
/// `<class> ON <lm> <lm-class> <category>` line, or the `SEARCHFOROBJECT <lm-class> IN <room>
/// <lm>` step that finds the landmark.
pub fn searches(trace: &[Event]) -> Vec<(String, Option<String>)> {
    let mut plan: &[String] = &[];
    let mut out = Vec::new();
    for e in trace {
        match e {
            Event::PlanMade { steps, .. } => plan = steps,
            Event::ActionStarted { action } if action.starts_with("SEARCHFOROBJECT ") => {
                let w: Vec<&str> = action.split_whitespace().collect();
                let class = w.get(1).map(|s| s.to_string()).unwrap_or_default();
                let lm_class = if w.get(2) == Some(&"ON") {
                    let lm = w.get(3).copied().unwrap_or("");
                    Some(
                        landmark_class(plan, lm).unwrap_or_else(|| format!("{lm} (class unknown)")),
                    )
                } else {
                    None
                };
                out.push((class, lm_class));
            }
            _ => {}
        }
    }
    out
}

/// The class of landmark `lm` by the plan's listing lines.
pub fn landmark_class(plan: &[String], lm: &str) -> Option<String> {
    plan.iter().find_map(|s| {
        let w: Vec<&str> = s.split_whitespace().collect();
        match w.as_slice() {
            ["ASSUME-OBJECT-EXISTS", _, "ON", l, lc, _] if *l == lm => Some(lc.to_string()),
            ["SEARCHFOROBJECT", lc, "IN", _, o] if *o == lm => Some(lc.to_string()),
            _ => None,
        }
    })
}

/// Whether `want` occurs in `got` in order (not necessarily adjacent).
pub fn is_subsequence(want: &[String], got: &[String]) -> bool {
    let mut it = got.iter();
    want.iter().all(|w| it.any(|g| g == w))
}

/// One property of a scenario, judged.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PropertyResult {
    /// The property: the `expect.` field it comes from, or the name of a check made in every
    /// scenario.
    pub name: String,
    /// Whether it holds.
    pub pass: bool,
    /// What was expected and what happened.
    pub detail: String,
}

/// Every expected property that does not hold, as a message.
pub fn check_properties(sc: &Scenario, out: &ScenarioRun) -> Vec<String> {
    evaluate_properties(sc, out)
        .into_iter()
        .filter(|p| !p.pass)
        .map(|p| p.detail)
        .collect()
}

/// Every property of `sc` judged on `out`: the checks made in every scenario, then each
/// `expect` field the file sets.
pub fn evaluate_properties(sc: &Scenario, out: &ScenarioRun) -> Vec<PropertyResult> {
    let x = &sc.expect;
    let r = out.main();
    let t = &r.trace;
    let mut results = Vec::new();
    let mut bad: Vec<String> = Vec::new();
    // Records the property `name`: it holds when the checks since the last one added no
    // message to `bad`.
    let mut judge = |name: &str, bad: &mut Vec<String>, ok_detail: String| {
        let pass = bad.is_empty();
        results.push(PropertyResult {
            name: name.to_string(),
            pass,
            detail: if pass { ok_detail } else { bad.join("; ") },
        });
        bad.clear();
    };
    // In every scenario: a search's result is always filed in the world model, even when the
    // place map re-drew the searched room meanwhile.
    for (goal, rep) in &out.reports {
        for e in &rep.trace {
            if let Event::PlanMade { reason, .. } = e {
                if reason.contains("world model refused") {
                    bad.push(format!("search for {goal}: replanned because {reason}"));
                }
            }
        }
    }
    judge(
        "results_filed",
        &mut bad,
        "every search's result was filed in the world model".into(),
    );
    // In every scenario: no search reports an object where none of its class is.
    for (goal, rep) in &out.reports {
        if let Some(f) = &rep.found {
            let error = report_error(&out.world, goal, [f.pose.x, f.pose.y]);
            if error.is_none_or(|e| e > SUCCESS_RADIUS) {
                let off = match error {
                    Some(e) => format!("{e:.2} m from the nearest true {goal}"),
                    None => format!("but the world has no {goal}"),
                };
                bad.push(format!(
                    "the search for {goal} reported {} at ({:.2}, {:.2}), {off}",
                    f.name, f.pose.x, f.pose.y
                ));
            }
        }
    }
    judge(
        "no_wrong_report",
        &mut bad,
        format!("no report farther than {SUCCESS_RADIUS} m from a true object of its class"),
    );
    if let Some(want) = x.found {
        if r.found.is_some() != want {
            bad.push(format!(
                "expect.found: {want}, but the search reported {:?} ({})",
                r.found, r.reason
            ));
        }
    }
    if x.found.is_some() {
        judge("expect.found", &mut bad, "holds".into());
    }
    if let Some(d) = x.found_within_m {
        match &r.found {
            None => bad.push(format!(
                "expect.found_within_m: {d}, but nothing was reported"
            )),
            Some(f) => {
                let best = report_error(&out.world, &sc.goal, [f.pose.x, f.pose.y])
                    .unwrap_or(f64::INFINITY);
                if best > d {
                    bad.push(format!(
                        "expect.found_within_m: {d}, but the reported {} at ({:.2}, {:.2}) is \
                         {best:.2} m from the nearest true {}",
                        f.class, f.pose.x, f.pose.y, sc.goal
                    ));
                }
            }
        }
    }
    if x.found_within_m.is_some() {
        judge("expect.found_within_m", &mut bad, "holds".into());
    }
    let first = plans(t).next();
    if let Some(c) = &x.first_plan_assumes_category {
        let line = first.and_then(|p| {
            p.iter().find(|s| {
                s.starts_with("ASSUME-LEADS-TO-ROOM ") || s.starts_with("ASSUME-CATEGORY ")
            })
        });
        if line.is_none_or(|l| l.split_whitespace().last() != Some(c.as_str())) {
            bad.push(format!(
                "expect.first_plan_assumes_category: {c}, but the first plan's room assumption \
                 is {line:?} (plan {first:?})"
            ));
        }
    }
    if x.first_plan_assumes_category.is_some() {
        judge(
            "expect.first_plan_assumes_category",
            &mut bad,
            "holds".into(),
        );
    }
    if let Some(want) = x.first_plan_assumes_new_room {
        let got = first.is_some_and(|p| p.iter().any(|s| s.starts_with("ASSUME-LEADS-TO-ROOM ")));
        if got != want {
            bad.push(format!(
                "expect.first_plan_assumes_new_room: {want}, but the first plan is {first:?}"
            ));
        }
    }
    if x.first_plan_assumes_new_room.is_some() {
        judge(
            "expect.first_plan_assumes_new_room",
            &mut bad,
            "holds".into(),
        );
    }
    if let Some(c) = &x.some_plan_assumes_new_room {
        let ok = plans(t).flatten().any(|s| {
            s.starts_with("ASSUME-LEADS-TO-ROOM ")
                && s.split_whitespace().last() == Some(c.as_str())
        });
        if !ok {
            bad.push(format!(
                "expect.some_plan_assumes_new_room: {c}, but no plan has an \
                 `ASSUME-LEADS-TO-ROOM <placeholder> {c}` line"
            ));
        }
    }
    if x.some_plan_assumes_new_room.is_some() {
        judge(
            "expect.some_plan_assumes_new_room",
            &mut bad,
            "holds".into(),
        );
    }
    if let Some(want) = x.assumption_violated {
        let got = t
            .iter()
            .any(|e| matches!(e, Event::AssumptionViolated { .. }));
        if got != want {
            bad.push(format!(
                "expect.assumption_violated: {want}, but the trace has {}",
                if got {
                    "a violated assumption"
                } else {
                    "no violated assumption"
                }
            ));
        }
    }
    if x.assumption_violated.is_some() {
        judge("expect.assumption_violated", &mut bad, "holds".into());
    }
    if let Some(n) = x.min_plans {
        if r.metrics.plans < n {
            bad.push(format!(
                "expect.min_plans: {n}, but {} plans were made",
                r.metrics.plans
            ));
        }
    }
    if x.min_plans.is_some() {
        judge("expect.min_plans", &mut bad, "holds".into());
    }
    if let Some(s) = &x.gave_up_reason_contains {
        let reason = r.gave_up.as_ref().map(|g| g.to_string());
        if !reason.as_deref().is_some_and(|g| g.contains(s.as_str())) {
            bad.push(format!(
                "expect.gave_up_reason_contains: {s:?}, but the search ended with {:?}",
                r.reason
            ));
        }
    }
    if x.gave_up_reason_contains.is_some() {
        judge("expect.gave_up_reason_contains", &mut bad, "holds".into());
    }
    let done = searches(t);
    for lc in &x.searched_on {
        let ok = done
            .iter()
            .any(|(c, on)| c == &sc.goal && on.as_deref() == Some(lc.as_str()));
        if !ok {
            bad.push(format!(
                "expect.searched_on: {lc}, but the {} was searched {:?} (class, on)",
                sc.goal, done
            ));
        }
    }
    if !x.searched_on.is_empty() {
        judge("expect.searched_on", &mut bad, "holds".into());
    }
    if !x.searched_for.is_empty() {
        let classes: Vec<String> = done.iter().map(|(c, _)| c.clone()).collect();
        if !is_subsequence(&x.searched_for, &classes) {
            bad.push(format!(
                "expect.searched_for: {:?} in this order, but the searches were for {classes:?}",
                x.searched_for
            ));
        }
    }
    if !x.searched_for.is_empty() {
        judge("expect.searched_for", &mut bad, "holds".into());
    }
    let path_rooms = rooms_along_path(&out.world, &out.trail);
    if !x.entered_rooms.is_empty() && !is_subsequence(&x.entered_rooms, &path_rooms) {
        bad.push(format!(
            "expect.entered_rooms: {:?} in this order, but the robot went through {path_rooms:?}",
            x.entered_rooms
        ));
    }
    if !x.entered_rooms.is_empty() {
        judge("expect.entered_rooms", &mut bad, "holds".into());
    }
    let views = view_rooms(&out.world, t);
    if let Some(room) = &x.first_search_in {
        if views.first() != Some(room) {
            bad.push(format!(
                "expect.first_search_in: {room}, but the view cones were processed in {views:?}"
            ));
        }
    }
    if x.first_search_in.is_some() {
        judge("expect.first_search_in", &mut bad, "holds".into());
    }
    for room in &x.never_searched_in {
        if views.contains(room) {
            bad.push(format!(
                "expect.never_searched_in: {room}, but the view cones were processed in {views:?}"
            ));
        }
    }
    if !x.never_searched_in.is_empty() {
        judge("expect.never_searched_in", &mut bad, "holds".into());
    }
    results
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listing_helpers_read_landmark_classes_and_subsequences() {
        let plan: Vec<String> = [
            "ASSUME-OBJECT-EXISTS cerealbox ON new-object1 table kitchen",
            "SEARCHFOROBJECT counter IN room3 new-object4",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(
            landmark_class(&plan, "new-object1").as_deref(),
            Some("table")
        );
        assert_eq!(
            landmark_class(&plan, "new-object4").as_deref(),
            Some("counter")
        );
        assert_eq!(landmark_class(&plan, "object9"), None);
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(is_subsequence(&s(&["a", "c"]), &s(&["a", "b", "c"])));
        assert!(!is_subsequence(&s(&["c", "a"]), &s(&["a", "b", "c"])));
    }
}
