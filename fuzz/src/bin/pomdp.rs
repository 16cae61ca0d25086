//! afl target `pomdp`: see `avs_fuzz::pomdp`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::pomdp(data));
}
