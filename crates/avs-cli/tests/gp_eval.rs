//! `avs gp eval`: the JSON it prints against scikit-learn's reference cases
//! (`shared/data/gp/sklearn_gpr.json`; skipped with a notice when absent), a small case with a
//! closed-form answer, and malformed case files (exit 1, naming the file and the field).
//!
//! Tolerances as in avs-verify's `tests/sklearn_gp.rs`: fixed cases within
//! `1e-6 · max(|ref|, 1)`; fitted cases at least scikit-learn's likelihood − 1e-3, with the
//! parameters inside the bounds.

mod common;
use common::avs;
use serde_json::Value;
use std::io::Write;
use std::path::PathBuf;

const KEYS: [&str; 7] = [
    "name",
    "log_marginal_likelihood",
    "lml_gradient_wrt_log_params",
    "mean",
    "std",
    "signal_variance",
    "length_scale",
];

/// `$AVS_REFERENCE_DATA/gp/sklearn_gpr.json` or `../shared/data/gp/sklearn_gpr.json` beside
/// the checkout; `None` with a notice on stderr and a line `gp<TAB>binary` in `$AVS_SKIP_LOG`
/// (the convention of `avs_testdata::reference_data`, which this crate does not depend on).
fn reference_file() -> Option<PathBuf> {
    let root = std::env::var_os("AVS_REFERENCE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let path = root.join("gp").join("sklearn_gpr.json");
    if path.is_file() {
        return Some(path);
    }
    let _ = writeln!(
        std::io::stderr(),
        "NOTICE: reference data {path:?} not found (set AVS_REFERENCE_DATA or place shared/data beside the checkout); skipping"
    );
    if let Some(log) = std::env::var_os("AVS_SKIP_LOG") {
        let binary = std::env::current_exe()
            .ok()
            .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_default();
        let _ = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(log)
            .and_then(|mut f| f.write_all(format!("gp\t{binary}\n").as_bytes()));
    }
    None
}

/// A file named `name` holding `text`, in a temporary directory of its own that is deleted
/// when the returned handle is dropped.
fn temp_file(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// `|a − b| / max(|b|, 1)`, worst over the entries.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1.0))
        .fold(0.0, f64::max)
}

/// Runs `avs gp eval FILE --json …` and returns its `cases`, each checked to have exactly
/// [`KEYS`].
fn eval_json(file: &str, extra: &[&str]) -> Vec<Value> {
    let mut args = vec!["gp", "eval", file, "--json"];
    args.extend(extra);
    let o = avs(&args);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    let v: Value = serde_json::from_slice(&o.stdout).expect("--json prints JSON");
    let cases = v["cases"].as_array().expect("a `cases` array").clone();
    for c in &cases {
        let mut keys: Vec<&str> = c.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut want = KEYS.to_vec();
        want.sort_unstable();
        assert_eq!(keys, want);
    }
    cases
}

#[test]
fn eval_json_matches_scikit_learn() {
    let Some(path) = reference_file() else { return };
    let reference: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let reference = reference["cases"].as_array().unwrap();
    let ours = eval_json(path.to_str().unwrap(), &[]);
    assert_eq!(ours.len(), reference.len());
    for (r, c) in ours.iter().zip(reference) {
        let name = c["name"].as_str().unwrap();
        assert_eq!(r["name"], c["name"]);
        let lml = r["log_marginal_likelihood"].as_f64().unwrap();
        let ref_lml = c["log_marginal_likelihood"].as_f64().unwrap();
        let grad = floats(&r["lml_gradient_wrt_log_params"]);
        let ref_grad = floats(&c["lml_gradient_wrt_log_params"]);
        assert_eq!(grad.len(), ref_grad.len(), "{name}");
        assert_eq!(
            floats(&r["length_scale"]).len(),
            floats(&c["length_scale"]).len()
        );
        if c["fitted"].as_bool().unwrap() {
            assert!(lml >= ref_lml - 1e-3, "{name}: {lml} < {ref_lml} − 1e-3");
            let b = &c["bounds"];
            let (sv, sv_b) = (
                r["signal_variance"].as_f64().unwrap(),
                floats(&b["signal_variance"]),
            );
            let ls_b = floats(&b["length_scale"]);
            let inside = |v: f64, b: &[f64]| v >= b[0] * (1.0 - 1e-12) && v <= b[1] * (1.0 + 1e-12);
            assert!(inside(sv, &sv_b), "{name}: σ² {sv} outside {sv_b:?}");
            for l in floats(&r["length_scale"]) {
                assert!(inside(l, &ls_b), "{name}: l {l} outside {ls_b:?}");
            }
        } else {
            assert!(
                worst(&[lml], &[ref_lml]) <= 1e-6,
                "{name}: lml {lml} vs {ref_lml}"
            );
            assert!(
                worst(&grad, &ref_grad) <= 1e-6,
                "{name}: {grad:?} vs {ref_grad:?}"
            );
            for key in ["mean", "std"] {
                let (a, b) = (floats(&r[key]), floats(&c[key]));
                assert!(worst(&a, &b) <= 1e-6, "{name} {key}: {a:?} vs {b:?}");
            }
            assert_eq!(r["signal_variance"], c["signal_variance"]);
            assert_eq!(r["length_scale"], c["length_scale"]);
        }
    }
}

const ONE_POINT: &str = r#"{"cases": [{
    "name": "one point", "X": [[0.0]], "y": [1.0], "X_query": [[0.0], [0.7], [30.0]],
    "noise_variance_alpha": 0.0, "fitted": false, "signal_variance": 2.0, "length_scale": [1.0]
}]}"#;

#[test]
fn one_training_point_gives_the_closed_form_answer() {
    // K = σ² = 2, α = y/2: mean(q) = e^{−q²/2}, var(q) = 2 − 2e^{−q²},
    // log p = −y²/4 − ½ ln 2 − ½ ln 2π, ∂/∂ log σ² = y²/4 − ½, ∂/∂ log l = 0.
    let (_dir, file) = temp_file("one.json", ONE_POINT);
    let cases = eval_json(file.to_str().unwrap(), &[]);
    assert_eq!(cases.len(), 1);
    let r = &cases[0];
    assert_eq!(r["name"], "one point");
    let q = [0.0f64, 0.7, 30.0];
    let mean: Vec<f64> = q.iter().map(|q| (-q * q / 2.0).exp()).collect();
    let std: Vec<f64> = q
        .iter()
        .map(|q| (2.0 - 2.0 * (-q * q).exp()).sqrt())
        .collect();
    assert!(worst(&floats(&r["mean"]), &mean) < 1e-12, "{r}");
    assert!(worst(&floats(&r["std"]), &std) < 1e-7, "{r}");
    let lml = -0.25 - 0.5 * 2f64.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln();
    assert!(worst(&[r["log_marginal_likelihood"].as_f64().unwrap()], &[lml]) < 1e-12);
    assert!(worst(&floats(&r["lml_gradient_wrt_log_params"]), &[-0.25, 0.0]) < 1e-12);

    // The table names the case.
    let o = avs(&["gp", "eval", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.lines().any(|l| l.starts_with("one point")), "{out}");
}

#[test]
fn a_fit_is_reproducible_for_a_seed() {
    let text = r#"{"cases": [{
        "name": "fit", "X": [[0.0], [0.5], [1.1], [2.0], [2.2], [3.0]],
        "y": [0.1, 0.6, 0.8, 0.9, 0.7, 0.2], "X_query": [[1.5]],
        "noise_variance_alpha": 1e-4, "fitted": true, "signal_variance": 1.0, "length_scale": [1.0],
        "bounds": {"signal_variance": [0.01, 100.0], "length_scale": [0.01, 100.0]}
    }]}"#;
    let (_dir, file) = temp_file("fit.json", text);
    let f = file.to_str().unwrap();
    let a = eval_json(f, &["--seed", "5"]);
    let b = eval_json(f, &["--seed", "5"]);
    assert_eq!(a, b);
    // The fit ends where the gradient vanishes (the optimum is inside the bounds here).
    let g = floats(&a[0]["lml_gradient_wrt_log_params"]);
    assert!(g.iter().all(|c| c.abs() < 1e-4), "{g:?}");
}

/// Runs `avs gp eval` on `text` and returns stderr, asserting exit 1 and the file named once.
fn fails(name: &str, text: &str) -> String {
    let (_dir, file) = temp_file(name, text);
    let f = file.to_str().unwrap();
    let o = avs(&["gp", "eval", f, "--json"]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{name}: {err}");
    assert!(o.stdout.is_empty(), "{name}: printed {:?}", o.stdout);
    assert_eq!(err.matches(f).count(), 1, "{name}: {err}");
    err
}

#[test]
fn malformed_case_files_exit_1_naming_the_file_and_the_field() {
    // X and y of different lengths.
    let err = fails(
        "xy.json",
        &ONE_POINT.replace(r#""y": [1.0]"#, r#""y": [1.0, 2.0]"#),
    );
    assert!(err.contains("`y`") && err.contains("one point"), "{err}");
    // A query point with two coordinates for a one-input kernel.
    let err = fails("dim.json", &ONE_POINT.replace("[0.7]", "[0.7, 1.0]"));
    assert!(err.contains("X_query[1]"), "{err}");
    // A zero length scale.
    let err = fails(
        "ls.json",
        &ONE_POINT.replace(r#""length_scale": [1.0]"#, r#""length_scale": [0.0]"#),
    );
    assert!(err.contains("length_scale[0]"), "{err}");
    // A fitted case without bounds.
    let err = fails(
        "bounds.json",
        &ONE_POINT.replace(r#""fitted": false"#, r#""fitted": true"#),
    );
    assert!(err.contains("bounds"), "{err}");
    // A string where a number belongs: the path in the document.
    let err = fails(
        "type.json",
        &ONE_POINT.replace("[[0.0]], \"y\"", "[[\"a\"]], \"y\""),
    );
    assert!(err.contains("cases[0].X[0][0]"), "{err}");
    // A missing field.
    let err = fails("missing.json", &ONE_POINT.replace(r#""y": [1.0],"#, ""));
    assert!(err.contains("missing field `y`"), "{err}");
    // Not JSON at all.
    fails("bad.json", "{\"cases\": [");
    // Too many inputs per point: refused, not attempted.
    let wide = format!("[{}]", vec!["0.0"; 65].join(", "));
    let err = fails(
        "wide.json",
        &ONE_POINT.replace("[[0.0]], \"y\"", &format!("[{wide}], \"y\"")),
    );
    assert!(err.contains("at most 64"), "{err}");
}

#[test]
fn a_missing_file_exits_1_naming_it_once() {
    let o = avs(&["gp", "eval", "no/such/cases.json"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.matches("no/such/cases.json").count(), 1, "{err}");
}
