//! `BENCHMARKS.md` is assembled from the parts in `docs/benchmarks/` (its README): every part
//! must appear in it word for word, each heading one level deeper and link targets aside (the
//! assembly rewrites them relative to the top of the tree), so that a figure updated in one
//! place and not the other is caught here rather than read stale.

use std::path::Path;

/// `text` with every Markdown heading one level deeper (`# A` → `## A`).
fn one_level_deeper(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.starts_with('#') {
                format!("#{l}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `text` with every Markdown link target left out (`[a](b)` → `[a]()`).
fn without_link_targets(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        out.push_str(&rest[..i + 2]);
        rest = &rest[i + 2..];
        match rest.find(')') {
            Some(j) => rest = &rest[j..],
            None => break,
        }
    }
    out.push_str(rest);
    out
}

#[test]
fn every_benchmark_part_appears_in_benchmarks_md_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let whole = without_link_targets(&std::fs::read_to_string(root.join("BENCHMARKS.md")).unwrap());
    let mut parts = 0;
    for entry in std::fs::read_dir(root.join("docs/benchmarks")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.ends_with(".md") || name == "README.md" {
            continue;
        }
        parts += 1;
        let part = without_link_targets(&one_level_deeper(
            std::fs::read_to_string(&path).unwrap().trim_end(),
        ));
        if !whole.contains(&part) {
            let first_stale = part
                .lines()
                .find(|l| !whole.contains(l))
                .unwrap_or("(every line is there, not in this order)");
            panic!("docs/benchmarks/{name} is not in BENCHMARKS.md as written; first line that is not: {first_stale}");
        }
    }
    assert!(parts >= 6, "only {parts} parts found in docs/benchmarks");
}
