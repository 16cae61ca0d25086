//! afl target `pddl`: see `avs_fuzz::pddl`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::pddl(data));
}
