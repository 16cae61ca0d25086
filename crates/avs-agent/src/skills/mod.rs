//! The agent's skills, one per module, each a function over the
//! [`Memory`](crate::memory::Memory), the [`Body`](crate::body::Body) and the
//! [`Run`](crate::run::Run) of a search:
//!
//! * [`look_around`] — pan the camera round for landmarks on entering a room (evidence on the
//!   room's category, locations for indirect search);
//! * [`enter`] — ENTER / EXPLORE a placeholder: go into the space beyond it and explore the
//!   room found there;
//! * [`views`] — CREATEVIEWCONES: view planning over a room's or a landmark's points;
//! * [`session`] — SEARCHFOROBJECT: the closed-loop view-cone POMDP session;
//! * [`verify`] — a closer look at a sighting before it is reported;
//! * [`sighted`] — the sightings of a later goal's class made by an earlier goal's looks
//!   ([`Goal::find_all`](crate::Goal::find_all)), verified before the later goal plans.

pub(crate) mod enter;
pub(crate) mod look_around;
pub(crate) mod session;
pub(crate) mod sighted;
pub(crate) mod verify;
pub(crate) mod views;

use crate::config::{AgentConfig, Tuning};
use avs_format::knowledge::Knowledge;

/// What every skill reads and never changes: the knowledge and the settings.
#[derive(Clone, Copy)]
pub(crate) struct Ctx<'a> {
    pub knowledge: &'a Knowledge,
    pub config: &'a AgentConfig,
}

impl Ctx<'_> {
    /// The executive's constants.
    pub fn tuning(&self) -> &Tuning {
        &self.config.tuning
    }
}

#[cfg(test)]
pub(crate) mod testing;
