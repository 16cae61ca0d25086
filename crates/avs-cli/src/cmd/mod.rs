//! One module per subcommand. Each exposes `Args` (clap) and `run(Args) -> anyhow::Result<ExitCode>`.

pub mod bench;
pub mod defaults;
pub mod examples;
pub mod generate;
pub mod gp;
pub mod infer;
pub mod plan;
pub mod pomdp;
pub mod render;
pub mod run;
pub mod scenario;
pub mod schema;
pub mod search;
pub mod segment;
pub mod serve;
pub mod validate;
pub mod verify;
pub mod views;
pub mod zoom_bench;
