//! `avs bench`: the JSON keys scripts rely on, determinism, and errors for bad flags.

mod common;
use common::avs;

fn bench_json(args: &[&str]) -> serde_json::Value {
    let out = avs(args);
    assert!(
        out.status.success(),
        "avs {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("--json prints JSON")
}

/// Everything but wall times.
fn without_timings(mut v: serde_json::Value) -> serde_json::Value {
    if let Some(o) = v.as_object_mut() {
        o.remove("plan_ms_median");
        o.remove("compute_s_max");
        if let Some(runs) = o.get_mut("runs").and_then(|r| r.as_array_mut()) {
            for r in runs {
                if let Some(r) = r.as_object_mut() {
                    r.remove("plan_ms_median");
                    r.remove("dt_ms_median");
                    r.remove("compute_s");
                }
            }
        }
    }
    v
}

#[test]
fn bench_json_has_the_contract_keys_and_the_same_seed_gives_the_same_figures() {
    let args = [
        "bench",
        "--generate",
        "2",
        "--seed",
        "5",
        "--rooms",
        "2",
        "--strategy",
        "frontier",
        "--json",
    ];
    let a = bench_json(&args);
    for key in [
        "success_rate",
        "spl_mean",
        "path_length_mean",
        "plans_mean",
        "plan_ms_median",
        "soft_spl_mean",
        "wrong_reports",
        "path_by_activity_mean",
        "room_revisits_mean",
        "runs",
    ] {
        assert!(a.get(key).is_some(), "missing `{key}` in {a:#}");
    }
    let runs = a["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    let reachable: Vec<&serde_json::Value> =
        runs.iter().filter(|r| r["reachable"] == true).collect();
    let found = reachable.iter().filter(|r| r["found"] == true).count();
    let rate = a["success_rate"].as_f64().unwrap();
    assert!(
        (rate * reachable.len() as f64 - found as f64).abs() < 1e-9,
        "success_rate {rate} is not found/reachable = {found}/{}",
        reachable.len()
    );
    for r in runs {
        // The path's breakdown adds up to it; a wrong report is a report that is not a find.
        let by = &r["path_by_activity"];
        let total: f64 = ["exploration", "view_cones", "verification", "coverage"]
            .iter()
            .map(|k| by[*k].as_f64().unwrap())
            .sum();
        let path = r["path_length"].as_f64().unwrap();
        assert!((total - path).abs() < 1e-6, "{r:#}");
        let reported = !r["reported_pose"].is_null();
        assert_eq!(
            r["wrong_report"] == true,
            reported && r["found"] != true,
            "{r:#}"
        );
        let soft = r["soft_spl"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&soft), "{r:#}");
        assert!(r["room_revisits"].as_u64().is_some(), "{r:#}");
        let spl = r["spl"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&spl), "{r:#}");
        if r["found"] != true {
            assert_eq!(spl, 0.0, "SPL of a failed run: {r:#}");
        }
        // SPL never exceeds the shortest path's share of what was driven.
        if let (Some(l), Some(p)) = (
            r["shortest_path_length"].as_f64(),
            r["path_length"].as_f64(),
        ) {
            assert!(spl <= l / l.max(p) + 1e-9, "{r:#}");
        }
    }
    let b = bench_json(&args);
    assert_eq!(without_timings(a), without_timings(b));
}

#[test]
fn the_correlated_detector_and_the_look_alike_rate_are_flags_and_candidates_add_up() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "bench",
            "--generate",
            "2",
            "--seed",
            "3",
            "--rooms",
            "2",
            "--json",
        ];
        args.extend_from_slice(extra);
        bench_json(&args)
    };
    let corr = run(&["--detector", "correlated", "--lookalikes", "2"]);
    for r in corr["runs"].as_array().unwrap() {
        let n = r["candidates"].as_u64().unwrap();
        let acc = r["candidates_accepted"].as_u64().unwrap();
        let rej = r["candidates_rejected"].as_u64().unwrap();
        assert_eq!(n, acc + rej, "{r:#}");
        // A found or wrongly reported target was an accepted candidate.
        if !r["reported_pose"].is_null() {
            assert!(acc >= 1, "{r:#}");
        }
        assert!(r["verification_detector_s"].as_f64().is_some(), "{r:#}");
    }
    // The detector is a real switch: the same floors searched with the independent detector
    // give other runs.
    let indep = run(&["--detector", "independent", "--lookalikes", "2"]);
    assert_ne!(without_timings(corr), without_timings(indep));
    for (bad, named) in [
        ("--detector=psychic", "detector"),
        ("--lookalikes=-1", "lookalikes"),
        ("--lookalikes=11", "lookalikes"),
    ] {
        let out = avs(&["bench", "--generate", "1", bad]);
        assert!(!out.status.success(), "{bad} was accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(named), "{bad}: {err}");
    }
}

#[test]
fn unknown_strategy_and_goal_are_errors_naming_what_is_expected() {
    let out = avs(&["bench", "--generate", "1", "--strategy", "random"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("planner, uninformed, frontier or informed"),
        "stderr: {err}"
    );
    let out = avs(&["bench", "--generate", "1", "--goal", "unicorn"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--goal unicorn") && err.contains("cerealbox"),
        "stderr: {err}"
    );
    let out = avs(&["bench", "--generate", "0"]);
    assert!(!out.status.success());
}

#[test]
fn a_saved_floor_replays_with_avs_search_to_the_same_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("floors");
    let d = dir.to_str().unwrap();
    let a = bench_json(&[
        "bench",
        "--generate",
        "1",
        "--seed",
        "7",
        "--rooms",
        "2",
        "--strategy",
        "frontier",
        "--json",
        "--save-floors",
        d,
    ]);
    let run = &a["runs"][0];
    let floor = dir.join("floor-7.yaml");
    assert!(floor.exists(), "no {}", floor.display());
    let goal = run["goal"].as_str().unwrap();
    // The replay line `avs bench --help` prints: knowledge and domain are the defaults.
    let out = avs(&[
        "search",
        "--env",
        floor.to_str().unwrap(),
        "--goal",
        goal,
        "--seed",
        "7",
        "--strategy",
        "frontier",
        "--json",
    ]);
    let replay: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "avs search --json: {e}; stderr {}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    for key in ["found", "path_length", "shortest_path_length", "reason"] {
        assert_eq!(
            replay[key], run[key],
            "`{key}` differs between bench and replay"
        );
    }
}

/// Issue 19: with stderr not a terminal (a log file, CI) the bench printed nothing for minutes;
/// it now says each floor it finished.
#[test]
fn a_bench_without_a_terminal_reports_each_floor_on_stderr() {
    let out = avs(&[
        "bench",
        "--generate",
        "2",
        "--seed",
        "7",
        "--rooms",
        "2",
        "--strategy",
        "frontier",
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("frontier 1/2 floors") && err.contains("frontier 2/2 floors"),
        "{err}"
    );
}
