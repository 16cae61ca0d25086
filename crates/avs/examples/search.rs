//! A program with the single dependency `avs`: search the shipped office for an object class
//! (default: the cereal box) with the simulated robot and print the trace and the verdict.
//!
//! ```sh
//! cargo run -p avs --example search -- mug
//! ```

use avs::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let class = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cerealbox".into());
    let world = Shipped::Environment.input().world()?;
    let knowledge = Shipped::Knowledge.input().knowledge()?;
    let domain = Shipped::Domain.input().domain()?;
    let mut robot = SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), 1)?;
    let mut agent = Agent::new(domain, knowledge, AgentConfig::default())?;
    let mut print = |e: &avs::agent::Event| print!("{}", e.text());
    let report = agent.search_with(&mut robot, Goal::find(&class), &mut print)?;
    println!("{}", report.reason);
    Ok(())
}
