//! Helpers for the skills' unit tests: the shipped knowledge, a walled room the scripted
//! robot knows whole, and the memory, body and run of a search over it.

use crate::body::Body;
use crate::config::AgentConfig;
use crate::memory::Memory;
use crate::run::Run;
use crate::trace::Event;
use crate::world_model::WorldModel;
use avs_format::knowledge::Knowledge;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_robot::{Camera, Detection, Point3, Pose2D, ScriptedRobot};

/// The shipped office knowledge.
pub fn knowledge() -> Knowledge {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../knowledge/office.yaml");
    avs_format::load_yaml(std::path::Path::new(path)).expect("the shipped knowledge loads")
}

/// The shipped object-search domain.
pub fn domain() -> avs_plan::domain::Domain {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../domains/object_search.yaml"
    );
    avs_plan::domain::Domain::load(std::path::Path::new(path)).expect("the shipped domain loads")
}

/// A walled room of `w` × `h` metres (0.1 m cells, origin at the outer corner), all known.
pub fn room(w: f64, h: f64) -> OccupancyGrid {
    let (cols, rows) = ((w / 0.1).round() as usize, (h / 0.1).round() as usize);
    let mut g = OccupancyGrid::new(cols, rows, 0.1, [0.0, 0.0], Cell::Free).expect("valid size");
    for c in 0..cols {
        g.set(c, 0, Cell::Occupied);
        g.set(c, rows - 1, Cell::Occupied);
    }
    for r in 0..rows {
        g.set(0, r, Cell::Occupied);
        g.set(cols - 1, r, Cell::Occupied);
    }
    g
}

/// `grid` with a piece of furniture standing at `(x, y)`: its axis-aligned `w` × `d` metre
/// footprint occupied, as a laser map holds it.
pub fn furnish(mut grid: OccupancyGrid, [x, y]: [f64; 2], [w, d]: [f64; 2]) -> OccupancyGrid {
    // The cell boundaries nearest the footprint's edges (a floor would put 2.4 m on the
    // 0.1 m grid at 23.999… cells).
    let [ox, oy] = grid.origin();
    let at = |v: f64, o: f64| ((v - o) / grid.resolution()).round() as i64;
    let (c0, c1) = (at(x - w / 2.0, ox), at(x + w / 2.0, ox));
    let (r0, r1) = (at(y - d / 2.0, oy), at(y + d / 2.0, oy));
    for row in r0..r1 {
        for col in c0..c1 {
            if grid.contains(col, row) {
                grid.set(col as usize, row as usize, Cell::Occupied);
            }
        }
    }
    grid
}

/// Two 4 m × 4 m rooms side by side ([`room`] 8 × 4 m), a 0.9 m door in the wall between
/// them at x = 4 m.
pub fn two_rooms() -> OccupancyGrid {
    let mut g = room(8.0, 4.0);
    for row in 0..40 {
        if !(16..25).contains(&row) {
            g.set(40, row, Cell::Occupied);
        }
    }
    g
}

/// The skills' context over a test's knowledge and configuration.
pub fn ctx<'a>(knowledge: &'a Knowledge, config: &'a AgentConfig) -> super::Ctx<'a> {
    super::Ctx { knowledge, config }
}

/// The shipped knowledge with `class` verified by `strategy` (with the model, unless `count`)
/// and a hand-written sensor model
/// `hand` over 6 m: an object scores about 2 (the scripted robot's object score), a
/// look-alike about 0.8, one look's spread 0.3 about a smooth per-candidate field.
pub fn knowledge_verified_by(
    class: &str,
    strategy: avs_format::verifier::VerifierStrategy,
) -> Knowledge {
    use avs_format::verifier::{
        CorrSpec, HypothesisSpec, KernelSpec, ModelKind, NamedSensorModel, SensorModelSpec,
        VerifierSpec,
    };
    let hyp = |m: f64| HypothesisSpec {
        mean: m,
        kernel: KernelSpec {
            signal_variance: 0.1,
            length_scales: vec![2.0, 0.8],
        },
        noise_variance: 0.01,
        spread: 0.3,
        points: [1.0, 2.0, 3.0, 4.5, 6.0]
            .iter()
            .flat_map(|&r| [-2.0, 0.0, 2.0].map(|a| [r, a, m]))
            .collect(),
        corr: CorrSpec {
            kernel: KernelSpec {
                signal_variance: 0.2,
                length_scales: vec![1.5, 0.6],
            },
            noise_variance: 0.1,
        },
    };
    let mut k = knowledge();
    k.sensor_models.push(NamedSensorModel {
        name: "hand".into(),
        model: SensorModelSpec {
            kind: ModelKind::Dynamic { alpha_scale: 1.0 },
            max_range: 6.0,
            aspect_limit: None,
            object: hyp(2.0),
            no_object: hyp(0.8),
        },
    });
    let c = k
        .object_classes
        .iter_mut()
        .find(|c| c.name == class)
        .expect("the class is in the shipped knowledge");
    c.verifier = Some(VerifierSpec {
        strategy,
        model: strategy.accepts_model().then(|| "hand".into()),
        threshold: None,
    });
    k
}

/// A sighting of `class` at `(x, y, z)` with confidence 0.8.
pub fn object(class: &str, x: f64, y: f64, z: f64) -> Detection {
    Detection {
        class: class.into(),
        pose: Point3 { x, y, z },
        confidence: 0.8,
    }
}

/// A scripted robot at `at` (facing +x) in `grid`, with the default camera.
pub fn robot(grid: OccupancyGrid, at: [f64; 2]) -> ScriptedRobot {
    ScriptedRobot::new(grid, Pose2D::new(at[0], at[1], 0.0), Camera::default())
}

/// A memory made as a search makes it: the robot's first laser map, then the survey.
pub fn memory(config: &AgentConfig, k: &Knowledge, robot: &mut ScriptedRobot) -> Memory {
    let wm = WorldModel::new("knowledge", k, config.places.clone()).expect("knowledge is usable");
    let mut body = Body::new(robot);
    let grid = body.laser_map();
    let mut mem = Memory::new(
        wm,
        grid,
        config.robot_radius,
        crate::memory::pocket_size(k),
        config.tuning.clone(),
    );
    body.survey(&mut mem).expect("the survey syncs");
    mem
}

/// A sink that keeps nothing (the run keeps its own events).
pub fn sink() -> impl FnMut(&Event) {
    |_: &Event| {}
}

/// A run writing to `sink`.
pub fn run(sink: &mut dyn crate::trace::TraceSink) -> Run<'_> {
    Run::new(sink, 0.1)
}

/// The text of the run's trace.
pub fn text(run: &Run) -> String {
    crate::trace::render_text(&run.events)
}

/// What verifying a sighting left behind ([`verify_cerealbox`]).
pub struct Verified {
    /// The detection to report, if the verifier accepted the sighting.
    pub confirmed: Option<Detection>,
    /// The trace of the verification.
    pub events: Vec<Event>,
    /// The sightings memory remembers as rejected.
    pub rejected: Vec<(String, [f64; 2])>,
    /// The search's figures.
    pub metrics: crate::report::Metrics,
    /// The robot afterwards.
    pub robot: ScriptedRobot,
}

/// The robot of the verification tests, at (1, 2) facing +x in an empty 6 × 4 m room, and
/// the memory its search would have made there.
pub fn verification_room(config: &AgentConfig, k: &Knowledge) -> (ScriptedRobot, Memory) {
    let mut robot = robot(room(6.0, 4.0), [1.0, 2.0]);
    let mem = memory(config, k, &mut robot);
    (robot, mem)
}

/// Verify a cerealbox sighting at (4.5, 2) seen from (1, 2) in a 6 × 4 m room with
/// knowledge `k`; `prepare` sets the robot up first (places the object, scripts replies).
pub fn verify_cerealbox(k: &Knowledge, prepare: impl FnOnce(&mut ScriptedRobot)) -> Verified {
    verify_cerealbox_with(k, &AgentConfig::default(), prepare)
}

/// [`verify_cerealbox`] under agent configuration `config`.
pub fn verify_cerealbox_with(
    k: &Knowledge,
    config: &AgentConfig,
    prepare: impl FnOnce(&mut ScriptedRobot),
) -> Verified {
    let config = config.clone();
    let (mut robot, mut mem) = verification_room(&config, k);
    prepare(&mut robot);
    let mut sink = sink();
    let mut run = run(&mut sink);
    let confirmed = super::verify::verify(
        ctx(k, &config),
        &mut mem,
        &mut Body::new(&mut robot),
        &mut run,
        "cerealbox",
        &object("cerealbox", 4.5, 2.0, 0.14),
    )
    .expect("verification runs");
    Verified {
        confirmed,
        events: run.events.clone(),
        rejected: mem
            .rejected
            .iter()
            .map(|r| (r.class.clone(), r.at))
            .collect(),
        metrics: run.metrics.clone(),
        robot,
    }
}
