//! afl target `map`: see `avs_fuzz::map`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::map(data));
}
