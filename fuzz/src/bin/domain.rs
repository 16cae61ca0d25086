//! afl target `domain`: see `avs_fuzz::domain`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::domain(data));
}
