//! What earlier looks saw of the goal's class: the searches of a
//! [`Goal::find_all`](crate::Goal::find_all) share their images (every look runs the detector
//! for every class still sought, Sjöö et al. `004` §2.1's multi-object search), so the search
//! for a later class may start with sightings of it. They are candidates like any other: each
//! goes to the class's verifier ([`super::verify`]), nearest first by the known map, before the
//! planner is asked for a plan; the first one accepted is the goal's object, and a rejected
//! one is remembered as a look-alike as usual. A search that accepts none goes on as if there
//! had been none — a sighting says nothing about the rooms not looked at.
//!
//! A look around on entering a room runs the goal's detector too ([`super::look_around`]);
//! what it confirms is kept the same way and verified before the plan goes on.

use super::verify::verify;
use super::Ctx;
use crate::body::Body;
use crate::memory::Memory;
use crate::report::{Activity, FoundObject};
use crate::run::Run;
use crate::AgentError;
use avs_map::places::dist;
use avs_robot::Robot;

/// Which looks made the kept sightings, for the trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sighted {
    /// The looks of earlier searches, before the search plans.
    Before,
    /// The look around on entering a room, in the middle of a plan.
    LookAround,
}

/// Verify the kept sightings of `class` (nearest first); the first one accepted, filed in
/// the memory as a found object. The sightings of `class` are used up either way.
pub(crate) fn verify_sightings<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    class: &str,
    by: Sighted,
) -> Result<Option<FoundObject>, AgentError> {
    let (mut mine, rest): (Vec<_>, Vec<_>) = std::mem::take(&mut mem.sightings)
        .into_iter()
        .partition(|d| d.class == class);
    mem.sightings = rest;
    if !mine.is_empty() {
        let n = mine.len();
        run.observe(match by {
            Sighted::Before => {
                format!(
                    "{n} sighting(s) of {class} by earlier looks: verifying them before planning"
                )
            }
            Sighted::LookAround => {
                format!("{n} sighting(s) of {class} in the look around: verifying them")
            }
        });
    }
    while !mine.is_empty() {
        let here = body.at();
        let how_far = |p: [f64; 2]| mem.path_len(here, p, true).unwrap_or(f64::INFINITY);
        let (i, _) = mine
            .iter()
            .enumerate()
            .map(|(i, d)| {
                let p = [d.pose.x, d.pose.y];
                (i, (how_far(p), dist(here, p)))
            })
            .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0).then(a.1 .1.total_cmp(&b.1 .1)))
            .expect("not empty");
        let d = mine.swap_remove(i);
        // A spot rejected often enough since it was seen is a known look-alike.
        if !mem.is_new_sighting(&d) {
            continue;
        }
        let confirmed = body.with_activity(Activity::Verification, |b| {
            verify(cx, mem, b, run, class, &d)
        })?;
        if let Some(v) = confirmed {
            return Ok(Some(mem.file_found(class, &v)));
        }
    }
    Ok(None)
}
