//! The fault matrix, small (issue 18 item 7): two generated floors under every fault of
//! [`Fault::matrix`]. No run panics or runs past its budgets; every give-up with a cause to
//! name names it (the failed actions, the closed door); no wrong report under a fault that adds
//! no false alarm. False positives ×2 and ×5 are counted, not asserted: the fixed verification
//! rule (three zoomed looks from one standpoint, two hits) accepts a spurious sighting now and
//! then once the detector fires more often than the knowledge says, and whether one of the few
//! dozen sightings of a run is the one is the luck of its path (×2 on 20 floors: 0 wrong
//! reports with the paper's view greedy, 1 with the weighted one; BENCHMARKS.md). The planned
//! verifier of the verification issue replaces the rule. The full matrix is
//! `avs bench --faults --generate 20`.

use avs_agent::AgentConfig;
use avs_eval::episode::{load_domain, load_knowledge};
use avs_eval::faults::{fault_matrix, Fault, FaultParams};
use std::path::Path;

#[test]
fn faults_end_within_budget_name_their_cause_and_add_no_wrong_report_without_more_false_alarms() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let knowledge = load_knowledge(&root.join("knowledge/office.yaml")).unwrap();
    let domain = load_domain(&root.join("domains/object_search.yaml")).unwrap();
    // The fixed budgets (no growth with the rooms known), so that "within budget" can be
    // checked from the run alone.
    let config = AgentConfig {
        plans_per_room: 0,
        actions_per_room: 0,
        ..AgentConfig::default()
    };
    let params = FaultParams {
        floors: 2,
        seed: 1,
        rooms: 6,
        faults: Fault::matrix(),
        config: config.clone(),
    };
    let m = fault_matrix(&knowledge, &domain, &params, &|| {}).unwrap();
    assert_eq!(m.runs.len(), 2 * Fault::matrix().len());
    for r in &m.runs {
        let what = format!("{}, floor {} ({})", r.fault.label(), r.seed, r.goal);
        assert!(
            r.plans <= config.max_plans,
            "{what}: {} plans past the budget",
            r.plans
        );
        assert!(
            r.actions <= config.max_actions + config.max_cover_actions,
            "{what}: {} actions past the budgets",
            r.actions
        );
        assert_eq!(
            r.found || r.wrong_report,
            !r.gave_up,
            "{what}: {}",
            r.reason
        );
        assert_ne!(r.cause_named, Some(false), "{what}: {}", r.reason);
        let adds_false_alarms = matches!(r.fault, Fault::FalsePositives { scale } if scale > 1.0);
        assert!(
            adds_false_alarms || !r.wrong_report,
            "{what}: wrong report: {}",
            r.reason
        );
    }
    // The door faults shut a door on some floor, and its give-ups name it: the test is not
    // vacuous.
    let door_give_ups = m
        .runs
        .iter()
        .filter(|r| r.applicable && r.fault == Fault::TargetBehindClosedDoor && r.gave_up)
        .count();
    assert!(door_give_ups > 0, "no floor gave up behind a closed door");
    for row in &m.rows {
        eprintln!(
            "{}: {} runs, {} found, {} gave up ({}/{} naming the cause), {} wrong, slowest {:.1} s",
            row.label,
            row.runs,
            row.found,
            row.gave_up,
            row.cause_named,
            row.cause_expected,
            row.wrong_reports,
            row.slowest_s
        );
    }
}
