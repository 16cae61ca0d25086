//! Frontier exploration of a simulated world by the place map: repeatedly go to the placeholder
//! of highest exploration utility (Masuzawa & Miura eq. 6). Used by `avs render --explore`, the
//! `uninformed`/`frontier` baselines, and tests.

use crate::robot::SimRobot;
use crate::world::World;
use avs_map::explore::rank_viewpoints;
use avs_map::nav::Traversability;
use avs_map::places::{dist, PlaceMap, PlaceMapParams};

/// An exploration run in progress.
#[derive(Debug, Clone)]
pub struct Explorer<'w> {
    /// The robot.
    pub robot: SimRobot<'w>,
    /// The place map built so far.
    pub places: PlaceMap,
    /// Goals already tried, to skip placeholders that proved unreachable or fruitless.
    tried: Vec<[f64; 2]>,
    /// Steps taken.
    pub steps: usize,
}

/// Smallest expected gain (m²) that is worth a trip.
const MIN_GAIN: f64 = 0.25;

impl<'w> Explorer<'w> {
    /// Start at the world's start pose; `params` sets the place map's spacing and door widths.
    pub fn new(world: &'w World, params: PlaceMapParams, seed: u64) -> Self {
        let mut robot = SimRobot::new(world, seed);
        robot.scan_around();
        let mut places = PlaceMap::new(params);
        let p = [robot.pose[0], robot.pose[1]];
        places.robot_moved(&robot.known, p, p);
        places.update(&robot.known);
        Self {
            robot,
            places,
            tried: Vec::new(),
            steps: 0,
        }
    }

    /// Go to the best placeholder; returns false when none is left worth visiting.
    pub fn step(&mut self) -> bool {
        let radius = self.robot.world().env.robot.radius;
        let trav = Traversability::new(&self.robot.known, radius, false);
        let here = [self.robot.pose[0], self.robot.pose[1]];
        let cands: Vec<[f64; 2]> = self.places.placeholders.iter().map(|p| p.pos).collect();
        let ranked = rank_viewpoints(
            &self.robot.known,
            &trav,
            here,
            &cands,
            self.robot.laser.range,
            0.5,
        );
        let Some(best) = ranked.iter().find(|s| {
            s.gain >= MIN_GAIN && self.tried.iter().all(|t| dist(*t, cands[s.index]) > 0.3)
        }) else {
            return false;
        };
        self.tried.push(cands[best.index]);
        let goal = best.stand;
        let motion = self.robot.move_to(goal);
        for w in motion.waypoints.windows(2) {
            self.places.robot_moved(&self.robot.known, w[0], w[1]);
            self.places.update(&self.robot.known);
        }
        self.robot.scan_around();
        self.places.update(&self.robot.known);
        self.steps += 1;
        true
    }

    /// Explore until no placeholder is worth visiting or `max_steps` steps were taken.
    pub fn run(&mut self, max_steps: usize) {
        while self.steps < max_steps && self.step() {}
    }
}
