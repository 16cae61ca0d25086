//! The `count` rule: a closer look at a sighting before it is reported (the verification step
//! of Masuzawa & Miura, `001` §4, reduced to one viewpoint), accepted on enough detections.

use super::closer::approach;
use super::{CandidateRef, Verdict};
use crate::body::Body;
use crate::memory::Memory;
use crate::run::Run;
use crate::skills::Ctx;
use crate::AgentError;
use avs_robot::Robot;

/// Verify a sighting before reporting it: walk to a closer standpoint ([`approach`]) and look
/// at it ([`super::closer::Closer::look`]); `verify_hits` detections of the class within `confirm_radius` of
/// the sighting in at most `verify_looks` looks confirm it (the best of them, measured closer,
/// is the pose reported). With the knowledge's miss rate 0.2 a real object passes with 0.90;
/// a look-alike that fires one look in four with 0.16. The candidate's prior is not used.
pub(crate) fn count_rule<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    c: &CandidateRef,
) -> Result<Verdict, AgentError> {
    let t = cx.tuning();
    let Some(mut closer) = approach(cx, mem, body, run, c)? else {
        return Ok(Verdict::rejected("the class is not in the knowledge file"));
    };
    let mut hits = 0;
    let mut looks = 0;
    for look in 0..t.verify_looks {
        if hits + (t.verify_looks - look) < t.verify_hits {
            break; // cannot reach the hits needed any more
        }
        looks += 1;
        if closer.look(cx, body, run, false).is_some() {
            hits += 1;
            if hits >= t.verify_hits {
                break;
            }
        }
    }
    body.refresh_map(mem);
    Ok(
        match closer.best().filter(|_| hits >= t.verify_hits).cloned() {
            Some(c) => Verdict {
                confirmed: Some(c),
                belief: None,
                looks,
                reason: format!("{hits} of {looks} closer looks detected it"),
                reach: closer.reach(),
            },
            None => Verdict {
                looks,
                reach: closer.reach(),
                ..Verdict::rejected(&format!("{hits} of {looks} closer looks detected it"))
            },
        },
    )
}

#[cfg(test)]
mod tests {
    use crate::skills::testing::{self, object, Verified};
    use crate::trace::Event;
    use avs_format::verifier::VerifierStrategy;

    /// A cerealbox sighting verified by the count rule; the box is there when `placed`.
    /// Returns what was left and the looks taken.
    fn verdict(placed: bool) -> (Verified, usize) {
        let k = testing::knowledge_verified_by("cerealbox", VerifierStrategy::Count);
        let v = testing::verify_cerealbox(&k, |r| {
            if placed {
                r.place(object("cerealbox", 4.5, 2.0, 0.14));
            }
        });
        let looks = v
            .events
            .iter()
            .filter(|e| matches!(e, Event::DtAction { action, .. } if action.starts_with("VERIFY")))
            .count();
        (v, looks)
    }

    #[test]
    fn a_real_object_is_confirmed_by_two_closer_looks_from_inside_its_recognition_range() {
        let (v, looks) = verdict(true);
        let c = v.confirmed.expect("a real object is confirmed");
        assert!(c.pose.planar_distance(4.5, 2.0) < 1e-9);
        assert_eq!(looks, 2);
        assert!(v.rejected.is_empty());
        // The robot moved to a standpoint within the class's recognition range (or as near as
        // the camera's tilt allows) and looked at the sighting.
        let k = testing::knowledge();
        let range = k.class("cerealbox").unwrap().detection_range[1];
        let stand = avs_robot::Robot::pose(&v.robot);
        assert!(stand.distance(&avs_robot::Pose2D::new(1.0, 2.0, 0.0)) > 0.5);
        assert!(((4.5 - stand.x).hypot(2.0 - stand.y)) <= range, "{stand:?}");
    }

    #[test]
    fn a_sighting_no_closer_look_repeats_is_rejected_and_remembered() {
        let (v, looks) = verdict(false);
        assert!(v.confirmed.is_none());
        // Two misses leave no way to the two hits needed: the third look is not taken.
        assert_eq!(looks, 2);
        assert_eq!(v.rejected, vec![("cerealbox".to_string(), [4.5, 2.0])]);
        // The decision is in the trace, with the rule's reason.
        assert!(v.events.iter().any(|e| matches!(e,
            Event::VerificationDecision { accepted: false, belief: None, looks: 2, reason, .. }
                if reason.contains("0 of 2"))));
    }
}
