//! Bringing the memory in step with the laser map: the world model's sync (places, doors,
//! rooms, the conceptual map), the room of every cell, and the placeholders offered to the
//! planner under stable names — frontier placeholders of the place map and unvisited areas.

use super::{standable, Cand, Memory, PhEntry, Segment};
use crate::AgentError;
use avs_concepts::PlaceholderId;
use avs_map::grid::Cell;
use avs_map::places::dist;
use avs_map::raycast::line_of_sight;
use petgraph::graph::NodeIndex;
use std::collections::BTreeSet;

/// Conceptual-map ids of unvisited-area placeholders start here.
const EXTRA_BASE: u64 = 1_000_000;

impl Memory {
    /// Sync the world model with the grid, file every cell under its room, and name the
    /// placeholders offered to the planner.
    pub fn sync(&mut self) -> Result<(), AgentError> {
        let grid = self.grid.clone();
        self.wm.sync(&grid)?;
        self.cell_rooms = self.wm.places.cell_rooms(&grid);
        self.pockets = avs_map::pockets::enclosed_pockets(
            &grid,
            &self.cell_rooms,
            self.pocket_size.area,
            self.pocket_size.radius,
        );
        // Placeholders the known map gives no short path to from their place are artefacts
        // (frontier seen through a gap, behind furniture): not worth a plan.
        let ends: Vec<Segment> = {
            let g = &self.wm.places.graph;
            self.wm
                .places
                .placeholders
                .iter()
                .map(|ph| (g.node_weight(ph.place).map_or(ph.pos, |p| p.pos), ph.pos))
                .collect()
        };
        // A pure function of the grid and the ends; most syncs see the map of the one before.
        let mut memo = std::mem::take(&mut self.spurious_cache);
        let spurious = memo.get_or_insert_with((grid, ends.clone()), || {
            ends.iter()
                .map(|&(a, p)| {
                    self.path_len_within(a, p, true, 2.0 * dist(a, p) + 2.0)
                        .is_none()
                })
                .collect()
        });
        self.spurious_cache = memo;
        let min_open_area = self.tuning.min_open_area;
        let mut cands: Vec<(Cand, bool)> = self
            .wm
            .places
            .placeholders
            .iter()
            .enumerate()
            .zip(&spurious)
            .map(|((i, ph), &sp)| {
                let c = Cand {
                    pos: ph.pos,
                    attach: ph.place,
                    cm_id: i as u64,
                };
                (c, sp || ph.open_area < min_open_area)
            })
            .collect();
        let offered: Vec<[f64; 2]> = cands
            .iter()
            .filter(|(_, skip)| !skip)
            .map(|(c, _)| c.pos)
            .collect();
        let extras = self.unvisited_areas(&offered)?;
        cands.extend(extras.into_iter().map(|c| (c, false)));
        // Name them: keep the name of a tracked one within 1 m; skip those next to an explored
        // one (the same frontier seen again); new ones get new names.
        let mut taken = BTreeSet::new();
        let mut phs = Vec::new();
        for (c, skip) in cands {
            if skip
                || self
                    .registry
                    .iter()
                    .any(|e| e.explored.is_some() && dist(e.pos, c.pos) < 0.8)
            {
                continue;
            }
            let hit = self.registry.iter().position(|e| {
                e.explored.is_none() && !taken.contains(&e.id) && dist(e.pos, c.pos) < 1.0
            });
            let k = match hit {
                Some(k) => {
                    self.registry[k].pos = c.pos;
                    k
                }
                None => {
                    self.registry.push(PhEntry {
                        id: self.next_ph,
                        pos: c.pos,
                        explored: None,
                    });
                    self.next_ph += 1;
                    self.registry.len() - 1
                }
            };
            taken.insert(self.registry[k].id);
            phs.push((self.registry[k].id, c));
        }
        // Forget unexplored placeholders that vanished.
        self.registry
            .retain(|e| e.explored.is_some() || taken.contains(&e.id));
        let registry = &self.registry;
        self.phs = phs
            .into_iter()
            .filter_map(|(id, c)| registry.iter().position(|e| e.id == id).map(|k| (k, c)))
            .collect();
        Ok(())
    }

    /// Known free space far from every place and from the offered `frontier` placeholders:
    /// unvisited areas (a room seen through its door but not entered has no places, so the
    /// place map has no room for it). One placeholder per area, attached to the nearest
    /// place, set in the conceptual map with the open area around it so that
    /// P_category(placeholder) applies (Aydemir et al. 2011, §III-A.1).
    fn unvisited_areas(&mut self, frontier: &[[f64; 2]]) -> Result<Vec<Cand>, AgentError> {
        // The areas depend only on the key's parts; while the robot processes views in rooms
        // it knows, the map rarely changes, and the search spent 40% of its time here.
        let key = UnvisitedKey {
            grid: self.grid.clone(),
            places: {
                let g = &self.wm.places.graph;
                g.node_indices()
                    .map(|n| (n, g[n].pos, self.wm.room_of(n)))
                    .collect()
            },
            frontier: frontier.to_vec(),
            explored: self
                .registry
                .iter()
                .filter(|e| e.explored.is_some())
                .map(|e| e.pos)
                .collect(),
            doors: self
                .wm
                .places
                .doors
                .iter()
                .map(|d| d.hypothesis.center)
                .collect(),
        };
        let mut memo = std::mem::take(&mut self.unvisited_cache);
        let found = memo.try_get_or_insert_with(key, || self.find_unvisited_areas(frontier));
        self.unvisited_cache = memo;
        let (picked, extra) = found?;
        for id in std::mem::take(&mut self.extra_ids) {
            self.wm.concepts.remove_placeholder(PlaceholderId(id))?;
        }
        for &(id, ph) in &extra {
            self.wm.concepts.set_placeholder(PlaceholderId(id), ph)?;
            self.extra_ids.push(id);
        }
        Ok(picked)
    }

    /// The unvisited areas of [`Self::unvisited_areas`] and the conceptual-map placeholders
    /// they become.
    fn find_unvisited_areas(&mut self, frontier: &[[f64; 2]]) -> Result<Unvisited, AgentError> {
        let grid = self.grid.clone();
        let res = grid.resolution();
        let t = self.tuning.clone();
        let places: Vec<[f64; 2]> = {
            let g = &self.wm.places.graph;
            g.node_indices().map(|n| g[n].pos).collect()
        };
        if places.is_empty() {
            return Ok((Vec::new(), Vec::new()));
        }
        // Whether a place near enough sees the point (a place behind a wall does not make the
        // space beyond it visited); the first one found settles it.
        let seen_from_a_place = |p: [f64; 2]| {
            places
                .iter()
                .any(|q| dist(*q, p) <= t.unvisited_distance && line_of_sight(&grid, *q, p, false))
        };
        let mut picked: Vec<Cand> = Vec::new();
        let mut extra: Vec<(u64, avs_concepts::Placeholder)> = Vec::new();
        for pos in self.with_trav(false, |tr| standable(&grid, tr, 1.0)) {
            if seen_from_a_place(pos)
                || picked
                    .iter()
                    .any(|c| dist(c.pos, pos) < t.unvisited_spacing)
            {
                continue;
            }
            if frontier.iter().any(|f| dist(*f, pos) < 2.0)
                || self
                    .registry
                    .iter()
                    .any(|e| e.explored.is_some() && dist(e.pos, pos) < 2.0)
            {
                tracing::debug!(?pos, "unvisited area near a placeholder");
                continue;
            }
            // Attach to the place it is reached from: of the few nearest places with a
            // room, the one with the shortest known path (the nearest in a straight line
            // may be behind a wall).
            let g = &self.wm.places.graph;
            let mut near: Vec<(NodeIndex, f64)> = g
                .node_indices()
                .filter(|&n| self.wm.room_of(n).is_some())
                .map(|n| (n, dist(g[n].pos, pos)))
                .collect();
            near.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            let best = near
                .iter()
                .take(t.attach_candidates)
                .filter_map(|&(n, d)| {
                    let a = g[n].pos;
                    let l = self.path_len_within(a, pos, false, 2.0 * d + 2.0)?;
                    Some((n, l))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            let Some((attach, _)) = best else {
                tracing::debug!(?pos, "unvisited area without a short path");
                continue;
            };
            let Some(room) = self.wm.room_of(attach) else {
                continue;
            };
            // Unvisited free area within 2.5 m of it.
            let r = (2.5 / res).ceil() as i64;
            let (c0, r0) = grid.world_to_cell(pos[0], pos[1]);
            let mut cells = 0usize;
            for dr in -r..=r {
                for dc in -r..=r {
                    if grid.get_i(c0 + dc, r0 + dr) == Cell::Free {
                        let (cx, cy) = grid.cell_center(c0 + dc, r0 + dr);
                        if dist([cx, cy], pos) <= 2.5 && !seen_from_a_place([cx, cy]) {
                            cells += 1;
                        }
                    }
                }
            }
            let door = self
                .wm
                .places
                .doors
                .iter()
                .map(|d| dist(d.hypothesis.center, pos))
                .min_by(f64::total_cmp);
            let id = EXTRA_BASE + picked.len() as u64;
            extra.push((
                id,
                avs_concepts::Placeholder {
                    room,
                    open_area_m2: cells as f64 * res * res,
                    door_distance_m: door,
                },
            ));
            picked.push(Cand {
                pos,
                attach,
                cm_id: id,
            });
        }
        Ok((picked, extra))
    }
}

/// Unvisited areas offered as placeholders, and their conceptual-map placeholders.
pub(crate) type Unvisited = (Vec<Cand>, Vec<(u64, avs_concepts::Placeholder)>);

/// Everything the unvisited areas are computed from: the known map, the places (and their
/// rooms), the frontier placeholders offered, the explored placeholders and the doors.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct UnvisitedKey {
    grid: avs_map::grid::OccupancyGrid,
    places: Vec<(NodeIndex, [f64; 2], Option<avs_concepts::RoomId>)>,
    frontier: Vec<[f64; 2]>,
    explored: Vec<[f64; 2]>,
    doors: Vec<[f64; 2]>,
}
