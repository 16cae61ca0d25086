//! avs-workspace-hack: no code. Every workspace member depends on this crate, whose
//! dependencies (written by `cargo hakari generate`, see `.config/hakari.toml`) enable each
//! third-party crate's features as the whole workspace needs them, tests and benches included.
//! So `cargo run -p avs-cli` and `cargo test --workspace` build every dependency once, with the
//! same features, and the second command reuses the first's build (README, quick start).
