//! afl target `scenario`: see `avs_fuzz::scenario`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::scenario(data));
}
