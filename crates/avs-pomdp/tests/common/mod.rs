//! Models shared by the avs-pomdp test crates.
#![allow(
    dead_code,
    reason = "each test crate that includes this module uses a different part of it"
)]

use avs_pomdp::{parse_pomdp, Pomdp};

/// The tiger problem (Kaelbling, Littman & Cassandra 1998) in Cassandra's format, discount 0.95.
pub const TIGER: &str = "discount: 0.95\nvalues: reward\nstates: tiger-left tiger-right\n\
    actions: listen open-left open-right\nobservations: tiger-left tiger-right\nstart: uniform\n\
    T: listen\nidentity\nT: open-left\nuniform\nT: open-right\nuniform\n\
    O: listen\n0.85 0.15\n0.15 0.85\nO: open-left\nuniform\nO: open-right\nuniform\n\
    R: listen : * : * : * -1\n\
    R: open-left : tiger-left : * : * -100\nR: open-left : tiger-right : * : * 10\n\
    R: open-right : tiger-left : * : * 10\nR: open-right : tiger-right : * : * -100\n";

/// Tiger with another discount.
pub fn tiger(discount: f64) -> Pomdp {
    let text = TIGER.replace("discount: 0.95", &format!("discount: {discount}"));
    parse_pomdp(&text, "tiger").expect("tiger parses")
}
