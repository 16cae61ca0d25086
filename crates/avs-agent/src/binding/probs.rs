//! The costs and probabilities of the object-search domain, from the conceptual map.

use super::{Binding, PhRef};
use avs_concepts::{ConceptualMap, Location, PlaceholderId};
use avs_format::knowledge::Relation;
use avs_map::places::dist;
use avs_plan::problem::Functions;

/// What a room search costs where no price is known, metres (the domain's flat cost before
/// searches were priced).
const FLAT_ROOM_SEARCH: f64 = 20.0;
/// What a search on a landmark's top costs where no price is known, metres.
const FLAT_LANDMARK_SEARCH: f64 = 5.0;

/// Costs and probabilities of the object-search domain from the conceptual map: the domain's
/// functions (see `domains/object_search.yaml`) over the binding's names.
pub(crate) struct Probs<'a> {
    pub binding: &'a Binding,
    pub cm: &'a ConceptualMap,
    /// 1 − the knowledge's false-negative rate.
    pub p_detect: f64,
    /// Probabilities are kept at least this large (an exact 0 stays 0).
    pub p_min: f64,
}

impl<'a> Probs<'a> {
    /// The domain's functions over `binding`'s names, from the conceptual map `cm` with the
    /// knowledge's detector miss rate and the probability floor `p_min`.
    pub fn new(
        binding: &'a Binding,
        cm: &'a ConceptualMap,
        false_negative: f64,
        p_min: f64,
    ) -> Self {
        Self {
            binding,
            cm,
            p_detect: 1.0 - false_negative,
            p_min,
        }
    }
}

impl Functions for Probs<'_> {
    fn value(&self, name: &str, args: &[&str]) -> Option<f64> {
        let s = self.binding;
        let m = self.cm.model();
        let cat = |c: &str| m.category(c).ok();
        let exists = |rate: f64| 1.0 - (-rate).exp();
        let p = match (name, args) {
            ("distance", [a, b]) => {
                return Some(dist(*s.pos.get(*a)?, *s.pos.get(*b)?));
            }
            // What the search's views cost where they were priced (`skills::views`); a room
            // not priced (not known yet, or no view sees it yet) as a room not known yet.
            ("search-cost-in", [l, r]) => {
                let key = (l.to_string(), r.to_string());
                return Some(
                    s.search_cost
                        .get(&key)
                        .map(|c| c.metres)
                        .or_else(|| s.typical_cost.get(*l).map(|c| c.metres))
                        .unwrap_or(FLAT_ROOM_SEARCH),
                );
            }
            ("search-cost-on", [l, lm]) => {
                let key = (l.to_string(), lm.to_string());
                return Some(
                    s.search_cost
                        .get(&key)
                        .map_or(FLAT_LANDMARK_SEARCH, |c| c.metres),
                );
            }
            ("p-leads-to-room", [ph, c]) => match s.placeholders.get(*ph)? {
                PhRef::Current(i) => self.cm.p_category_placeholder(PlaceholderId(*i), c).ok()?,
                PhRef::Explored(Some(r)) => self.cm.p_category(*r, c).ok()?,
                PhRef::Explored(None) => 0.0,
            },
            ("p-category", [r, c]) => match s.rooms.get(*r) {
                Some(&room) => self.cm.p_category(room, c).ok()?,
                // A hypothesised room: the prior (its category is assumed with the room).
                None => *m.prior.get(cat(c)?)?,
            },
            ("p-object-in" | "p-object-on" | "p-object-inside", [l, ..])
                if !s.relevant.contains(*l) =>
            {
                0.0
            }
            ("p-object-in", [l, r, c]) => {
                let k = cat(c)?;
                match s.rooms.get(*r) {
                    Some(&room) => exists(*self.cm.rates(Location::Room(room), l).ok()?.get(k)?),
                    // A hypothesised room: its open space; with unfound landmarks counted, its
                    // whole hierarchy (the landmarks it is expected to hold too), 002 §III-A.
                    None if self.cm.unfound_landmarks() => {
                        exists(*m.unseen_room_rates(m.class(l).ok()?).get(k)?)
                    }
                    None => exists(*m.room_rates.get(m.class(l).ok()?)?.get(k)?),
                }
            }
            ("p-object-on" | "p-object-inside", [l, lc, c]) => {
                let k = cat(c)?;
                let rel = if name == "p-object-on" {
                    Relation::On
                } else {
                    Relation::In
                };
                let r = m.landmark_rate(m.class(l).ok()?, rel, m.class(lc).ok()?);
                exists(*r.get(k)?)
            }
            ("p-detect", [_]) => self.p_detect,
            // A search that made no progress here (no cone saw a point of the room) would
            // make none again until the room's known map grows: it cannot succeed.
            ("p-detect-in", [l, r]) if s.stalled.contains(&(l.to_string(), r.to_string())) => 0.0,
            // One pass over the views, which look at the share of the room's points they cover
            // (a room not priced: as a room not known yet, as its cost).
            ("p-detect-in", [l, r]) => {
                let key = (l.to_string(), r.to_string());
                let priced = s.search_cost.get(&key).or_else(|| s.typical_cost.get(*l));
                self.p_detect * priced.map_or(1.0, |c| c.share)
            }
            _ => return None,
        };
        Some(if p == 0.0 {
            0.0
        } else if p.is_finite() {
            p.clamp(self.p_min, 1.0)
        } else {
            self.p_min
        })
    }
}
