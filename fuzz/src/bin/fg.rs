//! afl target `fg`: see `avs_fuzz::fg`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::fg(data));
}
