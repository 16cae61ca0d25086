//! The search agent hands its candidate detections to the verifier a class names in the
//! knowledge file: with a sensor model trained on the simulator's generic detector and the
//! correlated detector behind the `Robot` trait, the planned verifier confirms the default
//! office's cereal box and never reports a look-alike; a verifier block the agent cannot use
//! stops it before the search.

use avs_agent::{Agent, AgentConfig, Event, Goal};
use avs_eval::verification::{profile_of, train_model};
use avs_format::knowledge::Knowledge;
use avs_format::verification::DetectorName;
use avs_format::verifier::{ModelKind, NamedSensorModel, VerifierSpec, VerifierStrategy};
use avs_plan::domain::Domain;
use avs_sim::score::SUCCESS_RADIUS;
use avs_sim::sim_robot::{DetectorKind, SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::{Path, PathBuf};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn domain() -> Domain {
    Domain::load(&shipped("domains/object_search.yaml")).unwrap()
}

/// The shipped knowledge with a `generic` model trained on the simulator's generic detector
/// and `class` verified by `strategy` with it (as `avs verify train` and an edit would make it).
fn knowledge_with(class: &str, strategy: VerifierStrategy, model: &str) -> Knowledge {
    let mut k: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let spec = train_model(
        &profile_of(DetectorName::Generic),
        ModelKind::Dynamic { alpha_scale: 1.0 },
        3,
    )
    .unwrap();
    k.sensor_models.push(NamedSensorModel {
        name: "generic".into(),
        model: spec,
    });
    k.object_classes
        .iter_mut()
        .find(|c| c.name == class)
        .unwrap()
        .verifier = Some(VerifierSpec {
        strategy,
        model: Some(model.into()),
        threshold: None,
    });
    k
}

#[test]
fn the_planned_verifier_confirms_the_cerealbox_and_never_reports_a_look_alike() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let k = knowledge_with("cerealbox", VerifierStrategy::Planned, "generic");
    let truth: Vec<[f64; 2]> = world
        .env
        .objects
        .iter()
        .filter(|o| o.class == "cerealbox")
        .map(|o| [o.pose.x, o.pose.y])
        .collect();
    let mut found = 0;
    for seed in 1..=4 {
        let config = SimRobotConfig {
            detector_kind: DetectorKind::Correlated,
            ..SimRobotConfig::default()
        };
        let mut robot = SimAgentRobot::new(&world, k.clone(), config, seed).unwrap();
        let mut agent = Agent::new(domain(), k.clone(), AgentConfig::default()).unwrap();
        let r = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
        let text = avs_agent::trace::render_text(&r.trace);
        // Every candidate of the target class went to the planned verifier and was decided.
        let created: Vec<&Event> = r
            .trace
            .iter()
            .filter(|e| matches!(e, Event::CandidateCreated { class, .. } if class == "cerealbox"))
            .collect();
        assert!(!created.is_empty(), "seed {seed}: no candidate\n{text}");
        assert!(created.iter().all(|e| matches!(e,
            Event::CandidateCreated { verifier, prior, .. }
                if verifier == "planned" && *prior > 0.0 && *prior < 1.0)));
        let decisions = r
            .trace
            .iter()
            .filter(|e| matches!(e, Event::VerificationDecision { .. }))
            .count();
        let m = &r.metrics;
        assert_eq!(m.candidates, decisions, "seed {seed}");
        assert_eq!(m.candidates, m.candidates_accepted + m.candidates_rejected);
        // Every score image costs the simulated detector a second (the generic profile), those
        // that saw nothing included. (Landmark sightings are verified by the default
        // sequential rule, whose closer looks are plain detections and cost no score image.)
        let planned_looks: usize = r
            .trace
            .iter()
            .filter_map(|e| match e {
                Event::VerificationDecision { class, looks, .. } if class == "cerealbox" => {
                    Some(*looks)
                }
                _ => None,
            })
            .sum();
        assert!(
            m.verification_detector_s >= planned_looks as f64,
            "seed {seed}: {} s for {planned_looks} looks",
            m.verification_detector_s,
        );
        if let Some(f) = &r.found {
            // A report is a true cereal box, never a look-alike.
            let near = truth
                .iter()
                .any(|t| (t[0] - f.pose.x).hypot(t[1] - f.pose.y) <= SUCCESS_RADIUS);
            assert!(near, "seed {seed}: wrong report {f:?}\n{text}");
            found += 1;
            assert!(m.candidates_accepted >= 1);
            assert!(
                m.path_by_activity.verification > 0.0 || m.verification_looks >= 1,
                "seed {seed}: accepted without a verification look\n{text}"
            );
        }
    }
    assert!(found >= 3, "the cerealbox found on {found} of 4 seeds");
}

#[test]
fn a_verifier_naming_a_model_the_knowledge_lacks_stops_the_agent_before_the_search() {
    let k = knowledge_with("mug", VerifierStrategy::Greedy, "doors");
    let mug = k
        .object_classes
        .iter()
        .position(|c| c.name == "mug")
        .unwrap();
    let e = Agent::new(domain(), k, AgentConfig::default())
        .unwrap_err()
        .to_string();
    // The knowledge file's own check names the field, as `avs validate` does.
    assert!(
        e.contains(&format!("object_classes[{mug}].verifier.model")) && e.contains("doors"),
        "{e}"
    );
}
